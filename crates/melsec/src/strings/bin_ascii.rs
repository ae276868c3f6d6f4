//! Fixed-width conversions between BIN/BCD values and ASCII characters (PM §7.11):
//! BINDA, DBINDA, BINHA, DBINHA, BCDDA, DBCDDA (BIN/BCD → ASCII) and DABIN,
//! DDABIN, HABIN, DHABIN, DABCD, DDABCD (ASCII → BIN/BCD).

use super::{read_bytes, sm701, store_bytes};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// Which fixed-width ASCII conversion a [`ToAsciiInstr`] performs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ToAscii {
    /// PM §7.11.1 BINDA(P): BIN 16 bits → sign (20H or 2DH) and 5 decimal
    /// digits, zeros before the first significant digit as 20H (space): −12345 →
    /// "-12345", 123 → "   123", 0 → "     0"; then 0000H in D+3.
    Dec16,
    /// PM §7.11.1 DBINDA(P): BIN 32 bits → sign and 10 digits, then 00H in the
    /// high byte of D+5.
    Dec32,
    /// PM §7.11.2 BINHA(P): BIN 16 bits → 4 hexadecimal digits "0"-"9", "A"-"F",
    /// no zero suppression (02A6H → "02A6"); then 0000H in D+2.
    Hex16,
    /// PM §7.11.2 DBINHA(P): 8 hexadecimal digits; then 0000H in D+4.
    Hex32,
    /// PM §7.11.3 BCDDA(P): BCD 4 digits → 4 decimal characters (0012H →
    /// "0012"); a nibble above 9 is 4100. Decision: no zero suppression, as for
    /// BINHA — the manual's layout is a fixed 4-digit field (BINDA's suppression
    /// is tied to its sign column).
    Bcd16,
    /// PM §7.11.3 DBCDDA(P): BCD 8 digits → 8 characters.
    Bcd32,
}

/// BINDA, DBINDA, BINHA, DBINHA, BCDDA, DBCDDA `S D`: S a 16/32-bit operand, the
/// characters from D on (4101 past the device end). The terminating 00H is
/// written only while SM701 is OFF.
#[derive(Debug)]
struct ToAsciiInstr {
    kind: ToAscii,
    s: WordArg,
    d: Block,
    sm701: Option<u32>,
}

pub(super) fn compile_to_ascii(a: &mut Args<'_, '_>, kind: ToAscii) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let num = match kind {
        ToAscii::Dec16 | ToAscii::Hex16 | ToAscii::Bcd16 => Num::I16,
        _ => Num::I32,
    };
    let s = a.word_src(0, num);
    let d = a.block_dest(1);
    Some(Box::new(ToAsciiInstr {
        kind,
        s: s?,
        d: d?,
        sm701: sm701(a),
    }))
}

pub(super) const HEX: &[u8; 16] = b"0123456789ABCDEF";

/// Writes the `n` low hexadecimal digits of `v`, most significant first.
fn hex_digits(v: u32, out: &mut [u8]) {
    let n = out.len();
    for (k, c) in out.iter_mut().enumerate() {
        *c = HEX[(v >> (4 * (n - 1 - k)) & 0xF) as usize];
    }
}

/// Writes `v` in decimal right-aligned into `out`, zero-filled.
pub(super) fn dec_digits(mut v: u128, out: &mut [u8]) {
    for c in out.iter_mut().rev() {
        *c = b'0' + (v % 10) as u8;
        v /= 10;
    }
}

impl Instr for ToAsciiInstr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mut buf = [0u8; 11];
        let n = match self.kind {
            ToAscii::Dec16 | ToAscii::Dec32 => {
                let (v, n) = match self.kind {
                    ToAscii::Dec16 => (cx.mem.read16(&self.s)? as i16 as i64, 6),
                    _ => (cx.mem.read32(&self.s)? as i32 as i64, 11),
                };
                buf[0] = if v < 0 { b'-' } else { b' ' };
                dec_digits(v.unsigned_abs() as u128, &mut buf[1..n]);
                // Zero suppression: every 0 before the first significant digit
                // (but not the units digit) becomes a space.
                for c in &mut buf[1..n - 1] {
                    if *c != b'0' {
                        break;
                    }
                    *c = b' ';
                }
                n
            }
            ToAscii::Hex16 | ToAscii::Bcd16 => {
                let v = cx.mem.read16(&self.s)? as u32;
                bcd_check(self.kind, v, 4)?;
                hex_digits(v, &mut buf[..4]);
                4
            }
            ToAscii::Hex32 | ToAscii::Bcd32 => {
                let v = cx.mem.read32(&self.s)?;
                bcd_check(self.kind, v, 8)?;
                hex_digits(v, &mut buf[..8]);
                8
            }
        };
        let nul = !self.sm701.is_some_and(|i| cx.mem.bits[i as usize]);
        store_bytes(cx.mem, &self.d, &buf[..n], nul)
    }
}

