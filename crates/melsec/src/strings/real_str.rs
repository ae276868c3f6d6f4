//! Real number ↔ character string (PM §7.11): ESTR, EVAL.

use super::bin_ascii::dec_digits;
use super::len_str_val::fixed;
use super::{read_str, read_words, store_bytes, str_src, Str, StrSrc};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// 10^k for 0 ≤ k ≤ 22, exact in f64.
fn pow10(k: i32) -> f64 {
    const P: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    P[k as usize]
}

/// x·10^p. For |p| ≤ 22 multiplying or dividing by an exact power of ten rounds
/// once, so a decimal tie of a single-precision value stays an exact tie.
fn scale10(mut x: f64, mut p: i32) -> f64 {
    while p > 22 {
        x *= pow10(22);
        p -= 22;
    }
    while p < -22 {
        x /= pow10(22);
        p += 22;
    }
    if p >= 0 {
        x * pow10(p)
    } else {
        x / pow10(-p)
    }
}

/// PM §7.11.11 ESTR(P) `S1 S2 D`: the real S1 as a string in the format of
/// S2 (0 decimal-point format, 1 exponent format), S2+1 characters in total
/// (2-24), S2+2 digits after the point (0-7). Decimal-point format: sign, spaces,
/// integer part, point, fraction — S2+2 ≤ S2+1 − 3 when S2+2 > 0. Exponent
/// format: sign, spaces, one digit, point, fraction, "E", exponent sign ("+" or
/// "-") and two exponent digits — S2+1 ≥ 6, and S2+2 ≤ S2+1 − 7 when S2+2 > 0.
/// The fraction is rounded half away from zero at the last digit shown, and the
/// sign always comes first: −12.34567 with 8 characters and 2 decimals is
/// "-  12.35". Errors (4100): an invalid real, a format or digit count
/// outside these ranges, an integer part that does not fit.
#[derive(Debug)]
struct Estr {
    s1: WordArg,
    s2: Block,
    d: Block,
}

pub(super) fn compile_estr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = a.word_src(0, Num::F32);
    let s2 = a.block(1);
    let d = a.block_dest(2);
    Some(Box::new(Estr {
        s1: s1?,
        s2: s2?,
        d: d?,
    }))
}

impl Instr for Estr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let x = cx.mem.read_f32(&self.s1)? as f64;
        let [form, total, dec] = read_words::<3>(cx.mem, &self.s2)?.map(|w| w as i16 as i32);
        let bad = || Err(Fault::Operation);
        if !(0..=7).contains(&dec) || total > 24 {
            return bad();
        }
        let (total, dec) = (total as usize, dec as usize);
        let neg = x < 0.0;
        let ax = x.abs();
        let mut buf = [0u8; 24];
        match form {
            0 => {
                if total < 2 || (dec > 0 && total < dec + 3) {
                    return bad();
                }
                let r = scale10(ax, dec as i32).round();
                if r >= 1e24 {
                    return bad();
                }
                fixed(neg, r as u128, total, dec, &mut buf)?;
            }
            1 => {
                let need = 6 + if dec > 0 { dec + 1 } else { 0 };
                if total < need {
                    return bad();
                }
                // Mantissa digits m (dec + 1 of them) and exponent e with
                // |x| ≈ m·10^(e − dec).
                let (m, e) = if ax == 0.0 {
                    (0u128, 0i32)
                } else {
                    let mut e = ax.log10().floor() as i32;
                    let lo = pow10(dec as i32);
                    let mut m = scale10(ax, dec as i32 - e).round();
                    if m >= 10.0 * lo {
                        e += 1;
                        m = scale10(ax, dec as i32 - e).round();
                    } else if m < lo {
                        e -= 1;
                        m = scale10(ax, dec as i32 - e).round();
                    }
                    (m as u128, e)
                };
                buf[0] = if neg { b'-' } else { b' ' };
                let spaces = total - need;
                buf[1..1 + spaces].fill(b' ');
                let mut digits = [0u8; 8];
                dec_digits(m, &mut digits[..dec + 1]);
                let mut i = 1 + spaces;
                buf[i] = digits[0];
                i += 1;
                if dec > 0 {
                    buf[i] = b'.';
                    buf[i + 1..i + 1 + dec].copy_from_slice(&digits[1..dec + 1]);
                    i += 1 + dec;
                }
                buf[i] = b'E';
                buf[i + 1] = if e < 0 { b'-' } else { b'+' };
                dec_digits(e.unsigned_abs() as u128, &mut buf[i + 2..i + 4]);
            }
            _ => return bad(),
        }
        store_bytes(cx.mem, &self.d, &buf[..total], true)
    }
}

