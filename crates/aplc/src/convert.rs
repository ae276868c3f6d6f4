//! Conversions (002 §6.5 L5241-5656; spec aplc.md §4.8) and the integer
//! functions SQT, VABS, NEG with their D forms (002 §6.3 L4392-4530,
//! L4654-4793). Flags only where the text defines them (D8): INT/DINT Z, B
//! (a fraction dropped), C (saturated at either end); SQT/DSQT Z, B.
//! Illegal values are error 64 with the destination unchanged.

use softplc_ir::fault::Fault;
use softplc_ir::kernels::bcd;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::calc::{self, Fl, Layout, Spec};
use crate::constant::Width;
use crate::num::E_VALUE;

static CONV: Doc = Doc {
    family: "conversion",
    cite: "002 §6.5 L5241-5656",
    notes: "DTI out of range is error 64; INT/DINT truncate (Z, B on a dropped fraction, C on saturation); BCD > 9999 / 99999999 and bad BCD digits are error 64; SEG uses the FX table, S > 15 is error 64",
};
static FUNC: Doc = Doc {
    family: "integer functions",
    cite: "002 §6.3 L4392-4530, L4654-4793",
    notes: "SQT floor √ (Z, B when truncated; S < 0 error 64); VABS/NEG of the minimum is error 64",
};

/// Each definition with its operation and the widths of its source and
/// destination (`OP S D`).
macro_rules! defs {
    ($doc:expr, $($name:literal $steps:literal $f:ident $src:ident $dst:ident),*) => {
        &[$(Def::app($name, $doc, |a| {
            calc::compile(a, Spec::new($f, Width::$src, Width::$dst, Layout::SD))
        })
        .no_pulse()
        .steps(Steps::Fixed($steps)),)*]
    };
}

pub static DEFS: &[Def] = defs!(&CONV,
    "DTI" 6 dti W32 W16, "ITD" 6 itd W16 W32, "FLT" 6 flt W16 Real, "DFLT" 7 dflt W32 Real,
    "INT" 6 int Real W16, "DINT" 7 dint Real W32, "BCD" 5 bcd W16 W16, "DBCD" 7 dbcd W32 W32,
    "BIN" 5 bin W16 W16, "DBIN" 7 bin W32 W32, "GRY" 5 gry W16 W16, "DGRY" 7 gry W32 W32,
    "GBIN" 5 gbin W16 W16, "DGBIN" 7 gbin W32 W32, "SEG" 5 seg W16 W16);
pub static FUNCS: &[Def] = defs!(&FUNC,
    "SQT" 5 sqt W16 W16, "DSQT" 7 dsqt W32 W32, "VABS" 5 vabs W16 W16, "DVABS" 7 dvabs W32 W32,
    "NEG" 5 neg W16 W16, "DNEG" 7 dneg W32 W32);

/// 7-segment codes of 0-F (the FX SEGD table, spec aplc.md §4.8).
const SEG: [u32; 16] = [
    0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71,
];

fn s16(x: u32) -> i64 {
    x as u16 as i16 as i64
}
fn s32(x: u32) -> i64 {
    x as i32 as i64
}

fn dti(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    let v = s32(x);
    if (-32768..=32767).contains(&v) {
        Ok(v as u32 & 0xFFFF)
    } else {
        Err(E_VALUE)
    }
}
fn itd(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(s16(x) as u32)
}
fn flt(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok((s16(x) as f32).to_bits())
}
fn dflt(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok((s32(x) as f32).to_bits())
}

fn to_int(x: u32, fl: &mut Fl, min: f64, max: f64) -> i64 {
    let v = f32::from_bits(x) as f64;
    let t = v.trunc();
    let s = t.clamp(min, max);
    fl.zero = Some(s == 0.0);
    fl.borrow = Some(t != v);
    fl.carry = Some(s != t);
    s as i64
}
fn int(x: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    Ok(to_int(x, fl, -32768.0, 32767.0) as u32 & 0xFFFF)
}
fn dint(x: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    Ok(to_int(x, fl, i32::MIN as f64, i32::MAX as f64) as u32)
}

