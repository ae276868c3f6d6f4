//! The last QnH common instructions that need no hardware: TIMCHK, RAMP,
//! RND/SRND, ZPUSH/ZPOP, and precise load-time rejections for STMR, ROTC,
//! CHKST/CHK/CHKCIR/CHKEND, IX/IXEND and IXDEV/IXSET.
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions), SH-080039;
//! 004 = the Q CPU function manual (`shared/seeds/004_…`). PM is not among the
//! references at hand: its section numbers and the behaviour below are as
//! remembered from it, and every point it might settle otherwise is marked as
//! a decision.
//!
//! # Condition OFF
//!
//! A family instruction runs only while its condition is ON, so it never sees
//! the condition turn OFF. Instructions whose outputs change while the
//! condition is OFF (STMR's off-delay and one-shot outputs, ROTC's drive
//! outputs) cannot be built on that and are rejected at load.
//!
//! TIMCHK and RAMP only need to know, when they run, whether their condition
//! was OFF since their last execution (a new measurement / a new ramp starts).
//! They find it with the scan counter SD420 (004: +1 at every END after RUN,
//! 32767 → −32768 → 0): each keeps the SD420 value of its last execution in a
//! state word; not executed in the previous scan (nor earlier in this one)
//! means the condition was OFF. This is exact for instructions of scan
//! programs whose condition is OFF or under an MC that is OFF. It differs from
//! the CPU, which keeps the last condition in the instruction, only where an
//! instruction is not executed at all for a scan (skipped by CJ/SCJ/JMP, in a
//! subroutine not called, in a low-speed, fixed-scan or interrupt program that
//! does not run every scan): there the next execution starts anew, where the
//! CPU would continue; and after exactly a multiple of 65536 scans without
//! execution (SD420 has wrapped) it continues where the CPU would start anew.
//!
//! # CPU-wide state
//!
//! The RND/SRND random series is one per CPU. It lives in the CPU-wide
//! [`ExecCtx::shared`] words at [`SHARED_AT`] ([`SHARED_WORDS`] words), which
//! `instructions::SHARED_WORDS` must include (`misc::SHARED_AT +
//! misc::SHARED_WORDS`); until it does, RND/SRND are rejected at load rather
//! than sharing a word of another family.

use super::data::read_i16;
use super::{Args, CompileFn, ExecCtx, Instr};
use crate::device::{DeviceKind, DeviceMemory};
use crate::engine::{ErrorCode, Fault};
use crate::program::compile::Block;
use crate::program::ops::{BitArg, Num, WordArg};

/// Words of the CPU-wide shared state ([`ExecCtx::shared`]) this family keeps:
/// the state of the RND/SRND random series.
pub const SHARED_WORDS: usize = 1;

/// Offset of this family's words in [`ExecCtx::shared`]: after the two PID
/// registrations.
pub const SHARED_AT: usize = 2 * super::pid::registry::REGISTRY_WORDS;

/// `instructions::SHARED_WORDS` makes room for this family's words.
const SHARED_READY: bool = super::SHARED_WORDS >= SHARED_AT + SHARED_WORDS;

/// The compile function for a mnemonic of this family (pulse suffix removed).
pub fn lookup(m: &str) -> Option<CompileFn> {
    Some(match m {
        "TIMCHK" => timchk as CompileFn,
        "RAMP" => ramp,
        "RND" => rnd,
        "SRND" => srnd,
        "ZPUSH" => |a| zstack(a, false),
        "ZPOP" => |a| zstack(a, true),
        "STMR" => stmr,
        "ROTC" => rotc,
        "CHKST" | "CHK" | "CHKCIR" | "CHKEND" => chk,
        "IX" | "IXEND" => ix,
        "IXDEV" | "IXSET" => ixdev,
        _ => return None,
    })
}

// ------------------------------------------------------------ shared helpers

/// Stamp bit: the instruction has executed since RUN (state words are zeroed at
/// power-on and STOP→RUN).
const SEEN: u32 = 1 << 16;

