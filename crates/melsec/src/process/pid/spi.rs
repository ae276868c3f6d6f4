//! 000 §9.4 S.SPI L9750-10583 (spec §4.12): sampled PI for processes with a
//! long dead time. S2 +0/1 DVLS (2.0), +2 PN, +3 TRK, +4 SVPTN; loop tag +46
//! ST (operate time), +56 STHT (the whole sampling period); past values +96
//! flag, +97 sampling counter, +98 operation definition (1 operate, 0 hold),
//! +99 operate executions left in the period, +100/101 DVn-1.
//!
//! Each period of n = int(STHT/ΔT) executions (the integer part, L10562-
//! 10578; counted per DEC-1 on +96/+97: the start execution and every reach
//! begin a period) operates on its first int(ST/ΔT) executions and holds on
//! the rest. Operate: SV → tracking → gain → `ΔMV = KP × {(DVn − DVn-1) +
//! (BT/TI)·DVn}` with BT = ΔT (freeze rules as S.PID) → deviation check.
//! Hold: tracking, ΔMV = 0 (past values untouched), deviation check on the
//! stored DV. n ≤ int(ST/ΔT): no hold time, continuous PI. n = 0 (STHT = 0,
//! the default): nothing is processed; BW := 0 so that MV stays unchanged
//! (L10575-10578, "MV 亦保持不变"). Processing No. 1 is the operation-time
//! monitoring.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::layout::At;

use super::front::{run, Areas, Front, Halt, Operands, Pattern};
use super::{PiConsts, PI_PATTERN};
use crate::process::common::{count, result, tick, Area, BlockMemory, PcError};
use crate::process::tag::{alm, bb, LoopTag};
use crate::{Args, ExecCtx, Instr};

/// S.SPI's meanings of +46 and +56 (000 §9.4 L10250-10270).
const ST: At<f32> = LoopTag::ct;
const STHT: At<f32> = LoopTag::d;

softplc_ir::layout! {
    /// The past values of S.SPI in the loop tag (000 §9.4 L10250-10270).
    pub struct SpiPast[128] {
        /// The operation definition: 1 operate, 0 hold.
        operate: u16 @ 98,
        /// The operate executions left in the period.
        left: u16 @ 99,
        /// DVn-1.
        dv1: f32 @ 100,
    }
}

#[derive(Debug)]
pub struct Spi {
    f: Front,
    ops: Operands,
}

/// The integer part of p/ΔT (0 allowed), checked as every count (DEC-2).
fn whole(p: f32, dt: f32, f: &Front) -> Result<u16, PcError> {
    let n = count(p, dt, true, &f.s, 1)?;
    Ok(if (p / dt).trunc() < 1.0 { 0 } else { n })
}

impl Spi {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        let ops = Operands::compile(a, 2, 3, 5)?;
        let f = Front::new(a)?;
        Some(Box::new(Spi { f, ops }))
    }

    /// The operation-time monitoring: Some(operate?) or None (n = 0).
    fn phase(&self, m: &mut DeviceMemory, d2: Area) -> Result<Option<bool>, PcError> {
        let f = &self.f;
        let dt = f.sys.dt(m, 1)?;
        let stht = d2.real(m, STHT, 1)?;
        let st = d2.real(m, ST, 1)?;
        let n = whole(stht, dt, f)?;
        let ns = whole(st, dt, f)?;
        if n == 0 {
            return Ok(None);
        }
        if n <= ns {
            d2.set(m, SpiPast::operate, 1);
            return Ok(Some(true));
        }
        let s = f.s;
        let t = tick(
            m,
            d2.index(LoopTag::ct_flag),
            d2.index(LoopTag::ct_count),
            &s,
            || Ok(n),
        )?;
        if t.begins() {
            d2.set(m, SpiPast::left, ns);
        }
        let left = d2.get(m, SpiPast::left);
        let operate = left > 0;
        if operate {
            d2.set(m, SpiPast::left, left - 1);
        }
        d2.set(m, SpiPast::operate, operate as u16);
        Ok(Some(operate))
    }

    fn body(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), Halt> {
        let f = &self.f;
        let d2 = a.d2;
        if f.stopped(m, d2) {
            a.d1.set(m, BlockMemory::bw, 0.0);
            a.d1.set_bits(m, BlockMemory::bb, bb::BB1, false);
            f.stop(m, d2, alm::DVLA, None)?;
            if !f.s.early_end_skips_counters {
                self.phase(m, d2)?;
            }
            return Ok(());
        }
        let Some(operate) = self.phase(m, d2)? else {
            a.d1.set(m, BlockMemory::bw, 0.0);
            return Ok(());
        };
        let pat = Pattern::read(m, a.s2, PI_PATTERN, 4)?;
        let mode = d2.get(m, LoopTag::mode);
        let dv = if operate {
            let svn = f.sv(m, a, pat, mode)?;
            let sv1 = f.track(m, a, pat, mode, svn)?;
            let (dv, kp) = f.gain(m, a, pat, sv1)?;
            let ti = super::front::tag_pos(m, d2, LoopTag::i, 5)?;
            let bt = f.sys.dt(m, 5)?;
            let dv1 = d2.real(m, SpiPast::dv1, 5)?;
            let inc = f.integral(m, d2, bt, ti, dv, 5)?;
            d2.set(m, SpiPast::dv1, dv);
            a.d1.set(m, BlockMemory::bw, result(kp * (dv - dv1 + inc), 5)?);
            dv
        } else {
            let sv = d2.real(m, LoopTag::sv, 3)?;
            f.track(m, a, pat, mode, sv)?;
            a.d1.set(m, BlockMemory::bw, 0.0);
            d2.real(m, LoopTag::dv, 6)?
        };
        let dvls = a.s2.real(m, PiConsts::dvls, 6)?;
        f.check(m, a, dv, dvls, bb::BB1, 6)?;
        Ok(())
    }
}

impl Instr for Spi {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = self.ops.resolve(cx.mem)?;
        run(&self.f.sys, cx.mem, |m| self.body(m, &a))
    }
}
