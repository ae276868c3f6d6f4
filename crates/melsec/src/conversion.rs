//! Programming manual (common instructions): data conversion instructions (PM
//! §6.3: BCD, BIN, DBL, WORD, GRY, GBIN, NEG, ENEG, BKBCD, BKBIN) and the
//! angle conversions of the special function instructions (PM §7.12: RAD, DEG).
//! FLT/INT are basic instructions compiled by `program::compile`.
//!
//! Section numbers are those of the QCPU (Q mode)/QnACPU Programming Manual
//! (Common Instructions), SH-080039. Every error is OPERATION ERROR 4100 (bad
//! data) or 4101 (a block running past the end of its device); the destination
//! is left unchanged when an instruction fails.

use super::{Args, ExecCtx, Instr};
use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("BCD", &BCD_CONVERSION, Bcd::compile),
    Def::app("DBCD", &BCD_CONVERSION, DBcd::compile),
    Def::app("BIN", &BCD_CONVERSION, Bin::compile),
    Def::app("DBIN", &BCD_CONVERSION, DBin::compile),
    Def::app("GRY", &CONVERSION, Gry::compile),
    Def::app("DGRY", &CONVERSION, DGry::compile),
    Def::app("GBIN", &CONVERSION, GBin::compile),
    Def::app("DGBIN", &CONVERSION, DGBin::compile),
    Def::app("DBL", &CONVERSION, Dbl::compile),
    Def::app("WORD", &CONVERSION, Word::compile),
    Def::app("RAD", &REAL_FUNCTIONS, Rad::compile),
    Def::app("DEG", &REAL_FUNCTIONS, Deg::compile),
    Def::app("NEG", &CONVERSION, Neg::compile),
    Def::app("DNEG", &CONVERSION, DNeg::compile),
    Def::app("ENEG", &CONVERSION, ENeg::compile),
    Def::app("BKBCD", &BLOCK_CONVERSION, BkBcd::compile),
    Def::app("BKBIN", &BLOCK_CONVERSION, BkBin::compile),
];

static BCD_CONVERSION: Doc = Doc {
    family: "BCD conversion",
    cite: "PM §6.3.1-2",
    notes: "out of range / invalid digit → 4100",
};
static CONVERSION: Doc = Doc {
    family: "conversion",
    cite: "PM §6.3.5-10",
    notes: "WORD out of range → 4100; negative Gray input → 4100",
};
static REAL_FUNCTIONS: Doc = Doc {
    family: "real functions",
    cite: "PM §7.12",
    notes: "f64 internally, stored as f32; domain errors → 4100",
};
static BLOCK_CONVERSION: Doc = Doc {
    family: "block conversion",
    cite: "PM §6.3.11-12",
    notes: "n=0 no-op; past end → 4101; invalid word → 4100, D unchanged",
};

// ------------------------------------------------------------------ BCD helpers

// The packing itself is the shared kernel.
pub(crate) use softplc_ir::kernels::bcd::{pack as to_bcd, unpack as from_bcd};

/// Reads a BCD operand of 4 (`wide` false) or 8 digits as binary; an A-F digit
/// is 4100. A digit-specified operand reads only its own digits.
pub(crate) fn read_bcd(mem: &DeviceMemory, a: &WordArg, wide: bool) -> Result<u64, Fault> {
    let raw = if wide {
        mem.read32(a)? as u64
    } else {
        mem.read16(a)? as u64
    };
    from_bcd(raw).ok_or(Fault::Operation)
}

/// Gray code → binary over `bits` bits (16 or 32).
fn gray_to_bin(g: u32, bits: u32) -> u32 {
    let mut b = g;
    let mut shift = 1;
    while shift < bits {
        b ^= b >> shift;
        shift <<= 1;
    }
    b
}

// ------------------------------------------------------------------ S → D forms

/// Checks `S D` and resolves them: S read as `sn`, D written as `dn`.
fn src_dst(a: &mut Args<'_, '_>, sn: Num, dn: Num) -> Option<(WordArg, WordArg)> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, sn);
    let d = a.word_dest(1, dn, dn.words());
    Some((s?, d?))
}

