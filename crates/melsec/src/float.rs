//! Programming manual (common instructions) §7.12, special function instructions:
//! trigonometric and other functions of real numbers — SIN, COS, TAN, ASIN, ACOS,
//! ATAN, SQR, EXP, LOG (RAD and DEG live with the conversion family) — and the
//! BCD-type functions BSQR, BDSQR, BSIN, BCOS, BTAN, BASIN, BACOS, BATAN.
//!
//! Real functions take `S D`: `S` a real number (two words or an `E` constant),
//! `D` the two words of the real result. Angles are in radians.
//!
//! Numerics: the CPU's default "floating-point arithmetic: internal arithmetic in
//! double precision" (004 L7905-7910) is followed — the single-precision input is
//! widened to `f64`, the function evaluated in `f64` and the result rounded once
//! to single precision. Errors (OPERATION ERROR 4100, 004 §2.8): an input that is
//! not a real number for the CPU (±∞ and NaN bit patterns, read through
//! `read_f32`), an argument outside the function's domain, and a result outside
//! the single-precision range. A result below the smallest normal number is 0,
//! as for the other real-number instructions; a zero result is stored as +0.

use super::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::kernels::bcd;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("SIN", &REAL_FUNCTIONS, |a| compile(a, Func::Sin)),
    Def::app("COS", &REAL_FUNCTIONS, |a| compile(a, Func::Cos)),
    Def::app("TAN", &REAL_FUNCTIONS, |a| compile(a, Func::Tan)),
    Def::app("ASIN", &REAL_FUNCTIONS, |a| compile(a, Func::Asin)),
    Def::app("ACOS", &REAL_FUNCTIONS, |a| compile(a, Func::Acos)),
    Def::app("ATAN", &REAL_FUNCTIONS, |a| compile(a, Func::Atan)),
    Def::app("SQR", &REAL_FUNCTIONS, |a| compile(a, Func::Sqr)),
    Def::app("EXP", &REAL_FUNCTIONS, |a| compile(a, Func::Exp)),
    Def::app("LOG", &REAL_FUNCTIONS, |a| compile(a, Func::Log)),
    Def::app("BSQR", &BCD_FUNCTIONS, |a| compile_bsqr(a, false)),
    Def::app("BDSQR", &BCD_FUNCTIONS, |a| compile_bsqr(a, true)),
    Def::app("BSIN", &BCD_FUNCTIONS, |a| compile_btrig(a, Trig::Sin)),
    Def::app("BCOS", &BCD_FUNCTIONS, |a| compile_btrig(a, Trig::Cos)),
    Def::app("BTAN", &BCD_FUNCTIONS, |a| compile_btrig(a, Trig::Tan)),
    Def::app("BASIN", &BCD_FUNCTIONS, |a| compile_binv(a, Inv::Asin)),
    Def::app("BACOS", &BCD_FUNCTIONS, |a| compile_binv(a, Inv::Acos)),
    Def::app("BATAN", &BCD_FUNCTIONS, |a| compile_binv(a, Inv::Atan)),
];

static REAL_FUNCTIONS: Doc = Doc {
    family: "real functions",
    cite: "PM §7.12",
    notes: "f64 internally, stored as f32; domain errors → 4100",
};
static BCD_FUNCTIONS: Doc = Doc {
    family: "BCD functions",
    cite: "PM §7.12",
    notes: "4 decimals rounded at the 5th",
};

/// The function a [`RealFunction`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Func {
    /// PM §7.12.1 SIN(P): sine of `S` (radians). Any real `S` is accepted.
    Sin,
    /// PM §7.12.2 COS(P): cosine of `S` (radians). Any real `S` is accepted.
    Cos,
    /// PM §7.12.3 TAN(P): tangent of `S` (radians). The manual gives 4100 when
    /// `S` is π/2 or 3π/2. Decision: a single-precision `S` is never exactly
    /// (k + ½)π, so the error is raised when `S` is the single-precision number
    /// nearest to (k + ½)π for some integer k (E1.570796 is π/2 on the CPU) —
    /// there the double-precision tangent is about ±2.3·10⁷ instead of a pole.
    Tan,
    /// PM §7.12.4 ASIN(P): arc sine, −π/2 … π/2; `S` outside −1.0 … 1.0 is 4100.
    Asin,
    /// PM §7.12.5 ACOS(P): arc cosine, 0 … π; `S` outside −1.0 … 1.0 is 4100.
    Acos,
    /// PM §7.12.6 ATAN(P): arc tangent, −π/2 … π/2. Any real `S` is accepted.
    Atan,
    /// PM §7.12.9 SQR(P): square root; a negative `S` is 4100 (−0 is 0).
    Sqr,
    /// PM §7.12.10 EXP(P): eˢ; a result beyond the real range (`S` > about
    /// 88.72) is 4100, a result below it (`S` < about −87.34) is 0.
    Exp,
    /// PM §7.12.11 LOG(P): natural logarithm; `S` of 0 or less is 4100.
    Log,
}

