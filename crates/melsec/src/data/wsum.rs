//! Sums of tables of signed values (PM §7.5.13): WSUM, DWSUM.

use super::{elem, fixed_block, read_i16, width};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// PM §7.5.13 WSUM(P) `S D n`: the sum of the n signed 16-bit values from S as
/// a 32-bit value in D, D+1. DWSUM(P): the sum of n signed 32-bit values as a
/// 64-bit value in D to D+3. Neither can overflow (n ≤ 32767). n ≤ 0: no
/// processing (decision: as SER and MAX). S or D past the end of its device:
/// 4101.
#[derive(Debug)]
struct Wsum {
    s: Block,
    d: Block,
    n: WordArg,
    wide: bool,
}

pub(super) fn wsum(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = fixed_block(a, 1, 2 * width(wide));
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Wsum {
        s: s?,
        d: d?,
        n: n?,
        wide,
    }))
}

impl Instr for Wsum {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n <= 0 {
            return Ok(());
        }
        let w = width(self.wide);
        let s = mem.block_start(&self.s, n as u32 * w)?;
        let d = mem.block_start(&self.d, 2 * w)?;
        let total: i64 = (0..n as usize)
            .map(|k| elem(mem, s, k, self.wide) as i64)
            .sum();
        for k in 0..2 * w as usize {
            mem.words[d + k] = (total >> (16 * k)) as u16;
        }
        Ok(())
    }
}