/// PM §7.11.12 EVAL(P) `S D`: the string S (1-24 characters) in decimal-point
/// ("-12.345") or exponent format ("-1.2345E+02") to a real in D. An optional
/// sign ("+" or "-") leads the number and the exponent; spaces anywhere and
/// zeros before the first significant digit are ignored; only the first 6
/// significant digits count, later ones are cut off (truncated), as the manual
/// specifies. Errors (4100): no or more than 24 characters, a character outside
/// the format, two points or two exponents, no digit, a result outside 0 and
/// 2⁻¹²⁶ ≤ |x| < 2¹²⁸; no NUL is 4101.
#[derive(Debug)]
struct Eval {
    s: StrSrc,
    d: WordArg,
}

pub(super) fn compile_eval(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.word_dest(1, Num::F32, 2);
    Some(Box::new(Eval { s: s?, d: d? }))
}

/// Parses an EVAL string to (negative, significant digits, decimal exponent of
/// the last kept digit).
fn parse_real(s: Str<'_>, w: &[u16]) -> Result<(bool, u32, i32), Fault> {
    let bad = Err(Fault::Operation);
    let mut neg = false;
    let mut seen_sign = false;
    let mut digits = 0u32; // significant digits kept (≤ 6)
    let mut mant = 0u32;
    let mut any_digit = false;
    let mut point = false;
    // Decimal exponent correction: + for integer digits dropped, − for kept
    // fraction digits.
    let mut shift = 0i32;
    let mut i = 0;
    while i < s.len {
        let c = s.byte(w, i);
        i += 1;
        match c {
            b' ' => {}
            b'+' | b'-' if !seen_sign && !any_digit && !point => {
                seen_sign = true;
                neg = c == b'-';
            }
            b'.' if !point => point = true,
            b'0'..=b'9' => {
                any_digit = true;
                let d = (c - b'0') as u32;
                if digits == 0 && d == 0 {
                    // Leading zero: only moves the point.
                    if point {
                        shift -= 1;
                    }
                } else if digits < 6 {
                    mant = mant * 10 + d;
                    digits += 1;
                    if point {
                        shift -= 1;
                    }
                } else if !point {
                    // A cut integer digit still counts for the magnitude.
                    shift += 1;
                }
            }
            b'E' if any_digit => {
                let mut eneg = false;
                let mut eany = false;
                let mut esign = false;
                let mut e: i32 = 0;
                while i < s.len {
                    let c = s.byte(w, i);
                    i += 1;
                    match c {
                        b' ' => {}
                        b'+' | b'-' if !esign && !eany => {
                            esign = true;
                            eneg = c == b'-';
                        }
                        b'0'..=b'9' => {
                            eany = true;
                            e = (e * 10 + (c - b'0') as i32).min(1000);
                        }
                        _ => return bad,
                    }
                }
                if !eany {
                    return bad;
                }
                shift += if eneg { -e } else { e };
            }
            _ => return bad,
        }
    }
    if !any_digit {
        return bad;
    }
    Ok((neg, mant, shift))
}

impl Instr for Eval {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s = read_str(cx.mem, &self.s)?;
        if s.len == 0 || s.len > 24 {
            return Err(Fault::Operation);
        }
        let (neg, mant, shift) = parse_real(s, &cx.mem.words)?;
        if mant == 0 {
            return cx.mem.write_f32(&self.d, 0.0);
        }
        let v = scale10(mant as f64, shift.clamp(-100, 100)) as f32;
        if v.is_infinite() || v < f32::MIN_POSITIVE {
            return Err(Fault::Operation);
        }
        cx.mem.write_f32(&self.d, if neg { -v } else { v })
    }
}