/// Flat index of the scan counter SD420, or a diagnostic.
fn scan_counter(a: &mut Args<'_, '_>) -> Option<usize> {
    match a.map().index(DeviceKind::SD, 420) {
        Some(i) => Some(i as usize),
        None => {
            let m = a.mnemonic().to_string();
            let at = a.len();
            a.error(
                at,
                format!("`{m}` needs the scan counter SD420, beyond the SD points configured"),
            );
            None
        }
    }
}

/// Records this execution in the stamp word and tells whether the condition
/// stayed ON since the last execution: the instruction also executed in the
/// previous scan or earlier in this one (SD420 one less or equal). False at
/// the first execution since RUN. See the module documentation.
#[inline]
fn continued(mem: &DeviceMemory, stamp: &mut u32, sd420: usize) -> bool {
    let now = mem.words[sd420] as u32;
    let last = std::mem::replace(stamp, SEEN | now);
    last & SEEN != 0 && now.wrapping_sub(last) & 0xFFFF <= 1
}

/// Rejects the pulse form of an instruction the manual gives none.
fn no_pulse(a: &mut Args<'_, '_>, base: &str, why: &str) -> bool {
    if a.mnemonic() == base {
        return true;
    }
    let m = a.mnemonic().to_string();
    let at = a.len();
    a.error(at, format!("`{m}`: {base} has no pulse form ({why})"));
    false
}

/// Reports a load-time rejection at the mnemonic.
fn reject(a: &mut Args<'_, '_>, msg: &str) -> Option<Box<dyn Instr>> {
    let at = a.len();
    a.error(at, msg);
    None
}

// ------------------------------------------------------------------ TIMCHK

/// 100 ms, the unit of TIMCHK's set and current values.
const UNIT_US: u64 = 100_000;

/// PM §7.18.3 TIMCHK `S1 S2 D` (time check): measures how long the condition
/// stays ON in 100 ms units in S1; when the measured time reaches the set
/// value S2, D turns ON.
///
/// * The execution that finds the condition newly ON (see the module
///   documentation) starts a measurement: S1 = 0, D OFF, and, as with `OUT T`
///   (`sequence::timer`), it adds nothing; every later execution adds the scan
///   time measured at the previous END (SD520) and carries the part below
///   100 ms to the next.
/// * S1 keeps counting past S2 (it is the measured ON time) up to 32767
///   (decision). D stays ON once the time is up, until the next measurement
///   starts, even if S2 is raised (as a timed-out timer).
/// * When the condition turns OFF, S1 and D keep their values (the result of
///   the check stays readable); the next measurement clears them. Decision:
///   the clearing happens when the condition turns ON again, not when it
///   turns OFF, as remembered from the manual's description (the manual is not
///   among the references at hand); clearing at OFF would need execution with
///   the condition OFF, which family instructions do not get.
/// * S2 = 0 turns D ON at once (as a timer's set value 0).
///
/// Errors: S2 negative: 4100 (decision, as `OUT T` with a negative set value);
/// an index-modified operand out of range: 4101. No pulse form.
#[derive(Debug)]
struct TimChk {
    cur: WordArg,
    set: WordArg,
    out: BitArg,
    sd420: usize,
    /// State words: the stamp, then the sub-unit remainder (µs).
    state: usize,
}

fn timchk(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !no_pulse(a, "TIMCHK", "it measures how long its condition stays ON") || !a.count(&[3]) {
        return None;
    }
    let cur = a.word_dest(0, Num::I16, 1);
    let set = a.word_src(1, Num::I16);
    let out = a.bit_dest(2);
    let sd420 = scan_counter(a);
    let state = a.state_words(2) as usize;
    Some(Box::new(TimChk {
        cur: cur?,
        set: set?,
        out: out?,
        sd420: sd420?,
        state,
    }))
}

