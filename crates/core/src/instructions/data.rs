//! Programming manual (common instructions) §7.5 data processing: SER, DSER,
//! SUM, DSUM, DECO, ENCO, SEG, DIS, UNI, NDIS, NUNI, WTOB, BTOW, MAX, MIN,
//! DMAX, DMIN, SORT, DSORT, WSUM, DWSUM.
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! Not implemented: MEAN/DMEAN (§7.5.14) are Universal model (QnU/LCPU)
//! instructions, not in the QnH set; they stay "unsupported" at load.
//!
//! Word blocks (search ranges, tables, destinations of several words) must be
//! word devices (`D100`, `R0Z1`, `W10`); digit-specified bit devices (`K4M0`)
//! are rejected at load for block operands. Every block is range-checked when
//! the instruction runs: a block past the last point of its device, or an
//! index-modified start out of range, is OPERATION ERROR 4101 and nothing is
//! written.
//!
//! This module also holds the block helpers the table and comparison modules
//! share (`fixed_block`, `Bits`, `sm_index`, `elem`).

use super::{Args, ExecCtx, Instr};
use crate::device::{DeviceKind, DeviceMemory, Operand};
use crate::engine::{ErrorCode, Fault};
use crate::program::compile::{BitBlock, Block};
use crate::program::isa::{Def, Doc};
use crate::program::ops::{BitArg, Num, WordArg};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("SER", &DATA_PROCESSING, |a| ser(a, false)),
    Def::app("DSER", &DATA_PROCESSING, |a| ser(a, true)),
    Def::app("SUM", &DATA_PROCESSING, |a| sum(a, false)),
    Def::app("DSUM", &DATA_PROCESSING, |a| sum(a, true)),
    Def::app("DECO", &DATA_PROCESSING, deco),
    Def::app("ENCO", &DATA_PROCESSING, enco),
    Def::app("SEG", &DATA_PROCESSING, seg),
    Def::app("DIS", &DATA_PROCESSING, dis),
    Def::app("UNI", &DATA_PROCESSING, uni),
    Def::app("NDIS", &DATA_PROCESSING, |a| ndis(a, false)),
    Def::app("NUNI", &DATA_PROCESSING, |a| ndis(a, true)),
    Def::app("WTOB", &DATA_PROCESSING, |a| wtob(a, false)),
    Def::app("BTOW", &DATA_PROCESSING, |a| wtob(a, true)),
    Def::app("MAX", &MAX_MIN_WSUM, |a| maxmin(a, false, true)),
    Def::app("MIN", &MAX_MIN_WSUM, |a| maxmin(a, false, false)),
    Def::app("DMAX", &MAX_MIN_WSUM, |a| maxmin(a, true, true)),
    Def::app("DMIN", &MAX_MIN_WSUM, |a| maxmin(a, true, false)),
    Def::app("SORT", &SORT, |a| sort(a, false)).no_pulse(),
    Def::app("DSORT", &SORT, |a| sort(a, true)).no_pulse(),
    Def::app("WSUM", &MAX_MIN_WSUM, |a| wsum(a, false)),
    Def::app("DWSUM", &MAX_MIN_WSUM, |a| wsum(a, true)),
];

static DATA_PROCESSING: Doc = Doc {
    family: "data processing",
    cite: "PM §7.5",
    notes: "see golden_data.rs",
};
static MAX_MIN_WSUM: Doc = Doc {
    family: "data processing",
    cite: "PM §7.5",
    notes: "n ≤ 0 does nothing",
};
static SORT: Doc = Doc {
    family: "data processing",
    cite: "PM §7.5.12",
    notes: "S2 comparisons per scan, D1 completion, SM703 order; no pulse form",
};

// ------------------------------------------------------------ shared helpers

/// Operand `k` as a word block of a fixed `n` words. Without index
/// modification the whole block is checked at load; with it, at run time.
pub(super) fn fixed_block(a: &mut Args<'_, '_>, k: usize, n: u32) -> Option<Block> {
    let b = a.block(k)?;
    if let WordArg::Word(i) = b.start {
        if i as u64 + n as u64 > b.limit as u64 {
            let msg = format!(
                "`{}`: this operand uses {n} words, beyond the last device",
                a.text(k)
            );
            a.error(k, msg);
            return None;
        }
    }
    Some(b)
}

/// Flat bit index of special relay SM`n`, if the configuration has it.
pub(super) fn sm_index(a: &Args<'_, '_>, n: u32) -> Option<u32> {
    a.map().index(DeviceKind::SM, n)
}

#[inline]
pub(super) fn get_flag(mem: &DeviceMemory, f: Option<u32>) -> bool {
    f.is_some_and(|i| mem.bits[i as usize])
}

#[inline]
pub(super) fn set_flag(mem: &mut DeviceMemory, f: Option<u32>, v: bool) {
    if let Some(i) = f {
        mem.bits[i as usize] = v;
    }
}

/// A 16-bit count operand read as signed BIN.
#[inline]
pub(super) fn read_i16(mem: &DeviceMemory, a: &WordArg) -> Result<i32, Fault> {
    Ok(mem.read16(a)? as i16 as i32)
}

