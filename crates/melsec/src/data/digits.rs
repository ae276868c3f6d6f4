//! Dissociating and linking digits, bit fields and bytes (PM §7.5.6-9): DIS, UNI,
//! NDIS, NUNI, WTOB, BTOW.

use super::read_i16;
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// PM §7.5.6 DIS(P) `S D n`: dissociates the low n digits (4 bits each, n =
/// 1-4) of S into the low 4 bits of n words from D; the high 12 bits of those
/// words become 0. n = 0: no processing; n < 0 or n > 4: 4100; n words past
/// the end of D's device: 4101.
#[derive(Debug)]
struct Dis {
    s: WordArg,
    d: Block,
    n: WordArg,
}

pub(super) fn dis(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = a.block_dest(1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Dis {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Dis {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n == 0 {
            return Ok(());
        }
        if !(1..=4).contains(&n) {
            return Err(Fault::Operation);
        }
        let v = mem.read16(&self.s)?;
        let d = mem.block_start(&self.d, n as u32)?;
        for k in 0..n as usize {
            mem.words[d + k] = (v >> (4 * k)) & 0xF;
        }
        Ok(())
    }
}

/// PM §7.5.7 UNI(P) `S D n`: links the low 4 bits of n words from S (n = 1-4)
/// into D, digit k from S+k; the digits of D above n become 0. n = 0: no
/// processing; n < 0 or n > 4: 4100; n words past the end of S's device: 4101.
#[derive(Debug)]
struct Uni {
    s: Block,
    d: WordArg,
    n: WordArg,
}

pub(super) fn uni(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.word_dest(1, Num::I16, 1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Uni {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Uni {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n == 0 {
            return Ok(());
        }
        if !(1..=4).contains(&n) {
            return Err(Fault::Operation);
        }
        let s = mem.block_start(&self.s, n as u32)?;
        let mut v = 0u16;
        for k in 0..n as usize {
            v |= (mem.words[s + k] & 0xF) << (4 * k);
        }
        mem.write16(&self.d, v)
    }
}

// ------------------------------------------------------------ NDIS / NUNI

/// PM §7.5.8 NDIS(P) `S1 D S2` / NUNI(P) `S1 D S2`: dissociation/linking of
/// bit fields of any width. S2, S2+1 … hold the field widths (1-16 bits), the
/// list ending at the first 0.
///
/// NDIS: the bit stream from S1 (bit 0 of S1 first, across words) is cut into
/// fields of those widths; field k goes to the low bits of D+k, its high bits 0.
/// NUNI: the low bits of S1+k (field k) are packed into a bit stream from D;
/// the unused high bits of the last word of D become 0.
///
/// A width outside 0-16 (negative or > 16): 4100. No terminating 0 before the
/// end of S2's device, or S1/D running past their device: 4101. An empty list
/// (S2 = 0): no processing.
#[derive(Debug)]
struct Ndis {
    s1: Block,
    d: Block,
    s2: Block,
    link: bool,
}

pub(super) fn ndis(a: &mut Args<'_, '_>, link: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = a.block(0);
    let d = a.block_dest(1);
    let s2 = a.block(2);
    Some(Box::new(Ndis {
        s1: s1?,
        d: d?,
        s2: s2?,
        link,
    }))
}

impl Instr for Ndis {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        // Field list: count the fields and their total width.
        let mut fields = 0u32;
        let mut total = 0u32;
        let w = loop {
            let base = mem.block_start(&self.s2, fields + 1)?;
            match mem.words[base + fields as usize] as i16 {
                0 => break base,
                v if !(1..=16).contains(&v) => return Err(Fault::Operation),
                v => {
                    total += v as u32;
                    fields += 1;
                }
            }
        };
        if fields == 0 {
            return Ok(());
        }
        let packed_words = total.div_ceil(16);
        let (fields_blk, packed_blk) = if self.link {
            (&self.s1, &self.d)
        } else {
            (&self.d, &self.s1)
        };
        let f = mem.block_start(fields_blk, fields)?;
        let p = mem.block_start(packed_blk, packed_words)?;
        let mut pos = 0usize;
        if self.link {
            // Clear the packed destination, then OR the fields in.
            for k in 0..packed_words as usize {
                mem.words[p + k] = 0;
            }
            for k in 0..fields as usize {
                let width = mem.words[w + k] as usize;
                let v = mem.words[f + k];
                for b in 0..width {
                    if v >> b & 1 != 0 {
                        mem.words[p + (pos + b) / 16] |= 1 << ((pos + b) % 16);
                    }
                }
                pos += width;
            }
        } else {
            for k in 0..fields as usize {
                let width = mem.words[w + k] as usize;
                let mut v = 0u16;
                for b in 0..width {
                    if mem.words[p + (pos + b) / 16] >> ((pos + b) % 16) & 1 != 0 {
                        v |= 1 << b;
                    }
                }
                mem.words[f + k] = v;
                pos += width;
            }
        }
        Ok(())
    }
}

// ------------------------------------------------------------ WTOB / BTOW

/// PM §7.5.9 WTOB(P) `S D n`: the n bytes of the words from S (low byte first)
/// go to the low bytes of n words from D, whose high bytes become 0.
/// BTOW(P) `S D n`: the low bytes of n words from S are packed two per word
/// into D (low byte first); for odd n the high byte of the last word is 0.
/// n = 0: no processing. n < 0: 4100 (a byte count cannot be negative).
/// Either block past the end of its device: 4101.
#[derive(Debug)]
struct Wtob {
    s: Block,
    d: Block,
    n: WordArg,
    to_words: bool,
}

pub(super) fn wtob(a: &mut Args<'_, '_>, to_words: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.block_dest(1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Wtob {
        s: s?,
        d: d?,
        n: n?,
        to_words,
    }))
}

impl Instr for Wtob {
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
        let packed = n.div_ceil(2);
        let (sn, dn) = if self.to_words {
            (n, packed)
        } else {
            (packed, n)
        };
        let s = mem.block_start(&self.s, sn)?;
        let d = mem.block_start(&self.d, dn)?;
        let n = n as usize;
        // Overlapping blocks: BTOW packs (destination k from source 2k, 2k+1)
        // and runs forward when D ≤ S; WTOB spreads (destination k from source
        // k/2) and runs backward when D ≥ S, so in-place conversions work.
        let forward = if self.to_words { d <= s } else { d < s };
        let count = if self.to_words { n.div_ceil(2) } else { n };
        for i in 0..count {
            let k = if forward { i } else { count - 1 - i };
            let v = if self.to_words {
                let lo = mem.words[s + 2 * k] & 0xFF;
                let hi = if 2 * k + 1 < n {
                    mem.words[s + 2 * k + 1] & 0xFF
                } else {
                    0
                };
                lo | hi << 8
            } else {
                (mem.words[s + k / 2] >> (8 * (k % 2))) & 0xFF
            };
            mem.words[d + k] = v;
        }
        Ok(())
    }
}