/// PM §7.12.1-§7.12.6, §7.12.9-§7.12.11: a real-number function instruction
/// `D ← f(S)` (SIN … LOG, see [`Func`] for each one's domain). Errors: an invalid
/// real in S (4100), S outside the function's domain (4100), a result beyond the
/// single-precision range (4100), an index-modified operand out of range (4101).
#[derive(Debug)]
struct RealFunction {
    f: Func,
    s: WordArg,
    d: WordArg,
}

fn compile(a: &mut Args<'_, '_>, f: Func) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, Num::F32);
    let d = a.word_dest(1, Num::F32, 2);
    Some(Box::new(RealFunction { f, s: s?, d: d? }))
}

/// True when `x` is the single-precision number nearest to (k + ½)π.
fn tan_pole(x: f32) -> bool {
    use std::f64::consts::PI;
    let k = (x as f64 / PI - 0.5).round();
    ((k + 0.5) * PI) as f32 == x
}

impl Instr for RealFunction {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let x32 = cx.mem.read_f32(&self.s)?;
        let x = x32 as f64;
        let y = match self.f {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan if tan_pole(x32) => return Err(Fault::Operation),
            Func::Tan => x.tan(),
            Func::Asin | Func::Acos if !(-1.0..=1.0).contains(&x) => return Err(Fault::Operation),
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Atan => x.atan(),
            Func::Sqr if x < 0.0 => return Err(Fault::Operation),
            Func::Sqr => x.sqrt(),
            Func::Exp => x.exp(),
            Func::Log if x <= 0.0 => return Err(Fault::Operation),
            Func::Log => x.ln(),
        };
        // `as f32` rounds to nearest; a value beyond f32::MAX becomes ∞ and
        // write_f32 reports it (4100).
        let y = if y == 0.0 { 0.0 } else { y as f32 };
        cx.mem.write_f32(&self.d, y)
    }
}

// ------------------------------------------------------------------ BCD type

/// A BCD value of the `n` low digits of `v` (4100 when a nibble is above 9).
fn from_bcd(v: u32, n: u32) -> Result<u32, Fault> {
    let digits = v as u64 & ((1u64 << (4 * n)) - 1);
    bcd::unpack(digits)
        .map(|x| x as u32)
        .ok_or(Fault::Operation)
}

/// `v` (0-9999) as 4 BCD digits.
fn to_bcd(v: u32) -> u16 {
    bcd::pack(v as u64 % 10_000) as u16
}

/// |v| rounded at the fifth decimal place: (integer part, 4 decimals), both as
/// BCD. 4100 when the integer part exceeds 4 digits.
fn bcd_fixed4(v: f64) -> Result<(u16, u16), Fault> {
    let r = (v.abs() * 10_000.0).round() as u64;
    if r / 10_000 > 9999 {
        return Err(Fault::Operation);
    }
    Ok((to_bcd((r / 10_000) as u32), to_bcd((r % 10_000) as u32)))
}

/// Writes consecutive words from a block (4101 past the device's end).
fn write_block(cx: &mut ExecCtx<'_>, b: &Block, w: &[u16]) -> Result<(), Fault> {
    let i = cx.mem.block_start(b, w.len() as u32)?;
    cx.mem.words[i..i + w.len()].copy_from_slice(w);
    Ok(())
}

/// PM §7.12 BSQR(P) / BDSQR(P) `S D`: square root of the BCD value S (4 digits,
/// 0-9999; BDSQR: 8 digits in S, S+1) as BCD: D = integer part, D+1 = 4 decimal
/// digits, rounded at the fifth decimal place (√2 → 1, 4142). A digit above 9
/// is 4100; D+1 past the end of the device is 4101.
#[derive(Debug)]
struct BcdSqrt {
    wide: bool,
    s: WordArg,
    d: Block,
}

