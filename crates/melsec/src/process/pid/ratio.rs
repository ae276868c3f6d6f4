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

use super::front::{past, put, run, tag, tag_pos, word, Areas, Front, Halt, Operands, Pattern};
use crate::process::common::{real, result, set_f, PcError};
use crate::process::tag::LoopTag;
use crate::{Args, ExecCtx, Instr};

/// S.R's meanings of loop-tag words (000 §9.7 L12520-12580).
const SPR: At<f32> = LoopTag::sv;
const BIAS: At<f32> = LoopTag::dv;
const DR: At<f32> = LoopTag::dvl;
const RMAX: At<f32> = LoopTag::p;
const RMIN: At<f32> = LoopTag::i;
const RN: At<f32> = LoopTag::d;

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
                 does not give (000 §9.7 L12700-12710 is garbled); only DEC-17's form is \
                 implemented",
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
        // S2 +0 TRK, +1 SVPTN: Pattern reads PN, TRK, SVPTN from S2 + at.
        let trk = m.words[a.s2];
        let svptn = m.words[a.s2 + 1];
        if trk > 1 || svptn > 3 {
            return Err(PcError::range(2).into());
        }
        let pat = Pattern {
            forward: false,
            trk: trk == 1,
            e2_used: svptn & 1 == 0,
            e2_upper_mv: svptn & 2 == 0,
        };
        let mode = word(m, d2, LoopTag::mode);
        let rmax = tag(m, d2, RMAX, 2)?;
        let rmin = tag(m, d2, RMIN, 2)?;
        let spr = if f.mode.cascade(mode) {
            if pat.e2_used {
                let e2 = real(m, a.s3, 2)?;
                let spr = result((rmax - rmin) / 100.0 * e2 + rmin, 2)?;
                if f.s.cascade_writes_sv {
                    put(m, d2, SPR, spr);
                }
                spr
            } else {
                tag(m, d2, SPR, 2)?
            }
        } else {
            let spr = tag(m, d2, SPR, 3)?;
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
        let r1 = real(m, d2 + past::W98, 4)?;
        let d = result(spr - r1, 4)?;
        let rn = if d > dr {
            result(r1 + dr, 4)?
        } else if d < -dr {
            result(r1 - dr, 4)?
        } else {
            spr
        };
        put(m, d2, RN, rn);
        set_f(m, d2 + past::W98, rn);
        let e1 = real(m, a.s1, 5)?;
        let bias = tag(m, d2, BIAS, 5)?;
        if rmax == rmin {
            return Err(PcError::divide(5).into());
        }
        set_f(
            m,
            a.d1,
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