fn bcd(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    if x > 9999 {
        return Err(E_VALUE);
    }
    Ok(bcd::pack(x as u64) as u32)
}
fn dbcd(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    if x > 99_999_999 {
        return Err(E_VALUE);
    }
    Ok(bcd::pack(x as u64) as u32)
}
/// BIN and DBIN: every nibble of the 16- or 32-bit source is a digit.
fn bin(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    bcd::unpack(x as u64).map(|v| v as u32).ok_or(E_VALUE)
}
fn gry(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(x ^ (x >> 1))
}
fn gbin(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    let mut v = x;
    let mut s = x >> 1;
    while s != 0 {
        v ^= s;
        s >>= 1;
    }
    Ok(v)
}
fn seg(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    SEG.get(x as usize).copied().ok_or(E_VALUE)
}

fn sqrt(v: i64, fl: &mut Fl) -> Result<u32, Fault> {
    if v < 0 {
        return Err(E_VALUE);
    }
    let r = (v as f64).sqrt().floor() as i64;
    fl.zero = Some(r == 0);
    fl.borrow = Some(r * r != v);
    Ok(r as u32)
}
fn sqt(x: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    sqrt(s16(x), fl)
}
fn dsqt(x: u32, _: u32, fl: &mut Fl) -> Result<u32, Fault> {
    sqrt(s32(x), fl)
}
fn vabs(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    let v = x as u16 as i16;
    v.checked_abs().map(|v| v as u16 as u32).ok_or(E_VALUE)
}
fn dvabs(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    (x as i32).checked_abs().map(|v| v as u32).ok_or(E_VALUE)
}
fn neg(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    let v = x as u16 as i16;
    v.checked_neg().map(|v| v as u16 as u32).ok_or(E_VALUE)
}
fn dneg(x: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    (x as i32).checked_neg().map(|v| v as u32).ok_or(E_VALUE)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(f: calc::Fn2, x: u32) -> u32 {
        f(x, 0, &mut Fl::default()).unwrap()
    }

    /// §8.4 #52-58 (L5275-5656).
    #[test]
    fn manual_examples() {
        assert_eq!(run(dti, 10000), 10000);
        assert!(dti(100000, 0, &mut Fl::default()).is_err());
        assert_eq!(run(itd, (-1000i16) as u16 as u32) as i32, -1000);
        assert_eq!(f32::from_bits(run(flt, 10005)), 10005.0);
        assert_eq!(f32::from_bits(run(dflt, 100000)), 100000.0);
        let mut fl = Fl::default();
        assert_eq!(int(10000.5f32.to_bits(), 0, &mut fl).unwrap(), 10000);
        assert_eq!(
            (fl.zero, fl.borrow, fl.carry),
            (Some(false), Some(true), Some(false))
        );
        assert_eq!(int((-40000.0f32).to_bits(), 0, &mut fl).unwrap(), 0x8000);
        assert_eq!(fl.carry, Some(true));
        assert_eq!(run(dint, 100000.5f32.to_bits()), 100000);
        assert_eq!(run(bcd, 3333), 0x3333);
        assert_eq!(run(dbcd, 66666666), 0x66666666);
        assert_eq!(run(bin, 0x5555), 5555);
        assert_eq!(run(bin, 0x99999999), 99999999);
        assert!(bin(0x5A55, 0, &mut Fl::default()).is_err());
        assert_eq!(run(gry, 0xAAAA), 0xFFFF);
        assert_eq!(run(gry, 0x88888888), 0xCCCCCCCC);
        assert_eq!(run(gbin, 0xFFFF), 0xAAAA);
        assert_eq!(run(gbin, 0xCCCCCCCC), 0x88888888);
        assert_eq!(run(seg, 15), 0x71);
        assert!(seg(16, 0, &mut Fl::default()).is_err());
        let mut fl = Fl::default();
        assert_eq!(sqt(1000, 0, &mut fl).unwrap(), 31);
        assert_eq!(fl.borrow, Some(true));
        assert_eq!(run(dsqt, 83000), 288);
        assert_eq!(run(vabs, (-1000i16) as u16 as u32), 1000);
        assert_eq!(run(neg, 1000) as u16 as i16, -1000);
        assert!(neg(0x8000, 0, &mut Fl::default()).is_err());
        assert_eq!(run(dvabs, (-100000i32) as u32), 100000);
        assert_eq!(run(dneg, 100000) as i32, -100000);
    }
}
