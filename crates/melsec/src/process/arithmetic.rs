//! Arithmetic (000 ch. 11): S.ADD, S.SUB, S.MUL, S.DIV, S.SQR, S.ABS, in
//! f32 in the manual's order. Not in Table 14.2: SD1503 = 1.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, count_word, def, dummy, only_default, result, Area, Areas, BlockMemory, Input, InputList,
    PcError, Sys,
};
use super::settings::ProcessSettings;
use super::tag::bb;
use crate::{Args, ExecCtx, Instr};

static TERMS: Doc = Doc {
    family: "process control: arithmetic",
    cite: "000 §11.1 L20425-20594, §11.2 L20599-20762, §11.3 L20763-20926",
    notes: "K1·E1 ± … (or ×) Kn·En + B, n = 0..5 from the input n, both n words checked \
            (DEC-29, 4100 with SD1502 = 3), B after the coefficients, added (DEC-30)",
};
static DIV: Doc = Doc {
    family: "process control: arithmetic",
    cite: "000 §11.4 L20927-21094",
    notes: "A × (K1·E1 + B1)/(K2·E2 + B2) + B3; a zero denominator gives B3, not an error",
};
static SQR: Doc = Doc {
    family: "process control: arithmetic",
    cite: "000 §11.5 L21095-21222",
    notes: "K·√E1, 0 at or below the low cut OLC and for E1 < 0",
};
static ABS: Doc = Doc {
    family: "process control: arithmetic",
    cite: "000 §11.6 L21223-21412",
    notes: "|E1| with the sign in BB1 (> 0) / BB2 (< 0)",
};

pub static DEFS: &[Def] = &[
    def("S.ADD", 4, &TERMS, Terms::compile_add),
    def("S.SUB", 4, &TERMS, Terms::compile_sub),
    def("S.MUL", 4, &TERMS, Terms::compile_mul),
    def("S.DIV", 4, &DIV, Div::compile),
    def("S.SQR", 4, &SQR, Sqr::compile),
    def("S.ABS", 4, &ABS, Abs::compile),
];

softplc_ir::layout! {
    /// The operation constants (S2) of S.ADD, S.SUB and S.MUL: n, K1 … Kn,
    /// then B.
    pub struct TermConsts[13] {
        /// n: the number of coefficients (BIN16, 0..5).
        n: i16 @ 0,
        /// K1, the first of the n coefficients; B follows Kn.
        k: f32 @ 1,
    }
}

