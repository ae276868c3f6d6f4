//! Compensation instructions (000 ch. 10): S.FG, S.IFG, S.FLT, S.SUM, S.TPC,
//! S.ENG, S.IENG.

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{area, def, dummy, real, result, set_f, Sys};
use super::settings::ProcessSettings;
use crate::{Args, ExecCtx, Instr};

static ENG: Doc = Doc {
    family: "process control: compensation",
    cite: "000 §10.6 L20079-20244, §10.7 L20245-20421",
    notes: "f32; S.IENG with RH = RL gives 0, with RH < RL the formula (DEC-28)",
};

pub static DEFS: &[Def] = &[
    def("S.ENG", 4, &ENG, Eng::compile_eng),
    def("S.IENG", 4, &ENG, Eng::compile_ieng),
];

/// 000 §10.6 S.ENG `S.ENG S1 D1 S2 D2(dmy)`: BW = (RH − RL)/100 × E1 + RL;
/// 000 §10.7 S.IENG: BW = 100/(RH − RL) × (E1 − RL) %, 0 when RH = RL
/// (L20408-20416), the formula also when RH < RL (DEC-28; the alternative
/// holds BW). S1 +0 E1; D1 +0 BW; S2 +0 RH, +2 RL. Errors: a bad float is
/// 4100 with SD1502 = 1, SD1503 = 1 (DEC-36).
#[derive(Debug)]
struct Eng {
    inverse: bool,
    decreasing: bool,
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
}

impl Eng {
    fn compile_eng(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Eng::compile(a, false)
    }

    fn compile_ieng(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Eng::compile(a, true)
    }

    fn compile(a: &mut Args<'_, '_>, inverse: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 2, "block memory");
        let s2 = area(a, 2, 4, "operation constants");
        dummy(a, 3)?;
        Some(Box::new(Eng {
            inverse,
            decreasing: s.ieng_decreasing,
            sys,
            s1: s1?,
            d1: d1?,
            s2: s2?,
        }))
    }
}

impl Instr for Eng {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = cx.mem.block_start(&self.s1, 2)?;
        let d1 = cx.mem.block_start(&self.d1, 2)?;
        let s2 = cx.mem.block_start(&self.s2, 4)?;
        self.sys.run(cx.mem, |m| {
            let e1 = real(m, s1, 1)?;
            let rh = real(m, s2, 1)?;
            let rl = real(m, s2 + 2, 1)?;
            let bw = if !self.inverse {
                (rh - rl) / 100.0 * e1 + rl
            } else if rh == rl {
                0.0
            } else if rh < rl && !self.decreasing {
                return Ok(());
            } else {
                100.0 / (rh - rl) * (e1 - rl)
            };
            set_f(m, d1, result(bw, 1)?);
            Ok(())
        })
    }
}
