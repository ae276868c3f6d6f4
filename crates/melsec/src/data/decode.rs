//! Decoding, encoding and 7-segment decoding (PM §7.5.3-5): DECO, ENCO, SEG.

use super::{read_i16, Bits, BitsAt};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::device::Operand;
use softplc_ir::fault::Fault;
use softplc_ir::ops::BitBlock;
use softplc_ir::ops::{Num, WordArg};

/// PM §7.5.3 DECO(P) `S D n`: decodes the low n bits of S (n = 1-8) into 2ⁿ
/// bits from D: the bit numbered by that value turns ON, the others OFF. D is a
/// bit device (2ⁿ points) or a word device (bits from bit 0 of D). Decision for
/// a word device with n < 4 (fewer than 16 bits): the whole word is the
/// destination and its other bits are cleared, as FX DECO documents; the Q
/// manual does not say. n = 0: no processing. n < 0 or n > 8: 4100. The 2ⁿ
/// bits past the end of D's device: 4101.
#[derive(Debug)]
struct Deco {
    s: WordArg,
    d: Bits,
    n: WordArg,
}

pub(super) fn deco(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = Bits::compile(a, 1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Deco {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Deco {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n == 0 {
            return Ok(());
        }
        if !(1..=8).contains(&n) {
            return Err(Fault::Operation);
        }
        let v = (mem.read16(&self.s)? as usize) & ((1 << n) - 1);
        let bits = 1usize << n;
        let at = self.d.resolve(mem, bits as u32)?;
        // A word destination is written in whole words (16 bits at least).
        let len = match at {
            BitsAt::Bit(_) => bits,
            BitsAt::Word(_) => bits.max(16),
        };
        for k in 0..len {
            at.set(mem, k, k == v);
        }
        Ok(())
    }
}

/// PM §7.5.4 ENCO(P) `S D n`: the position of the highest ON bit among the 2ⁿ
/// bits from S (n = 1-8) is stored in D. S is a bit device or a word device
/// (bit 0 of S first). n = 0: no processing. n < 0 or n > 8: 4100. No bit ON:
/// 4100. The 2ⁿ bits past the end of S's device: 4101.
#[derive(Debug)]
struct Enco {
    s: Bits,
    d: WordArg,
    n: WordArg,
}

pub(super) fn enco(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = Bits::compile(a, 0);
    let d = a.word_dest(1, Num::I16, 1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Enco {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Enco {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n == 0 {
            return Ok(());
        }
        if !(1..=8).contains(&n) {
            return Err(Fault::Operation);
        }
        let bits = 1usize << n;
        let at = self.s.resolve(mem, bits as u32)?;
        match (0..bits).rev().find(|&k| at.get(mem, k)) {
            Some(k) => mem.write16(&self.d, k as u16),
            None => Err(Fault::Operation),
        }
    }
}

// ------------------------------------------------------------ SEG

/// 7-segment patterns for 0-F (bit 0 = segment a … bit 6 = segment g), the
/// table of PM §7.5.5.
const SEVEN_SEG: [u8; 16] = [
    0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x27, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71,
];

/// PM §7.5.5 SEG(P) `S D`: decodes the low 4 bits of S (0-F) into 7-segment
/// data. D is a bit device (8 points from D, bit 7 = 0), a word device (low 8
/// bits of D) or a digit-specified device (its low 8 bits). Decision: the high
/// 8 bits of a word destination are not changed (the manual describes only the
/// low 8 bits; FX SEGD documents them as unchanged). Errors: 8 points past the
/// end of a bit device, index modification out of range: 4101.
#[derive(Debug)]
struct Seg {
    s: WordArg,
    d: SegDest,
}

#[derive(Debug)]
enum SegDest {
    Bits(BitBlock),
    Word(WordArg),
}

pub(super) fn seg(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = match a.operand(1)? {
        Operand::Device {
            dev,
            digits: None,
            bit: None,
            ..
        } if dev.kind.is_bit() && !dev.generic => a.bit_block(1).map(SegDest::Bits),
        _ => a.word_dest(1, Num::I16, 1).map(SegDest::Word),
    };
    Some(Box::new(Seg { s: s?, d: d? }))
}

impl Instr for Seg {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let pattern = SEVEN_SEG[(mem.read16(&self.s)? & 0xF) as usize];
        match &self.d {
            SegDest::Bits(b) => {
                let i = mem.bit_block_start(b, 8)?;
                mem.unpack_bits(i, 8, pattern as u32);
                Ok(())
            }
            SegDest::Word(w) => {
                let old = mem.read16(w)?;
                mem.write16(w, (old & 0xFF00) | pattern as u16)
            }
        }
    }
}