impl Instr for TimChk {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let st = &mut cx.state[self.state..self.state + 2];
        let on_before = continued(mem, &mut st[0], self.sd420);
        let set = read_i16(mem, &self.set)?;
        if set < 0 {
            return Err(ErrorCode::OPERATION);
        }
        // Range checks of index-modified operands before anything is written.
        let old = read_i16(mem, &self.cur)?;
        mem.read_bit(&self.out)?;
        let cur = if on_before {
            let total = st[1] as u64 + cx.scan_us as u64;
            st[1] = (total % UNIT_US) as u32;
            (old as i64 + (total / UNIT_US) as i64).min(i16::MAX as i64) as i32
        } else {
            st[1] = 0;
            mem.write_bit(&self.out, false)?;
            0
        };
        mem.write16(&self.cur, cur as u16)?;
        if cur >= set {
            mem.write_bit(&self.out, true)?;
        }
        Ok(())
    }
}

// -------------------------------------------------------------------- RAMP

/// PM RAMP `n1 n2 D1 n3 D2` (ramp signal): moves D1 from the initial value n1
/// to the final value n2 in n3 executions (scans); D1+1 holds the number of
/// executions so far, and D2 turns ON at the execution that reaches n2.
///
/// * Execution k (k = 1 … n3) writes D1 = n1 + (n2 − n1)·k ÷ n3: the
///   computation Mitsubishi gives for the QnA (FAQ 14530 on
///   fa-faq.mitsubishielectric.co.jp: 10 → 100 in 6 gives 25, 40, 55, 70, 85,
///   100; n2 changed to 200 before the 3rd execution gives 105, 136, 168,
///   200), so n1 and n2 are read at every execution. The quotient is
///   truncated toward zero as in BIN division (the FAQ's examples only show
///   positive quotients; toward zero for a falling ramp is a decision).
/// * When the condition turns OFF, the ramp is interrupted: D1, D1+1 and D2
///   keep their values. When it turns ON again (see the module
///   documentation), D1+1 is cleared, D2 turns OFF and the ramp starts again
///   from n1. Decision, from the FX RAMP this instruction comes from
///   ("interrupted, current value held; D+1 cleared and restarted from S1 when
///   driven again"); the Q manual is not among the references at hand.
/// * After completion, while the condition stays ON, D1 stays at n2 and D2
///   stays ON (decision: hold, there is no repeat-mode flag in the QnH).
/// * The ramp continues from D1+1 while the condition stays ON; a value
///   outside 0 … n3 written there by the program is taken as 0 (below) or as
///   complete (above).
///
/// Errors: n3 outside 1 … 32767: 4100; D1+1 past the end of its device or an
/// index-modified operand out of range: 4101. No pulse form (it runs over
/// several scans).
#[derive(Debug)]
struct Ramp {
    n1: WordArg,
    n2: WordArg,
    d1: Block,
    n3: WordArg,
    d2: BitArg,
    sd420: usize,
    /// State word: the stamp.
    state: usize,
}

fn ramp(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !no_pulse(a, "RAMP", "it runs over several scans") || !a.count(&[5]) {
        return None;
    }
    let n1 = a.word_src(0, Num::I16);
    let n2 = a.word_src(1, Num::I16);
    let d1 = super::data::fixed_block(a, 2, 2);
    let n3 = a.word_src(3, Num::I16);
    let d2 = a.bit_dest(4);
    let sd420 = scan_counter(a);
    let state = a.state_words(1) as usize;
    Some(Box::new(Ramp {
        n1: n1?,
        n2: n2?,
        d1: d1?,
        n3: n3?,
        d2: d2?,
        sd420: sd420?,
        state,
    }))
}

impl Instr for Ramp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let on_before = continued(mem, &mut cx.state[self.state], self.sd420);
        let n3 = read_i16(mem, &self.n3)?;
        if n3 <= 0 {
            return Err(ErrorCode::OPERATION);
        }
        let (n1, n2) = (read_i16(mem, &self.n1)?, read_i16(mem, &self.n2)?);
        let d = mem.block_start(&self.d1, 2)?;
        mem.read_bit(&self.d2)?;
        let done = if on_before {
            (mem.words[d + 1] as i16 as i32).clamp(0, n3)
        } else {
            mem.write_bit(&self.d2, false)?;
            0
        };
        let k = (done + 1).min(n3);
        let v = n1 as i64 + (n2 - n1) as i64 * k as i64 / n3 as i64;
        mem.words[d] = v as i16 as u16;
        mem.words[d + 1] = k as u16;
        if k == n3 {
            mem.write_bit(&self.d2, true)?;
        }
        Ok(())
    }
}