/// Defines an `S D` conversion: its struct (with the manual citation), its
/// compile function and its execution.
macro_rules! s_to_d {
    ($(#[doc = $doc:literal])+ $name:ident, $sn:expr => $dn:expr,
     |$mem:ident, $s:ident, $d:ident| $body:expr) => {
        $(#[doc = $doc])+
        #[derive(Debug)]
        struct $name {
            s: WordArg,
            d: WordArg,
        }

        impl $name {
            fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
                let (s, d) = src_dst(a, $sn, $dn)?;
                Some(Box::new($name { s, d }))
            }
        }

        impl Instr for $name {
            fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
                let $mem: &mut DeviceMemory = &mut *cx.mem;
                let ($s, $d) = (&self.s, &self.d);
                $body
            }
        }
    };
}

s_to_d!(
    /// PM §6.3.1 BCD: BIN 16 bits (0-9999) → BCD 4 digits. S outside 0-9999
    /// (negative included) is 4100. A digit-specified D (K1-K3) keeps the low
    /// digits, as any digit-specified destination.
    Bcd, Num::I16 => Num::I16,
    |mem, s, d| {
        let v = mem.read16(s)? as i16;
        if !(0..=9999).contains(&v) {
            return Err(Fault::Operation);
        }
        mem.write16(d, to_bcd(v as u64) as u16)
    }
);

s_to_d!(
    /// PM §6.3.1 DBCD: BIN 32 bits (0-99999999) → BCD 8 digits in D, D+1. S
    /// outside 0-99999999 is 4100.
    DBcd, Num::I32 => Num::I32,
    |mem, s, d| {
        let v = mem.read32(s)? as i32;
        if !(0..=99_999_999).contains(&v) {
            return Err(Fault::Operation);
        }
        mem.write32(d, to_bcd(v as u64) as u32)
    }
);

s_to_d!(
    /// PM §6.3.2 BIN: BCD 4 digits (0-9999) → BIN 16 bits. A digit of S that is
    /// not 0-9 (A-F) is 4100. A digit-specified S (K1-K3) reads only its digits.
    Bin, Num::I16 => Num::I16,
    |mem, s, d| {
        let v = read_bcd(mem, s, false)?;
        mem.write16(d, v as u16)
    }
);

s_to_d!(
    /// PM §6.3.2 DBIN: BCD 8 digits (0-99999999) in S, S+1 → BIN 32 bits. A
    /// digit that is not 0-9 is 4100.
    DBin, Num::I32 => Num::I32,
    |mem, s, d| {
        let v = read_bcd(mem, s, true)?;
        mem.write32(d, v as u32)
    }
);

s_to_d!(
    /// PM §6.3.7 GRY: BIN 16 bits → Gray code (`v ^ v >> 1`). A negative S is
    /// 4100.
    Gry, Num::I16 => Num::I16,
    |mem, s, d| {
        let v = mem.read16(s)?;
        if v & 0x8000 != 0 {
            return Err(Fault::Operation);
        }
        mem.write16(d, v ^ v >> 1)
    }
);

s_to_d!(
    /// PM §6.3.7 DGRY: BIN 32 bits → Gray code. A negative S is 4100.
    DGry, Num::I32 => Num::I32,
    |mem, s, d| {
        let v = mem.read32(s)?;
        if v & 0x8000_0000 != 0 {
            return Err(Fault::Operation);
        }
        mem.write32(d, v ^ v >> 1)
    }
);

s_to_d!(
    /// PM §6.3.8 GBIN: Gray code → BIN 16 bits. A negative S (b15 set; no Gray
    /// code of 0-32767 has it) is 4100, as for GRY.
    GBin, Num::I16 => Num::I16,
    |mem, s, d| {
        let g = mem.read16(s)?;
        if g & 0x8000 != 0 {
            return Err(Fault::Operation);
        }
        mem.write16(d, gray_to_bin(g as u32, 16) as u16)
    }
);

