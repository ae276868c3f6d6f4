//! Transfer MOV/DMOV/RMOV (002 §6.2 L3804-3887) and integer arithmetic
//! ADD, SUB, MUL, DIV, INC, DAT, DADD, DSUB, DMUL, DDIV, DINC, DDAT
//! (002 §6.3 L4273-4735; spec aplc.md §4.6). Flags per decision D8 (each
//! execution writes the flags its text defines), overflow wraps (D17); 32-bit
//! values high word first.

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::kernels::basic::Move;
use softplc_ir::ops::{Op as LadderOp, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::compile::Compiler;
use softplc_lang::isa::{Class, Def, Doc, Steps, Use};

use crate::constant::Width;
use crate::num::{self, E_DIV0};
use crate::resolve::{ArgsExt, Flags};

static MOVE: Doc = Doc {
    family: "transfer",
    cite: "002 §6.2 L3804-3887",
    notes: "MOV (destination may be SD), DMOV, RMOV; 32-bit and REAL high word first",
};
static ARITH: Doc = Doc {
    family: "integer arithmetic",
    cite: "002 §6.3 L4273-4735",
    notes: "ADD/SUB/DADD/DSUB write Z/C/B (SM180-SM182, D8), wrap (D17); MUL/DMUL/DIV/DDIV results high word first; ÷0 is error 69; INC/DAT/DINC/DDAT wrap, no flags",
};

pub static DEFS: &[Def] = &[
    // 002 §6.2.1 L3804 MOV
    Def::lower("MOV", Class::Output, &MOVE, mov).steps(Steps::Fixed(5)),
    // 002 §6.2.2 L3834 DMOV
    Def::app("DMOV", &MOVE, dmov)
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.2.3 L3864 RMOV
    Def::app("RMOV", &MOVE, rmov)
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.3 L4275 ADD
    Def::app("ADD", &ARITH, |a| arith(a, Op::Add, false))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.3 L4304 SUB
    Def::app("SUB", &ARITH, |a| arith(a, Op::Sub, false))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.3 L4333 MUL
    Def::app("MUL", &ARITH, |a| arith(a, Op::Mul, false))
        .no_pulse()
        .steps(Steps::Fixed(8)),
    // 002 §6.3 L4360 DIV
    Def::app("DIV", &ARITH, |a| arith(a, Op::Div, false))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.3 L4532 DADD
    Def::app("DADD", &ARITH, |a| arith(a, Op::Add, true))
        .no_pulse()
        .steps(Steps::Fixed(10)),
    // 002 §6.3 L4561 DSUB
    Def::app("DSUB", &ARITH, |a| arith(a, Op::Sub, true))
        .no_pulse()
        .steps(Steps::Fixed(10)),
    // 002 §6.3 L4590 DMUL
    Def::app("DMUL", &ARITH, |a| arith(a, Op::Mul, true))
        .no_pulse()
        .steps(Steps::Fixed(10)),
    // 002 §6.3 L4622 DDIV
    Def::app("DDIV", &ARITH, |a| arith(a, Op::Div, true))
        .no_pulse()
        .steps(Steps::Fixed(10)),
    // 002 §6.3 L4422 INC
    Def::app("INC", &ARITH, |a| step(a, false, 1))
        .no_pulse()
        .steps(Steps::Fixed(3)),
    // 002 §6.3 L4448 DAT
    Def::app("DAT", &ARITH, |a| step(a, false, -1))
        .no_pulse()
        .steps(Steps::Fixed(3)),
    // 002 §6.3 L4684 DINC
    Def::app("DINC", &ARITH, |a| step(a, true, 1))
        .no_pulse()
        .steps(Steps::Fixed(4)),
    // 002 §6.3 L4711 DDAT (headed DDEC, L4711-4715)
    Def::app("DDAT", &ARITH, |a| step(a, true, -1))
        .no_pulse()
        .steps(Steps::Fixed(4)),
    Def::app("DDEC", &ARITH, |a| step(a, true, -1))
        .no_pulse()
        .steps(Steps::Fixed(4)),
];

/// 16-bit MOV on the shared ladder ops (one word: no word order): the
/// inline `MovK`/`MovW` for plain words, the shared `Move` otherwise.
fn mov(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[2]) || !c.output(i, u.m) {
        return;
    }
    let r = crate::resolve::word(c.map, &i.operands[0].text, Width::W16, false, false);
    let s = crate::resolve::at(c, &i.operands[0], r);
    let r = crate::resolve::word(c.map, &i.operands[1].text, Width::W16, true, true);
    let d = crate::resolve::at(c, &i.operands[1], r);
    let (Some(s), Some(d)) = (s, d) else {
        return;
    };
    match (s, d) {
        (WordArg::Const(k), WordArg::Word(d)) => {
            c.emit(LadderOp::MovK { k: k as u16, d });
        }
        (WordArg::Word(s), WordArg::Word(d)) => {
            c.emit(LadderOp::MovW { s, d });
        }
        (s, d) => c.emit_instr(false, false, Box::new(Move { words: 1, s, d })),
    }
}

#[derive(Debug)]
struct Mov32 {
    s: WordArg,
    d: WordArg,
}

