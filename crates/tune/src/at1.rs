//! The identification S.AT1 performs (process-control spec §4.37 steps 9-11),
//! computed on a recorded step response, so that the tuning table can be
//! compared with what the instruction would write on the same plant.
//!
//! S.AT1 samples PV (in %) every AT1ST after the MV step (sample 0 at the
//! step, DEC-32), keeps the largest change between consecutive samples (the
//! maximum slope, in the expected direction), draws the tangent through the
//! sample that ends it, and takes the time where that tangent meets PV0 as
//! the equivalent dead time L:
//!
//! ```text
//! R' = maxslope/AT1ST (%/s)      R = |R'|/100 (1/s)
//! b  = PV_at_max − R'·(k_max·AT1ST)
//! L  = (PV0 − b)/R'
//! ```
//!
//! Then the Ziegler–Nichols table of step 11: `Kp = c/(R·L)·|STEP|/100` with
//! c = 1 (P), 0.9 (PI, TI = 3.33·L), 1.2 (PID, TI = 2·L, TD = 0.5·L).
//!
//! **Known differences from the FOPDT fit's ZN rows.** For a FOPDT the exact
//! tangent has R' = K·STEP/τ and L = θ. Sampled every h = AT1ST, the largest
//! secant slope is at most `K·STEP·(1 − e^(−h/τ))/h`, smaller by about
//! h/(2τ); the secant of the first samples after θ still meets PV0 close to θ
//! (the response starts as a ramp), so L is θ to within O(h²/τ) unless the
//! steepest secant straddles θ (then up to h later). So Kp agrees with the
//! fit's ZN row to O(h/τ + h/θ), TI and TD to O(h/θ). Noise on PV makes the
//! maximum slope larger (S.AT1 has no filter); the least-squares fit does
//! not suffer from that.

use serde::Serialize;

use crate::rules::{Rule, Tuning};

/// What S.AT1 would identify.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ReactionCurve {
    /// Sampling period AT1ST, s.
    pub sample_period: f64,
    /// R' (%/s, signed), the maximum slope.
    pub slope: f64,
    /// R = |R'|/100, 1/s (D3+18, DEC-33).
    pub r: f64,
    /// Equivalent dead time L, s (D3+20).
    pub l: f64,
    /// Sample number of the maximum slope.
    pub max_slope_sample: usize,
}

/// Runs S.AT1's steps 9-10 on `pv_pct`, PV in % sampled every `period`
/// seconds from the step (`pv_pct[0]` = PV0 at the step). `rising` is the
/// expected direction (S.AT1: PN = 0 with STEP > 0, or PN = 1 with STEP < 0).
/// Errors as S.AT1's identification alarm (BB8): R = 0 or L ≤ 0.
pub fn identify(pv_pct: &[f64], period: f64, rising: bool) -> Result<ReactionCurve, String> {
    if !(period > 0.0 && period.is_finite()) {
        return Err(format!("S.AT1: sampling period {period} s"));
    }
    if pv_pct.len() < 3 {
        return Err("S.AT1: fewer than 3 samples".into());
    }
    let pv0 = pv_pct[0];
    let mut max_slope = 0.0;
    let mut max_k = 0;
    let mut pv_at_max = pv0;
    for k in 1..pv_pct.len() {
        let t2 = pv_pct[k] - pv_pct[k - 1];
        let better = if rising {
            t2 > max_slope
        } else {
            t2 < max_slope
        };
        if better {
            max_slope = t2;
            max_k = k;
            pv_at_max = pv_pct[k];
        }
    }
    let slope = max_slope / period;
    let r = slope.abs() / 100.0;
    if r == 0.0 {
        return Err("S.AT1 identification alarm (BB8): no slope in the expected direction".into());
    }
    let b = pv_at_max - slope * (max_k as f64 * period);
    let l = (pv0 - b) / slope;
    if l <= 0.0 {
        return Err(format!(
            "S.AT1 identification alarm (BB8): L = {l:.3} s ≤ 0 (no dead time visible at AT1ST = {period} s)"
        ));
    }
    Ok(ReactionCurve {
        sample_period: period,
        slope,
        r,
        l,
        max_slope_sample: max_k,
    })
}

impl ReactionCurve {
    /// The Ziegler–Nichols row S.AT1 would write for `rule` (zn-p, zn-pi or
    /// zn-pid) after a step of `step_pct` % MV; `None` for other rules.
    pub fn zn(&self, rule: Rule, step_pct: f64, mtd: f64) -> Option<Tuning> {
        let base = step_pct.abs() / 100.0 / (self.r * self.l);
        let (p, ti, td) = match rule {
            Rule::ZnP => (base, 0.0, 0.0),
            Rule::ZnPi => (0.9 * base, 3.33 * self.l, 0.0),
            Rule::ZnPid => (1.2 * base, 2.0 * self.l, 0.5 * self.l),
            _ => return None,
        };
        Some(Tuning {
            rule,
            p,
            ti,
            td,
            eta: (td > 0.0).then(|| 1.0 / mtd),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::fopdt_step;

    #[test]
    fn hand_worked_ramp() {
        // PV (%): 20, 20, 20, 22, 26, 29, 31: the largest rise is 4 from
        // sample 3 to 4; with AT1ST = 2 s: R' = 2 %/s, b = 26 − 2·8 = 10,
        // L = (20 − 10)/2 = 5 s, R = 0.02.
        let pv = [20.0, 20.0, 20.0, 22.0, 26.0, 29.0, 31.0];
        let rc = identify(&pv, 2.0, true).unwrap();
        assert_eq!(rc.max_slope_sample, 4);
        assert!((rc.slope - 2.0).abs() < 1e-12 && (rc.r - 0.02).abs() < 1e-12);
        assert!((rc.l - 5.0).abs() < 1e-12);
        // STEP 10 %: PID Kp = 1.2/(0.02·5)·0.1 = 1.2, TI = 10, TD = 2.5.
        let t = rc.zn(Rule::ZnPid, 10.0, 8.0).unwrap();
        assert!((t.p - 1.2).abs() < 1e-12 && t.ti == 10.0 && t.td == 2.5);
        assert!(rc.zn(Rule::SimcPi, 10.0, 8.0).is_none());
    }

    #[test]
    fn falling_response_and_alarms() {
        let pv = [50.0, 50.0, 48.0, 44.0, 42.0];
        let rc = identify(&pv, 1.0, false).unwrap();
        assert!((rc.slope + 4.0).abs() < 1e-12 && rc.max_slope_sample == 3);
        // b = 44 + 4·3 = 56, L = (50 − 56)/(−4) = 1.5.
        assert!((rc.l - 1.5).abs() < 1e-12);
        assert!(identify(&pv, 1.0, true).unwrap_err().contains("BB8"));
        // No dead time: the steepest slope is the first one and L = 0.
        let pv = [0.0, 10.0, 15.0, 17.5];
        assert!(identify(&pv, 1.0, true).unwrap_err().contains("L = "));
    }

    #[test]
    fn fopdt_agrees_to_the_sampling_period() {
        // K = 0.5, τ = 60 s, θ = 10 s, STEP 10 %, AT1ST 1 s.
        let pv: Vec<f64> = (0..400)
            .map(|k| fopdt_step(0.5, 60.0, 10.0, 10.0, 30.0, k as f64))
            .collect();
        let rc = identify(&pv, 1.0, true).unwrap();
        let exact_slope = 0.5 * 10.0 / 60.0;
        assert!((rc.slope / exact_slope - 1.0).abs() < 1.0 / 60.0, "{rc:?}");
        assert!((rc.l - 10.0).abs() < 0.05, "{rc:?}");
    }
}
