//! String length and decimal-point conversions (PM §7.11): LEN, STR, DSTR, VAL, DVAL.

use super::{read_str, read_words, store_bytes, str_src, StrSrc};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// PM §7.11.8 LEN(P) `S D`: the number of characters of the string S (up to its
/// NUL) as BIN 16 bits in D. No NUL in S's device is 4101.
#[derive(Debug)]
struct Len {
    s: StrSrc,
    d: WordArg,
}

pub(super) fn compile_len(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.word_dest(1, Num::I16, 1);
    Some(Box::new(Len { s: s?, d: d? }))
}

impl Instr for Len {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = read_str(cx.mem, &self.s)?.len;
        cx.mem.write16(&self.d, n.min(u16::MAX as usize) as u16)
    }
}

// ------------------------------------------------------------------ STR, VAL

/// Formats sign, right-aligned digits of `mag` with `dec` of them after a
/// decimal point, as `total` characters: the sign (20H or 2DH) first, spaces
/// between sign and number, at least one digit before the point ("0.05").
/// 4100 when the number needs more characters than `total`.
pub(super) fn fixed(
    neg: bool,
    mag: u128,
    total: usize,
    dec: usize,
    out: &mut [u8],
) -> Result<(), Fault> {
    let point = (dec > 0) as usize;
    let avail = total - 1 - point;
    let mut nd = 1;
    let mut t = mag / 10;
    while t > 0 {
        nd += 1;
        t /= 10;
    }
    let nd = nd.max(dec + 1);
    if nd > avail {
        return Err(Fault::Operation);
    }
    out[0] = if neg { b'-' } else { b' ' };
    let spaces = avail - nd;
    out[1..1 + spaces].fill(b' ');
    let body = &mut out[1 + spaces..total];
    // Digits right-aligned, the point `dec` places from the right.
    let mut v = mag;
    let mut i = body.len();
    for k in 0..nd {
        if point == 1 && k == dec {
            i -= 1;
            body[i] = b'.';
        }
        i -= 1;
        body[i] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    Ok(())
}

/// PM §7.11.9 STR(P) / DSTR(P) `S1 S2 D`: the BIN value S2 (16/32 bits) as a
/// string of S1 characters (2-8 / 2-13, sign and point included) with S1+1
/// digits after the decimal point (0-5 / 0-10, at most S1 − 3): sign 20H or
/// 2DH, spaces between sign and number, "0." added for small values, then 00H.
/// Errors (4100): S1 or S1+1 out of range, or the value needs more digits.
/// Example: S1 = 6, S1+1 = 2, S2 = −1234 → "-12.34".
#[derive(Debug)]
struct StrInstr {
    wide: bool,
    s1: Block,
    s2: WordArg,
    d: Block,
}

pub(super) fn compile_str(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = a.block(0);
    let s2 = a.word_src(1, if wide { Num::I32 } else { Num::I16 });
    let d = a.block_dest(2);
    Some(Box::new(StrInstr {
        wide,
        s1: s1?,
        s2: s2?,
        d: d?,
    }))
}

impl Instr for StrInstr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let [total, dec] = read_words::<2>(cx.mem, &self.s1)?.map(|w| w as i16 as i32);
        let (max_total, max_dec) = if self.wide { (13, 10) } else { (8, 5) };
        // Decimals need a point and a digit before it: dec ≤ total − 3 when dec > 0.
        if !(2..=max_total).contains(&total)
            || !(0..=max_dec).contains(&dec)
            || (dec > 0 && dec > total - 3)
        {
            return Err(Fault::Operation);
        }
        let v = if self.wide {
            cx.mem.read32(&self.s2)? as i32 as i64
        } else {
            cx.mem.read16(&self.s2)? as i16 as i64
        };
        let mut buf = [0u8; 13];
        let total = total as usize;
        fixed(
            v < 0,
            v.unsigned_abs() as u128,
            total,
            dec as usize,
            &mut buf,
        )?;
        store_bytes(cx.mem, &self.d, &buf[..total], true)
    }
}

/// PM §7.11.10 VAL(P) / DVAL(P) `S D1 D2`: the string S (2-8 / 2-13 characters:
/// a sign 20H or 2DH, digits, at most one decimal point) to D1 = number of
/// characters, D1+1 = digits after the point (0-5 / 0-10, at most D1 − 3) and
/// D2 = the digits without the point as BIN 16/32 bits: "-123.45" → 7, 2,
/// −12345. Spaces and zeros between the sign and the first significant digit are
/// ignored. Errors (4100): a length, sign, character or point count outside
/// these rules, or a value outside the BIN range; no NUL is 4101.
#[derive(Debug)]
struct Val {
    wide: bool,
    s: StrSrc,
    d1: Block,
    d2: WordArg,
}

pub(super) fn compile_val(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let num = if wide { Num::I32 } else { Num::I16 };
    let s = str_src(a, 0);
    let d1 = a.block_dest(1);
    let d2 = a.word_dest(2, num, num.words());
    Some(Box::new(Val {
        wide,
        s: s?,
        d1: d1?,
        d2: d2?,
    }))
}

impl Instr for Val {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s = read_str(cx.mem, &self.s)?;
        let w = &cx.mem.words;
        let (max_total, max_dec) = if self.wide { (13, 10) } else { (8, 5) };
        let n = s.len;
        if !(2..=max_total).contains(&n) {
            return Err(Fault::Operation);
        }
        let neg = match s.byte(w, 0) {
            b' ' => false,
            b'-' => true,
            _ => return Err(Fault::Operation),
        };
        let mut v: i64 = 0;
        let mut point: Option<usize> = None;
        let mut leading = true;
        for i in 1..n {
            match s.byte(w, i) {
                b'.' if point.is_none() => {
                    point = Some(i);
                    leading = false;
                }
                b' ' | b'0' if leading => {}
                c @ b'0'..=b'9' => {
                    leading = false;
                    // At most 12 digits: no overflow.
                    v = v * 10 + (c - b'0') as i64;
                }
                _ => return Err(Fault::Operation),
            }
        }
        let dec = point.map_or(0, |p| n - 1 - p);
        if dec > max_dec || (dec > 0 && dec + 3 > n) {
            return Err(Fault::Operation);
        }
        let v = if neg { -v } else { v };
        let ok = if self.wide {
            (i32::MIN as i64..=i32::MAX as i64).contains(&v)
        } else {
            (-32768..=32767).contains(&v)
        };
        if !ok {
            return Err(Fault::Operation);
        }
        let i = cx.mem.block_start(&self.d1, 2)?;
        cx.mem.words[i] = n as u16;
        cx.mem.words[i + 1] = dec as u16;
        if self.wide {
            cx.mem.write32(&self.d2, v as u32)
        } else {
            cx.mem.write16(&self.d2, v as u16)
        }
    }
}
