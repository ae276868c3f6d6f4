//! REAL arithmetic (002 §6.4 L4863-5239; spec aplc.md §4.7): RADD, RSUB,
//! RMUL, RDIV, RSQT, RVABS, RNEG, SIN, COS, TAN, POWER, LN, EXP. Operands
//! are D/V pairs or constants, high word first. Z = result 0; C = |result| >
//! 1.701412E+38 (the stated threshold; the stored value saturates at the f32
//! range). Division by 0 is error 69; a root of a negative number, a
//! logarithm of a value ≤ 0 and the undefined powers are error 64.

use softplc_ir::fault::Fault;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::calc::{self, Fl, Layout, Spec};
use crate::constant::Width;
use crate::num::{E_DIV0, E_VALUE};

static DOC: Doc = Doc {
    family: "REAL arithmetic",
    cite: "002 §6.4 L4863-5239",
    notes: "Z on 0, C above 1.701412E+38 (saturating); ÷0 error 69; √ of < 0, ln of ≤ 0, 0^(≤0) and (<0)^non-integer error 64; SIN/COS/TAN in radians",
};

/// Each definition with its operation and operand order: `OP S1 S2 D` or
/// `OP S D`, REAL throughout.
macro_rules! defs {
    ($($name:literal $steps:literal $f:ident $layout:ident),*) => {
        &[$(Def::app($name, &DOC, |a| {
            calc::compile(a, Spec::new($f, Width::Real, Width::Real, Layout::$layout))
        })
        .no_pulse()
        .steps(Steps::Fixed($steps)),)*]
    };
}

pub static DEFS: &[Def] = defs!(
    "RADD" 10 radd S1S2D, "RSUB" 10 rsub S1S2D, "RMUL" 10 rmul S1S2D, "RDIV" 10 rdiv S1S2D,
    "RSQT" 7 rsqt SD, "RVABS" 7 rvabs SD, "RNEG" 7 rneg SD,
    "SIN" 7 sin SD, "COS" 7 cos SD, "TAN" 7 tan SD, "POWER" 10 power S1S2D,
    "LN" 7 ln SD, "EXP" 7 exp SD
);

/// Stores a result with the flags: Z when 0, C beyond 1.701412E+38.
fn out(v: f64, fl: &mut Fl, carry: bool) -> Result<u32, Fault> {
    if v.is_nan() {
        return Err(E_VALUE);
    }
    fl.zero = Some(v == 0.0);
    let over = v.abs() > 1.701412e38;
    if carry {
        fl.carry = Some(over);
    }
    let f = (v as f32).clamp(f32::MIN, f32::MAX);
    let f = if f.abs() < f32::MIN_POSITIVE { 0.0 } else { f };
    Ok(f.to_bits())
}

fn r(x: u32) -> f64 {
    f32::from_bits(x) as f64
}

fn radd(a: u32, b: u32, fl: &mut Fl) -> Result<u32, Fault> {
    out(r(a) + r(b), fl, true)
}
fn rsub(a: u32, b: u32, fl: &mut Fl) -> Result<u32, Fault> {
    out(r(a) - r(b), fl, true)
}
fn rmul(a: u32, b: u32, fl: &mut Fl) -> Result<u32, Fault> {
    out(r(a) * r(b), fl, true)
}
fn rdiv(a: u32, b: u32, fl: &mut Fl) -> Result<u32, Fault> {
    if r(b) == 0.0 {
        return Err(E_DIV0);
    }
    out(r(a) / r(b), fl, true)
}
fn rsqt(a: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    if r(a) < 0.0 {
        return Err(E_VALUE);
    }
    out(r(a).sqrt(), fl, false)
}
fn rvabs(a: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(a & 0x7FFF_FFFF)
}
fn rneg(a: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(if a << 1 == 0 { 0 } else { a ^ 0x8000_0000 })
}
fn sin(a: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    out(r(a).sin(), fl, false)
}
fn cos(a: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    out(r(a).cos(), fl, false)
}
fn tan(a: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    out(r(a).tan(), fl, true)
}
fn power(a: u32, b: u32, fl: &mut Fl) -> Result<u32, Fault> {
    let (x, y) = (r(a), r(b));
    if x == 0.0 && y <= 0.0 || x < 0.0 && y.fract() != 0.0 {
        return Err(E_VALUE);
    }
    out(x.powf(y), fl, true)
}
fn ln(a: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    if r(a) <= 0.0 {
        return Err(E_VALUE);
    }
    out(r(a).ln(), fl, true)
}
fn exp(a: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    out(r(a).exp(), fl, true)
}