s_to_d!(
    /// PM §6.3.8 DGBIN: Gray code → BIN 32 bits. A negative S (b31 set) is 4100.
    DGBin, Num::I32 => Num::I32,
    |mem, s, d| {
        let g = mem.read32(s)?;
        if g & 0x8000_0000 != 0 {
            return Err(Fault::Operation);
        }
        mem.write32(d, gray_to_bin(g, 32))
    }
);

s_to_d!(
    /// PM §6.3.5 DBL: BIN 16 bits → BIN 32 bits with the sign extended into D+1.
    /// No operation error. A digit-specified S (K1-K3) is positive (zero-extended).
    Dbl, Num::I16 => Num::I32,
    |mem, s, d| {
        let v = mem.read16(s)? as i16 as i32;
        mem.write32(d, v as u32)
    }
);

s_to_d!(
    /// PM §6.3.6 WORD: BIN 32 bits → BIN 16 bits. S outside -32768 to 32767 is
    /// 4100.
    Word, Num::I32 => Num::I16,
    |mem, s, d| {
        let v = mem.read32(s)? as i32;
        let Ok(v) = i16::try_from(v) else {
            return Err(Fault::Operation);
        };
        mem.write16(d, v as u16)
    }
);

s_to_d!(
    /// PM §7.12 RAD: real angle in degrees → radians (S × π/180). A non-real S
    /// (±∞, NaN) or an overflowing result is 4100 (004 §2.8); an underflowing
    /// result is stored as 0. Decision: computed in double precision and rounded
    /// once to single (the manual gives no rounding rule).
    Rad, Num::F32 => Num::F32,
    |mem, s, d| {
        let v = mem.read_f32(s)? as f64;
        mem.write_f32(d, (v * std::f64::consts::PI / 180.0) as f32)
    }
);

s_to_d!(
    /// PM §7.12 DEG: real angle in radians → degrees (S × 180/π). Errors and
    /// rounding as RAD: a result beyond the single-precision range is 4100.
    Deg, Num::F32 => Num::F32,
    |mem, s, d| {
        let v = mem.read_f32(s)? as f64;
        mem.write_f32(d, (v * 180.0 / std::f64::consts::PI) as f32)
    }
);

// ------------------------------------------------------------------ in place (D)

/// Checks `D` (read and written in place, `num` wide).
fn in_place(a: &mut Args<'_, '_>, num: Num) -> Option<WordArg> {
    if !a.count(&[1]) {
        return None;
    }
    a.word_dest(0, num, num.words())
}

/// PM §6.3.9 NEG: two's complement of the BIN 16 bits at D, in place. No
/// operation error: -32768 stays -32768. A digit-specified D (K1-K3) is read
/// zero-extended and gets the low digits of the result.
#[derive(Debug)]
struct Neg {
    d: WordArg,
}

impl Neg {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Some(Box::new(Neg {
            d: in_place(a, Num::I16)?,
        }))
    }
}

impl Instr for Neg {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = cx.mem.read16(&self.d)?;
        cx.mem.write16(&self.d, v.wrapping_neg())
    }
}

/// PM §6.3.9 DNEG: two's complement of the BIN 32 bits at D, D+1, in place. No
/// operation error: -2147483648 stays as it is.
#[derive(Debug)]
struct DNeg {
    d: WordArg,
}

impl DNeg {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Some(Box::new(DNeg {
            d: in_place(a, Num::I32)?,
        }))
    }
}

impl Instr for DNeg {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = cx.mem.read32(&self.d)?;
        cx.mem.write32(&self.d, v.wrapping_neg())
    }
}

/// PM §6.3.10 ENEG: inverts the sign of the real number at D, D+1, in place. A
/// non-real D (±∞, NaN) is 4100 (004 §2.8), as for every real instruction.
/// Decision: 0 (and a denormal, read as 0) gives +0, never -0.
#[derive(Debug)]
struct ENeg {
    d: WordArg,
}

