//! The PID operation of one loop at one sampling instant: input filter,
//! velocity-form, measured-value-derivative PID of 001 §3.1.2 (incomplete
//! derivative, S.PIDCONT) and §3.2.2 (complete derivative, PIDCONT), MV
//! limits (001 §4.3.2, Appendix 2 anti-windup), change-rate alarms (001 §5.1
//! Table 5.2 data 9/10), manual mode with PV→SV tracking (001 §4.3.1, §4.3.4)
//! and the limited ranges (001 §4.3.5, §5.2 Table 5.4).
//!
//! Arithmetic, rounding and evaluation order are softplc's \[DECISION\]s of
//! pid-instructions.md §2.6, implemented exactly as written there:
//!
//! 1. Inputs are range-clamped when the loop is "limited" (SD794/SD795,
//!    SD774/SD775 bit = 0): SV 0..2000; PV, MV_MAN, MVLL, MVHL −50..2050;
//!    ΔMVL, ΔPVL 0..2000. Clamped values are used internally and never written
//!    back (\[DECISION\] §2.6 step 1).
//! 2. PV alarm: not on the first processing; `|PVn − PVn−1| > ΔPVL` sets ALARM
//!    b0 (latched; PV itself is not limited). PV is the clamped raw PV.
//! 3. Filter (001 §3.1.2/§3.2.2 要点(1)): `PVfn = PVn + α·(PVfn−1 − PVn)`, with
//!    α = a/100, evaluated in f64 and then quantised to the Q16.16 state grid
//!    (`super::work`); every later use of PVfn is the quantised value. The
//!    PVf word is its [`round_word`].
//! 4. Manual mode: with SM794/SM774 OFF the SV word ← PVn (\[DECISION\] §1.4: at
//!    each sampling instant, raw clamped PV). History shifts (PVfn−2 ← PVfn−1 ←
//!    PVfn, SVn−1 ← the SV as it will be read, Dn−1 ← 0); no ΔMV, no MV alarm,
//!    the auto MV word and the MV state are held.
//! 5. Auto mode: `EVn = PVfn − SV` (forward) or `SV − PVfn` (reverse);
//!    `EVn−1` from the history (0 on the first processing);
//!    `dd = (PVfn − 2·PVfn−1) + PVfn−2`, negated for reverse action;
//!    * complete: `Dn = (td/ts)·dd`, 0 when td = 0;
//!    * incomplete: with `den = ts·kd + 100·td`,
//!      `Dn = (td·kd/den)·dd + (100·td/den)·Dn−1`; `Dn = (td/ts)·dd` when
//!      kd > 30000 (KD = ∞); `Dn = 0` when td = 0 or kd = 0 (\[DECISION\] §2.5);
//!    * integral `I = (ts/(10·ti))·EVn`, 0 when ti > 30000 (TI = ∞);
//!    * `ΔMV = (kp/100)·((EVn − EVn−1) + I + Dn)`;
//!
//!    where ts is the sampling time actually used (10 ms units, 001 §5.1.2(2)).
//! 6. MV alarm: `|ΔMV| > ΔMVL` sets ALARM b1 (ΔMV before limiting; ΔMV is
//!    not limited).
//! 7. `MVn = min(max(MVn−1 + ΔMV, MVLL), MVHL)`, quantised to Q16.36 and stored
//!    as the next MVn−1 (\[DECISION\] §1.5: clamped before stored, which is the
//!    anti-reset-windup of 001 Appendix 2). The MV word is its [`round_word`].
//!    (MVLL ≤ MVHL are int16, so MVn is always within the int16 range.)
//! 8. History shift: PVfn−2 ← PVfn−1 ← PVfn, SVn−1 ← SV, Dn−1 ← Dn, PVn−1 ← PVn.

use super::params::LoopParams;
use super::work::{quantize_mv, quantize_pvf, LoopState, F_REVERSE};
use super::Family;

softplc_ir::layout! {
    /// A loop's I/O data words m+0 … m+6 (001 §5.2(4) Table 5.4); its work
    /// words follow from m+7 ([`super::work::LoopWork`]).
    pub struct LoopIo[7] {
        /// SV: set value (engineering range of the loop).
        sv: i16 @ 0,
        /// PV: process value as input.
        pv: i16 @ 1,
        /// MV: manipulated value output by the instruction.
        mv: i16 @ 2,
        /// PVf: filtered process value.
        pvf: i16 @ 3,
        /// MVMAN: manual manipulated value.
        mvman: i16 @ 4,
        /// MAN/AUTO: 0 manual, 1 automatic.
        mode: u16 @ 5,
        /// ALARM: b0 PV change over ΔPVL, b1 MV change over ΔMVL.
        alarm: u16 @ 6,
    }
}

/// ALARM bits (001 §5.2 Table 5.4): b0 PV change over ΔPVL, b1 MV change over ΔMVL.
pub(crate) const ALARM_PV: u16 = 1;
pub(crate) const ALARM_MV: u16 = 2;

/// The word shown to the user for an internal value: round half away from zero,
/// saturated to int16 (\[DECISION\] pid-instructions.md §2.6 "one named function").
#[inline]
pub fn round_word(x: f64) -> i16 {
    // `as` saturates; f64::round rounds half away from zero.
    x.round() as i16
}

/// The fixed "limited" ranges of 001 §5.2 Table 5.4 and §5.1 Table 5.2,
/// applied when the loop's SD774/SD775 (SD794/SD795) bit is 0 (001 §4.3.5).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Range {
    pub limited: bool,
}

impl Range {
    #[inline]
    fn clamp(self, v: i16, lo: i16, hi: i16) -> i16 {
        if self.limited {
            v.clamp(lo, hi)
        } else {
            v
        }
    }

