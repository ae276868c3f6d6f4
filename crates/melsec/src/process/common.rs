//! What every process-control instruction shares (000 §2.2, §3, §14; spec
//! §1.2-§1.4, §5): operand areas, the system devices (ΔT in SD1500, the error
//! details SD1502/SD1503, the hold flags SM1500/SM1501), float words with the
//! manual's validity checks, the error path, and the one period-counter rule
//! (DEC-1 … DEC-4).

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::fault::Fault;
use softplc_ir::layout::{At, WordValue};
use softplc_ir::ops::{Block, WordArg};
use softplc_lang::isa::{CompileFn, Def, Doc, Pulse, Steps};

use super::settings::ProcessSettings;
use super::tag::UPPER_INH_BELOW;
use crate::Args;

/// A process-control instruction (000 §2.2.6-§2.2.7): runs on every scan
/// while its condition is ON, has no pulse form, and takes
/// 2 + ⌈len(name without "S.")/2⌉ + operands steps (`S.IN R0 R100 R200 R1000`
/// is 7, L669-677).
pub const fn def(name: &'static str, operands: u32, doc: &'static Doc, compile: CompileFn) -> Def {
    let len = name.len() as u32 - 2;
    Def::app(name, doc, compile)
        .pulse(Pulse::None)
        .steps(Steps::Fixed(2 + len.div_ceil(2) + operands))
}

/// A process-control operation error: SD1502 detail code (000 Table 14.1)
/// and SD1503 processing number (Table 14.2) where the instruction stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PcError {
    pub detail: u16,
    pub step: u16,
}

impl PcError {
    /// Not a number, ±∞ or denormal (SD1502 = 1).
    pub const fn bad_number(step: u16) -> PcError {
        PcError { detail: 1, step }
    }
    /// A negative value where none is allowed (2).
    pub const fn negative(step: u16) -> PcError {
        PcError { detail: 2, step }
    }
    /// A value out of its range (3).
    pub const fn range(step: u16) -> PcError {
        PcError { detail: 3, step }
    }
    /// An execution count over 32767 (4).
    pub const fn count(step: u16) -> PcError {
        PcError { detail: 4, step }
    }
    /// Division by 0 (5).
    pub const fn divide(step: u16) -> PcError {
        PcError { detail: 5, step }
    }
    /// A result beyond the float range (6).
    pub const fn overflow(step: u16) -> PcError {
        PcError { detail: 6, step }
    }
}

/// The process CPU's system devices, resolved when an instruction compiles.
#[derive(Clone, Copy, Debug)]
pub struct Sys {
    /// SD1500-SD1501: the execution cycle ΔT, float seconds.
    dt: usize,
    /// SD1502 / SD1503: the error detail code and processing number.
    detail: usize,
    step: usize,
    /// SM1500: S.IN holds BW on input range-over.
    sm1500: usize,
    /// SM1501: output instructions hold MV while SEA = 1.
    sm1501: usize,
    /// SD1508: S.PIDP options.
    sd1508: usize,
}

impl Sys {
    /// The system devices of the CPU being compiled for.
    pub fn new(a: &Args<'_, '_>) -> Option<Sys> {
        let map = a.map();
        let w = |n| map.index(DeviceKind::SD, n).map(|i| i as usize);
        let b = |n| map.index(DeviceKind::SM, n).map(|i| i as usize);
        Some(Sys {
            dt: w(1500)?,
            detail: w(1502)?,
            step: w(1503)?,
            sm1500: b(1500)?,
            sm1501: b(1501)?,
            sd1508: w(1508)?,
        })
    }

    /// ΔT from SD1500-SD1501, checked (a bad float is detail 1 at `step`).
    pub fn dt(&self, m: &DeviceMemory, step: u16) -> Result<f32, PcError> {
        real(m, self.dt, step)
    }

    /// SM1500 (S.IN hold on range-over).
    pub fn hold_input(&self, m: &DeviceMemory) -> bool {
        m.bits[self.sm1500]
    }

    /// SM1501 (hold MV while SEA = 1).
    pub fn hold_output(&self, m: &DeviceMemory) -> bool {
        m.bits[self.sm1501]
    }

    /// SD1508.
    pub fn options(&self, m: &DeviceMemory) -> u16 {
        m.words[self.sd1508]
    }

