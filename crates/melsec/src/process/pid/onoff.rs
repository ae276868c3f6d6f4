//! 000 §9.20 S.ONF2 L15929-16516, §9.21 S.ONF3 L16517-17151 (spec §4.24):
//! 2- and 3-position ON/OFF control. S2 +0 PN, +1 TRK, +2 SVPTN (3). D1 +0
//! BW (%), +2 BB (ONF2: BB1; ONF3: BB1, BB2). Loop tag: MV +12, SV +14, DV
//! +16, HS0 +18 (hysteresis), ONF3 HS1 +20, RH, RL, CT +46; +96/+97 the CT
//! counter.
//!
//! Order: (6) loop stop (BW and BB hold, MODE := MAN) → (7) control cycle:
//! not reached: A-group BW holds and ends, M-group BW = MV then (5) → (1) SV
//! → (2) tracking → (3) MV compensation: DV as the PID front end (written to
//! +16); ONF2: DV > HS0 → 100 %, DV < −HS0 → 0 %, else the previous BW;
//! ONF3: DV ≥ HS1 + HS0 → 100 %, DV ≤ −(HS1 + HS0) → 0 %, −(HS1 − HS0) ≤ DV
//! ≤ HS1 − HS0 → 50 %, else the previous BW → (4) MV output: M-group BW =
//! MV; A-group BW = MV′ and MV := BW → (5) bits: ONF2 BB1 = |BW| ≥ 50 %;
//! ONF3 BW ≥ 75 % → BB1, BW ≤ 25 % → BB2, else neither.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::layout::At;

use super::front::{run, tag_pos, Areas, Front, Halt, Operands, Pattern, PatternFields};
use crate::process::common::{BlockMemory, PcError};
use crate::process::tag::bb::{BB1, BB2};
use crate::process::tag::LoopTag;
use crate::{Args, ExecCtx, Instr};

/// The hysteresis widths S.ONF2/3 keep at +18/+20 (000 §9.20 L16100-16140).
const HS0: At<f32> = LoopTag::mh;
const HS1: At<f32> = LoopTag::ml;

softplc_ir::layout! {
    /// The operation constants (S2) of S.ONF2 and S.ONF3.
    pub struct OnfConsts[3] {
        /// PN: 0 reverse, 1 forward action.
        pn: u16 @ 0,
        /// TRK: 1 tracking.
        trk: u16 @ 1,
        /// SVPTN (3): b0 = 1 E2 not used, b1 = 0 E2 is the upper loop's MV.
        svptn: u16 @ 2,
    }
}

const PATTERN: PatternFields = PatternFields {
    pn: Some(OnfConsts::pn),
    trk: OnfConsts::trk,
    svptn: OnfConsts::svptn,
};

#[derive(Debug)]
pub struct OnOff {
    three: bool,
    f: Front,
    ops: Operands,
}

impl OnOff {
    fn compile(a: &mut Args<'_, '_>, three: bool) -> Option<Box<dyn Instr>> {
        let ops = Operands::compile(a, 2, 3, 3)?;
        let f = Front::new(a)?;
        Some(Box::new(OnOff { three, f, ops }))
    }

    pub fn compile_2(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        OnOff::compile(a, false)
    }

    pub fn compile_3(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        OnOff::compile(a, true)
    }

    /// (3) MV′ (processing No. 4).
    fn compensate(&self, m: &DeviceMemory, a: &Areas, dv: f32) -> Result<f32, PcError> {
        let hs0 = tag_pos(m, a.d2, HS0, 4)?;
        let prev = a.d1.get(m, BlockMemory::bw);
        Ok(if !self.three {
            if dv > hs0 {
                100.0
            } else if dv < -hs0 {
                0.0
            } else {
                prev
            }
        } else {
            let hs1 = tag_pos(m, a.d2, HS1, 4)?;
            if dv >= hs1 + hs0 {
                100.0
            } else if dv <= -(hs1 + hs0) {
                0.0
            } else if -(hs1 - hs0) <= dv && dv <= hs1 - hs0 {
                50.0
            } else {
                prev
            }
        })
    }

    /// (5) the ON/OFF bits from BW (processing No. 6).
    fn bits(&self, m: &mut DeviceMemory, a: &Areas, bw: f32) {
        let (d1, bb) = (a.d1, BlockMemory::bb);
        if self.three {
            d1.set_bits(m, bb, BB1, bw >= 75.0);
            d1.set_bits(m, bb, BB2, bw <= 25.0);
        } else {
            d1.set_bits(m, bb, BB1, bw.abs() >= 50.0);
        }
    }

    fn body(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), Halt> {
        let f = &self.f;
        let d2 = a.d2;
        if f.stopped(m, d2) {
            f.stop(m, d2, 0, Some(LoopTag::ct))?;
            return Ok(());
        }
        let mode = d2.get(m, LoopTag::mode);
        let manual = f.mode.manual(mode);
        let bw = if !f.cycle(m, d2, LoopTag::ct)?.reached {
            if !manual {
                return Ok(());
            }
            d2.real(m, LoopTag::mv, 5)?
        } else {
            let pat = Pattern::read(m, a.s2, PATTERN, 4)?;
            let svn = f.sv(m, a, pat, mode)?;
            let sv1 = f.track(m, a, pat, mode, svn)?;
            let dv = f.deviation(m, a, pat, sv1, 4)?;
            let mv1 = self.compensate(m, a, dv)?;
            if manual {
                d2.real(m, LoopTag::mv, 5)?
            } else {
                d2.set(m, LoopTag::mv, mv1);
                mv1
            }
        };
        a.d1.set(m, BlockMemory::bw, bw);
        self.bits(m, a, bw);
        Ok(())
    }
}

impl Instr for OnOff {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = self.ops.resolve(cx.mem)?;
        run(&self.f.sys, cx.mem, |m| self.body(m, &a))
    }
}
