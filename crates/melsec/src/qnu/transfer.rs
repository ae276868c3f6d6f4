//! The Universal models' data transfer instructions (SH-080809ENG §6.4):
//! DFMOV.

use crate::transfer::{count, WordBlock};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[Def::app("DFMOV", &TRANSFER, dfmov)];

static TRANSFER: Doc = Doc {
    family: "transfer (QnU)",
    cite: "SH-080809ENG §6.4 (FMOV, DFMOV)",
    notes: "Universal models only; D a word device (digit-specified D refused at load); n = 0 does nothing, n < 0 or a block past the device end is 4101",
};

/// DFMOV(P) `S D n`: transfers the 32-bit value of S (S+1, S; a constant, a
/// word pair or K1-K8 digits) to the n 32-bit points starting at D (D … D+2n−1),
/// as FMOV does with 16-bit data. S is read once before writing, so an S
/// inside the block still fills it with its old value.
#[derive(Debug)]
struct Dfmov {
    s: WordArg,
    d: WordBlock,
    n: WordArg,
}

fn dfmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.word_src(0, Num::I32);
    let d = a.block_dest(1).map(WordBlock::Words);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Dfmov {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Dfmov {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let v = cx.mem.read32(&self.s)?;
        let d = self.d.resolve(cx.mem, 2 * n)?;
        for k in 0..n as usize {
            d.set(cx.mem, 2 * k, v as u16);
            d.set(cx.mem, 2 * k + 1, (v >> 16) as u16);
        }
        Ok(())
    }
}
