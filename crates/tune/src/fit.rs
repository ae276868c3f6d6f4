//! First-order-plus-dead-time identification from an open-loop step response.
//!
//! The model fitted to the samples `(tᵢ, yᵢ)` (time since the step in s, PV)
//! after a step `ΔU` of the input at `t = 0` from a steady state `y0` is
//!
//! ```text
//! ŷ(t) = y0                                   t ≤ θ
//! ŷ(t) = y0 + K·ΔU·(1 − e^(−(t−θ)/τ))         t > θ
//! ```
//!
//! the step response of `K·e^(−θs)/(1 + τs)`, the process model S.AT1 assumes
//! (process-control spec §4.37). The fit minimises `Σ (yᵢ − ŷ(tᵢ))²` over
//! (K, τ, θ) by Levenberg–Marquardt with the analytic Jacobian, started from
//! the two-point estimate (the times the response crosses 28.3 % and 63.2 %
//! of its final change: `τ = 1.5·(t63 − t28)`, `θ = t63 − τ`) and from the
//! same point with θ scaled by 0.5, 1.5 and 0 (the cost has a kink in θ); the
//! best of the four is kept. `y0` is not fitted: it is the steady state
//! measured before the step.

use serde::Serialize;

/// The samples of a step test.
#[derive(Clone, Debug, PartialEq)]
pub struct StepResponse {
    /// Time since the step, s, increasing (samples before the step are left
    /// out; `t = 0` is the first instant the process sees the new input).
    pub t: Vec<f64>,
    /// The process output at `t`.
    pub y: Vec<f64>,
    /// Steady-state output before the step.
    pub y0: f64,
    /// Size of the input step (output units of K per this unit).
    pub du: f64,
}

/// A fitted FOPDT model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FopdtFit {
    /// Static gain K (output units per input unit).
    pub gain: f64,
    /// Time constant τ, s.
    pub tau: f64,
    /// Dead time θ, s.
    pub dead_time: f64,
    /// Root-mean-square residual, output units.
    pub rms: f64,
    /// Coefficient of determination of the fit (1 = perfect).
    pub r2: f64,
    /// Samples used.
    pub samples: usize,
    /// Levenberg–Marquardt iterations of the kept start.
    pub iterations: usize,
}

/// Samples used by the fit at most (longer records are thinned evenly).
pub const MAX_FIT_SAMPLES: usize = 4000;

/// The FOPDT step response at `t` (see the module documentation).
pub fn fopdt_step(gain: f64, tau: f64, dead_time: f64, du: f64, y0: f64, t: f64) -> f64 {
    if t <= dead_time {
        y0
    } else if tau <= 0.0 {
        y0 + gain * du
    } else {
        y0 - gain * du * (-(t - dead_time) / tau).exp_m1()
    }
}

/// Fits K, τ, θ to a step response. Errors name what is missing: too few
/// samples, a zero step, no visible response.
pub fn fit_fopdt(data: &StepResponse) -> Result<FopdtFit, String> {
    let n = data.t.len();
    if n != data.y.len() {
        return Err(format!(
            "step response: {} times but {} values",
            n,
            data.y.len()
        ));
    }
    if n < 10 {
        return Err(format!(
            "step response: {n} samples after the step; at least 10 are needed"
        ));
    }
    if !(data.du.is_finite() && data.du != 0.0) {
        return Err(format!("step response: the input step is {}", data.du));
    }
    if data.t.iter().chain(&data.y).any(|v| !v.is_finite()) || !data.y0.is_finite() {
        return Err("step response: a sample is not a finite number".into());
    }
    if data.t.windows(2).any(|w| w[1] <= w[0]) {
        return Err("step response: the times do not increase".into());
    }
    let (t, y) = thin(&data.t, &data.y);
    let start = two_point_estimate(&t, &y, data.y0, data.du)?;
    // The cost has a kink in θ (where the response starts), so besides the
    // two-point start a few other dead times are tried and the best fit kept.
    let mut best: Option<([f64; 3], usize, f64)> = None;
    let mut r = vec![0.0; t.len()];
    for theta_factor in [1.0, 0.5, 1.5, 0.0] {
        let p0 = [start[0], start[1], start[2] * theta_factor];
        let (p, it) = levenberg_marquardt(&t, &y, data.y0, data.du, p0);
        let cost = residuals(&t, &y, data.y0, data.du, &p, &mut r);
        match &best {
            Some(b) if b.2 <= cost => {}
            _ => best = Some((p, it, cost)),
        }
        if start[2] == 0.0 {
            break;
        }
    }
    let Some((p, iterations, _)) = best else {
        return Err("step response: no fit".into());
    };
    let (gain, tau, dead_time) = (p[0], p[1], p[2]);
    let mut ss_res = 0.0;
    for (ti, yi) in t.iter().zip(&y) {
        let r = yi - fopdt_step(gain, tau, dead_time, data.du, data.y0, *ti);
        ss_res += r * r;
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let ss_tot: f64 = y.iter().map(|v| (v - mean) * (v - mean)).sum();
    let fit = FopdtFit {
        gain,
        tau,
        dead_time,
        rms: (ss_res / y.len() as f64).sqrt(),
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            0.0
        },
        samples: y.len(),
        iterations,
    };
    // Finite samples can still overflow (a step of 1e-300 gives K = inf,
    // outputs near 1e200 square to inf): such a fit says nothing.
    if [fit.gain, fit.tau, fit.dead_time, fit.rms, fit.r2]
        .iter()
        .any(|v| !v.is_finite())
    {
        return Err(format!(
            "step response: the fit is not finite (K = {}, τ = {} s, θ = {} s, RMS error {}, R² = {}): \
             the input step or the output is too small or too large to fit; scale them",
            fit.gain, fit.tau, fit.dead_time, fit.rms, fit.r2
        ));
    }
    Ok(fit)
}

