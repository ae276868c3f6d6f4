//! S.IN, analog input processing.

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;

use crate::process::common::{area, result, Area, BlockMemory, Input, PcError, Sys};
use crate::process::settings::ProcessSettings;
use crate::process::tag::{alm, bb, put, Inh, LoopTag, Mode, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

softplc_ir::layout! {
    /// The operation constants (S2) of S.IN.
    pub struct InConsts[16] {
        /// EMAX: the engineering value at NMAX (100.0).
        emax: f32 @ 0,
        /// EMIN: the engineering value at NMIN (0.0).
        emin: f32 @ 2,
        /// NMAX: the input upper limit (100.0).
        nmax: f32 @ 4,
        /// NMIN: the input lower limit (0.0).
        nmin: f32 @ 6,
        /// HH: the high range error occurs (110.0).
        hh: f32 @ 8,
        /// H: the high range error returns (100.0).
        h: f32 @ 10,
        /// L: the low range error returns (0.0).
        l: f32 @ 12,
        /// LL: the low range error occurs (-10.0).
        ll: f32 @ 14,
    }
}

/// 000 §8.1 S.IN `S.IN S1 D1 S2 D2` (L3306-3893), analog input processing.
///
/// Operands: S1 +0 E1 (raw input); D1 +0 BW (%), +2 BB (BB1 alarm = SEA,
/// BB2 input high, BB3 input low); S2 +0 EMAX (100.0), +2 EMIN (0.0), +4
/// NMAX (100.0), +6 NMIN (0.0), +8 HH "high range error occurs" (110.0),
/// +10 H "returns" (100.0), +12 L "low returns" (0.0), +14 LL "low occurs"
/// (-10.0); D2 the loop tag: MODE +1, ALM +3 (SPA, SEA), INH +4 (ERRI,
/// SEI), α +38 (0.2).
///
/// Processing (L3770-3888): (5) loop stop (SPA = 1: BW holds, SEA := 0,
/// MODE := MAN, BB1..BB3 := 0) → (1) range check with hysteresis (E1 ≥ HH →
/// BB2 = 1, E1 ≤ H → 0, between: held; E1 ≤ LL → BB3 = 1, E1 ≥ L → 0;
/// BB1 = SEA = BB2 ∨ BB3 after both checks (DEC-9; the alternative applies
/// the table row by row, the low check last); SEI or ERRI makes all four 0;
/// on range-over with SM1500 ON BW holds and the instruction ends) → (2)
/// limiter T1 = E1 within NMIN..NMAX → (3) T2 = (EMAX − EMIN)/(NMAX − NMIN)
/// × (T1 − NMIN) + EMIN → (4) BW = T2 + α × (BW_prev − T2), BW_prev being
/// D1 as found (DEC-8).
///
/// Errors (4100; SD1503 per Table 14.2: 1 range check, 2 limiter, 3
/// inverse conversion, 4 filter): a bad float is SD1502 = 1 at the step
/// that reads it, NMAX = NMIN is 5 at 3, an overflowing result 6.
#[derive(Debug)]
pub(crate) struct In {
    sys: Sys,
    s: ProcessSettings,
    inh: Inh,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl In {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 3, "block memory");
        let s2 = area(a, 2, 16, "operation constants");
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        Some(Box::new(In {
            sys,
            s,
            inh: Inh::new(&s),
            s1: s1?,
            d1: d1?,
            s2: s2?,
            d2: d2?,
        }))
    }
}

/// One hysteresis check of the range table: 1 on the set row, 0 on the
/// reset row, `None` (the last value) between them.
fn check(set: bool, reset: bool) -> Option<bool> {
    if set {
        Some(true)
    } else if reset {
        Some(false)
    } else {
        None
    }
}

impl Instr for In {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        let s2 = Area::of(cx.mem, &self.s2, 16)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        self.sys.run(cx.mem, |m| {
            let sea_bits = bb::BB1 | bb::BB2 | bb::BB3;
            if d2.get(m, LoopTag::alm) & alm::SPA != 0 {
                d2.set_bits(m, LoopTag::alm, alm::SEA, false);
                d2.set(m, LoopTag::mode, Mode::MAN);
                d1.set_bits(m, BlockMemory::bb, sea_bits, false);
                return Ok(());
            }
            // (1) range check.
            let e1 = s1.real(m, Input::e1, 1)?;
            let hh = s2.real(m, InConsts::hh, 1)?;
            let h = s2.real(m, InConsts::h, 1)?;
            let l = s2.real(m, InConsts::l, 1)?;
            let ll = s2.real(m, InConsts::ll, 1)?;
            let mut bbw = d1.get(m, BlockMemory::bb);
            let high = check(e1 >= hh, e1 <= h);
            let low = check(e1 <= ll, e1 >= l);
            let bb2 = high.unwrap_or(bbw & bb::BB2 != 0);
            let bb3 = low.unwrap_or(bbw & bb::BB3 != 0);
            let bb1 = if self.s.in_sea_after_both_checks {
                bb2 || bb3
            } else {
                // Row by row: each check's row writes BB1/SEA, the low check last.
                let after_high = high.unwrap_or(bbw & bb::BB1 != 0);
                low.unwrap_or(after_high)
            };
            let inh = d2.get(m, LoopTag::inh);
            let on = self.inh.allows(inh, alm::SEA);
            put(&mut bbw, bb::BB2, bb2 && on);
            put(&mut bbw, bb::BB3, bb3 && on);
            put(&mut bbw, bb::BB1, bb1 && on);
            d1.set(m, BlockMemory::bb, bbw);
            d2.set_bits(m, LoopTag::alm, alm::SEA, bb1 && on);
            if bb1 && on && self.sys.hold_input(m) {
                return Ok(());
            }
            // (2) input limiter.
            let nmax = s2.real(m, InConsts::nmax, 2)?;
            let nmin = s2.real(m, InConsts::nmin, 2)?;
            let t1 = if e1 >= nmax {
                nmax
            } else if e1 <= nmin {
                nmin
            } else {
                e1
            };
            // (3) engineering-value inverse conversion.
            let emax = s2.real(m, InConsts::emax, 3)?;
            let emin = s2.real(m, InConsts::emin, 3)?;
            if nmax == nmin {
                return Err(PcError::divide(3));
            }
            let t2 = result((emax - emin) / (nmax - nmin) * (t1 - nmin) + emin, 3)?;
            // (4) digital filter on the previous BW (DEC-8).
            let a = d2.real(m, LoopTag::filter, 4)?;
            let prev = d1.real(m, BlockMemory::bw, 4)?;
            d1.set(m, BlockMemory::bw, result(t2 + a * (prev - t2), 4)?);
            Ok(())
        })
    }
}