// --------------------------------------------------------------- RND / SRND

/// The series of a CPU after power-on or STOP→RUN (the shared word is zeroed
/// then; it holds the generator state xor this seed).
const DEFAULT_SEED: u32 = 1;

/// PM §7.12.12 RND(P) `D`: the next number of the CPU's random series, 0 …
/// 32767, to D.
///
/// The CPU's generator is not documented; softplc uses the linear congruential
/// generator of the C standard's `rand` example, so that runs are
/// reproducible: state = state × 1103515245 + 12345 (mod 2³²), number =
/// bits 16-30 of the state. The series starts from seed 1 at power-on and
/// STOP→RUN (first numbers 16838, 5758, 10113 …); SRND chooses another. One
/// series for the whole CPU, shared by every program file. No errors besides
/// 4101 for an index-modified D out of range.
#[derive(Debug)]
struct Rnd {
    d: WordArg,
}

/// PM §7.12.12 SRND(P) `S`: restarts the random series from the seed S (any
/// 16-bit value, taken as 0 … 65535): RND then gives the numbers of that
/// series from its first. SRND K1 gives the series of power-on.
#[derive(Debug)]
struct Srnd {
    s: WordArg,
}

/// RND/SRND need their word of the CPU-wide state (module documentation).
fn rng_ready(a: &mut Args<'_, '_>) -> bool {
    if SHARED_READY {
        return true;
    }
    let at = a.len();
    a.error(
        at,
        "unsupported: RND/SRND need the CPU-wide random series, but \
         instructions::SHARED_WORDS does not include misc::SHARED_WORDS yet",
    );
    false
}

fn rnd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) || !rng_ready(a) {
        return None;
    }
    Some(Box::new(Rnd {
        d: a.word_dest(0, Num::I16, 1)?,
    }))
}

fn srnd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) || !rng_ready(a) {
        return None;
    }
    Some(Box::new(Srnd {
        s: a.word_src(0, Num::I16)?,
    }))
}

impl Instr for Rnd {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let word = &mut cx.shared[SHARED_AT];
        let state = (*word ^ DEFAULT_SEED)
            .wrapping_mul(1_103_515_245)
            .wrapping_add(12_345);
        // Checked before the series advances: an out-of-range D draws nothing.
        cx.mem.read16(&self.d)?;
        *word = state ^ DEFAULT_SEED;
        cx.mem.write16(&self.d, (state >> 16 & 0x7FFF) as u16)
    }
}

impl Instr for Srnd {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let seed = cx.mem.read16(&self.s)? as u32;
        cx.shared[SHARED_AT] = seed ^ DEFAULT_SEED;
        Ok(())
    }
}

// ------------------------------------------------------------- ZPUSH / ZPOP

/// Index registers saved per ZPUSH.
const Z_REGS: u32 = 16;

/// PM §7.18.7 ZPUSH(P) `D` / ZPOP(P) `D` (batch save and recovery of the index
/// registers). D is the number of saves made so far; save k (k = 1, 2 …)
/// occupies D+16(k−1)+1 … D+16k, Z0 first (the QnH layout: 1 + 16 words a
/// save; the Universal models differ):
///
/// * ZPUSH writes Z0-Z15 as save n+1 (n = D) and makes D = n+1;
/// * ZPOP restores Z0-Z15 from save n (the last one) and makes D = n−1; the
///   save stays in the words (they are not cleared).
///
/// Nesting is by D (ZPUSH twice, ZPOP twice restores the first values). An
/// index-modified D is resolved before the index registers change.
///
/// Errors (nothing is written): ZPUSH with n negative or 32767, ZPOP with
/// n ≤ 0 (nothing saved): 4100 (decisions: the count cannot take them / there
/// is nothing to restore); the area D … D+16(n+1) (ZPUSH) or D … D+16n (ZPOP)
/// past the end of its device: 4101.
#[derive(Debug)]
struct ZStack {
    d: Block,
    /// Flat index of Z0 and the number of index registers (16 on the QnH).
    z: usize,
    nz: usize,
    pop: bool,
}

