//! Instructions that work across scans and see their condition turn OFF
//! (`Drive::Always`): TIMCHK, RAMP and STMR. Each keeps its memory of the
//! last execution in a typed [`LocalState`], cleared at power-on and STOP→RUN.
//! An instruction that is not executed at all in a scan (jumped over, in a
//! subroutine not called) keeps that memory, as the CPU does.
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions), SH-080039.
//! PM is not among the references at hand: its section numbers and the
//! behaviour below are as remembered from it, and every point it might settle
//! otherwise is marked as a decision.

use super::data::read_i16;
use super::{Args, ExecCtx, Instr, LocalSlot};
use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::local_state;
use softplc_ir::ops::Block;
use softplc_ir::ops::{BitArg, Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("TIMCHK", &TIMCHK, timchk).always(),
    Def::app("RAMP", &RAMP, ramp).always(),
    Def::app("STMR", &STMR, stmr).always(),
];

static TIMCHK: Doc = Doc {
    family: "time check",
    cite: "PM §7.18.3",
    notes: "100 ms units; S1/D held while OFF, cleared when the condition turns ON again; S2<0 → 4100; no pulse form",
};
static RAMP: Doc = Doc {
    family: "ramp signal",
    cite: "PM RAMP",
    notes: "D1 = n1+(n2−n1)·k/n3, D1+1 = k, D2 ON at k=n3; restarts from n1 when the condition turns ON again; n3≤0 → 4100",
};
static STMR: Doc = Doc {
    family: "special timer",
    cite: "PM STMR",
    notes: "100 ms units in the timer's current value; D+0 off delay, D+1 one shot after OFF, D+2 one shot after ON, D+3 ON delay + OFF delay; no pulse form",
};

local_state! {
    /// The condition at the last execution.
    struct Condition {
        on: bool,
    }
}

local_state! {
    /// TIMCHK: the condition at the last execution and the time below one
    /// 100 ms unit carried to the next.
    struct Measuring {
        on: bool,
        rem_us: u32,
    }
}

// ------------------------------------------------------------------ TIMCHK

/// 100 ms, the unit of TIMCHK's set and current values.
const UNIT_US: u64 = 100_000;

/// PM §7.18.3 TIMCHK `S1 S2 D` (time check): measures how long the condition
/// stays ON in 100 ms units in S1; when the measured time reaches the set
/// value S2, D turns ON.
///
/// * The execution that finds the condition newly ON (the instruction runs with its
///   condition OFF too, `Drive::Always`) starts a measurement: S1 = 0, D OFF, and, as with `OUT T`
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
///   among the references at hand).
/// * S2 = 0 turns D ON at once (as a timer's set value 0).
///
/// Errors: S2 negative: 4100 (decision, as `OUT T` with a negative set value);
/// an index-modified operand out of range: 4101. No pulse form.
#[derive(Debug)]
struct TimChk {
    cur: WordArg,
    set: WordArg,
    out: BitArg,
    state: LocalSlot<Measuring>,
}

fn timchk(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let cur = a.word_dest(0, Num::I16, 1);
    let set = a.word_src(1, Num::I16);
    let out = a.bit_dest(2);
    let state = a.local();
    Some(Box::new(TimChk {
        cur: cur?,
        set: set?,
        out: out?,
        state,
    }))
}

impl Instr for TimChk {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mut st = cx.local(&self.state);
        let on_before = std::mem::replace(&mut st.on, true);
        let mem = &mut *cx.mem;
        let set = read_i16(mem, &self.set)?;
        if set < 0 {
            return Err(Fault::Operation);
        }
        // Range checks of index-modified operands before anything is written.
        let old = read_i16(mem, &self.cur)?;
        mem.read_bit(&self.out)?;
        let cur = if on_before {
            let total = st.rem_us as u64 + cx.scan_us as u64;
            st.rem_us = (total % UNIT_US) as u32;
            (old as i64 + (total / UNIT_US) as i64).min(i16::MAX as i64) as i32
        } else {
            st.rem_us = 0;
            mem.write_bit(&self.out, false)?;
            0
        };
        mem.write16(&self.cur, cur as u16)?;
        if cur >= set {
            mem.write_bit(&self.out, true)?;
        }
        cx.set_local(&self.state, st);
        Ok(())
    }

    /// The condition is OFF: S1 and D hold; the next ON starts anew.
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.set_local(&self.state, Measuring::default());
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
///   keep their values. When it turns ON again (the instruction runs with its
///   condition OFF too, `Drive::Always`), D1+1 is cleared, D2 turns OFF and the ramp starts again
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
    state: LocalSlot<Condition>,
}

fn ramp(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[5]) {
        return None;
    }
    let n1 = a.word_src(0, Num::I16);
    let n2 = a.word_src(1, Num::I16);
    let d1 = super::data::fixed_block(a, 2, 2);
    let n3 = a.word_src(3, Num::I16);
    let d2 = a.bit_dest(4);
    let state = a.local();
    Some(Box::new(Ramp {
        n1: n1?,
        n2: n2?,
        d1: d1?,
        n3: n3?,
        d2: d2?,
        state,
    }))
}

