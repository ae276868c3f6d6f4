//! S.OUT1 and S.OUT2, output processing with mode switching.

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;

use super::stage::{convert, positional, velocity, Bb, Flow, Kit, OutputRange};
use crate::process::common::{area, Area, BlockMemory, Sys};
use crate::process::settings::ProcessSettings;
use crate::process::tag::{LoopTag, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

/// 000 §8.2 S.OUT1 `S.OUT1 S1 D1 S2 D2` (L3894-4506), output processing
/// with mode switching 1 (velocity input), and 000 §8.3 S.OUT2 (L4507-5017),
/// mode switching 2 (positional input).
///
/// Operands: S1 +0 E1 (S.OUT1: ΔMV %, S.OUT2: MV %); D1 +0 BW (output,
/// engineering units), +2 BB (BB1 alarm, BB2 output high, BB3 output low,
/// BB4 change rate); S2 +0 NMAX (100.0), +2 NMIN (0.0); D2 the 128-word loop
/// tag: MODE +1, ALM +3 (SPA, DMLA, MHA, MLA, SEA), INH +4 (ERRI, TRKF,
/// DMLI, MHI, MLI), MV +12, MH +18, ML +20, DML +48; S.OUT1 also I +54, MVP
/// +62 and ALM2 +116 (see [`super::stage`] for the exact word contract).
///
/// Processing (S.OUT1): (6) loop stop → (1) mode judgment (manual modes:
/// alarms and ALM2 cleared, TRKF := 1, output from the operator's MV; auto
/// modes: SEA with SM1501 ON holds) → (2) T = E1 + MVP, MVP := T (TRKF: MVP
/// := MV, E1 := 0 once) → (3) change-rate and MH/ML limiter, only when
/// T ≠ MV (DEC-10) → (4) reset windup (DEC-11; TI = 0 skips) → (5) BW =
/// (NMAX − NMIN)/100 × MV + NMIN. S.OUT2 has no MVP, TRKF or ALM2: E1 is the
/// MV target, limited when E1 ≠ MV.
///
/// Errors (4100): a bad float is SD1502 = 1, an overflowing result 6;
/// SD1503 per Table 14.2: 1 input addition, 2 change rate/limiter, 3 reset
/// windup, 4 output conversion (S.OUT2: 2 and 4).
#[derive(Debug)]
pub(crate) struct Out {
    velocity: bool,
    k: Kit,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl Out {
    pub fn compile_out1(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Out::compile(a, true)
    }

    pub fn compile_out2(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Out::compile(a, false)
    }

    fn compile(a: &mut Args<'_, '_>, velocity: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 3, "block memory");
        let s2 = area(a, 2, 4, "operation constants");
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        Some(Box::new(Out {
            velocity,
            k: Kit::new(sys, s),
            s1: s1?,
            d1: d1?,
            s2: s2?,
            d2: d2?,
        }))
    }
}

impl Instr for Out {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        let s2 = Area::of(cx.mem, &self.s2, 4)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        let bb = Bb(d1, BlockMemory::bb);
        self.k.sys.run(cx.mem, |m| {
            let flow = if self.velocity {
                velocity(&self.k, m, s1, bb, d2)?
            } else {
                positional(&self.k, m, s1, bb, d2)?
            };
            if flow == Flow::Output {
                let nmax = s2.real(m, OutputRange::nmax, 4)?;
                let nmin = s2.real(m, OutputRange::nmin, 4)?;
                let mv = d2.real(m, LoopTag::mv, 4)?;
                d1.set(m, BlockMemory::bw, convert(nmax, nmin, mv, 4)?);
            }
            Ok(())
        })
    }
}