impl ENeg {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Some(Box::new(ENeg {
            d: in_place(a, Num::F32)?,
        }))
    }
}

impl Instr for ENeg {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = cx.mem.read_f32(&self.d)?;
        cx.mem.write_f32(&self.d, -v)
    }
}

// ------------------------------------------------------------------ blocks

/// `S D n` of the block conversions.
#[derive(Debug)]
struct BlockArgs {
    s: Block,
    d: Block,
    n: WordArg,
}

fn block_args(a: &mut Args<'_, '_>) -> Option<BlockArgs> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.block_dest(1);
    let n = a.word_src(2, Num::I16);
    Some(BlockArgs {
        s: s?,
        d: d?,
        n: n?,
    })
}

/// Runs a block conversion: checks the ranges (4101) and every source word
/// (`valid`, else 4100) before writing anything, then converts word by word as
/// if the whole source had been read first (overlapping S and D are safe).
fn convert_block(
    mem: &mut DeviceMemory,
    b: &BlockArgs,
    valid: fn(u16) -> bool,
    conv: fn(u16) -> u16,
) -> Result<(), Fault> {
    // n is read as an unsigned count (see BkBcd).
    let n = mem.read16(&b.n)? as u32;
    if n == 0 {
        return Ok(());
    }
    let s = mem.block_start(&b.s, n)?;
    let d = mem.block_start(&b.d, n)?;
    let n = n as usize;
    let w = &mut mem.words;
    if !w[s..s + n].iter().all(|&v| valid(v)) {
        return Err(Fault::Operation);
    }
    if d <= s {
        for i in 0..n {
            w[d + i] = conv(w[s + i]);
        }
    } else {
        for i in (0..n).rev() {
            w[d + i] = conv(w[s + i]);
        }
    }
    Ok(())
}

/// PM §6.3.11 BKBCD: converts n words of BIN (0-9999) from S to BCD 4 digits at
/// D onwards. A word outside 0-9999 is 4100; n words from S or D running past
/// the last device is 4101; n = 0 does nothing. Decisions (the manual is
/// silent): n is taken as an unsigned count, so a negative n names 32768-65535
/// words (4101 unless the device is that large); every source word is checked
/// before anything is written (D unchanged on error); S and D may overlap, the
/// result is as if the whole source had been read first. Word devices only (no
/// digit specification), as for the other block instructions.
#[derive(Debug)]
struct BkBcd(BlockArgs);

impl BkBcd {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Some(Box::new(BkBcd(block_args(a)?)))
    }
}

impl Instr for BkBcd {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        convert_block(cx.mem, &self.0, |v| v <= 9999, |v| to_bcd(v as u64) as u16)
    }
}

/// PM §6.3.12 BKBIN: converts n words of BCD 4 digits from S to BIN at D
/// onwards. A word with a digit A-F is 4100; past the device end 4101; n = 0
/// does nothing. Decisions as BKBCD.
#[derive(Debug)]
struct BkBin(BlockArgs);

impl BkBin {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Some(Box::new(BkBin(block_args(a)?)))
    }
}

impl Instr for BkBin {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        convert_block(
            cx.mem,
            &self.0,
            |v| from_bcd(v as u64).is_some(),
            |v| from_bcd(v as u64).unwrap_or(0) as u16,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bcd_round_trip() {
        assert_eq!(to_bcd(0), 0);
        assert_eq!(to_bcd(9999), 0x9999);
        assert_eq!(to_bcd(1234), 0x1234);
        assert_eq!(to_bcd(99_999_999), 0x9999_9999);
        assert_eq!(from_bcd(0x9999), Some(9999));
        assert_eq!(from_bcd(0x12A4), None);
        assert_eq!(from_bcd(0xF000_0000), None);
    }

    #[test]
    fn gray_inverse() {
        for v in [0u32, 1, 2, 3, 1234, 32767] {
            assert_eq!(gray_to_bin(v ^ v >> 1, 16), v);
        }
        let v = 305_419_896u32;
        assert_eq!(gray_to_bin(v ^ v >> 1, 32), v);
    }
}