/// For the BCD kinds: 4100 when one of the `n` nibbles is above 9.
fn bcd_check(kind: ToAscii, v: u32, n: u32) -> Result<(), Fault> {
    if matches!(kind, ToAscii::Bcd16 | ToAscii::Bcd32) && (0..n).any(|k| v >> (4 * k) & 0xF > 9) {
        return Err(Fault::Operation);
    }
    Ok(())
}

// ------------------------------------------------------------------ ASCII → BIN/BCD

/// Which fixed-width ASCII conversion a [`FromAsciiInstr`] performs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FromAscii {
    /// PM §7.11.4 DABIN(P): 6 characters from S — sign (20H positive, 2DH
    /// negative) and 5 decimal digits, 20H in a digit counting as 0 — to BIN 16
    /// bits (−32768 … 32767).
    Dec16,
    /// PM §7.11.4 DDABIN(P): sign and 10 digits (11 characters) to BIN 32 bits.
    Dec32,
    /// PM §7.11.5 HABIN(P): 4 hexadecimal characters ("0"-"9", "A"-"F") to BIN 16.
    Hex16,
    /// PM §7.11.5 DHABIN(P): 8 hexadecimal characters to BIN 32 bits.
    Hex32,
    /// PM §7.11.6 DABCD(P): 4 decimal characters (20H counting as 0) to BCD 4
    /// digits.
    Bcd16,
    /// PM §7.11.6 DDABCD(P): 8 decimal characters to BCD 8 digits.
    Bcd32,
}

/// DABIN, DDABIN, HABIN, DHABIN, DABCD, DDABCD `S D`: a fixed number of
/// characters from S (no NUL needed; 4101 past the device end) to a 16/32-bit D.
/// A character outside the allowed set, a wrong sign or a value outside the BIN
/// range is 4100.
#[derive(Debug)]
struct FromAsciiInstr {
    kind: FromAscii,
    s: Block,
    d: WordArg,
}

pub(super) fn compile_from_ascii(a: &mut Args<'_, '_>, kind: FromAscii) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let num = match kind {
        FromAscii::Dec16 | FromAscii::Hex16 | FromAscii::Bcd16 => Num::I16,
        _ => Num::I32,
    };
    let s = a.block(0);
    let d = a.word_dest(1, num, num.words());
    Some(Box::new(FromAsciiInstr { kind, s: s?, d: d? }))
}

/// A decimal digit, 20H counting as 0.
fn dec_char(c: u8) -> Result<u32, Fault> {
    match c {
        b'0'..=b'9' => Ok((c - b'0') as u32),
        b' ' => Ok(0),
        _ => Err(Fault::Operation),
    }
}

pub(super) fn hex_char(c: u8) -> Result<u32, Fault> {
    match c {
        b'0'..=b'9' => Ok((c - b'0') as u32),
        b'A'..=b'F' => Ok((c - b'A' + 10) as u32),
        _ => Err(Fault::Operation),
    }
}

/// Sign and decimal digits (20H = 0) to a value within `min..=max`.
fn signed_dec(c: &[u8], min: i64, max: i64) -> Result<i64, Fault> {
    let neg = match c[0] {
        b' ' => false,
        b'-' => true,
        _ => return Err(Fault::Operation),
    };
    let mut v: i64 = 0;
    for &d in &c[1..] {
        v = v * 10 + dec_char(d)? as i64;
    }
    let v = if neg { -v } else { v };
    if !(min..=max).contains(&v) {
        return Err(Fault::Operation);
    }
    Ok(v)
}

/// Characters to the nibbles of a hexadecimal or BCD value, first = highest.
fn nibbles(c: &[u8], digit: fn(u8) -> Result<u32, Fault>) -> Result<u32, Fault> {
    c.iter().try_fold(0u32, |v, &d| Ok(v << 4 | digit(d)?))
}

impl Instr for FromAsciiInstr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let m = &*cx.mem;
        match self.kind {
            FromAscii::Dec16 => {
                let c: [u8; 6] = read_bytes(m, &self.s)?;
                let v = signed_dec(&c, -32768, 32767)?;
                cx.mem.write16(&self.d, v as u16)
            }
            FromAscii::Dec32 => {
                let c: [u8; 11] = read_bytes(m, &self.s)?;
                let v = signed_dec(&c, i32::MIN as i64, i32::MAX as i64)?;
                cx.mem.write32(&self.d, v as u32)
            }
            FromAscii::Hex16 => {
                let c: [u8; 4] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, hex_char)?;
                cx.mem.write16(&self.d, v as u16)
            }
            FromAscii::Hex32 => {
                let c: [u8; 8] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, hex_char)?;
                cx.mem.write32(&self.d, v)
            }
            FromAscii::Bcd16 => {
                let c: [u8; 4] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, dec_char)?;
                cx.mem.write16(&self.d, v as u16)
            }
            FromAscii::Bcd32 => {
                let c: [u8; 8] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, dec_char)?;
                cx.mem.write32(&self.d, v)
            }
        }
    }
}