    /// Reports `e` as the CPU does: SD1502/SD1503 set, 4100 raised (000 §14).
    pub fn fail(&self, m: &mut DeviceMemory, e: PcError) -> Fault {
        m.words[self.detail] = e.detail;
        m.words[self.step] = e.step;
        Fault::Operation
    }

    /// Runs an instruction body and reports its error, if any.
    pub fn run(
        &self,
        m: &mut DeviceMemory,
        body: impl FnOnce(&mut DeviceMemory) -> Result<(), PcError>,
    ) -> Result<(), Fault> {
        body(m).map_err(|e| self.fail(m, e))
    }

    /// [`Sys::run`] for a body with a result (what the instruction still has
    /// to do outside the error path, e.g. resolve another operand).
    pub fn run_with<T>(
        &self,
        m: &mut DeviceMemory,
        body: impl FnOnce(&mut DeviceMemory) -> Result<T, PcError>,
    ) -> Result<T, Fault> {
        body(m).map_err(|e| self.fail(m, e))
    }
}

softplc_ir::layout! {
    /// The block memory (D1) of most process instructions (000 §3.3.2):
    /// the output and, where the instruction has them, its BB bits.
    pub struct BlockMemory[3] {
        /// BW: the output value.
        bw: f32 @ 0,
        /// BB: alarm and state bits (BB1 … BB16 = b0 … b15, see
        /// [`super::tag::bb`]); each instruction says which it writes.
        bb: u16 @ 2,
    }
}

softplc_ir::layout! {
    /// The block memory (D1) of the instructions whose outputs are bits
    /// (S.DUTY, S.BC).
    pub struct BitBlockMemory[2] {
        /// BW1 = b0, BW2 = b1, …: the outputs (other bits left alone).
        bw: u16 @ 0,
        /// BB: alarm bits.
        bb: u16 @ 1,
    }
}

softplc_ir::layout! {
    /// Input data (S1) that is one value E1 (000 §3.3.2).
    pub struct Input[2] {
        /// E1: the input value.
        e1: f32 @ 0,
    }
}

softplc_ir::layout! {
    /// Input data (S1) that is a value E1 and control bits (000 §3.3.2).
    pub struct InputCtl[3] {
        /// E1: the input value.
        e1: f32 @ 0,
        /// The control bits e1 = b0, e2 = b1, … (each instruction says which).
        ctl: u16 @ 2,
    }
}

softplc_ir::layout! {
    /// Input data (S1) that is a count n and n values (S.ADD … S.MUL: n =
    /// 0..5; S.HS … S.AVE: 1..16).
    pub struct InputList[33] {
        /// n: the number of inputs (BIN16).
        n: i16 @ 0,
        /// E1, the first input; Ei is `e.nth(i − 1)`.
        e: f32 @ 1,
    }
}

/// An operand area resolved for one execution: the flat index of its first
/// word, read and written through the fields of the area's declared layout
/// (`softplc_ir::layout!`) so that no word offset is computed by hand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Area(pub usize);

impl Area {
    /// The area of `words` words at operand `b` (4101 when an index-modified
    /// area runs past its device).
    #[inline]
    pub fn of(m: &DeviceMemory, b: &Block, words: u32) -> Result<Area, Fault> {
        m.block_start(b, words).map(Area)
    }

    /// Field `f`.
    #[inline]
    pub fn get<T: WordValue>(self, m: &DeviceMemory, f: At<T>) -> T {
        f.get(&m.words[self.0..])
    }

    /// Writes field `f`.
    #[inline]
    pub fn set<T: WordValue>(self, m: &mut DeviceMemory, f: At<T>, v: T) {
        f.set(&mut m.words[self.0..], v)
    }

    /// A float field, checked as [`real`] checks (detail 1 at `step`).
    #[inline]
    pub fn real(self, m: &DeviceMemory, f: At<f32>, step: u16) -> Result<f32, PcError> {
        real(m, self.index(f), step)
    }

    /// The flat index of field `f` (for the period counters, which count in
    /// place).
    #[inline]
    pub fn index<T: WordValue>(self, f: At<T>) -> usize {
        self.0 + f.offset()
    }

    /// Bit `b` of word field `f` (a control bit e1 …, a BB bit).
    #[inline]
    pub fn bit(self, m: &DeviceMemory, f: At<u16>, b: u32) -> bool {
        self.get(m, f) >> b & 1 != 0
    }

    /// Sets (`on`) or clears `bits` of word field `f`.
    #[inline]
    pub fn set_bits(self, m: &mut DeviceMemory, f: At<u16>, bits: u16, on: bool) {
        let w = self.get(m, f);
        self.set(m, f, if on { w | bits } else { w & !bits });
    }

