//! Compare contacts (002 §6.19 L9078-9583; spec aplc.md §4.19):
//! `LDop`, `ANDop`, `ORop` (INT), `LDDop`, `ANDDop`, `ORDop` (DINT), `LDRop`,
//! `ANDRop`, `ORRop` (REAL), op one of `=`, `<>`, `>`, `<`, `>=`, `<=`; the
//! operator may be written apart (L9442-9447, joined by the loader).

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::kernels::basic::test;
use softplc_ir::ops::{CmpOp, CondOp, Condition, Join, Num, Op, WordArg};
use softplc_lang::compile::Compiler;
use softplc_lang::isa::{Def, Doc, Steps, Test, Use};

use crate::constant::Width;
use crate::num;
use crate::resolve::{self, at};

static DOC: Doc = Doc {
    family: "compare contacts",
    cite: "002 §6.19 L9078-9583",
    notes: "signed INT, DINT (high word first) and REAL comparison; the operator may be written apart (`LDR < > D0 D2`)",
};

macro_rules! compares {
    ($(($base:literal, $join:ident, $num:ident)),*) => {
        &[$(
            Def::contact(concat!($base, "="), Join::$join, Test::Compare(Num::$num), &DOC, compare).steps(Steps::Fixed(5)),
            Def::contact(concat!($base, "<>"), Join::$join, Test::Compare(Num::$num), &DOC, compare).steps(Steps::Fixed(5)),
            Def::contact(concat!($base, ">"), Join::$join, Test::Compare(Num::$num), &DOC, compare).steps(Steps::Fixed(5)),
            Def::contact(concat!($base, "<"), Join::$join, Test::Compare(Num::$num), &DOC, compare).steps(Steps::Fixed(5)),
            Def::contact(concat!($base, ">="), Join::$join, Test::Compare(Num::$num), &DOC, compare).steps(Steps::Fixed(5)),
            Def::contact(concat!($base, "<="), Join::$join, Test::Compare(Num::$num), &DOC, compare).steps(Steps::Fixed(5)),
        )*]
    };
}

/// INT, DINT and REAL compare contacts, each as LD, AND and OR.
pub static DEFS: &[Def] = compares!(
    ("LD", Load, I16),
    ("AND", And, I16),
    ("OR", Or, I16),
    ("LDD", Load, I32),
    ("ANDD", And, I32),
    ("ORD", Or, I32),
    ("LDR", Load, F32),
    ("ANDR", And, F32),
    ("ORR", Or, F32)
);

/// A DINT or REAL comparison (high word first).
#[derive(Debug)]
struct Cmp32 {
    op: CmpOp,
    real: bool,
    a: WordArg,
    b: WordArg,
}

impl Condition for Cmp32 {
    fn eval(&self, mem: &DeviceMemory) -> Result<bool, Fault> {
        let ord = if self.real {
            let (a, b) = (num::read_real(mem, &self.a)?, num::read_real(mem, &self.b)?);
            a.partial_cmp(&b).unwrap_or(std::cmp::Ordering::Equal)
        } else {
            (num::read32(mem, &self.a)? as i32).cmp(&(num::read32(mem, &self.b)? as i32))
        };
        Ok(test(self.op, ord))
    }
}

// 002 §6.19 L9078 LD=, ANDD<, ORR<> … (one lowering for all 54)
fn compare(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[2]) {
        return;
    }
    let split = u.m.find(['<', '>', '=']).unwrap_or(u.m.len());
    let (base, opt) = u.m.split_at(split);
    let op = match opt {
        "=" => CmpOp::Eq,
        "<>" => CmpOp::Ne,
        ">" => CmpOp::Gt,
        "<" => CmpOp::Lt,
        ">=" => CmpOp::Ge,
        "<=" => CmpOp::Le,
        _ => return c.unmatched(u),
    };
    let (join, width) = match base {
        "LD" => (Join::Load, Width::W16),
        "AND" => (Join::And, Width::W16),
        "OR" => (Join::Or, Width::W16),
        "LDD" => (Join::Load, Width::W32),
        "ANDD" => (Join::And, Width::W32),
        "ORD" => (Join::Or, Width::W32),
        "LDR" => (Join::Load, Width::Real),
        "ANDR" => (Join::And, Width::Real),
        "ORR" => (Join::Or, Width::Real),
        _ => return c.unmatched(u),
    };
    let ra = resolve::word(c.map, &i.operands[0].text, width, false, false);
    let rb = resolve::word(c.map, &i.operands[1].text, width, false, false);
    let a = at(c, &i.operands[0], ra);
    let b = at(c, &i.operands[1], rb);
    let (Some(a), Some(b)) = (a, b) else {
        return;
    };
    let op = match width {
        Width::W16 => Op::Compare(Box::new(softplc_ir::ops::Compare {
            join,
            op,
            num: Num::I16,
            a,
            b,
        })),
        _ => Op::Cond(Box::new(CondOp {
            join,
            cond: Box::new(Cmp32 {
                op,
                real: width == Width::Real,
                a,
                b,
            }),
        })),
    };
    c.contact(i, join, op);
}
