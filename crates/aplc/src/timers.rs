//! Timers TON, TONR, TOF, TMON (002 §5.3 L3103-3235; spec aplc.md §4.2,
//! decision D21). `Txx` is the coil/contact and the current value; the time
//! base follows the number: T0-T209 100 ms, T210-T251 10 ms, T252-T255 1 ms
//! (L1667-1677).
//!
//! Timing (D21): each timer keeps its own sub-unit remainder and counts from
//! its own start. An execution of a timer that was already timing adds the
//! scan time measured at the previous END; the value saturates at 32767 and
//! the coil is compared with the preset when the instruction executes (L3123).
//! Deviation, until the engine has a housekeeping hook for instructions: the
//! value shown between scans is the one of the last execution, one scan
//! behind D21's housekeeping update; the coil switches on the same scan.

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
        /// Time below one unit, µs.
        rem: u32,
        /// Timing is in progress (the previous execution counted).
        timing: bool,
        /// The power flow at the previous execution.
        prev: bool,
        /// Executed since RUN (TON resets on its first execution, L3123).
        seen: bool,
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
    base_us: u32,
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
        base_us: base_us(n),
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
    /// Adds the previous scan's time to the value (saturating at 32767).
    fn count(&self, cx: &mut ExecCtx<'_>, st: &mut TimerState) -> i32 {
        let v = self.value as usize;
        let mut cur = cx.mem.words[v] as i16 as i32;
        if st.timing {
            let total = st.rem as u64 + cx.scan_us as u64;
            let units = total / self.base_us as u64;
            st.rem = (total % self.base_us as u64) as u32;
            cur = (cur.max(0) as i64 + units as i64).min(32767) as i32;
            cx.mem.words[v] = cur as u16;
        } else {
            st.timing = true;
            st.rem = 0;
        }
        cur
    }

    fn step(&self, cx: &mut ExecCtx<'_>, pf: bool) -> Result<(), Fault> {
        let mut st = cx.local(&self.st);
        let preset = cx.mem.read16(&self.preset)? as i16 as i32;
        let (v, c) = (self.value as usize, self.contact as usize);
        if !st.seen && self.mode == Mode::On {
            cx.mem.words[v] = 0;
            cx.mem.bits[c] = false;
            st.timing = false;
        }
        st.seen = true;
        match self.mode {
            Mode::On | Mode::Retentive if pf => {
                let cur = self.count(cx, &mut st);
                cx.mem.bits[c] = cur >= preset;
            }
            Mode::On => {
                cx.mem.words[v] = 0;
                cx.mem.bits[c] = false;
                st.timing = false;
            }
            // TONR: PF OFF holds value and coil (L3135-3169).
            Mode::Retentive => st.timing = false,
            // TOF: PF ON: value 0, coil ON; the falling edge starts timing;
            // at the preset the coil goes OFF and the value holds (L3171-3199).
            Mode::Off if pf => {
                cx.mem.words[v] = 0;
                cx.mem.bits[c] = true;
                st.timing = false;
            }
            Mode::Off => {
                if st.prev {
                    st.timing = true;
                    st.rem = 0;
                } else if st.timing {
                    let cur = self.count(cx, &mut st);
                    if cur >= preset {
                        cx.mem.words[v] = preset.max(0) as u16;
                        cx.mem.bits[c] = false;
                        st.timing = false;
                    }
                }
            }
            // TMON: a rising edge while idle starts a pulse from the current
            // value; PF is ignored while timing; at the preset the value
            // returns to 0 and the coil goes OFF (L3201-3235).
            Mode::OneShot => {
                if st.timing {
                    let cur = self.count(cx, &mut st);
                    if cur >= preset {
                        cx.mem.words[v] = 0;
                        cx.mem.bits[c] = false;
                        st.timing = false;
                    }
                } else if pf && !st.prev {
                    cx.mem.bits[c] = true;
                    st.timing = true;
                    st.rem = 0;
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