softplc_ir::layout! {
    /// The input data (S1) of S.DIV.
    pub struct DivInputs[4] {
        /// E1: the numerator input.
        e1: f32 @ 0,
        /// E2: the denominator input.
        e2: f32 @ 2,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.DIV.
    pub struct DivConsts[12] {
        /// A: the gain of the quotient.
        a: f32 @ 0,
        /// K1: the numerator coefficient.
        k1: f32 @ 2,
        /// K2: the denominator coefficient.
        k2: f32 @ 4,
        /// B1: the numerator bias.
        b1: f32 @ 6,
        /// B2: the denominator bias.
        b2: f32 @ 8,
        /// B3: the output bias.
        b3: f32 @ 10,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.SQR.
    pub struct SqrConsts[4] {
        /// OLC: the output low cut.
        olc: f32 @ 0,
        /// K: the gain.
        k: f32 @ 2,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Add,
    Sub,
    Mul,
}

/// 000 §11.1 S.ADD L20425-20594, §11.2 S.SUB L20599-20762, §11.3 S.MUL
/// L20763-20926.
///
/// 000 §11.1 S.ADD, §11.2 S.SUB, §11.3 S.MUL `S.x S1 D1 S2 D2(dmy)`: S1 +0 n
/// (BIN16, 0..5), +1/+2 E1 … +2n−1/+2n En; D1 +0 BW; S2 +0 n (coefficient
/// count, 0..5), +1/+2 K1 … +2n−1/+2n Kn, +2n+1/+2n+2 B.
/// * S.ADD: BW = (K1·E1) + (K2·E2) + … + (Kn·En) + B (L20583).
/// * S.SUB: BW = (K1·E1) − (K2·E2) − … − (Kn·En) + B (L20751).
/// * S.MUL: BW = (K1·E1) × (K2·E2) × … × (Kn·En) + B (L20915).
/// * n = 0: BW = B.
///
/// DEC-29: the input n sets the number of terms, K1 … are read from S2+1
/// on and B from S2 + 2·(coefficient n) + 1; either n outside 0..5 is 4100
/// with SD1502 = 3. DEC-30: B is added (`arith_bias_added = false`
/// subtracts it, n = 0 then giving −B).
#[derive(Debug)]
struct Terms {
    op: Op,
    bias_added: bool,
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
}

impl Terms {
    fn compile_add(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Terms::compile(a, Op::Add)
    }

    fn compile_sub(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Terms::compile(a, Op::Sub)
    }

    fn compile_mul(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Terms::compile(a, Op::Mul)
    }

    fn compile(a: &mut Args<'_, '_>, op: Op) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        if !only_default(a, s.arith_input_n, "arith_input_n", 29) {
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 1, "input data");
        let d1 = area(a, 1, 2, "block memory");
        let s2 = area(a, 2, 3, "operation constants");
        dummy(a, 3)?;
        Some(Box::new(Terms {
            op,
            bias_added: s.arith_bias_added,
            sys,
            s1: s1?,
            d1: d1?,
            s2: s2?,
        }))
    }

    fn body(
        &self,
        m: &mut DeviceMemory,
        s1: Area,
        d1: Area,
        s2: Area,
        n: usize,
        kn: usize,
    ) -> Result<(), PcError> {
        let mut acc = 0f32;
        for i in 0..n {
            let e = s1.real(m, InputList::e.nth(i), 1)?;
            let k = s2.real(m, TermConsts::k.nth(i), 1)?;
            let term = result(k * e, 1)?;
            acc = if i == 0 {
                term
            } else {
                match self.op {
                    Op::Add => acc + term,
                    Op::Sub => acc - term,
                    Op::Mul => acc * term,
                }
            };
            acc = result(acc, 1)?;
        }
        let b = s2.real(m, TermConsts::k.nth(kn), 1)?;
        let bw = if self.bias_added { acc + b } else { acc - b };
        d1.set(m, BlockMemory::bw, result(bw, 1)?);
        Ok(())
    }
}

impl Instr for Terms {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 1)?;
        let d1 = Area::of(cx.mem, &self.d1, 2)?;
        let s2 = Area::of(cx.mem, &self.s2, 1)?;
        let counts = count_word(cx.mem, s1, InputList::n, 0, 5, 1)
            .and_then(|n| Ok((n, count_word(cx.mem, s2, TermConsts::n, 0, 5, 1)?)));
        let (n, kn) = match counts {
            Ok(c) => c,
            Err(e) => return Err(self.sys.fail(cx.mem, e)),
        };
        // The words up to En, Kn and B.
        let end = |f: softplc_ir::layout::At<f32>, k: usize| f.nth(k).offset() as u32;
        let s1 = Area::of(cx.mem, &self.s1, end(InputList::e, n))?;
        let s2 = Area::of(
            cx.mem,
            &self.s2,
            end(TermConsts::k, n).max(end(TermConsts::k, kn + 1)),
        )?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2, n, kn))
    }
}

/// 000 §11.4 S.DIV L20927-21094.
///
/// 000 §11.4 S.DIV `S.DIV S1 D1 S2 D2(dmy)`: S1 +0 E1 (numerator), +2 E2
/// (denominator); D1 +0 BW; S2 +0 A, +2 K1, +4 K2, +6 B1, +8 B2, +10 B3.
/// BW = A × (K1·E1 + B1)/(K2·E2 + B2) + B3 (L21077-21083); a denominator of 0
/// gives BW = B3 (L21087, not an error).
#[derive(Debug)]
struct Div {
    sys: Sys,
    areas: Areas,
}

impl Div {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [4, 2, 12]);
        Some(Box::new(Div { sys, areas: areas? }))
    }

    fn body(&self, m: &mut DeviceMemory, s1: Area, d1: Area, s2: Area) -> Result<(), PcError> {
        let e1 = s1.real(m, DivInputs::e1, 1)?;
        let e2 = s1.real(m, DivInputs::e2, 1)?;
        let c = |f| s2.real(m, f, 1);
        let a = c(DivConsts::a)?;
        let (k1, k2) = (c(DivConsts::k1)?, c(DivConsts::k2)?);
        let (b1, b2, b3) = (c(DivConsts::b1)?, c(DivConsts::b2)?, c(DivConsts::b3)?);
        let num = result(k1 * e1 + b1, 1)?;
        let den = result(k2 * e2 + b2, 1)?;
        let bw = if den == 0.0 {
            b3
        } else {
            a * result(num / den, 1)? + b3
        };
        d1.set(m, BlockMemory::bw, result(bw, 1)?);
        Ok(())
    }
}