    /// The `k`-th of a run of blocks of `words` words that begins with this
    /// area (a table of records, e.g. S.FG's points of one layout each).
    #[inline]
    pub fn row(self, k: usize, words: usize) -> Area {
        Area(self.0 + k * words)
    }

    /// Writes the bits of `mask` in word field `f` from `value`, the others
    /// kept (BB bits an instruction does not define are left as found).
    #[inline]
    pub fn put_bits(self, m: &mut DeviceMemory, f: At<u16>, mask: u16, value: u16) {
        let w = self.get(m, f);
        self.set(m, f, w & !mask | value & mask);
    }
}

/// An operand area of `words` words: a word device (index modification
/// allowed), not a constant, bit or digit-specified device (the CPU's 4302),
/// and, when its start is known at load, one that fits its device.
pub fn area(a: &mut Args<'_, '_>, k: usize, words: u32, what: &str) -> Option<Block> {
    let b = a.block(k)?;
    if let WordArg::Word(i) = b.start {
        if i as u64 + words as u64 > b.limit as u64 {
            let text = a.text(k).to_string();
            a.error(
                k,
                format!("`{text}`: the {what} takes {words} words, past the end of the device"),
            );
            return None;
        }
    }
    Some(b)
}

/// The S1, D1 and S2 areas of an instruction written `S.x S1 D1 S2 D2(dmy)`
/// with fixed word counts, declared once: checked at load by [`area`],
/// resolved at each execution by [`Areas::starts`].
#[derive(Debug)]
pub struct Areas {
    s1: Block,
    d1: Block,
    s2: Block,
    words: [u32; 3],
}

impl Areas {
    /// Operands 1-3 as areas of `words` words (every diagnostic reported)
    /// and operand 4 a dummy.
    pub fn compile(a: &mut Args<'_, '_>, words: [u32; 3]) -> Option<Areas> {
        let s1 = area(a, 0, words[0], "input data");
        let d1 = area(a, 1, words[1], "block memory");
        let s2 = area(a, 2, words[2], "operation constants");
        dummy(a, 3)?;
        Some(Areas {
            s1: s1?,
            d1: d1?,
            s2: s2?,
            words,
        })
    }

    /// S1, D1 and S2 for one execution (4101 when an index-modified area
    /// runs past its device).
    #[inline]
    pub fn starts(&self, m: &DeviceMemory) -> Result<(Area, Area, Area), Fault> {
        let [w1, w2, w3] = self.words;
        Ok((
            Area::of(m, &self.s1, w1)?,
            Area::of(m, &self.d1, w2)?,
            Area::of(m, &self.s2, w3)?,
        ))
    }
}

/// A dummy operand (000 §3.2: any word device, SD1506 recommended): checked
/// to be a word device, not used.
pub fn dummy(a: &mut Args<'_, '_>, k: usize) -> Option<()> {
    a.block(k).map(|_| ())
}

/// Whether `v` is a number the CPU operates on (000 §2.2.4: 0 or
/// 2^-126 ≤ |v| < 2^128).
#[inline]
pub fn valid(v: f32) -> bool {
    v == 0.0 || v.is_normal()
}

/// Reads a float operand, checked: NaN, ±∞ and denormals are detail 1.
#[inline]
pub fn real(m: &DeviceMemory, i: usize, step: u16) -> Result<f32, PcError> {
    let v = f32::read(&m.words[i..]);
    if valid(v) {
        Ok(v)
    } else {
        Err(PcError::bad_number(step))
    }
}

/// A computed result, checked: beyond the float range is detail 6. A
/// denormal result flushes to 0, as a CPU without gradual underflow gives.
#[inline]
pub fn result(v: f32, step: u16) -> Result<f32, PcError> {
    if v.is_nan() || v.is_infinite() {
        Err(PcError::overflow(step))
    } else if v.is_subnormal() {
        Ok(0.0)
    } else {
        Ok(v)
    }
}