/// Element `k` of a block of 16-bit (`wide` = false) or 32-bit values, signed.
#[inline]
pub(super) fn elem(mem: &DeviceMemory, base: usize, k: usize, wide: bool) -> i32 {
    if wide {
        let i = base + 2 * k;
        (mem.words[i] as u32 | (mem.words[i + 1] as u32) << 16) as i32
    } else {
        mem.words[base + k] as i16 as i32
    }
}

#[inline]
pub(super) fn set_elem(mem: &mut DeviceMemory, base: usize, k: usize, wide: bool, v: i32) {
    if wide {
        let i = base + 2 * k;
        mem.words[i] = v as u16;
        mem.words[i + 1] = (v as u32 >> 16) as u16;
    } else {
        mem.words[base + k] = v as u16;
    }
}

/// A bit field of run-time length: consecutive bit devices (`M0`, `Y10Z1`) or
/// the bits of consecutive word devices, bit 0 of the first word first (`D0`).
#[derive(Clone, Debug)]
pub(super) enum Bits {
    Bit(BitBlock),
    Word(Block),
}

/// A resolved [`Bits`]: the flat index of the first bit or word.
#[derive(Clone, Copy, Debug)]
pub(super) enum BitsAt {
    Bit(usize),
    Word(usize),
}

impl Bits {
    /// Operand `k`: a bit device (not digit-specified) or a word device.
    pub(super) fn compile(a: &mut Args<'_, '_>, k: usize) -> Option<Bits> {
        match a.operand(k)? {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                ..
            } if dev.kind.is_bit() && !dev.generic => a.bit_block(k).map(Bits::Bit),
            _ => a.block(k).map(Bits::Word),
        }
    }

    /// The first of `n` bits; 4101 past the end of the device.
    #[inline]
    pub(super) fn resolve(&self, mem: &DeviceMemory, n: u32) -> Result<BitsAt, Fault> {
        Ok(match self {
            Bits::Bit(b) => BitsAt::Bit(mem.bit_block_start(b, n)?),
            Bits::Word(b) => BitsAt::Word(mem.block_start(b, n.div_ceil(16))?),
        })
    }
}

impl BitsAt {
    #[inline]
    pub(super) fn get(self, mem: &DeviceMemory, k: usize) -> bool {
        match self {
            BitsAt::Bit(i) => mem.bits[i + k],
            BitsAt::Word(i) => mem.words[i + k / 16] >> (k % 16) & 1 != 0,
        }
    }

    #[inline]
    pub(super) fn set(self, mem: &mut DeviceMemory, k: usize, v: bool) {
        match self {
            BitsAt::Bit(i) => mem.bits[i + k] = v,
            BitsAt::Word(i) => {
                let w = &mut mem.words[i + k / 16];
                if v {
                    *w |= 1 << (k % 16);
                } else {
                    *w &= !(1 << (k % 16));
                }
            }
        }
    }
}

fn num(wide: bool) -> Num {
    if wide {
        Num::I32
    } else {
        Num::I16
    }
}

fn width(wide: bool) -> u32 {
    if wide {
        2
    } else {
        1
    }
}

// ------------------------------------------------------------ SER / DSER

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

