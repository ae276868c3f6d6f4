//! Programming manual (common instructions) §6.1 comparison operations, block
//! data comparisons: BKCMP=, BKCMP<>, BKCMP>, BKCMP<=, BKCMP<, BKCMP>= and the
//! 32-bit DBKCMP… forms. (The comparison contacts LD=, AND<>, OR>= … are
//! compiled by `program/compile.rs` and evaluated in `basic.rs`.)
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! Not Q instructions, hence not implemented: CMP, DCMP, ECMP, ZCP, DZCP (FX /
//! A-series compare-to-three-bits and zone compare). The QnH instruction set has
//! no equivalent; programs use the comparison contacts instead.

use super::data::{elem, read_i16, set_flag, Bits};
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::{Constant, Operand};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{CmpOp, Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("BKCMP=", &BKCMP, |a| bkcmp(a, false, CmpOp::Eq)),
    Def::app("BKCMP<>", &BKCMP, |a| bkcmp(a, false, CmpOp::Ne)),
    Def::app("BKCMP>", &BKCMP, |a| bkcmp(a, false, CmpOp::Gt)),
    Def::app("BKCMP<=", &BKCMP, |a| bkcmp(a, false, CmpOp::Le)),
    Def::app("BKCMP<", &BKCMP, |a| bkcmp(a, false, CmpOp::Lt)),
    Def::app("BKCMP>=", &BKCMP, |a| bkcmp(a, false, CmpOp::Ge)),
    Def::app("DBKCMP=", &BKCMP, |a| bkcmp(a, true, CmpOp::Eq)),
    Def::app("DBKCMP<>", &BKCMP, |a| bkcmp(a, true, CmpOp::Ne)),
    Def::app("DBKCMP>", &BKCMP, |a| bkcmp(a, true, CmpOp::Gt)),
    Def::app("DBKCMP<=", &BKCMP, |a| bkcmp(a, true, CmpOp::Le)),
    Def::app("DBKCMP<", &BKCMP, |a| bkcmp(a, true, CmpOp::Lt)),
    Def::app("DBKCMP>=", &BKCMP, |a| bkcmp(a, true, CmpOp::Ge)),
];

static BKCMP: Doc = Doc {
    family: "block comparison",
    cite: "PM §6.1",
    notes: "S1 may be a constant; one result bit per element; SM704 all true; n < 0 → 4100",
};

/// The first operand of a block comparison: a constant compared with every
/// element of S2, or a block compared element by element.
#[derive(Debug)]
enum Left {
    Const(u32),
    Block(Block),
}

/// A resolved [`Left`].
#[derive(Clone, Copy)]
enum Resolved {
    Const(i32),
    At(usize),
}

/// PM §6.1 BKCMP□(P) `S1 S2 D n` / DBKCMP□(P): compares the n signed 16-bit
/// (32-bit) values from S1 (or the constant S1) with the n values from S2,
/// element by element (S1+k □ S2+k); bit D+k turns ON when the condition
/// holds and OFF otherwise. SM704 turns ON when all n results are ON and OFF
/// otherwise. D is a bit device (n points) or a word device (n bits from bit 0).
///
/// n = 0: no processing (D and SM704 unchanged). n < 0: 4100 (decision: a
/// negative count is not a block length). A block past the end of its device
/// (S1, S2, D): 4101, nothing written.
#[derive(Debug)]
struct BkCmp {
    s1: Left,
    s2: Block,
    d: Bits,
    n: WordArg,
    op: CmpOp,
    wide: bool,
    sm704: Option<u32>,
}

fn bkcmp(a: &mut Args<'_, '_>, wide: bool, op: CmpOp) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let num = if wide { Num::I32 } else { Num::I16 };
    let s1 = match a.operand(0) {
        Some(Operand::Const(Constant::Int { .. })) => match a.word_src(0, num)? {
            WordArg::Const(k) => Some(Left::Const(k)),
            _ => None,
        },
        Some(_) => a.block(0).map(Left::Block),
        None => None,
    };
    let s2 = a.block(1);
    let d = Bits::compile(a, 2);
    let n = a.word_src(3, Num::I16);
    Some(Box::new(BkCmp {
        s1: s1?,
        s2: s2?,
        d: d?,
        n: n?,
        op,
        wide,
        sm704: a.flag(softplc_lang::dialect::Flag::AllTrue),
    }))
}

impl Instr for BkCmp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n == 0 {
            return Ok(());
        }
        if n < 0 {
            return Err(Fault::Operation);
        }
        let n = n as u32;
        let w = if self.wide { 2 } else { 1 };
        let s1 = match &self.s1 {
            Left::Const(k) if self.wide => Resolved::Const(*k as i32),
            Left::Const(k) => Resolved::Const(*k as u16 as i16 as i32),
            Left::Block(b) => Resolved::At(mem.block_start(b, n * w)?),
        };
        let s2 = mem.block_start(&self.s2, n * w)?;
        let d = self.d.resolve(mem, n)?;
        let mut all = true;
        for k in 0..n as usize {
            let x = match s1 {
                Resolved::Const(c) => c,
                Resolved::At(base) => elem(mem, base, k, self.wide),
            };
            let y = elem(mem, s2, k, self.wide);
            let r = match self.op {
                CmpOp::Eq => x == y,
                CmpOp::Ne => x != y,
                CmpOp::Gt => x > y,
                CmpOp::Le => x <= y,
                CmpOp::Lt => x < y,
                CmpOp::Ge => x >= y,
            };
            all &= r;
            d.set(mem, k, r);
        }
        set_flag(mem, self.sm704, all);
        Ok(())
    }
}