/// The count of executions of ΔT in a period `p` (DEC-2): round(p/ΔT) with
/// halves up, in f32, at least 1 (the integer part when `truncate` — the
/// manual's exceptions — or when the setting says so). ΔT < 0 or p < 0 is
/// detail 2, ΔT = 0 detail 5, a count over 32767 detail 4.
pub fn count(
    p: f32,
    dt: f32,
    truncate: bool,
    s: &ProcessSettings,
    step: u16,
) -> Result<u16, PcError> {
    if dt < 0.0 || p < 0.0 {
        return Err(PcError::negative(step));
    }
    if dt == 0.0 {
        return Err(PcError::divide(step));
    }
    let q = p / dt;
    let n = if truncate || !s.period_count_rounds {
        q.trunc()
    } else {
        (q + 0.5).floor()
    };
    if n > 32767.0 {
        return Err(PcError::count(step));
    }
    Ok((n as u16).max(1))
}

/// What one execution did to a period counter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tick {
    /// This execution started the counter (flag was 0): time 0 of a period.
    pub start: bool,
    /// The period was reached on this execution.
    pub reached: bool,
}

impl Tick {
    /// A period begins on this execution (the start or a reach): take a
    /// sample, a reference, start an operate phase.
    pub fn begins(self) -> bool {
        self.start || self.reached
    }
}

/// Advances the period counter whose preset flag and counter are the words at
/// `flag` and `counter` by one execution (spec §1.3.1, DEC-1 and DEC-3); `n`
/// gives the period's count and is evaluated only when the counter loads
/// (DEC-3), or every execution under the alternative.
pub fn tick(
    m: &mut DeviceMemory,
    flag: usize,
    counter: usize,
    s: &ProcessSettings,
    n: impl FnOnce() -> Result<u16, PcError>,
) -> Result<Tick, PcError> {
    if s.period_change_at_reach {
        if m.words[flag] == 0 {
            m.words[counter] = n()?;
            m.words[flag] = 1;
            return Ok(Tick {
                start: true,
                reached: !s.counter_start_is_time_zero,
            });
        }
        let c = m.words[counter].saturating_sub(1);
        if c == 0 {
            m.words[counter] = n()?;
            Ok(Tick {
                start: false,
                reached: true,
            })
        } else {
            m.words[counter] = c;
            Ok(Tick {
                start: false,
                reached: false,
            })
        }
    } else {
        // The alternative of DEC-3: an up-count compared with the current N.
        let n = n()?;
        if m.words[flag] == 0 {
            m.words[counter] = 0;
            m.words[flag] = 1;
            return Ok(Tick {
                start: true,
                reached: !s.counter_start_is_time_zero,
            });
        }
        let c = m.words[counter].saturating_add(1);
        let reached = c >= n;
        m.words[counter] = if reached { 0 } else { c };
        Ok(Tick {
            start: false,
            reached,
        })
    }
}

/// The change-rate check count m = int(CTIM/ΔT) of S.PHPL and S.BC (000
/// §9.8 L13410-13420, §8.6 L6355-6361: the integer part; m = 0 means no
/// change-rate processing). ΔT or CTIM < 0 is detail 2, ΔT = 0 detail 5,
/// m > 32767 detail 4 (DEC-36).
pub fn rate_count(ctim: f32, dt: f32, step: u16) -> Result<u16, PcError> {
    if dt < 0.0 || ctim < 0.0 {
        return Err(PcError::negative(step));
    }
    if dt == 0.0 {
        return Err(PcError::divide(step));
    }
    let q = (ctim / dt).trunc();
    if q > 32767.0 {
        return Err(PcError::count(step));
    }
    Ok(q as u16)
}

/// What one execution does in a change-rate window (DEC-18).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Window {
    /// m = 0: no change-rate processing, alarms and counter untouched.
    Skip,
    /// The start execution: take the reference, no evaluation.
    Start,
    /// Inside a window: the alarms keep the last window's result.
    Hold,
    /// Evaluate E1 − reference; re-take the reference when `retake` (the
    /// window ends on this execution).
    Evaluate { retake: bool },
}

/// Advances the change-rate window of S.PHPL/S.BC whose flag and counter are
/// the words `flag`/`counter` (spec §1.3.1 with P = CTIM, N = m; DEC-18):
/// the start execution takes the reference; every m-th execution after it
/// evaluates against it and re-takes it; the others hold (under the
/// alternative of DEC-18 they evaluate against the reference too).
pub fn window(
    m: &mut DeviceMemory,
    flag: usize,
    counter: usize,
    count: u16,
    s: &ProcessSettings,
) -> Result<Window, PcError> {
    if count == 0 {
        return Ok(Window::Skip);
    }
    let t = tick(m, flag, counter, s, || Ok(count))?;
    Ok(if t.start {
        Window::Start
    } else if t.reached {
        Window::Evaluate { retake: true }
    } else if !s.change_rate_window {
        Window::Evaluate { retake: false }
    } else {
        Window::Hold
    })
}

