//! The human-readable report and the JSON form of a tuning run.

use std::fmt::Write as _;

use crate::driver::Report;
use crate::rules::{Rule, Tuning};

/// A number with 4 significant digits (no exponent for ordinary values).
pub fn num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    // The magnitude after rounding to 4 digits (9.99996 prints as 10.00).
    let mag = (v.abs() * (1.0 + 5e-5)).log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{v:.3e}");
    }
    let decimals = (3 - mag).max(0) as usize;
    format!("{v:.decimals$}")
}

fn opt(v: Option<f64>, unit: &str) -> String {
    v.map_or_else(|| "—".into(), |x| format!("{}{unit}", num(x)))
}

/// The tuning table: one line per rule, `*` marking `chosen`.
pub fn table_text(rows: &[Tuning], chosen: Option<Rule>) -> String {
    let mut s = format!(
        "  {:<10} {:>10} {:>10} {:>10} {:>7}\n",
        "rule", "P", "TI [s]", "TD [s]", "η"
    );
    for r in rows {
        let mark = if Some(r.rule) == chosen { "*" } else { " " };
        let _ = writeln!(
            s,
            "{mark} {:<10} {:>10} {:>10} {:>10} {:>7}",
            r.rule.name(),
            num(r.p),
            num(r.ti),
            num(r.td),
            r.eta.map_or_else(|| "—".into(), num)
        );
    }
    s
}

impl Report {
    /// The report for a terminal.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{}: loop {} (range {}..{}, CT {} s, scan {} s)",
            self.scenario,
            self.loop_tag,
            num(self.range_low),
            num(self.range_high),
            num(self.control_cycle_s),
            num(self.scan_time_s)
        );
        let st = &self.step_test;
        let _ = writeln!(
            s,
            "step test: MAN, MV {} → {} % at t = {} s; PV {} → {} in {} s{} ({} samples)",
            num(st.mv_before),
            num(st.mv_after),
            num(st.at_s),
            num(st.pv_before),
            num(st.pv_after),
            num(st.record_s),
            if st.settled { "" } else { ", not settled" },
            st.samples
        );
        let id = &self.identification;
        let _ = writeln!(
            s,
            "FOPDT fit: K = {} PV/%MV = {} %/%, τ = {} s, θ = {} s; RMS error {} ({} % of range), R² = {:.6}",
            num(id.fit.gain),
            num(id.process.gain),
            num(id.fit.tau),
            num(id.fit.dead_time),
            num(id.fit.rms),
            num(id.rms_pct_of_range),
            id.fit.r2
        );
        match (&self.at1.curve, &self.at1.error) {
            (Some(c), _) => {
                let _ = writeln!(
                    s,
                    "S.AT1 equivalent (AT1ST {} s): R' = {} %/s, R = {} 1/s, L = {} s",
                    num(c.sample_period),
                    num(c.slope),
                    num(c.r),
                    num(c.l)
                );
            }
            (None, Some(e)) => {
                let _ = writeln!(s, "S.AT1 equivalent: {e}");
            }
            _ => {}
        }
        let chosen = self.verification.as_ref().map(|v| v.tuning.rule);
        s += "tuning (S.PID units: P on % of range, TI/TD in s, η = 1/MTD):\n";
        s += &table_text(&self.table, chosen);
        if !self.at1.rows.is_empty() {
            s += "S.AT1 would write (ZN from R and L):\n";
            for r in &self.at1.rows {
                let _ = writeln!(
                    s,
                    "  {:<10} {:>10} {:>10} {:>10} {:>7}",
                    format!("at1-{}", r.rule.name().trim_start_matches("zn-")),
                    num(r.p),
                    num(r.ti),
                    num(r.td),
                    r.eta.map_or_else(|| "—".into(), num)
                );
            }
        }
        if let Some(v) = &self.verification {
            let m = &v.metrics;
            let _ = writeln!(
                s,
                "verification ({}): AUT, SV {} → {} at t = {} s for {} s: overshoot {} %, \
                 rise time {}, settling time (±{} %) {}, IAE {}, MV {}..{} % — {}",
                v.tuning.rule.name(),
                num(v.sv_before),
                num(v.sv_after),
                num(v.at_s),
                num(v.duration_s),
                num(m.overshoot_pct),
                opt(m.rise_time, " s"),
                num(m.band_pct),
                opt(m.settling_time, " s"),
                num(m.iae),
                num(v.mv_min),
                num(v.mv_max),
                if v.settled { "settled" } else { "NOT settled" }
            );
        }
        for w in &self.warnings {
            let _ = writeln!(s, "warning: {w}");
        }
        s
    }

    /// The report as JSON (the trend is left out).
    pub fn json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rules::{table, Process, RuleOptions};

    #[test]
    fn numbers() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(12.345678), "12.35");
        assert_eq!(num(0.125), "0.1250");
        assert_eq!(num(1234.6), "1235");
        assert_eq!(num(1.5e-7), "1.500e-7");
        assert_eq!(num(9.99996), "10.00");
        assert_eq!(num(-9.9994), "-9.999");
    }

    #[test]
    fn table_lines() {
        let p = Process {
            gain: 0.5,
            tau: 60.0,
            dead_time: 10.0,
        };
        let t = table_text(&table(&p, &RuleOptions::default()), Some(Rule::SimcPi));
        assert!(
            t.contains("  zn-pid          14.40      20.00      5.000  0.1250"),
            "{t}"
        );
        assert!(
            t.contains("* simc-pi         6.000      60.00          0       —"),
            "{t}"
        );
    }
}
