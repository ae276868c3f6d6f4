//! Timers TON, TONR, TOF, TMON (002 §5.3 L3103-3235; spec aplc.md §4.2,
//! decision D21). `Txx` is the coil/contact and the current value; the time
//! base follows the number: T0-T209 100 ms, T210-T251 10 ms, T252-T255 1 ms
//! (L1667-1677).
//!
//! Timing (D21): each timer counts from its own start. The instruction marks
//! its timer as timing (a hidden bit, storage STS) and compares the value with
//! the preset when it executes (L3123); the housekeeping phase at the end of
//! each scan ([`housekeeping`], from the system devices) adds that scan's
//! duration to every timing timer, keeping the part below one unit (storage
//! STN, in 10 µs) and saturating at 32767.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr, LocalSlot};
use softplc_ir::local_state;
use softplc_ir::ops::WordArg;
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::devices::Dev;
use crate::resolve::{self, ArgsExt};

static DOC: Doc = Doc {
    family: "timers",
    cite: "002 §5.3 L3103-3235",
    notes: "T0-T209 100 ms, T210-T251 10 ms, T252-T255 1 ms; value saturates at 32767, coil = value ≥ preset (TON/TONR); decision D21",
};

pub static DEFS: &[Def] = &[
    // 002 §5.3 L3105 TON
    Def::app("TON", &DOC, ton).always().steps(Steps::Fixed(5)),
    // 002 §5.3 L3135 TONR
    Def::app("TONR", &DOC, tonr).always().steps(Steps::Fixed(5)),
    // 002 §5.3 L3171 TOF
    Def::app("TOF", &DOC, tof).always().steps(Steps::Fixed(5)),
    // 002 §5.3 L3201 TMON
    Def::app("TMON", &DOC, tmon).always().steps(Steps::Fixed(5)),
];

/// Time base of timer `n` in µs (L1667-1677).
pub fn base_us(n: u32) -> u32 {
    match n {
        0..=209 => 100_000,
        210..=251 => 10_000,
        _ => 1_000,
    }
}

local_state! {
    struct TimerState {
        /// The power flow at the previous execution.
        prev: bool,
        /// Executed since RUN (TON resets on its first execution, L3123).
        seen: bool,
    }
}

/// The housekeeping of 10/100 ms and 1 ms timers (L933, L1677): adds the
/// scan's duration to each timer marked as timing.
pub fn housekeeping(mem: &mut softplc_ir::device::DeviceMemory, scan_us: u64) {
    let (timing, rem, value) = (
        mem.map.base(DeviceKind::STS) as usize,
        mem.map.base(DeviceKind::STN) as usize,
        mem.map.base(DeviceKind::TN) as usize,
    );
    for n in 0..mem.map.points(DeviceKind::STS).min(256) as usize {
        if !mem.bits[timing + n] {
            continue;
        }
        let base = base_us(n as u32) as u64;
        let total = mem.words[rem + n] as u64 * 10 + scan_us;
        let v = (mem.words[value + n] as i16).max(0) as u64 + total / base;
        mem.words[value + n] = v.min(32767) as u16;
        mem.words[rem + n] = ((total % base) / 10) as u16;
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    On,
    Retentive,
    Off,
    OneShot,
}

#[derive(Debug)]
struct Timer {
    mode: Mode,
    contact: u32,
    value: u32,
    /// The hidden "timing" bit and sub-unit remainder (STS, STN).
    timing: u32,
    rem: u32,
    preset: WordArg,
    st: LocalSlot<TimerState>,
}

fn compile(a: &mut Args<'_, '_>, mode: Mode) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let r = resolve::tc(a.text(0), Dev::T);
    let n = a.check(0, r)?;
    let preset = a.word_at(1, Width::W16, false)?;
    let map = a.map();
    Some(Box::new(Timer {
        mode,
        contact: map.base(DeviceKind::TS) + n,
        value: map.base(DeviceKind::TN) + n,
        timing: map.base(DeviceKind::STS) + n,
        rem: map.base(DeviceKind::STN) + n,
        preset,
        st: a.local(),
    }))
}

fn ton(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    compile(a, Mode::On)
}
fn tonr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    compile(a, Mode::Retentive)
}
fn tof(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    compile(a, Mode::Off)
}
fn tmon(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    compile(a, Mode::OneShot)
}

impl Timer {
    fn start(&self, cx: &mut ExecCtx<'_>) {
        cx.mem.bits[self.timing as usize] = true;
        cx.mem.words[self.rem as usize] = 0;
    }

    fn stop(&self, cx: &mut ExecCtx<'_>) {
        cx.mem.bits[self.timing as usize] = false;
    }

    fn step(&self, cx: &mut ExecCtx<'_>, pf: bool) -> Result<(), Fault> {
        let mut st = cx.local(&self.st);
        let preset = cx.mem.read16(&self.preset)? as i16 as i32;
        let (v, c) = (self.value as usize, self.contact as usize);
        let timing = cx.mem.bits[self.timing as usize];
        if !st.seen && self.mode == Mode::On {
            cx.mem.words[v] = 0;
            cx.mem.bits[c] = false;
            self.stop(cx);
        }
        st.seen = true;
        let cur = cx.mem.words[v] as i16 as i32;
        match self.mode {
            Mode::On | Mode::Retentive if pf => {
                if !cx.mem.bits[self.timing as usize] {
                    self.start(cx);
                }
                cx.mem.bits[c] = cur >= preset;
            }
            Mode::On => {
                cx.mem.words[v] = 0;
                cx.mem.bits[c] = false;
                self.stop(cx);
            }
            // TONR: PF OFF holds value and coil (L3135-3169).
            Mode::Retentive => self.stop(cx),
            // TOF: PF ON: value 0, coil ON; the falling edge starts timing;
            // at the preset the coil goes OFF and the value holds (L3171-3199).
            Mode::Off if pf => {
                cx.mem.words[v] = 0;
                cx.mem.bits[c] = true;
                self.stop(cx);
            }
            Mode::Off => {
                if st.prev {
                    self.start(cx);
                } else if timing && cur >= preset {
                    cx.mem.words[v] = preset.max(0) as u16;
                    cx.mem.bits[c] = false;
                    self.stop(cx);
                }
            }
            // TMON: a rising edge while idle starts a pulse from the current
            // value; PF is ignored while timing; at the preset the value
            // returns to 0 and the coil goes OFF (L3201-3235).
            Mode::OneShot => {
                if timing {
                    if cur >= preset {
                        cx.mem.words[v] = 0;
                        cx.mem.bits[c] = false;
                        self.stop(cx);
                    }
                } else if pf && !st.prev {
                    cx.mem.bits[c] = true;
                    self.start(cx);
                }
            }
        }
        st.prev = pf;
        cx.set_local(&self.st, st);
        Ok(())
    }
}

impl Instr for Timer {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx, true)
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx, false)
    }
}
