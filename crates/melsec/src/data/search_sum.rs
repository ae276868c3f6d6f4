//! Searching and bit counting (PM §7.5.1-2): SER, DSER, SUM, DSUM.

use super::{elem, fixed_block, get_flag, num, read_i16, width};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// PM §7.5.1 SER(P)/DSER(P) `S1 S2 D n`: searches the n 16-bit (DSER: 32-bit)
/// values from S2 for S1; D = position of the first match counted from 1 at S2,
/// D+1 = number of matches; both 0 when nothing matches. n ≤ 0: no processing
/// (manual). With SM702 ON the search is binary (data sorted ascending, as the
/// manual requires); on sorted data it gives the same result as the sequential
/// search, on unsorted data the result is that of the binary search, as on the
/// CPU ("correct results are not obtained"). Errors: the n values past the end
/// of S2's device, or D+1 past its device: 4101.
#[derive(Debug)]
struct Ser {
    key: WordArg,
    s2: Block,
    d: Block,
    n: WordArg,
    wide: bool,
    sm702: Option<u32>,
}

pub(super) fn ser(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let key = a.word_src(0, num(wide));
    let s2 = a.block(1);
    let d = fixed_block(a, 2, 2);
    let n = a.word_src(3, Num::I16);
    Some(Box::new(Ser {
        key: key?,
        s2: s2?,
        d: d?,
        n: n?,
        wide,
        sm702: a.flag(softplc_lang::dialect::Flag::BinarySearch),
    }))
}

impl Instr for Ser {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let key = if self.wide {
            mem.read32(&self.key)? as i32
        } else {
            mem.read16(&self.key)? as i16 as i32
        };
        let n = read_i16(mem, &self.n)?;
        if n <= 0 {
            return Ok(());
        }
        let n = n as usize;
        let s = mem.block_start(&self.s2, n as u32 * width(self.wide))?;
        let d = mem.block_start(&self.d, 2)?;
        let (mut first, mut count) = (0usize, 0usize);
        if get_flag(mem, self.sm702) {
            // Binary search for the first element not below the key, then the
            // run of equal elements from there.
            let (mut lo, mut hi) = (0, n);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if elem(mem, s, mid, self.wide) < key {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            while lo + count < n && elem(mem, s, lo + count, self.wide) == key {
                count += 1;
            }
            if count > 0 {
                first = lo + 1;
            }
        } else {
            for k in 0..n {
                if elem(mem, s, k, self.wide) == key {
                    if count == 0 {
                        first = k + 1;
                    }
                    count += 1;
                }
            }
        }
        mem.words[d] = first as u16;
        mem.words[d + 1] = count as u16;
        Ok(())
    }
}

// ------------------------------------------------------------ SUM / DSUM

/// PM §7.5.2 SUM(P)/DSUM(P) `S D`: the number of bits that are 1 in the 16-bit
/// (DSUM: 32-bit) value S, stored as BIN 16 in D. No operation errors besides
/// index modification out of range (4101).
#[derive(Debug)]
struct Sum {
    s: WordArg,
    d: WordArg,
    wide: bool,
}

pub(super) fn sum(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, num(wide));
    let d = a.word_dest(1, Num::I16, 1);
    Some(Box::new(Sum { s: s?, d: d?, wide }))
}

impl Instr for Sum {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let ones = if self.wide {
            cx.mem.read32(&self.s)?.count_ones()
        } else {
            cx.mem.read16(&self.s)?.count_ones()
        };
        cx.mem.write16(&self.d, ones as u16)
    }
}