    /// SV: 0..2000.
    #[inline]
    pub(crate) fn sv(self, v: i16) -> i16 {
        self.clamp(v, 0, 2000)
    }

    /// PV, MV_MAN, MVLL, MVHL: −50..2050.
    #[inline]
    pub(crate) fn mv(self, v: i16) -> i16 {
        self.clamp(v, -50, 2050)
    }

    /// ΔMVL, ΔPVL: 0..2000.
    #[inline]
    pub(crate) fn rate(self, v: i16) -> i16 {
        self.clamp(v, 0, 2000)
    }
}

/// EV from a PVf and an SV (001 §3.1.2/§3.2.2; §4.2.2 forward/reverse).
#[inline]
fn deviation(reverse: bool, pvf: f64, sv: i16) -> f64 {
    if reverse {
        sv as f64 - pvf
    } else {
        pvf - sv as f64
    }
}

/// The derivative term Dn (001 §3.2.2 complete; §3.1.2 incomplete; scaling of
/// pid-instructions.md §2.5). `dd` is the action-signed second difference of PVf.
#[inline]
fn derivative(fam: Family, p: &LoopParams, ts: u16, dd: f64, d1: f64) -> f64 {
    if p.td == 0 {
        return 0.0;
    }
    let (td, ts) = (p.td as f64, ts as f64);
    match fam {
        Family::Complete => td / ts * dd,
        Family::Incomplete => {
            if p.kd == 0 {
                // \[DECISION\] §2.5: KD = 0 forces Dn = 0.
                0.0
            } else if p.kd > 30000 {
                // KD = ∞: exactly the complete derivative.
                td / ts * dd
            } else {
                let kd = p.kd as f64;
                let den = ts * kd + 100.0 * td;
                td * kd / den * dd + 100.0 * td / den * d1
            }
        }
    }
}

/// One sampling instant of one loop (001 §3.1.2/§3.2.2 formulas, §4.3.1–§4.3.5;
/// steps 1–8 of the module doc = \[DECISION\] pid-instructions.md §2.6). `io` is the loop's I/O block (SV … work
/// words), `ts` the sampling time used (10 ms units), `first` the first
/// processing (history already seeded by the caller, EVn−1 = 0, no PV alarm),
/// `track` true when SM794/SM774 is OFF (PV → SV in manual mode), `auto` the
/// MAN/AUTO word (already checked to be 0 or 1).
#[allow(clippy::too_many_arguments)]
pub(crate) fn sample(
    fam: Family,
    p: &LoopParams,
    range: Range,
    track: bool,
    auto: bool,
    io: &mut [u16],
    st: &mut LoopState,
    ts: u16,
    first: bool,
) {
    // 1. Inputs, clamped in limited mode.
    let sv = range.sv(LoopIo::sv.get(io));
    let pv = range.mv(LoopIo::pv.get(io));
    let mut alarm = LoopIo::alarm.get(io);
    // 2. PV change-rate alarm.
    let dpvl = range.rate(p.dpvl) as i32;
    if !first && (pv as i32 - st.pv1 as i32).abs() > dpvl {
        alarm |= ALARM_PV;
    }
    // 3. Input filter.
    let alpha = p.alpha as f64 / 100.0;
    let pvf = quantize_pvf(pv as f64 + alpha * (st.pvf1 - pv as f64));
    LoopIo::pvf.set(io, round_word(pvf));
    let ev1 = if first {
        0.0
    } else {
        deviation(st.has(F_REVERSE), st.pvf1, st.sv1)
    };
    if !auto {
        // 4. Manual mode.
        let sv_used = if track {
            LoopIo::sv.set(io, pv);
            range.sv(pv)
        } else {
            sv
        };
        st.pvf2 = st.pvf1;
        st.pvf1 = pvf;
        st.sv1 = sv_used;
        st.set(F_REVERSE, p.reverse);
        st.d1 = 0.0;
        st.pv1 = pv;
        LoopIo::alarm.set(io, alarm);
        return;
    }
    // 5. Auto mode: ΔMV.
    let ev = deviation(p.reverse, pvf, sv);
    let dd = (pvf - 2.0 * st.pvf1) + st.pvf2;
    let dd = if p.reverse { -dd } else { dd };
    let d = derivative(fam, p, ts, dd, st.d1);
    let integral = if p.ti > 30000 {
        0.0
    } else {
        ts as f64 / (10.0 * p.ti as f64) * ev
    };
    let dmv = p.kp as f64 / 100.0 * ((ev - ev1) + integral + d);
    // 6. MV change-rate alarm.
    if dmv.abs() > range.rate(p.dmvl) as f64 {
        alarm |= ALARM_MV;
    }
    // 7. MV limits on the stored accumulator (anti-windup).
    let (ll, hl) = (range.mv(p.mvll) as f64, range.mv(p.mvhl) as f64);
    let mut mv = st.mv + dmv;
    if mv > hl {
        mv = hl;
    }
    if mv < ll {
        mv = ll;
    }
    st.mv = quantize_mv(mv);
    LoopIo::mv.set(io, round_word(st.mv));
    LoopIo::alarm.set(io, alarm);
    // 8. History.
    st.pvf2 = st.pvf1;
    st.pvf1 = pvf;
    st.sv1 = sv;
    st.set(F_REVERSE, p.reverse);
    st.d1 = if fam == Family::Incomplete { d } else { 0.0 };
    st.pv1 = pv;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_is_half_away_from_zero() {
        assert_eq!(round_word(0.5), 1);
        assert_eq!(round_word(-0.5), -1);
        assert_eq!(round_word(1.4999), 1);
        assert_eq!(round_word(79.012), 79);
        assert_eq!(round_word(40000.0), 32767);
        assert_eq!(round_word(-40000.0), -32768);
    }
}
