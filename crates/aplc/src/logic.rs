//! Word logic WAND/WOR/WXOR/WINV and their D forms (002 §6.6 L5773-5989,
//! no flags) and shifts and rotations (002 §6.7 L5991-6384; spec aplc.md
//! §4.10): `OP S1 D S2`, S2 the count (≥ 0, else error 64); the rotations
//! write SM181 = the last bit out (D8); rotations count modulo the width
//! (width + 1 through the carry), shifts give 0 from the width on.

use softplc_ir::fault::Fault;
use softplc_ir::kernels::logic::WordLogic;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::calc::{self, Fl, Layout, Spec};
use crate::constant::Width;
use crate::num::E_VALUE;

static LOGIC: Doc = Doc {
    family: "word logic",
    cite: "002 §6.6 L5773-5989",
    notes: "bitwise, 16 and 32 bits; no flags",
};
static SHIFT: Doc = Doc {
    family: "shift and rotate",
    cite: "002 §6.7 L5991-6384",
    notes: "OP S1 D S2; rotations write SM181 = last bit out, count modulo the width (width + 1 through carry); shifts zero-fill, 0 from the width on; a bit-group source must be K4/K8; count < 0 is error 64",
};

/// Each definition with its operation, width and operand order.
macro_rules! defs {
    ($doc:expr, $($name:literal $steps:literal $f:ident $w:ident $layout:ident),*) => {
        &[$(Def::app($name, $doc, |a| {
            calc::compile(a, Spec::new($f, Width::$w, Width::$w, Layout::$layout))
        })
        .no_pulse()
        .steps(Steps::Fixed($steps)),)*]
    };
}

/// The shifts and rotations: `OP S1 D S2`, a bit-group source K4/K8.
macro_rules! shifts {
    ($doc:expr, $($name:literal $steps:literal $f:ident $w:ident),*) => {
        &[$(Def::app($name, $doc, |a| {
            calc::compile(a, Spec::new($f, Width::$w, Width::$w, Layout::S1DS2).full())
        })
        .no_pulse()
        .steps(Steps::Fixed($steps)),)*]
    };
}

pub static DEFS: &[Def] = defs!(&LOGIC,
    "WAND" 7 and W16 S1S2D, "WOR" 7 or W16 S1S2D, "WXOR" 7 xor W16 S1S2D, "WINV" 5 not W16 SD,
    "DWAND" 10 and W32 S1S2D, "DWOR" 10 or W32 S1S2D, "DWXOR" 10 xor W32 S1S2D,
    "DWINV" 7 not W32 SD);
pub static SHIFTS: &[Def] = shifts!(&SHIFT,
    "ROR" 7 ror W16, "ROL" 7 rol W16, "RCR" 7 rcr W16, "RCL" 7 rcl W16, "SHR" 7 shr W16,
    "SHL" 7 shl W16, "DROR" 9 dror W32, "DROL" 9 drol W32, "DRCR" 9 drcr W32, "DRCL" 9 drcl W32,
    "DSHR" 9 dshr W32, "DSHL" 9 dshl W32);

fn count(n: u32) -> Result<u32, Fault> {
    if n as i16 >= 0 {
        Ok(n as u16 as u32)
    } else {
        Err(E_VALUE)
    }
}

macro_rules! rotations {
    ($w:ty, $bits:literal, $ror:ident, $rol:ident, $rcr:ident, $rcl:ident, $shr:ident, $shl:ident) => {
        fn $ror(x: u32, n: u32, fl: &mut Fl) -> Result<u32, Fault> {
            let n = count(n)? % $bits;
            let r = (x as $w).rotate_right(n);
            if n > 0 {
                fl.carry = Some(r >> ($bits - 1) & 1 != 0);
            }
            Ok(r as u32)
        }
        fn $rol(x: u32, n: u32, fl: &mut Fl) -> Result<u32, Fault> {
            let n = count(n)? % $bits;
            let r = (x as $w).rotate_left(n);
            if n > 0 {
                fl.carry = Some(r & 1 != 0);
            }
            Ok(r as u32)
        }
        fn $rcr(x: u32, n: u32, fl: &mut Fl) -> Result<u32, Fault> {
            let (mut x, mut c) = (x as $w, fl.carry_in);
            for _ in 0..count(n)? % ($bits + 1) {
                let out = x & 1 != 0;
                x = x >> 1 | (c as $w) << ($bits - 1);
                c = out;
            }
            fl.carry = Some(c);
            Ok(x as u32)
        }
        fn $rcl(x: u32, n: u32, fl: &mut Fl) -> Result<u32, Fault> {
            let (mut x, mut c) = (x as $w, fl.carry_in);
            for _ in 0..count(n)? % ($bits + 1) {
                let out = x >> ($bits - 1) & 1 != 0;
                x = x << 1 | c as $w;
                c = out;
            }
            fl.carry = Some(c);
            Ok(x as u32)
        }
        fn $shr(x: u32, n: u32, _: &mut Fl) -> Result<u32, Fault> {
            Ok((x as $w).checked_shr(count(n)?).unwrap_or(0) as u32)
        }
        fn $shl(x: u32, n: u32, _: &mut Fl) -> Result<u32, Fault> {
            Ok((x as $w).checked_shl(count(n)?).unwrap_or(0) as u32)
        }
    };
}

rotations!(u16, 16, ror, rol, rcr, rcl, shr, shl);
rotations!(u32, 32, dror, drol, drcr, drcl, dshr, dshl);

fn and(a: u32, b: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(WordLogic::And.apply(a, b))
}
fn or(a: u32, b: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(WordLogic::Or.apply(a, b))
}
fn xor(a: u32, b: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(WordLogic::Xor.apply(a, b))
}
fn not(a: u32, b: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(WordLogic::Not.apply(a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(f: calc::Fn2, x: u32, n: u32, c: bool) -> (u32, Option<bool>) {
        let mut fl = Fl {
            carry_in: c,
            ..Fl::default()
        };
        let v = f(x, n, &mut fl).unwrap();
        (v, fl.carry)
    }

    /// The twelve examples of §4.10 (L6023-6384).
    #[test]
    fn manual_examples() {
        assert_eq!(run(ror, 52629, 3, false), (47538, Some(true)));
        assert_eq!(run(rol, 52629, 15, false), (59082, Some(false)));
        assert_eq!(run(rcr, 52629, 5, false), (22124, Some(true)));
        assert_eq!(run(rcl, 52629, 16, true), (59082, Some(true)));
        assert_eq!(run(dror, 3013123244, 7, false), (1499935033, Some(false)));
        assert_eq!(run(drol, 3013123244, 30, false), (753280811, Some(true)));
        assert_eq!(run(drcr, 3013123244, 11, false), (722891539, Some(true)));
        assert_eq!(run(drcl, 3013123244, 25, false), (1488165020, Some(true)));
        assert_eq!(run(shr, 31452, 5, false).0, 982);
        assert_eq!(run(shl, 31452, 7, false).0, 28160);
        assert_eq!(run(dshr, 1939381420, 10, false).0, 1893927);
        assert_eq!(run(dshl, 1939381420, 15, false).0, 1314258944);
        assert_eq!(run(shl, 1, 16, false).0, 0);
        assert!(shl(1, 0xFFFF, &mut Fl::default()).is_err());
    }
}