fn compile_bsqr(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, if wide { Num::I32 } else { Num::I16 });
    let d = a.block_dest(1);
    Some(Box::new(BcdSqrt { wide, s: s?, d: d? }))
}

impl Instr for BcdSqrt {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = if self.wide {
            from_bcd(cx.mem.read32(&self.s)?, 8)?
        } else {
            from_bcd(cx.mem.read16(&self.s)? as u32, 4)?
        };
        let (int, frac) = bcd_fixed4((v as f64).sqrt())?;
        write_block(cx, &self.d, &[int, frac])
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Trig {
    Sin,
    Cos,
    Tan,
}

/// PM §7.12 BSIN(P), BCOS(P), BTAN(P) `S D`: the function of the angle S in
/// degrees (BCD, 0-360) as D = sign (0 positive, 1 negative), D+1 = integer
/// part and D+2 = 4 decimal digits in BCD, rounded at the fifth decimal place
/// (BSIN of 30 → 0, 0, 5000H). A result that rounds to 0 has sign 0. Errors
/// (4100): S not BCD or above 360; BTAN of 90 or 270 degrees.
#[derive(Debug)]
struct BcdTrig {
    f: Trig,
    s: WordArg,
    d: Block,
}

fn compile_btrig(a: &mut Args<'_, '_>, f: Trig) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = a.block_dest(1);
    Some(Box::new(BcdTrig { f, s: s?, d: d? }))
}

impl Instr for BcdTrig {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let deg = from_bcd(cx.mem.read16(&self.s)? as u32, 4)?;
        if deg > 360 || (self.f == Trig::Tan && (deg == 90 || deg == 270)) {
            return Err(Fault::Operation);
        }
        let x = (deg as f64).to_radians();
        let v = match self.f {
            Trig::Sin => x.sin(),
            Trig::Cos => x.cos(),
            Trig::Tan => x.tan(),
        };
        let (int, frac) = bcd_fixed4(v)?;
        let sign = (v < 0.0 && (int, frac) != (0, 0)) as u16;
        write_block(cx, &self.d, &[sign, int, frac])
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Inv {
    Asin,
    Acos,
    Atan,
}

/// PM §7.12 BASIN(P), BACOS(P), BATAN(P) `S D`: S = sign (0 positive, 1
/// negative), S+1 = integer part and S+2 = 4 decimal digits in BCD; D = the
/// angle in whole degrees (rounded) as BCD. BASIN and BATAN give 0-90 for
/// positive values and 270-360 for negative ones (−30° → 330), BACOS 0-180.
/// Errors (4100): a part that is not BCD, a sign other than 0 or 1 (softplc
/// decision: the manual defines only 0 and 1), for BASIN/BACOS a value outside
/// −1.0000 … 1.0000.
#[derive(Debug)]
struct BcdInverse {
    f: Inv,
    s: Block,
    d: WordArg,
}

fn compile_binv(a: &mut Args<'_, '_>, f: Inv) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.block(0);
    let d = a.word_dest(1, Num::I16, 1);
    Some(Box::new(BcdInverse { f, s: s?, d: d? }))
}

impl Instr for BcdInverse {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let i = cx.mem.block_start(&self.s, 3)?;
        let [sign, int, frac] = [0, 1, 2].map(|k| cx.mem.words[i + k]);
        let (int, frac) = (from_bcd(int as u32, 4)?, from_bcd(frac as u32, 4)?);
        if sign > 1 {
            return Err(Fault::Operation);
        }
        let mag = int as f64 + frac as f64 / 10_000.0;
        let v = if sign == 1 { -mag } else { mag };
        if self.f != Inv::Atan && mag > 1.0 {
            return Err(Fault::Operation);
        }
        let deg = match self.f {
            Inv::Asin => v.asin(),
            Inv::Acos => v.acos(),
            Inv::Atan => v.atan(),
        }
        .to_degrees()
        .round();
        let deg = if deg < 0.0 { 360.0 + deg } else { deg.abs() };
        cx.mem.write16(&self.d, to_bcd(deg as u32))
    }
}
