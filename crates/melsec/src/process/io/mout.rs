//! S.MOUT, manual output.

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;

use super::stage::{convert, OutputRange};
use crate::process::common::{area, dummy, Area, BlockMemory, Sys};
use crate::process::settings::ProcessSettings;
use crate::process::tag::{alm, LoopTag, Mode, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

/// 000 §8.4 S.MOUT `S.MOUT S1(dmy) D1 S2 D2` (L5018-5288), manual output:
/// in the manual modes (MAN, CMB, CMV, LCM) BW = (NMAX − NMIN)/100 × MV +
/// NMIN from the operator's MV; in the auto modes BW holds; loop stop
/// (SPA = 1): BW holds and MODE := MAN.
///
/// Operands: S1 dummy; D1 +0 BW; S2 +0 NMAX (100.0), +2 NMIN (0.0); D2 the
/// loop tag: MODE +1, ALM +3 (SPA), MV +12 (read). Errors: a bad float is
/// 4100 with SD1502 = 1, SD1503 = 1 (not in Table 14.2).
#[derive(Debug)]
pub(crate) struct Mout {
    sys: Sys,
    mode: Mode,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl Mout {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = dummy(a, 0);
        let d1 = area(a, 1, 2, "block memory");
        let s2 = area(a, 2, 4, "operation constants");
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        s1?;
        Some(Box::new(Mout {
            sys,
            mode: Mode::new(&s),
            d1: d1?,
            s2: s2?,
            d2: d2?,
        }))
    }
}

impl Instr for Mout {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let d1 = Area::of(cx.mem, &self.d1, 2)?;
        let s2 = Area::of(cx.mem, &self.s2, 4)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        self.sys.run(cx.mem, |m| {
            if d2.get(m, LoopTag::alm) & alm::SPA != 0 {
                d2.set(m, LoopTag::mode, Mode::MAN);
                return Ok(());
            }
            if self.mode.manual(d2.get(m, LoopTag::mode)) {
                let nmax = s2.real(m, OutputRange::nmax, 1)?;
                let nmin = s2.real(m, OutputRange::nmin, 1)?;
                let mv = d2.real(m, LoopTag::mv, 1)?;
                d1.set(m, BlockMemory::bw, convert(nmax, nmin, mv, 1)?);
            }
            Ok(())
        })
    }
}
