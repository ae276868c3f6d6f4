//! Block transfer and exchange: BMOV, FMOV, DFMOV, SWAP, XCH, DXCH
//! (002 §6.2 L3889-4078; spec aplc.md §4.5). Blocks are word devices (D, SD,
//! C0-C199, T, V); a block past the device's last point is run error 65, a
//! negative count 64.

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{Block, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::num::{self, E_VALUE};
use crate::resolve::{self, ArgsExt};

static DOC: Doc = Doc {
    family: "block transfer",
    cite: "002 §6.2 L3889-4078",
    notes: "BMOV (overlap as memmove), FMOV, DFMOV (high word first), SWAP, XCH, DXCH; blocks on D, SD, C0-C199, T, V (K<n> blocks not implemented yet); count < 0 is error 64, past the device 65",
};

pub static DEFS: &[Def] = &[
    // 002 §6.2.4 L3889 BMOV
    Def::app("BMOV", &DOC, bmov)
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.2.5 L3917 FMOV
    Def::app("FMOV", &DOC, fmov)
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.2.6 L3951 DFMOV
    Def::app("DFMOV", &DOC, dfmov)
        .no_pulse()
        .steps(Steps::Fixed(9)),
    // 002 §6.2.7 L3985 SWAP
    Def::app("SWAP", &DOC, swap)
        .no_pulse()
        .steps(Steps::Fixed(3)),
    // 002 §6.2.8 L4012 XCH
    Def::app("XCH", &DOC, |a| xch(a, false))
        .no_pulse()
        .steps(Steps::Fixed(5)),
    // 002 §6.2.9 L4048 DXCH
    Def::app("DXCH", &DOC, |a| xch(a, true))
        .no_pulse()
        .steps(Steps::Fixed(7)),
];

fn block_at(a: &mut Args<'_, '_>, k: usize, dest: bool) -> Option<Block> {
    let r = resolve::block(a.map(), a.text(k), dest);
    a.check(k, r)
}

/// The count operand: negative is an illegal value (64).
fn count(cx: &ExecCtx<'_>, n: &WordArg) -> Result<u32, Fault> {
    let n = num::read16(cx.mem, n)?;
    if n < 0 {
        return Err(E_VALUE);
    }
    Ok(n as u32)
}

#[derive(Debug)]
struct Bmov {
    s: Block,
    d: Block,
    n: WordArg,
}

fn bmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = block_at(a, 0, false);
    let d = block_at(a, 1, true);
    let n = a.word_at(2, Width::W16, false)?;
    Some(Box::new(Bmov { s: s?, d: d?, n }))
}

impl Instr for Bmov {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = count(cx, &self.n)?;
        let s = cx.mem.block_start(&self.s, n)?;
        let d = cx.mem.block_start(&self.d, n)?;
        cx.mem.words.copy_within(s..s + n as usize, d);
        Ok(())
    }
}

#[derive(Debug)]
struct Fmov {
    s: WordArg,
    d: Block,
    n: WordArg,
    wide: bool,
}

fn fill(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.word_at(0, if wide { Width::W32 } else { Width::W16 }, false);
    let d = if wide {
        let r = resolve::block32(a.map(), a.text(1));
        a.check(1, r)
    } else {
        block_at(a, 1, true)
    };
    let n = a.word_at(2, Width::W16, false)?;
    Some(Box::new(Fmov {
        s: s?,
        d: d?,
        n,
        wide,
    }))
}

fn fmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    fill(a, false)
}

fn dfmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    fill(a, true)
}

impl Instr for Fmov {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = count(cx, &self.n)?;
        if self.wide {
            let v = num::read32(cx.mem, &self.s)?;
            let d = cx.mem.block_start(&self.d, 2 * n)?;
            for k in 0..n as usize {
                cx.mem.words[d + 2 * k] = (v >> 16) as u16;
                cx.mem.words[d + 2 * k + 1] = v as u16;
            }
        } else {
            let v = cx.mem.read16(&self.s)?;
            let d = cx.mem.block_start(&self.d, n)?;
            cx.mem.words[d..d + n as usize].fill(v);
        }
        Ok(())
    }
}

#[derive(Debug)]
struct Swap(WordArg);

fn swap(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    Some(Box::new(Swap(a.word_at(0, Width::W16, true)?)))
}

impl Instr for Swap {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = cx.mem.read16(&self.0)?;
        cx.mem.write16(&self.0, v.swap_bytes())
    }
}

#[derive(Debug)]
struct Xch {
    a: WordArg,
    b: WordArg,
    wide: bool,
}

/// XCH, or DXCH (`wide`).
fn xch(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let w = if wide { Width::W32 } else { Width::W16 };
    let x = a.word_at(0, w, true);
    let y = a.word_at(1, w, true)?;
    let x = x?;
    if let (WordArg::Digits { n: p, .. }, WordArg::Digits { n: q, .. }) = (&x, &y) {
        if p != q {
            a.error(
                1,
                format!(
                    "`{}`: both bit groups need the same K<n> (APLC programming manual §6.2.8)",
                    a.text(1)
                ),
            );
            return None;
        }
    }
    Some(Box::new(Xch { a: x, b: y, wide }))
}

impl Instr for Xch {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        if self.wide {
            let (p, q) = (num::read32(cx.mem, &self.a)?, num::read32(cx.mem, &self.b)?);
            num::write32(cx.mem, &self.a, q)?;
            num::write32(cx.mem, &self.b, p)
        } else {
            let (p, q) = (cx.mem.read16(&self.a)?, cx.mem.read16(&self.b)?);
            cx.mem.write16(&self.a, q)?;
            cx.mem.write16(&self.b, p)
        }
    }
}
