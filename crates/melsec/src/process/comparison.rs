//! Comparisons with hysteresis (000 ch. 12): S.>, S.<, S.=, S.>=, S.<=. The
//! relations are (R) (spec §4.36, DEC-31); the previous BB1 is D1+2 as found
//! (DEC-8; its alternative is a load error). Not in Table 14.2: SD1503 = 1.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_lang::isa::{Def, Doc};

use super::common::{def, history_in_block_memory, result, Area, Areas, BlockMemory, PcError, Sys};
use super::settings::ProcessSettings;
use super::tag::bb;
use crate::{Args, ExecCtx, Instr};

static CMP: Doc = Doc {
    family: "process control: comparison",
    cite: "000 §12.1 L21433-21645, §12.2 L21706-21875, §12.3 L21894-22056, §12.4 \
           L22075-22243, §12.5 L22262-22431",
    notes: "BW = E1, BB1 = E1 vs E2 + K with a complementary reset edge shifted by HS (DEC-31); \
            HS < 0 is 4100 (SD1502 = 2)",
};

pub static DEFS: &[Def] = &[
    def("S.>", 4, &CMP, Cmp::compile_gt),
    def("S.<", 4, &CMP, Cmp::compile_lt),
    def("S.=", 4, &CMP, Cmp::compile_eq),
    def("S.>=", 4, &CMP, Cmp::compile_ge),
    def("S.<=", 4, &CMP, Cmp::compile_le),
];

softplc_ir::layout! {
    /// The input data (S1) of the comparisons.
    pub struct CmpInput[4] {
        /// E1: the value compared (and output as BW).
        e1: f32 @ 0,
        /// E2: the value compared with.
        e2: f32 @ 2,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of the comparisons (S.=: K only).
    pub struct CmpConsts[4] {
        /// K: the set value added to E2.
        k: f32 @ 0,
        /// HS: the hysteresis (not S.=).
        hs: f32 @ 2,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Rel {
    Gt,
    Lt,
    Eq,
    Ge,
    Le,
}

/// 000 §12.1 S.> L21433-21645, §12.2 S.< L21706-21875, §12.3 S.= L21894-22056,
/// §12.4 S.>= L22075-22243, §12.5 S.<= L22262-22431.
///
/// 000 §12 `S.x S1 D1 S2 D2(dmy)`: S1 +0 E1, +2 E2; D1 +0 BW (= E1), +2 BB
/// (BB1 = b0, the result); S2 +0 K set value, +2 HS hysteresis (not S.=,
/// whose S2 is K only, 2 words). With X = E2 + K (L21628-21636):
///
/// | | BB1 := 1 | BB1 := 0 | otherwise |
/// |---|---|---|---|
/// | S.>  | E1 > X | E1 ≤ X − HS | held |
/// | S.<  | E1 < X | E1 ≥ X + HS | held |
/// | S.=  | E1 = X | E1 ≠ X | — |
/// | S.>= | E1 ≥ X | E1 < X − HS | held |
/// | S.<= | E1 ≤ X | E1 > X + HS | held |
///
/// DEC-31: the reset edge is the complement of the set edge, so with HS = 0
/// every input sets or resets BB1; HS < 0 is 4100 with SD1502 = 2 for all
/// but S.=. `compare_complementary = false` makes the reset edge the other
/// inclusivity (S.>: E1 < X − HS, S.<: E1 > X + HS, S.>=: E1 ≤ X − HS,
/// S.<=: E1 ≥ X + HS), the set edge tried first.
#[derive(Debug)]
struct Cmp {
    rel: Rel,
    complementary: bool,
    sys: Sys,
    areas: Areas,
}

impl Cmp {
    fn compile_gt(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Cmp::compile(a, Rel::Gt)
    }

    fn compile_lt(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Cmp::compile(a, Rel::Lt)
    }

    fn compile_eq(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Cmp::compile(a, Rel::Eq)
    }

    fn compile_ge(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Cmp::compile(a, Rel::Ge)
    }

    fn compile_le(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Cmp::compile(a, Rel::Le)
    }

    fn words(rel: Rel) -> u32 {
        if rel == Rel::Eq {
            2
        } else {
            4
        }
    }

    fn compile(a: &mut Args<'_, '_>, rel: Rel) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        history_in_block_memory(a)?;
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [4, 3, Cmp::words(rel)]);
        Some(Box::new(Cmp {
            rel,
            complementary: s.compare_complementary,
            sys,
            areas: areas?,
        }))
    }

    fn body(&self, m: &mut DeviceMemory, s1: Area, d1: Area, s2: Area) -> Result<(), PcError> {
        let e1 = s1.real(m, CmpInput::e1, 1)?;
        let e2 = s1.real(m, CmpInput::e2, 1)?;
        let k = s2.real(m, CmpConsts::k, 1)?;
        let x = result(e2 + k, 1)?;
        let hs = if self.rel == Rel::Eq {
            0.0
        } else {
            let hs = s2.real(m, CmpConsts::hs, 1)?;
            if hs < 0.0 {
                return Err(PcError::negative(1));
            }
            hs
        };
        let c = self.complementary;
        // (set, reset) for this input.
        let (set, reset) = match self.rel {
            Rel::Gt => {
                let r = result(x - hs, 1)?;
                (e1 > x, if c { e1 <= r } else { e1 < r })
            }
            Rel::Ge => {
                let r = result(x - hs, 1)?;
                (e1 >= x, if c { e1 < r } else { e1 <= r })
            }
            Rel::Lt => {
                let r = result(x + hs, 1)?;
                (e1 < x, if c { e1 >= r } else { e1 > r })
            }
            Rel::Le => {
                let r = result(x + hs, 1)?;
                (e1 <= x, if c { e1 > r } else { e1 >= r })
            }
            Rel::Eq => (e1 == x, e1 != x),
        };
        d1.set(m, BlockMemory::bw, e1);
        if set || reset {
            d1.set_bits(m, BlockMemory::bb, bb::BB1, set);
        }
        Ok(())
    }
}

impl Instr for Cmp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2))
    }
}
