//! Programming manual (common instructions) §7.1 logical operations: WAND, WOR,
//! WXOR, WXNR (16-bit), DAND, DOR, DXOR, DXNR (32-bit), each with two operands
//! (`S D`: D = D op S) or three (`S1 S2 D`: D = S1 op S2), and the block forms
//! BKAND, BKOR, BKXOR, BKXNR (`S1 S2 D n`).
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions). A
//! digit-specified source is zero-extended (the bits beyond the specified
//! digits count as 0, as the manual says); a digit-specified destination keeps
//! the low 4·k bits of the result.

use super::transfer::{count, Loc, WordBlock};
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::Operand;
use softplc_ir::fault::Fault;
// The bitwise operation: PM §7.1.1-§7.1.2 logical product, §7.1.3-§7.1.4
// sum, §7.1.5-§7.1.6 exclusive OR, §7.1.7-§7.1.8 exclusive NOR.
use softplc_ir::kernels::logic::WordLogic;
use softplc_ir::ops::{Num, WordArg};
use softplc_ir::word_op::{Binary, WordOp};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("WAND", &LOGIC, |a| word(a, WordLogic::And, Num::I16)),
    Def::app("WOR", &LOGIC, |a| word(a, WordLogic::Or, Num::I16)),
    Def::app("WXOR", &LOGIC, |a| word(a, WordLogic::Xor, Num::I16)),
    Def::app("WXNR", &LOGIC, |a| word(a, WordLogic::Xnr, Num::I16)),
    Def::app("DAND", &LOGIC, |a| word(a, WordLogic::And, Num::I32)),
    Def::app("DOR", &LOGIC, |a| word(a, WordLogic::Or, Num::I32)),
    Def::app("DXOR", &LOGIC, |a| word(a, WordLogic::Xor, Num::I32)),
    Def::app("DXNR", &LOGIC, |a| word(a, WordLogic::Xnr, Num::I32)),
    Def::app("BKAND", &BLOCK_LOGIC, |a| block(a, WordLogic::And)),
    Def::app("BKOR", &BLOCK_LOGIC, |a| block(a, WordLogic::Or)),
    Def::app("BKXOR", &BLOCK_LOGIC, |a| block(a, WordLogic::Xor)),
    Def::app("BKXNR", &BLOCK_LOGIC, |a| block(a, WordLogic::Xnr)),
];

static LOGIC: Doc = Doc {
    family: "logic",
    cite: "PM §7.1",
    notes: "2 and 3 operands",
};
static BLOCK_LOGIC: Doc = Doc {
    family: "block logic",
    cite: "PM §7.1",
    notes: "past end or n<0 → 4101",
};

/// PM §7.1.1/§7.1.3/§7.1.5/§7.1.7 WAND/WOR/WXOR/WXNR and DAND/DOR/DXOR/DXNR:
/// `S D` stores D op S in D, `S1 S2 D` stores S1 op S2 in D. Sources may be
/// constants (K/H); D is a device. No operation error.
#[derive(Debug)]
struct Word {
    op: WordLogic,
    num: Num,
    s1: WordArg,
    s2: WordArg,
    d: WordArg,
}

fn word(a: &mut Args<'_, '_>, op: WordLogic, num: Num) -> Option<Box<dyn Instr>> {
    if !a.count(&[2, 3]) {
        return None;
    }
    let (s1, s2, d) = if a.len() == 3 {
        let s1 = a.word_src(0, num);
        let s2 = a.word_src(1, num);
        (s1, s2, a.word_dest(2, num, num.words()))
    } else {
        // `S D`: D = D op S; D is both the first source and the destination.
        let s = a.word_src(0, num);
        let d = a.word_dest(1, num, num.words());
        (d.clone(), s, d)
    };
    Some(Box::new(Word {
        op,
        num,
        s1: s1?,
        s2: s2?,
        d: d?,
    }))
}

impl Instr for Word {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        match self.num {
            Num::I16 => {
                let a = cx.mem.read16(&self.s1)? as u32;
                let b = cx.mem.read16(&self.s2)? as u32;
                cx.mem.write16(&self.d, self.op.apply(a, b) as u16)
            }
            _ => {
                let a = cx.mem.read32(&self.s1)?;
                let b = cx.mem.read32(&self.s2)?;
                cx.mem.write32(&self.d, self.op.apply(a, b))
            }
        }
    }

    fn word_op(&self) -> Option<WordOp<'_>> {
        let op = match self.op {
            WordLogic::And => Binary::And,
            WordLogic::Or => Binary::Or,
            WordLogic::Xor => Binary::Xor,
            WordLogic::Xnr | WordLogic::Not => return None,
        };
        Some(WordOp::Binary {
            op,
            wide: self.num != Num::I16,
            s1: &self.s1,
            s2: &self.s2,
            d: &self.d,
        })
    }
}

/// The second source of a block logical operation.
#[derive(Debug)]
enum Src2 {
    Block(WordBlock),
    /// A constant applied to every point of S1.
    Const(u16),
}

/// PM §7.1.2/§7.1.4/§7.1.6/§7.1.8 BKAND/BKOR/BKXOR/BKXNR `S1 S2 D n`: point k
/// of D = point k of S1 op point k of S2, for k = 0..n-1. S2 may be a constant
/// (K-32768-32767 / H0-HFFFF), which is combined with every point of S1. The
/// blocks are word devices or digit-specified bit devices. n = 0 does nothing;
/// a block of n points past the end of its device is 4101 (negative n too).
/// Overlapping blocks are processed point by point from the first (the manual
/// does not define them; decision).
#[derive(Debug)]
struct BlockLogic {
    op: WordLogic,
    s1: WordBlock,
    s2: Src2,
    d: WordBlock,
    n: WordArg,
}

fn block(a: &mut Args<'_, '_>, op: WordLogic) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let s1 = WordBlock::compile(a, 0);
    let s2 = match a.operand(1) {
        Some(Operand::Const(_)) => match a.word_src(1, Num::I16) {
            Some(WordArg::Const(k)) => Some(Src2::Const(k as u16)),
            _ => None,
        },
        Some(_) => WordBlock::compile(a, 1).map(Src2::Block),
        None => None,
    };
    let d = WordBlock::compile(a, 2);
    let n = a.word_src(3, Num::I16);
    Some(Box::new(BlockLogic {
        op,
        s1: s1?,
        s2: s2?,
        d: d?,
        n: n?,
    }))
}

impl Instr for BlockLogic {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let s1 = self.s1.resolve(cx.mem, n)?;
        let s2 = match &self.s2 {
            Src2::Block(b) => Some(b.resolve(cx.mem, n)?),
            Src2::Const(_) => None,
        };
        let d = self.d.resolve(cx.mem, n)?;
        let k2 = match self.s2 {
            Src2::Const(k) => k,
            Src2::Block(_) => 0,
        };
        for k in 0..n as usize {
            let a = s1.get(cx.mem, k) as u32;
            let b = s2.map_or(k2, |s2: Loc| s2.get(cx.mem, k)) as u32;
            d.set(cx.mem, k, self.op.apply(a, b) as u16);
        }
        Ok(())
    }
}