impl Instr for Ramp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let on_before = cx.local(&self.state).on;
        cx.set_local(&self.state, Condition { on: true });
        let mem = &mut *cx.mem;
        let n3 = read_i16(mem, &self.n3)?;
        if n3 <= 0 {
            return Err(Fault::Operation);
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

    /// The condition is OFF: D1, D1+1 and D2 hold; the next ON restarts.
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.set_local(&self.state, Condition { on: false });
        Ok(())
    }
}

// -------------------------------------------------------------------- STMR

/// PM STMR `S n D` (special timer): four timer outputs D+0 … D+3 from one
/// condition, timed in 100 ms units in the current value of timer S:
///
/// * D+0, off delay: ON with the condition; OFF n after it turns OFF;
/// * D+1, one shot after OFF: ON for n from the condition turning OFF;
/// * D+2, one shot after ON: ON for n from the condition turning ON, OFF
///   earlier when the condition turns OFF first;
/// * D+3, ON delay + OFF delay: ON n after the condition turns ON, OFF n after
///   it turns OFF (a condition OFF for less than n leaves it ON).
///
/// The current value of S counts the time since the last change of the
/// condition (up to n) and is 0 at the change; as with `OUT T`, the execution
/// that sees the change adds nothing and later ones add the scan time measured
/// at the previous END, carrying the part below 100 ms. The timer's contact and
/// coil are not used (decision: the manual reserves the timer for STMR).
/// n = 0 makes every delay end at the change.
///
/// Decisions (the manual is not among the references at hand; the outputs are
/// the ones of the FX STMR this instruction shares): the time unit is 100 ms
/// whatever the timer's time base; S must be a timer T without index
/// modification; n negative is 4100; D+3 past the end of its device is a load
/// error (fixed size). No pulse form.
#[derive(Debug)]
struct Stmr {
    /// Flat word index of the timer's current value.
    value: usize,
    set: WordArg,
    /// Flat bit index of D+0 (D+0 … D+3 are in range).
    out: usize,
    state: LocalSlot<Measuring>,
}

fn stmr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let timer = match a.operand(0) {
        Some(softplc_ir::device::Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) if dev.generic && dev.kind == DeviceKind::TS => {
            let value = a.map().index(DeviceKind::TN, dev.number);
            if value.is_none() {
                let text = a.text(0).to_string();
                a.error(
                    0,
                    format!("`{text}` is outside the configured timer points"),
                );
            }
            value
        }
        Some(_) => {
            let text = a.text(0).to_string();
            a.error(
                0,
                format!("`{text}`: STMR needs a timer T without index modification"),
            );
            None
        }
        None => None,
    };
    let set = a.word_src(1, Num::I16);
    let out = four_bits(a, 2);
    let state = a.local();
    Some(Box::new(Stmr {
        value: timer? as usize,
        set: set?,
        out: out?,
        state,
    }))
}

impl Stmr {
    /// One execution with the condition `on`.
    fn step(&self, cx: &mut ExecCtx<'_>, on: bool) -> Result<(), Fault> {
        let set = read_i16(cx.mem, &self.set)?;
        if set < 0 {
            return Err(Fault::Operation);
        }
        let mut st = cx.local(&self.state);
        let mem = &mut *cx.mem;
        let elapsed = if st.on == on {
            let total = st.rem_us as u64 + cx.scan_us as u64;
            st.rem_us = (total % UNIT_US) as u32;
            let cur = mem.words[self.value] as i16 as i64 + (total / UNIT_US) as i64;
            cur.min(set as i64) as i16
        } else {
            st.rem_us = 0;
            0
        };
        let done = elapsed as i32 >= set;
        mem.words[self.value] = elapsed as u16;
        let d = &mut mem.bits[self.out..self.out + 4];
        if on {
            if !st.on {
                d[1] = false;
            }
            d[0] = true;
            d[2] = !done;
            d[3] |= done;
        } else {
            if st.on {
                d[2] = false;
                d[1] = d[0];
            }
            if done {
                d[0] = false;
                d[1] = false;
                d[3] = false;
            }
        }
        st.on = on;
        cx.set_local(&self.state, st);
        Ok(())
    }
}

impl Instr for Stmr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx, true)
    }

    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx, false)
    }
}

/// Operand `k` as the first of 4 consecutive bits of a bit device, without
/// index modification, all within the device.
fn four_bits(a: &mut Args<'_, '_>, k: usize) -> Option<usize> {
    let b = a.bit_block(k)?;
    match b.start {
        BitArg::Bit(i) if i + 4 <= b.limit => Some(i as usize),
        _ => {
            let msg = format!(
                "`{}`: STMR uses 4 bits from this device, without index modification, within its points",
                a.text(k)
            );
            a.error(k, msg);
            None
        }
    }
}