fn ser(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
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
        sm702: sm_index(a, 702),
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

fn sum(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
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

// ------------------------------------------------------------ DECO / ENCO

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

fn deco(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
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
            return Err(ErrorCode::OPERATION);
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

fn enco(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
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
            return Err(ErrorCode::OPERATION);
        }
        let bits = 1usize << n;
        let at = self.s.resolve(mem, bits as u32)?;
        match (0..bits).rev().find(|&k| at.get(mem, k)) {
            Some(k) => mem.write16(&self.d, k as u16),
            None => Err(ErrorCode::OPERATION),
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

fn seg(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
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

// ------------------------------------------------------------ DIS / UNI

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

fn dis(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = a.block(1);
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
            return Err(ErrorCode::OPERATION);
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

fn uni(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
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
            return Err(ErrorCode::OPERATION);
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

fn ndis(a: &mut Args<'_, '_>, link: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = a.block(0);
    let d = a.block(1);
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
                v if !(1..=16).contains(&v) => return Err(ErrorCode::OPERATION),
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

fn wtob(a: &mut Args<'_, '_>, to_words: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.block(1);
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
            return Err(ErrorCode::OPERATION);
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

// ------------------------------------------------------------ MAX / MIN

/// PM §7.5.10-11 MAX(P)/MIN(P)/DMAX(P)/DMIN(P) `S D n`: the largest (smallest)
/// of the n signed 16-bit (32-bit) values from S goes to D (D, D+1); the
/// position of its first occurrence counted from 1 at S goes to the next word,
/// the number of occurrences to the one after. n ≤ 0: no processing (decision:
/// as the SER page states for the same kind of count). S or D past the end of
/// its device: 4101.
#[derive(Debug)]
struct MaxMin {
    s: Block,
    d: Block,
    n: WordArg,
    wide: bool,
    max: bool,
}

fn maxmin(a: &mut Args<'_, '_>, wide: bool, max: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = fixed_block(a, 1, width(wide) + 2);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(MaxMin {
        s: s?,
        d: d?,
        n: n?,
        wide,
        max,
    }))
}

impl Instr for MaxMin {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n <= 0 {
            return Ok(());
        }
        let n = n as usize;
        let w = width(self.wide);
        let s = mem.block_start(&self.s, n as u32 * w)?;
        let d = mem.block_start(&self.d, w + 2)?;
        let mut best = elem(mem, s, 0, self.wide);
        let (mut pos, mut count) = (1usize, 1usize);
        for k in 1..n {
            let v = elem(mem, s, k, self.wide);
            if v == best {
                count += 1;
            } else if (v > best) == self.max {
                best = v;
                pos = k + 1;
                count = 1;
            }
        }
        set_elem(mem, d, 0, self.wide, best);
        let at = d + w as usize;
        mem.words[at] = pos as u16;
        mem.words[at + 1] = count as u16;
        Ok(())
    }
}

// ------------------------------------------------------------ SORT / DSORT

/// PM §7.5.12 SORT/DSORT `S1 n S2 D1 D2`: sorts the n signed 16-bit (32-bit)
/// values from S1 in place, ascending with SM703 OFF, descending with SM703 ON,
/// over several executions: each execution makes S2 comparisons of the
/// n(n−1)/2 the sort needs (exchange sort: element i against each later j), so
/// it completes after ⌈n(n−1)/2 ÷ S2⌉ executions. The first execution of a
/// sort turns D1 OFF; the execution that finishes it turns D1 ON, and D1 stays
/// ON (the user resets it). The execution after completion starts a new sort.
///
/// The progress (i, j, n of the running sort) is kept in hidden state words; D2
/// and D2+1, which the manual reserves for the system, are range-checked but
/// not written. An interrupted sort (condition OFF) resumes where it stopped
/// when the condition is ON again, since the CPU keeps its progress in D2.
/// SM703 is read at every execution.
///
/// The manual gives SORT/DSORT no pulse form: SORTP/DSORTP are rejected at
/// load. Errors: n < 0 or S2 ≤ 0: 4100 (decision: the manual gives no range
/// but a sort cannot progress with them); n = 0 or 1: the sort is complete at
/// once (D1 ON). S1 past the end of its device: 4101.
#[derive(Debug)]
struct Sort {
    s1: Block,
    n: WordArg,
    per_exec: WordArg,
    done: BitArg,
    work: Block,
    state: usize,
    wide: bool,
    sm703: Option<u32>,
}

fn sort(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[5]) {
        return None;
    }
    let s1 = a.block(0);
    let n = a.word_src(1, Num::I16);
    let per_exec = a.word_src(2, Num::I16);
    let done = a.bit_dest(3);
    let work = fixed_block(a, 4, 2);
    let state = a.state_words(4) as usize;
    Some(Box::new(Sort {
        s1: s1?,
        n: n?,
        per_exec: per_exec?,
        done: done?,
        work: work?,
        state,
        wide,
        sm703: sm_index(a, 703),
    }))
}

/// State words of a SORT: running flag, i, j, n.
const SORT_RUNNING: usize = 0;
const SORT_I: usize = 1;
const SORT_J: usize = 2;
const SORT_N: usize = 3;

impl Instr for Sort {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let st = &mut cx.state[self.state..self.state + 4];
        let per = read_i16(mem, &self.per_exec)?;
        if per <= 0 {
            return Err(ErrorCode::OPERATION);
        }
        mem.block_start(&self.work, 2)?;
        let starting = st[SORT_RUNNING] == 0;
        let n = if starting {
            let n = read_i16(mem, &self.n)?;
            if n < 0 {
                return Err(ErrorCode::OPERATION);
            }
            n as u32
        } else {
            st[SORT_N]
        };
        let s = mem.block_start(&self.s1, n * width(self.wide))?;
        // Also checks an index-modified D1 before anything is written.
        mem.read_bit(&self.done)?;
        let (mut i, mut j) = if starting {
            mem.write_bit(&self.done, false)?;
            (0, 1)
        } else {
            (st[SORT_I], st[SORT_J])
        };
        let descending = get_flag(mem, self.sm703);
        let mut left = per as u32;
        let finished = loop {
            if i + 1 >= n {
                break true;
            }
            if left == 0 {
                break false;
            }
            let (a, b) = (
                elem(mem, s, i as usize, self.wide),
                elem(mem, s, j as usize, self.wide),
            );
            if (a > b && !descending) || (a < b && descending) {
                set_elem(mem, s, i as usize, self.wide, b);
                set_elem(mem, s, j as usize, self.wide, a);
            }
            left -= 1;
            j += 1;
            if j >= n {
                i += 1;
                j = i + 1;
            }
        };
        if finished {
            st[SORT_RUNNING] = 0;
            mem.write_bit(&self.done, true)?;
        } else {
            st[SORT_RUNNING] = 1;
            st[SORT_I] = i;
            st[SORT_J] = j;
            st[SORT_N] = n;
        }
        Ok(())
    }
}

// ------------------------------------------------------------ WSUM / DWSUM

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

fn wsum(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
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