/// The word 8 below operand `k` — the INH (+4) of the loop tag whose MV
/// (+12) operand `k` names, where an instruction sets the upper loop's TRKF
/// (spec §1.8, L7424, L7497-7499; S.SEL §9.24). When `k` is a device number
/// below 8 (no such word) the block's limit is 0, so using it is 4101.
pub fn upper_inh(a: &mut Args<'_, '_>, k: usize) -> Option<Block> {
    use softplc_ir::device::Operand;
    let b = a.block(k)?;
    let base = match a.operand(k)? {
        Operand::Device { dev, .. } => a.map().base(dev.word_kind()),
        _ => return None,
    };
    let none = Block {
        start: WordArg::Word(0),
        limit: 0,
    };
    Some(match b.start {
        WordArg::Word(i) if i >= base + UPPER_INH_BELOW => Block {
            start: WordArg::Word(i - UPPER_INH_BELOW),
            limit: b.limit,
        },
        WordArg::Indexed(ix) if ix.number >= UPPER_INH_BELOW => Block {
            start: WordArg::Indexed(Box::new(softplc_ir::ops::Indexed {
                number: ix.number - UPPER_INH_BELOW,
                ..*ix
            })),
            limit: b.limit,
        },
        _ => none,
    })
}

/// [`tick`] for a period counter without a preset flag (S.DED local +1,
/// S.FLT local +3): the caller says whether this execution is the start
/// execution (spec §1.3.1 table: the S.DED 1→0 edge, the S.FLT ST/SN change);
/// otherwise the counter at `counter` counts down as under [`tick`] (DEC-1,
/// DEC-3, and the DEC-3 alternative's up-count).
pub fn tick_started(
    m: &mut DeviceMemory,
    counter: usize,
    start: bool,
    s: &ProcessSettings,
    n: impl FnOnce() -> Result<u16, PcError>,
) -> Result<Tick, PcError> {
    let started = Tick {
        start: true,
        reached: !s.counter_start_is_time_zero,
    };
    let not = |reached| Tick {
        start: false,
        reached,
    };
    if s.period_change_at_reach {
        if start {
            m.words[counter] = n()?;
            return Ok(started);
        }
        let c = m.words[counter].saturating_sub(1);
        if c == 0 {
            m.words[counter] = n()?;
            Ok(not(true))
        } else {
            m.words[counter] = c;
            Ok(not(false))
        }
    } else {
        let n = n()?;
        if start {
            m.words[counter] = 0;
            return Ok(started);
        }
        let c = m.words[counter].saturating_add(1);
        let reached = c >= n;
        m.words[counter] = if reached { 0 } else { c };
        Ok(not(reached))
    }
}

/// A signed BIN16 count (n, SN) checked against `lo..=hi` (detail 3, DEC-36).
#[inline]
pub fn count_word(
    m: &DeviceMemory,
    area: Area,
    f: At<i16>,
    lo: i16,
    hi: i16,
    step: u16,
) -> Result<usize, PcError> {
    let n = area.get(m, f);
    if (lo..=hi).contains(&n) {
        Ok(n as usize)
    } else {
        Err(PcError::range(step))
    }
}

/// Rejects a decision setting whose alternative the manual and the spec do
/// not describe (`[process] key = false`): a load error at the mnemonic
/// rather than a silently ignored setting. Returns whether the setting is
/// the spec's choice.
pub fn only_default(a: &mut Args<'_, '_>, value: bool, key: &str, dec: u8) -> bool {
    if !value {
        let m = a.mnemonic().to_string();
        a.error(
            usize::MAX,
            format!(
                "`{m}`: [process] {key} = false (DEC-{dec}) has no alternative described by \
                 the manual or the spec; only `true` is implemented"
            ),
        );
    }
    value
}

