//! The APLC PID instruction `PID S1 S2 S3 D` (002 §6.11.1 L7657-7817; spec
//! aplc.md §5, decision D22): SV in S1, PV in S2, the 20-word parameter block
//! at S3, MV in D; the velocity form
//!
//!   ΔMV = Kp·{(EVn − EVn−1) + (Ts/TI)·EVn + Dn},  MVn = MVn−1 + ΔMV,
//!
//! with the filtered PV (PVnf = PVn + α·(PVnf−1 − PVn)), EVn = PVnf − SV
//! (forward) or SV − PVnf (reverse, mode bit 0), and the derivative term of
//! §5.4. It computes with power flow each time Ts has elapsed.
//!
//! Decision, the working area S3+7..S3+14 (the manual says only that the
//! program zeroes it, L7726): +7 EVn−1, +8 PVnf−1, +9 PVnf−2, +10 Dn−1
//! (rounded), +11 PVn−1 (for the input alarm), +12 the fraction of MV
//! (×10000, signed), +13 reserved, +14 the milliseconds since the last
//! sample. Values out of range in S3..S3+6, limits upper < lower, or a negative
//! alarm setting are error 64 with no computation.

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::layout::At;
use softplc_ir::ops::{Block, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, LoopMemory, Steps};

use crate::constant::Width;
use crate::devices::{parse_device, Dev};
use crate::num::E_VALUE;
use crate::resolve::{self, ArgsExt};

static DOC: Doc = Doc {
    family: "PID",
    cite: "002 §6.11.1 L7657-7817",
    notes: "velocity form with input filter, derivative gain and time; limits (bit5) or change alarms (bits 1, 2) in S3+15..S3+19; working area layout S3+7..S3+14 is softplc's (decision, pid.rs); error 64 for parameters out of range",
};

pub static DEFS: &[Def] = &[
    // 002 §6.11.1 L7657 PID
    Def::app("PID", &DOC, compile)
        .no_pulse()
        .steps(Steps::Fixed(9))
        .loop_memory(2, &PID_BLOCK),
];

softplc_ir::layout! {
    /// PID's 20-word block at S3 (002 §6.11.1 L7657-7817, spec aplc.md §5.2;
    /// the use of the working area +7..+14 is softplc's decision, see the
    /// module documentation). One word each.
    pub struct PidBlock[20] {
        /// Sampling time Ts, ms (1..32767).
        ts: i16 @ 0,
        /// Mode: b0 reverse action, b1 input-change alarm, b2 output-change alarm, b5 output limits.
        mode: u16 @ 1,
        /// Input filter coefficient α, % (0..99).
        alpha: i16 @ 2,
        /// Proportional gain Kp, % (1..32767).
        kp: i16 @ 3,
        /// Integral time TI, ×100 ms (0: no integral action).
        ti: i16 @ 4,
        /// Derivative gain KD, % (0..100).
        kd: i16 @ 5,
        /// Derivative time TD, ×10 ms (0: no derivative action).
        td: i16 @ 6,
        /// Working area: EVn−1.
        ev1: i16 @ 7,
        /// Working area: PVnf−1.
        pvf1: i16 @ 8,
        /// Working area: PVnf−2.
        pvf2: i16 @ 9,
        /// Working area: Dn−1 (rounded).
        d1: i16 @ 10,
        /// Working area: PVn−1, for the input alarm.
        pv1: i16 @ 11,
        /// Working area: the fraction of MV, ×10000.
        mv_frac: i16 @ 12,
        /// Working area: milliseconds since the last sample.
        elapsed: u16 @ 14,
        /// Input-change alarm, increase side (b1).
        pv_rise: i16 @ 15,
        /// Input-change alarm, decrease side (b1).
        pv_fall: i16 @ 16,
        /// Output upper limit (b5), or output-change alarm, increase side (b2).
        mv_high: i16 @ 17,
        /// Output lower limit (b5), or output-change alarm, decrease side (b2).
        mv_low: i16 @ 18,
        /// Alarm bits: b0/b1 input change over +/−, b2/b3 output change over +/−.
        alarms: u16 @ 19,
    }
}

/// PID's S3 block as its loop memory (one loop; SV, PV and MV are other
/// operands).
pub static PID_BLOCK: LoopMemory = LoopMemory {
    name: "PID parameter block",
    fields: PidBlock::FIELDS,
    first: 0,
    stride: 0,
    count: None,
    settings: None,
};

#[derive(Debug)]
struct Pid {
    sv: WordArg,
    pv: WordArg,
    block: Block,
    mv: WordArg,
}

fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    for k in 0..4 {
        let ok = matches!(parse_device(&a.text(k).to_ascii_uppercase()), Ok(Some(d)) if d.dev == Dev::D && d.group.is_none());
        if !ok {
            a.error(
                k,
                format!(
                    "`{}`: PID's operands are D registers (APLC programming manual §6.11.1)",
                    a.text(k)
                ),
            );
            return None;
        }
    }
    let sv = a.word_at(0, Width::W16, false);
    let pv = a.word_at(1, Width::W16, false);
    let r = resolve::block(a.map(), a.text(2), true);
    let block = a.check(2, r);
    let mv = a.word_at(3, Width::W16, true)?;
    Some(Box::new(Pid {
        sv: sv?,
        pv: pv?,
        block: block?,
        mv,
    }))
}