/// At most [`MAX_FIT_SAMPLES`] evenly chosen samples (the last one kept).
fn thin(t: &[f64], y: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = t.len();
    if n <= MAX_FIT_SAMPLES {
        return (t.to_vec(), y.to_vec());
    }
    let idx: Vec<usize> = (0..MAX_FIT_SAMPLES)
        .map(|k| k * (n - 1) / (MAX_FIT_SAMPLES - 1))
        .collect();
    (
        idx.iter().map(|&i| t[i]).collect(),
        idx.iter().map(|&i| y[i]).collect(),
    )
}

/// The first time (linearly interpolated) the normalised response
/// `(y − y0)/(y_end − y0)` reaches `level`.
fn crossing(t: &[f64], y: &[f64], y0: f64, change: f64, level: f64) -> Option<f64> {
    let frac = |v: f64| (v - y0) / change;
    let mut prev = (0.0, 0.0);
    for (ti, yi) in t.iter().zip(y) {
        let f = frac(*yi);
        if f >= level {
            if f == prev.1 || *ti == prev.0 {
                return Some(*ti);
            }
            return Some(prev.0 + (ti - prev.0) * (level - prev.1) / (f - prev.1));
        }
        prev = (*ti, f);
    }
    None
}

/// The starting point (K, τ, θ): the final change over the last 5 % of the
/// record and the 28.3 %/63.2 % two-point method.
fn two_point_estimate(t: &[f64], y: &[f64], y0: f64, du: f64) -> Result<[f64; 3], String> {
    let tail = (y.len() / 20).max(1);
    let end = y[y.len() - tail..].iter().sum::<f64>() / tail as f64;
    let change = end - y0;
    let scale = y.iter().fold(y0.abs(), |m, v| m.max(v.abs())).max(1e-12);
    if change.abs() <= 1e-9 * scale {
        return Err(format!(
            "step response: the output did not respond to the step (it ends at {end}, \
             its value before the step was {y0})"
        ));
    }
    let gain = change / du;
    let span = t[t.len() - 1];
    let (t28, t63) = match (
        crossing(t, y, y0, change, 0.283),
        crossing(t, y, y0, change, 0.632),
    ) {
        (Some(a), Some(b)) => (a, b),
        _ => (0.1 * span, 0.3 * span),
    };
    let tau = (1.5 * (t63 - t28)).max(span * 1e-4);
    let dead_time = (t63 - tau).max(0.0);
    Ok([gain, tau, dead_time])
}

/// The residuals and the sum of their squares at `p`.
fn residuals(t: &[f64], y: &[f64], y0: f64, du: f64, p: &[f64; 3], r: &mut [f64]) -> f64 {
    let mut s = 0.0;
    for ((ri, ti), yi) in r.iter_mut().zip(t).zip(y) {
        *ri = yi - fopdt_step(p[0], p[1], p[2], du, y0, *ti);
        s += *ri * *ri;
    }
    s
}