/// For an instruction that reads its previous BW or BB from the block
/// memory (DEC-8): the alternative, a hidden copy, is not described (when it
/// is initialised, whether a program write presets it), so
/// `previous_in_block_memory = false` is a load error (see [`only_default`]).
pub fn history_in_block_memory(a: &mut Args<'_, '_>) -> Option<()> {
    let s: ProcessSettings = a.setting();
    only_default(a, s.previous_in_block_memory, "previous_in_block_memory", 8).then_some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use softplc_ir::device::{DeviceConfig, DeviceMemory};

    fn mem() -> DeviceMemory {
        DeviceMemory::new(&DeviceConfig::default())
    }

    #[test]
    fn counts_round_halves_up_in_f32_and_check_limits() {
        let s = ProcessSettings::default();
        // 0.9/0.3 is 2.9999998 in f32: rounding gives 3, truncation 2 (spec DEC-2).
        assert_eq!(count(0.9, 0.3, false, &s, 1), Ok(3));
        assert_eq!(count(0.9, 0.3, true, &s, 1), Ok(2));
        assert_eq!(count(2.5, 1.0, false, &s, 1), Ok(3));
        assert_eq!(count(0.0, 1.0, false, &s, 1), Ok(1));
        assert_eq!(count(32767.0, 1.0, false, &s, 1), Ok(32767));
        assert_eq!(count(32768.0, 1.0, false, &s, 7), Err(PcError::count(7)));
        assert_eq!(count(5.0, 0.0, false, &s, 1), Err(PcError::divide(1)));
        assert_eq!(count(5.0, -1.0, false, &s, 1), Err(PcError::negative(1)));
    }

    /// ΔT = 1 s, CT = 5 s: computes at t = 5, 10, 15 (spec §1.3.1).
    #[test]
    fn a_period_is_reached_on_the_nth_execution_after_the_start() {
        let s = ProcessSettings::default();
        let mut m = mem();
        let reached: Vec<bool> = (0..16)
            .map(|_| tick(&mut m, 0, 1, &s, || Ok(5)).unwrap().reached)
            .collect();
        let at: Vec<usize> = (0..16).filter(|&t| reached[t]).collect();
        assert_eq!(at, [5, 10, 15]);
        assert_eq!((m.words[0], m.words[1]), (1, 5));
        let up = ProcessSettings {
            period_change_at_reach: false,
            ..s
        };
        let mut m = mem();
        let at: Vec<usize> = (0..16)
            .filter(|_| tick(&mut m, 0, 1, &up, || Ok(5)).unwrap().reached)
            .collect();
        assert_eq!(at, [5, 10, 15]);
    }

    /// m = int(CTIM/ΔT), 0 allowed (no processing); the window of DEC-18.
    #[test]
    fn change_rate_window_takes_evaluates_and_retakes() {
        assert_eq!(rate_count(0.9, 1.0, 3), Ok(0));
        assert_eq!(rate_count(4.5, 1.0, 3), Ok(4));
        assert_eq!(rate_count(4.0, 0.0, 3), Err(PcError::divide(3)));
        assert_eq!(rate_count(-4.0, 1.0, 2), Err(PcError::negative(2)));
        assert_eq!(rate_count(32768.0, 1.0, 2), Err(PcError::count(2)));
        let s = ProcessSettings::default();
        let mut m = mem();
        let w: Vec<Window> = (0..6)
            .map(|_| window(&mut m, 0, 1, 2, &s).unwrap())
            .collect();
        let e = Window::Evaluate { retake: true };
        assert_eq!(
            w,
            [
                Window::Start,
                Window::Hold,
                e,
                Window::Hold,
                e,
                Window::Hold
            ]
        );
        assert_eq!(window(&mut m, 0, 1, 0, &s), Ok(Window::Skip));
        let every = ProcessSettings {
            change_rate_window: false,
            ..s
        };
        let mut m = mem();
        let w: Vec<Window> = (0..3)
            .map(|_| window(&mut m, 0, 1, 2, &every).unwrap())
            .collect();
        assert_eq!(w, [Window::Start, Window::Evaluate { retake: false }, e]);
    }

    #[test]
    fn floats_are_checked_as_the_cpu_does() {
        let mut m = mem();
        let at = Area(10);
        at.set(&mut m, Input::e1, 1.5);
        assert_eq!(real(&m, 10, 3), Ok(1.5));
        assert_eq!(at.real(&m, Input::e1, 3), Ok(1.5));
        at.set(&mut m, Input::e1, f32::NAN);
        assert_eq!(real(&m, 10, 3), Err(PcError::bad_number(3)));
        at.set(&mut m, Input::e1, f32::MIN_POSITIVE / 2.0);
        assert_eq!(real(&m, 10, 3), Err(PcError::bad_number(3)));
        assert_eq!(result(f32::MAX * 2.0, 4), Err(PcError::overflow(4)));
    }
}