impl Instr for Mov32 {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = num::read32(cx.mem, &self.s)?;
        num::write32(cx.mem, &self.d, v)
    }
}

fn dmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_at(0, Width::W32, false);
    let d = a.sd_dest_at(1, Width::W32)?;
    Some(Box::new(Mov32 { s: s?, d }))
}

fn rmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_at(0, Width::Real, false);
    let d = a.word_at(1, Width::Real, true)?;
    Some(Box::new(Mov32 { s: s?, d }))
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Debug)]
struct Arith {
    op: Op,
    wide: bool,
    s1: WordArg,
    s2: WordArg,
    d: WordArg,
    /// The second register of MUL's product / DIV's remainder (D+1), or the
    /// second pair of DDIV (D+2).
    d2: Option<WordArg>,
    flags: Flags,
}

fn next(d: &WordArg, k: u32) -> Option<WordArg> {
    match d {
        WordArg::Word(i) => Some(WordArg::Word(i + k)),
        _ => None,
    }
}

/// ADD … DDIV: `op` on 16-bit or (`wide`) 32-bit operands.
fn arith(a: &mut Args<'_, '_>, op: Op, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let w = if wide { Width::W32 } else { Width::W16 };
    let s1 = a.word_at(0, w, false);
    let s2 = a.word_at(1, w, false);
    // MUL: a 32-bit pair (L4333); DIV: quotient and remainder in D, D+1;
    // DDIV: quotient pair and remainder pair (L4622).
    let dw = if op == Op::Mul && !wide {
        Width::W32
    } else {
        w
    };
    let d = a.word_at(2, dw, true)?;
    let d2 = match (op, wide) {
        (Op::Div, false) => Some(next(&d, 1)),
        (Op::Div, true) => Some(next(&d, 2)),
        _ => None,
    };
    let d2 = match d2 {
        Some(None) => {
            a.error(
                2,
                format!(
                    "`{}`: {} needs a D or V register for its remainder",
                    a.text(2),
                    a.mnemonic()
                ),
            );
            return None;
        }
        Some(Some(x)) => Some(x),
        None => None,
    };
    Some(Box::new(Arith {
        op,
        wide,
        s1: s1?,
        s2: s2?,
        d,
        d2,
        flags: a.flags(),
    }))
}

impl Arith {
    fn flags(&self, cx: &mut ExecCtx<'_>, v: i64, min: i64, max: i64) {
        cx.mem.bits[self.flags.zero as usize] = v == 0;
        cx.mem.bits[self.flags.carry as usize] = v > max;
        cx.mem.bits[self.flags.borrow as usize] = v < min;
    }
}

impl Instr for Arith {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (a, b) = if self.wide {
            (
                num::read32(cx.mem, &self.s1)? as i32 as i64,
                num::read32(cx.mem, &self.s2)? as i32 as i64,
            )
        } else {
            (
                num::read16(cx.mem, &self.s1)? as i64,
                num::read16(cx.mem, &self.s2)? as i64,
            )
        };
        let (min, max) = if self.wide {
            (i32::MIN as i64, i32::MAX as i64)
        } else {
            (-32768, 32767)
        };
        match self.op {
            Op::Add | Op::Sub => {
                let v = if self.op == Op::Add { a + b } else { a - b };
                // The zero flag is of the stored (wrapped) result.
                let stored = if self.wide {
                    v as i32 as i64
                } else {
                    v as i16 as i64
                };
                if self.wide {
                    num::write32(cx.mem, &self.d, v as u32)?;
                } else {
                    cx.mem.write16(&self.d, v as u16)?;
                }
                self.flags(cx, v, min, max);
                cx.mem.bits[self.flags.zero as usize] = stored == 0;
            }
            // DMUL keeps the low 32 bits ("may overflow", L4590-4620).
            Op::Mul => num::write32(cx.mem, &self.d, (a * b) as u32)?,
            Op::Div => {
                if b == 0 {
                    return Err(E_DIV0);
                }
                let (q, r) = (a.wrapping_div(b), a.wrapping_rem(b));
                let d2 = self.d2.as_ref().unwrap_or(&self.d);
                if self.wide {
                    num::write32(cx.mem, &self.d, q as u32)?;
                    num::write32(cx.mem, d2, r as u32)?;
                } else {
                    cx.mem.write16(&self.d, q as u16)?;
                    cx.mem.write16(d2, r as u16)?;
                }
            }
        }
        Ok(())
    }
}

#[derive(Debug)]
struct Step {
    wide: bool,
    delta: i32,
    d: WordArg,
}

/// INC/DAT (`delta` 1/−1) on a 16-bit or (`wide`) 32-bit operand.
fn step(a: &mut Args<'_, '_>, wide: bool, delta: i32) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    let d = a.word_at(0, if wide { Width::W32 } else { Width::W16 }, true)?;
    Some(Box::new(Step { wide, delta, d }))
}

impl Instr for Step {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        if self.wide {
            let v = (num::read32(cx.mem, &self.d)? as i32).wrapping_add(self.delta);
            num::write32(cx.mem, &self.d, v as u32)
        } else {
            let v = num::read16(cx.mem, &self.d)?.wrapping_add(self.delta as i16);
            cx.mem.write16(&self.d, v as u16)
        }
    }
}