/// Solves the 3×3 system `a·x = b` by Gaussian elimination with partial
/// pivoting; `None` when singular.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for c in 0..3 {
        let piv = (c..3).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[piv][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, piv);
        b.swap(c, piv);
        let pivot_row = a[c];
        for r in c + 1..3 {
            let f = a[r][c] / pivot_row[c];
            for (x, p) in a[r][c..].iter_mut().zip(&pivot_row[c..]) {
                *x -= f * p;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 3];
    for r in (0..3).rev() {
        let s: f64 = (r + 1..3).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Levenberg–Marquardt on (K, τ, θ) with τ > 0 and θ ≥ 0 kept by clamping.
/// Returns the parameters and the iterations used.
fn levenberg_marquardt(t: &[f64], y: &[f64], y0: f64, du: f64, p0: [f64; 3]) -> ([f64; 3], usize) {
    let span = t[t.len() - 1].max(1e-9);
    let tau_min = span * 1e-6;
    let mut p = p0;
    let mut r = vec![0.0; t.len()];
    let mut cost = residuals(t, y, y0, du, &p, &mut r);
    let mut lambda = 1e-3;
    let mut iterations = 0;
    for it in 1..=200 {
        iterations = it;
        // Normal equations JᵀJ·δ = Jᵀr with the analytic derivatives of ŷ.
        let mut jtj = [[0.0; 3]; 3];
        let mut jtr = [0.0; 3];
        for (ti, ri) in t.iter().zip(&r) {
            if *ti <= p[2] {
                continue;
            }
            let e = (-(ti - p[2]) / p[1]).exp();
            let j = [
                du * (1.0 - e),
                -p[0] * du * e * (ti - p[2]) / (p[1] * p[1]),
                -p[0] * du * e / p[1],
            ];
            for a in 0..3 {
                jtr[a] += j[a] * ri;
                for b in 0..3 {
                    jtj[a][b] += j[a] * j[b];
                }
            }
        }
        let mut improved = false;
        while lambda < 1e12 {
            let mut a = jtj;
            for (d, row) in a.iter_mut().enumerate() {
                row[d] += lambda * jtj[d][d].max(1e-300);
            }
            let Some(delta) = solve3(a, jtr) else {
                lambda *= 10.0;
                continue;
            };
            let trial = [
                p[0] + delta[0],
                (p[1] + delta[1]).max(tau_min),
                (p[2] + delta[2]).max(0.0),
            ];
            let mut rt = vec![0.0; t.len()];
            let c = residuals(t, y, y0, du, &trial, &mut rt);
            if c < cost {
                let rel = (cost - c) / cost.max(1e-300);
                p = trial;
                r = rt;
                cost = c;
                lambda = (lambda / 10.0).max(1e-12);
                improved = true;
                if rel < 1e-14 {
                    return (p, iterations);
                }
                break;
            }
            lambda *= 10.0;
        }
        if !improved || cost == 0.0 {
            break;
        }
    }
    (p, iterations)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampled(k: f64, tau: f64, theta: f64, du: f64, y0: f64, h: f64, n: usize) -> StepResponse {
        let t: Vec<f64> = (0..n).map(|i| i as f64 * h).collect();
        let y = t
            .iter()
            .map(|&ti| fopdt_step(k, tau, theta, du, y0, ti))
            .collect();
        StepResponse { t, y, y0, du }
    }

    #[test]
    fn step_response_by_hand() {
        // K = 2, τ = 10 s, θ = 5 s, ΔU = 3: at t = 15 s the response is
        // 6·(1 − e⁻¹) = 3.79272… above y0 = 1.
        assert_eq!(fopdt_step(2.0, 10.0, 5.0, 3.0, 1.0, 5.0), 1.0);
        let v = fopdt_step(2.0, 10.0, 5.0, 3.0, 1.0, 15.0);
        assert!((v - (1.0 + 6.0 * (1.0 - (-1.0f64).exp()))).abs() < 1e-12);
        assert!((v - 4.792_723_35).abs() < 1e-8);
    }

    #[test]
    fn exact_data_is_recovered() {
        let d = sampled(1.5, 40.0, 7.0, 10.0, 20.0, 0.5, 800);
        let f = fit_fopdt(&d).unwrap();
        assert!((f.gain - 1.5).abs() < 1e-6, "{f:?}");
        assert!((f.tau - 40.0).abs() < 1e-4, "{f:?}");
        assert!((f.dead_time - 7.0).abs() < 1e-4, "{f:?}");
        assert!(f.rms < 1e-6 && f.r2 > 0.999_999, "{f:?}");
    }

    #[test]
    fn negative_gain_and_negative_step() {
        let d = sampled(-0.8, 12.0, 0.0, -5.0, 50.0, 0.1, 1500);
        let f = fit_fopdt(&d).unwrap();
        assert!((f.gain + 0.8).abs() < 1e-6, "{f:?}");
        assert!((f.tau - 12.0).abs() < 1e-3, "{f:?}");
        assert!(f.dead_time < 1e-3, "{f:?}");
    }

    #[test]
    fn noisy_data_within_a_few_percent() {
        // Deterministic pseudo-noise (±1 % of the change).
        let mut d = sampled(2.0, 30.0, 10.0, 5.0, 0.0, 0.5, 600);
        let mut s: u32 = 12345;
        for v in &mut d.y {
            s = s.wrapping_mul(1_103_515_245).wrapping_add(12345);
            *v += ((s >> 16) as f64 / 65536.0 - 0.5) * 0.2;
        }
        let f = fit_fopdt(&d).unwrap();
        assert!((f.gain - 2.0).abs() < 0.02, "{f:?}");
        assert!((f.tau - 30.0).abs() < 1.0, "{f:?}");
        assert!((f.dead_time - 10.0).abs() < 0.5, "{f:?}");
        assert!(f.rms > 0.03 && f.rms < 0.08 && f.r2 > 0.99, "{f:?}");
    }

    #[test]
    fn a_poor_start_still_finds_the_dead_time() {
        // A long dead time against τ: θ = 40 s, τ = 5 s.
        let d = sampled(1.0, 5.0, 40.0, 2.0, 0.0, 0.25, 400);
        let f = fit_fopdt(&d).unwrap();
        assert!(
            (f.dead_time - 40.0).abs() < 1e-3 && (f.tau - 5.0).abs() < 1e-3,
            "{f:?}"
        );
    }

    #[test]
    fn long_records_are_thinned() {
        let d = sampled(1.0, 50.0, 3.0, 1.0, 0.0, 0.01, 40_000);
        let f = fit_fopdt(&d).unwrap();
        assert_eq!(f.samples, MAX_FIT_SAMPLES);
        assert!((f.tau - 50.0).abs() < 1e-3 && (f.dead_time - 3.0).abs() < 1e-3);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let mut d = sampled(1.0, 5.0, 1.0, 1.0, 0.0, 0.1, 5);
        assert!(fit_fopdt(&d).unwrap_err().contains("at least 10"));
        d = sampled(0.0, 5.0, 1.0, 1.0, 0.0, 0.1, 100);
        assert!(fit_fopdt(&d).unwrap_err().contains("did not respond"));
        d = sampled(1.0, 5.0, 1.0, 0.0, 0.0, 0.1, 100);
        assert!(fit_fopdt(&d).unwrap_err().contains("input step"));
        d = sampled(1.0, 5.0, 1.0, 1.0, 0.0, 0.1, 100);
        d.y[3] = f64::NAN;
        assert!(fit_fopdt(&d).unwrap_err().contains("finite"));
        d = sampled(1.0, 5.0, 1.0, 1.0, 0.0, 0.1, 100);
        d.t[50] = 0.0;
        assert!(fit_fopdt(&d).unwrap_err().contains("increase"));
    }

    #[test]
    fn overflowing_fits_are_errors() {
        // A 1e-300 step answered by 1e10: K overflows to inf.
        let mut d = sampled(1.0, 5.0, 1.0, 1.0, 0.0, 0.5, 100);
        d.du = 1e-300;
        for y in &mut d.y {
            *y *= 1e10;
        }
        let e = fit_fopdt(&d).unwrap_err();
        assert!(e.contains("not finite") && e.contains("K = inf"), "{e}");
        // Outputs near 1e200: the squared residuals overflow, R² is NaN.
        let d = sampled(1e200, 5.0, 1.0, 1.0, 0.0, 0.5, 100);
        let e = fit_fopdt(&d).unwrap_err();
        assert!(e.contains("not finite"), "{e}");
    }
}
