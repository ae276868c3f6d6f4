//! Set-point step response metrics: overshoot, rise time, settling time, IAE.

use serde::Serialize;

/// Metrics of a response `y(t)` to a set-point step from `start` to `target`
/// at `t = 0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StepMetrics {
    /// Largest excursion beyond the target in the direction of the step, % of
    /// the step (0 when the target is never passed).
    pub overshoot_pct: f64,
    /// Time of the largest excursion, s.
    pub peak_time: Option<f64>,
    /// First time from 10 % to 90 % of the step, s (`None` if 90 % was never
    /// reached).
    pub rise_time: Option<f64>,
    /// Time after which `y` stays within the band around the target until the
    /// end of the record, s (`None` if the last sample is outside the band).
    pub settling_time: Option<f64>,
    /// The band, % of the step.
    pub band_pct: f64,
    /// Integral of |target − y| over the record (trapezoidal), units·s.
    pub iae: f64,
    /// Times the error changed sign (through the band's edges: crossings
    /// inside the band are not counted) — a sustained oscillation keeps
    /// adding to this count.
    pub band_crossings: usize,
}

/// Computes [`StepMetrics`]; `t` increasing (s since the step), `band_pct` > 0.
pub fn step_metrics(t: &[f64], y: &[f64], start: f64, target: f64, band_pct: f64) -> StepMetrics {
    let step = target - start;
    let sign = if step < 0.0 { -1.0 } else { 1.0 };
    let mag = step.abs();
    let band = band_pct / 100.0 * mag;
    let mut peak = (0.0, None);
    let mut t10 = None;
    let mut t90 = None;
    let mut last_outside = None;
    let mut iae = 0.0;
    let mut crossings = 0;
    let mut side = 0i8;
    let n = t.len().min(y.len());
    for i in 0..n {
        let progress = if mag > 0.0 {
            (y[i] - start) * sign / mag
        } else {
            0.0
        };
        if t10.is_none() && progress >= 0.1 {
            t10 = Some(t[i]);
        }
        if t90.is_none() && progress >= 0.9 {
            t90 = Some(t[i]);
        }
        let over = (y[i] - target) * sign;
        if over > peak.0 {
            peak = (over, Some(t[i]));
        }
        let err = target - y[i];
        if err.abs() > band {
            last_outside = Some(i);
            let s = if err > 0.0 { 1 } else { -1 };
            if side != 0 && s != side {
                crossings += 1;
            }
            side = s;
        }
        if i > 0 {
            iae += 0.5 * ((target - y[i - 1]).abs() + err.abs()) * (t[i] - t[i - 1]);
        }
    }
    let settling_time = match last_outside {
        None => Some(t.first().copied().unwrap_or(0.0)),
        Some(i) if i + 1 < n => Some(t[i + 1]),
        Some(_) => None,
    };
    StepMetrics {
        overshoot_pct: if mag > 0.0 { peak.0 / mag * 100.0 } else { 0.0 },
        peak_time: peak.1,
        rise_time: match (t10, t90) {
            (Some(a), Some(b)) => Some(b - a),
            _ => None,
        },
        settling_time,
        band_pct,
        iae,
        band_crossings: crossings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked_response() {
        // Step 0 → 10 at t = 0, sampled every second:
        // 0, 2, 6, 9, 11, 10.5, 10.1, 10, 10.
        let t: Vec<f64> = (0..9).map(f64::from).collect();
        let y = [0.0, 2.0, 6.0, 9.0, 11.0, 10.5, 10.1, 10.0, 10.0];
        let m = step_metrics(&t, &y, 0.0, 10.0, 2.0);
        assert!((m.overshoot_pct - 10.0).abs() < 1e-12);
        assert_eq!(m.peak_time, Some(4.0));
        // 10 % first reached at t = 1 (2 ≥ 1), 90 % at t = 3 (9 ≥ 9).
        assert_eq!(m.rise_time, Some(2.0));
        // Band ±0.2: the last sample outside is 10.5 at t = 5.
        assert_eq!(m.settling_time, Some(6.0));
        // IAE: errors 10, 8, 4, 1, 1, 0.5, 0.1, 0, 0 → trapezoids
        // 9 + 6 + 2.5 + 1 + 0.75 + 0.3 + 0.05 + 0 = 19.6.
        assert!((m.iae - 19.6).abs() < 1e-12);
        // Below the band, then above it (11, 10.5): one crossing.
        assert_eq!(m.band_crossings, 1);
    }

    #[test]
    fn downward_step_and_unsettled_end() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let y = [50.0, 45.0, 39.0, 42.0];
        let m = step_metrics(&t, &y, 50.0, 40.0, 5.0);
        assert!((m.overshoot_pct - 10.0).abs() < 1e-12);
        assert_eq!(m.settling_time, None);
        assert_eq!(m.rise_time, Some(1.0));
    }

    #[test]
    fn never_reaching_the_target() {
        let t = [0.0, 1.0, 2.0];
        let y = [0.0, 1.0, 2.0];
        let m = step_metrics(&t, &y, 0.0, 10.0, 2.0);
        assert_eq!(m.overshoot_pct, 0.0);
        assert_eq!(m.rise_time, None);
        assert_eq!(m.settling_time, None);
        assert_eq!(m.peak_time, None);
    }
}
