//! 000 §9.7 S.R L12242-12746 (spec §4.15): ratio. S2 +0 TRK, +1 SVPTN (3);
//! D1 +0 BW only. Loop tag: +14 SPR ratio setting, +16 BIAS (%), +46 CT, +50
//! DR ratio change limit per control cycle, +52 RMAX (100), +54 RMIN (0),
//! +56 Rn (current ratio, written); past values +96/+97 the CT counter,
//! +98/99 Rn-1.
//!
//! Order: (4) loop stop (BW holds, MODE := MAN) → (5) control cycle (not
//! reached: BW holds) → (6) mode: cascade group with E2 used: SPR = (RMAX −
//! RMIN)/100 × E2 + RMIN (written to +14, DEC-14); other modes: (1) tracking,
//! E2 := 100/(RMAX − RMIN) × (SPR − RMIN) and the upper loop's TRKF → (2)
//! rate limiter: SPR − Rn-1 > DR → Rn = Rn-1 + DR, < −DR → Rn-1 − DR, else
//! SPR → (3) `BW = E1 × (Rn − RMIN)/(RMAX − RMIN) + BIAS` (DEC-17; the only
//! form, the alternative is rejected at load). RMAX = RMIN is detail 5 at
//! tracking (3) or the ratio operation (5), whichever divides first.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::layout::At;

use super::front::{run, tag_pos, Areas, Front, Halt, Operands, Pattern, PatternFields};
use crate::process::common::{result, BlockMemory, Input, PcError};
use crate::process::tag::LoopTag;
use crate::{Args, ExecCtx, Instr};

/// S.R's meanings of loop-tag words (000 §9.7 L12520-12580).
const SPR: At<f32> = LoopTag::sv;
const BIAS: At<f32> = LoopTag::dv;
const DR: At<f32> = LoopTag::dvl;
const RMAX: At<f32> = LoopTag::p;
const RMIN: At<f32> = LoopTag::i;
const RN: At<f32> = LoopTag::d;

softplc_ir::layout! {
    /// The operation constants (S2) of S.R.
    pub struct RatioConsts[2] {
        /// TRK: 1 tracking.
        trk: u16 @ 0,
        /// SVPTN (3): b0 = 1 E2 not used, b1 = 0 E2 is the upper loop's MV.
        svptn: u16 @ 1,
    }
}

softplc_ir::layout! {
    /// The past value of S.R in the loop tag (000 §9.7 L12520-12580).
    pub struct RatioPast[128] {
        /// Rn-1: the last ratio.
        r1: f32 @ 98,
    }
}

/// S.R has no PN (reverse action, unused).
const PATTERN: PatternFields = PatternFields {
    pn: None,
    trk: RatioConsts::trk,
    svptn: RatioConsts::svptn,
};

#[derive(Debug)]
pub struct Ratio {
    f: Front,
    ops: Operands,
}

impl Ratio {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        let ops = Operands::compile(a, 2, 2, 2)?;
        let f = Front::new(a)?;
        if !f.s.ratio_reconstructed {
            a.error(
                0,
                "S.R: ratio_reconstructed = false asks for a ratio formula the manual's text \
                 does not give (Process Control Instructions manual §9.7: it is garbled); only \
                 the reconstructed BW = E1·(Rn − RMIN)/(RMAX − RMIN) + BIAS is implemented",
            );
            return None;
        }
        Some(Box::new(Ratio { f, ops }))
    }

    fn body(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), Halt> {
        let f = &self.f;
        let d2 = a.d2;
        if f.stopped(m, d2) {
            f.stop(m, d2, 0, Some(LoopTag::ct))?;
            return Ok(());
        }
        if !f.cycle(m, d2, LoopTag::ct)?.reached {
            return Ok(());
        }
        let pat = Pattern::read(m, a.s2, PATTERN, 4)?;
        let mode = d2.get(m, LoopTag::mode);
        let rmax = d2.real(m, RMAX, 2)?;
        let rmin = d2.real(m, RMIN, 2)?;
        let spr = if f.mode.cascade(mode) {
            if pat.e2_used {
                let e2 = a.s3.real(m, Input::e1, 2)?;
                let spr = result((rmax - rmin) / 100.0 * e2 + rmin, 2)?;
                if f.s.cascade_writes_sv {
                    d2.set(m, SPR, spr);
                }
                spr
            } else {
                d2.real(m, SPR, 2)?
            }
        } else {
            let spr = d2.real(m, SPR, 3)?;
            if pat.trk && pat.e2_used && f.mode.tracking(mode) {
                if rmax == rmin {
                    return Err(PcError::divide(3).into());
                }
                let e2 = result(100.0 / (rmax - rmin) * (spr - rmin), 3)?;
                f.write_back(m, a, pat, mode, e2)?;
            }
            spr
        };
        let dr = tag_pos(m, d2, DR, 4)?;
        let r1 = d2.real(m, RatioPast::r1, 4)?;
        let d = result(spr - r1, 4)?;
        let rn = if d > dr {
            result(r1 + dr, 4)?
        } else if d < -dr {
            result(r1 - dr, 4)?
        } else {
            spr
        };
        d2.set(m, RN, rn);
        d2.set(m, RatioPast::r1, rn);
        let e1 = a.s1.real(m, Input::e1, 5)?;
        let bias = d2.real(m, BIAS, 5)?;
        if rmax == rmin {
            return Err(PcError::divide(5).into());
        }
        a.d1.set(
            m,
            BlockMemory::bw,
            result(e1 * ((rn - rmin) / (rmax - rmin)) + bias, 5)?,
        );
        Ok(())
    }
}

impl Instr for Ratio {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = self.ops.resolve(cx.mem)?;
        run(&self.f.sys, cx.mem, |m| self.body(m, &a))
    }
}