fn zstack(a: &mut Args<'_, '_>, pop: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    let d = a.block(0)?;
    let map = a.map();
    Some(Box::new(ZStack {
        d,
        z: map.base(DeviceKind::Z) as usize,
        nz: map.points(DeviceKind::Z).min(Z_REGS) as usize,
        pop,
    }))
}

impl Instr for ZStack {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let s = mem.block_start(&self.d, 1)?;
        let n = mem.words[s] as i16 as i32;
        let (z, nz) = (self.z, self.nz);
        if self.pop {
            if n <= 0 {
                return Err(ErrorCode::OPERATION);
            }
            let s = mem.block_start(&self.d, 1 + Z_REGS * n as u32)?;
            let at = s + 1 + Z_REGS as usize * (n as usize - 1);
            mem.words.copy_within(at..at + nz, z);
            mem.words[s] = (n - 1) as u16;
        } else {
            if !(0..i16::MAX as i32).contains(&n) {
                return Err(ErrorCode::OPERATION);
            }
            let s = mem.block_start(&self.d, 1 + Z_REGS * (n as u32 + 1))?;
            let at = s + 1 + Z_REGS as usize * n as usize;
            mem.words.copy_within(z..z + nz, at);
            mem.words[at + nz..at + Z_REGS as usize].fill(0);
            mem.words[s] = (n + 1) as u16;
        }
        Ok(())
    }
}

// --------------------------------------------------------------- rejected

/// PM STMR `S1 S2 D` (special timer): rejected at load. Its outputs D+0 (off
/// delay), D+1 (one shot after OFF) and D+2 (one shot after ON, ended early by
/// the condition turning OFF) time while the condition is OFF, and D+3 turns
/// OFF with it, which needs the instruction to run with its condition OFF.
fn stmr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    reject(
        a,
        "unsupported: STMR (special timer) needs to run while its condition is OFF \
         (the off-delay and one-shot outputs D+0-D+2 time after the condition turns OFF), \
         but family instructions run only while their condition is ON",
    )
}

/// PM ROTC `S n1 n2 D` (rotary table shortest-direction control): rejected at
/// load. Its drive outputs D+3-D+7 turn OFF when the condition turns OFF, which
/// needs the instruction to run with its condition OFF.
fn rotc(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    reject(
        a,
        "unsupported: ROTC (rotary table shortest-direction control) turns its outputs \
         D+3-D+7 OFF when its condition turns OFF, which needs execution with the condition \
         OFF, but family instructions run only while their condition is ON",
    )
}

/// PM §7.10 CHKST/CHK, CHKCIR/CHKEND (special-format failure check and its
/// check format): rejected at load. CHK checks the ladder pattern programmed
/// with it (and CHKCIR … CHKEND redefines that pattern): program structure,
/// not data an instruction reads.
fn chk(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    reject(
        a,
        "unsupported: CHKST/CHK/CHKCIR/CHKEND special-format failure checks work on the \
         ladder pattern programmed around them (program structure)",
    )
}

/// PM §7.6 IX/IXEND (index modification of an entire ladder block): rejected
/// at load; every device of the enclosed ladder would have to be compiled with
/// the offsets of the modification table.
fn ix(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    reject(
        a,
        "unsupported: IX/IXEND index-modification blocks (the devices of the enclosed ladder \
         would be modified by the offset table)",
    )
}

/// PM §7.6 IXDEV/IXSET (modification values for IX): rejected at load; IXSET
/// builds the IX offset table from the devices of the ladder programmed
/// between IXDEV and IXSET (program structure), for IX blocks softplc does
/// not support.
fn ixdev(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    reject(
        a,
        "unsupported: IXDEV/IXSET build the IX/IXEND offset table from the devices of the \
         ladder between them (program structure); IX/IXEND index-modification blocks are \
         not supported",
    )
}