fn clamp16(v: f64) -> i16 {
    v.round().clamp(-32768.0, 32767.0) as i16
}

impl Instr for Pid {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let b = cx.mem.block_start(&self.block, PidBlock::WORDS as u32)?;
        let w = |cx: &ExecCtx<'_>, f: At<i16>| f.get(&cx.mem.words[b..]);
        let (ts, alpha, kp) = (
            w(cx, PidBlock::ts),
            w(cx, PidBlock::alpha),
            w(cx, PidBlock::kp),
        );
        let (ti, kd, td) = (
            w(cx, PidBlock::ti),
            w(cx, PidBlock::kd),
            w(cx, PidBlock::td),
        );
        let mode = PidBlock::mode.get(&cx.mem.words[b..]);
        let ok = ts >= 1
            && (0..=99).contains(&alpha)
            && kp >= 1
            && ti >= 0
            && (0..=100).contains(&kd)
            && td >= 0;
        if !ok {
            return Err(E_VALUE);
        }
        let (alarm_in, alarm_out, limits) = match (mode & 4 != 0, mode & 32 != 0) {
            (true, true) => (false, false, false),
            (o, l) => (mode & 2 != 0 && !l, o, l),
        };
        let (pv_rise, pv_fall) = (w(cx, PidBlock::pv_rise), w(cx, PidBlock::pv_fall));
        let (mv_high, mv_low) = (w(cx, PidBlock::mv_high), w(cx, PidBlock::mv_low));
        if limits && mv_high < mv_low
            || alarm_in && (pv_rise < 0 || pv_fall < 0)
            || alarm_out && (mv_high < 0 || mv_low < 0)
        {
            return Err(E_VALUE);
        }
        // Sampling: the scan time measured at the previous END accumulates.
        let block = &mut cx.mem.words[b..b + PidBlock::WORDS];
        let elapsed =
            (PidBlock::elapsed.get(block) as u32 + cx.scan_us / 1000).min(u16::MAX as u32);
        if elapsed < ts as u32 {
            PidBlock::elapsed.set(block, elapsed as u16);
            return Ok(());
        }
        PidBlock::elapsed.set(block, (elapsed - ts as u32).min(ts as u32) as u16);
        let (sv, pv) = (
            cx.mem.read16(&self.sv)? as i16 as f64,
            cx.mem.read16(&self.pv)? as i16 as f64,
        );
        let (ev1, pf1, pf2, d1, pv1) = (
            w(cx, PidBlock::ev1) as f64,
            w(cx, PidBlock::pvf1) as f64,
            w(cx, PidBlock::pvf2) as f64,
            w(cx, PidBlock::d1) as f64,
            w(cx, PidBlock::pv1),
        );
        let a = alpha as f64 / 100.0;
        let pvf = pv + a * (pf1 - pv);
        let reverse = mode & 1 != 0;
        let ev = if reverse { sv - pvf } else { pvf - sv };
        let (ts_ms, ti_ms, td_ms, ad) = (
            ts as f64,
            ti as f64 * 100.0,
            td as f64 * 10.0,
            kd as f64 / 100.0,
        );
        let dn = if td == 0 {
            0.0
        } else {
            let den = ts_ms + ad * td_ms;
            let curve = if reverse {
                2.0 * pf1 - pvf - pf2
            } else {
                pvf + pf2 - 2.0 * pf1
            };
            td_ms / den * curve + ad * td_ms / den * d1
        };
        let integral = if ti == 0 { 0.0 } else { ts_ms / ti_ms * ev };
        let dmv = kp as f64 / 100.0 * ((ev - ev1) + integral + dn);
        let frac = w(cx, PidBlock::mv_frac) as f64 / 10000.0;
        let prev = cx.mem.read16(&self.mv)? as i16 as f64;
        let mut mv = prev + frac + dmv;
        if limits {
            mv = mv.clamp(mv_low as f64, mv_high as f64);
        }
        let out = clamp16(mv);
        let rest = if limits { 0.0 } else { mv - out as f64 };
        cx.mem.write16(&self.mv, out as u16)?;
        let mut alarms = 0u16;
        if alarm_in {
            let dpv = pv as i32 - pv1 as i32;
            alarms |= (dpv > pv_rise as i32) as u16 | ((-dpv > pv_fall as i32) as u16) << 1;
        }
        if alarm_out {
            let d = out as i32 - prev as i32;
            alarms |= ((d > mv_high as i32) as u16) << 2 | ((-d > mv_low as i32) as u16) << 3;
        }
        let block = &mut cx.mem.words[b..b + PidBlock::WORDS];
        PidBlock::ev1.set(block, clamp16(ev));
        PidBlock::pvf1.set(block, clamp16(pvf));
        PidBlock::pvf2.set(block, pf1 as i16);
        PidBlock::d1.set(block, clamp16(dn));
        PidBlock::pv1.set(block, pv as i16);
        PidBlock::mv_frac.set(block, clamp16(rest * 10000.0));
        PidBlock::alarms.set(block, alarms);
        Ok(())
    }
}