impl Instr for Div {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2))
    }
}

/// 000 §11.5 S.SQR L21095-21222.
///
/// 000 §11.5 S.SQR `S.SQR S1 D1 S2 D2(dmy)`: S1 +0 E1; D1 +0 BW; S2 +0 OLC
/// output low cut, +2 K. BW = K·√E1; 0 when K·√E1 ≤ OLC or E1 < 0
/// (L21206-21213).
#[derive(Debug)]
struct Sqr {
    sys: Sys,
    areas: Areas,
}

impl Sqr {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [2, 2, 4]);
        Some(Box::new(Sqr { sys, areas: areas? }))
    }
}

impl Instr for Sqr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| {
            let e1 = s1.real(m, Input::e1, 1)?;
            let olc = s2.real(m, SqrConsts::olc, 1)?;
            let k = s2.real(m, SqrConsts::k, 1)?;
            let v = if e1 < 0.0 {
                0.0
            } else {
                result(k * e1.sqrt(), 1)?
            };
            d1.set(m, BlockMemory::bw, if v <= olc { 0.0 } else { v });
            Ok(())
        })
    }
}

/// 000 §11.6 S.ABS L21223-21412.
///
/// 000 §11.6 S.ABS `S.ABS S1 D1 S2(dmy) D2(dmy)`: S1 +0 E1; D1 +0 BW, +2 BB
/// (BB1 = b0: E1 > 0, BB2 = b1: E1 < 0, both 0 for E1 = 0). BW = |E1|
/// (L21395-21405).
#[derive(Debug)]
struct Abs {
    sys: Sys,
    s1: Block,
    d1: Block,
}

impl Abs {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 3, "block memory");
        dummy(a, 2)?;
        dummy(a, 3)?;
        Some(Box::new(Abs {
            sys,
            s1: s1?,
            d1: d1?,
        }))
    }
}

impl Instr for Abs {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        self.sys.run(cx.mem, |m| {
            let e1 = s1.real(m, Input::e1, 1)?;
            d1.set(m, BlockMemory::bw, e1.abs());
            d1.set_bits(m, BlockMemory::bb, bb::BB1, e1 > 0.0);
            d1.set_bits(m, BlockMemory::bb, bb::BB2, e1 < 0.0);
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::{comparison, compensation, dynamics, limiters, manual, selectors};

    /// Steps per 000 §2.2.7 as spec §2's inventory lists them (chapters 9-12).
    #[test]
    fn steps_follow_the_inventory() {
        let table = [
            ("S.LLAG", 8),
            ("S.I", 7),
            ("S.D", 7),
            ("S.DED", 8),
            ("S.HS", 7),
            ("S.LS", 7),
            ("S.MID", 8),
            ("S.AVE", 8),
            ("S.LIMT", 8),
            ("S.VLMT1", 9),
            ("S.VLMT2", 9),
            ("S.DBND", 8),
            ("S.BUMP", 8),
            ("S.AMR", 8),
            ("S.FG", 7),
            ("S.IFG", 8),
            ("S.FLT", 8),
            ("S.SUM", 8),
            ("S.TPC", 8),
            ("S.ADD", 8),
            ("S.SUB", 8),
            ("S.MUL", 8),
            ("S.DIV", 8),
            ("S.SQR", 8),
            ("S.ABS", 8),
            ("S.>", 7),
            ("S.<", 7),
            ("S.=", 7),
            ("S.>=", 7),
            ("S.<=", 7),
        ];
        let defs: Vec<_> = [
            dynamics::DEFS,
            selectors::DEFS,
            limiters::DEFS,
            manual::DEFS,
            compensation::DEFS,
            super::DEFS,
            comparison::DEFS,
        ]
        .concat();
        for (name, steps) in table {
            let d = defs.iter().find(|d| d.name == name).expect(name);
            assert_eq!(d.steps.count(&[]), steps, "{name}");
        }
    }
}
