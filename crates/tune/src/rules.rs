//! Tuning rules for a first-order-plus-dead-time process, in the units of the
//! process-control PID instructions (S.PID, S.2PID; spec §4.8-§4.9):
//!
//! - **P** (loop tag +52): the proportional gain on % of the engineering range,
//!   `ΔMV[%] = P·{ΔDV + (CT/TI)·DV + Bn}` with DV in % of (RH − RL), so the
//!   process gain K must be given in %PV-of-range per %MV;
//! - **TI** (+54) and **TD** (+56) in seconds (TI = 0 means no integral action,
//!   as S.AT1 reads it, §4.37 step 11);
//! - **η** = 1/MTD, the derivative filter of S.PID (`TD·s/(1 + η·TD·s)`; MTD is
//!   the instruction's operation constant S2+0, default 8.0, so η = 0.125).
//!   The rules below assume an ideal derivative; η is reported as the MTD the
//!   verification used, and only for rows with derivative action.
//!
//! S.PID is the parallel ("ideal", non-interacting) form
//! `P·(1 + 1/(TI·s) + TD·s)`. Rules given in series (interacting) form
//! `Kc·(1 + 1/(τI·s))·(1 + τD·s)` are converted with
//! `P = Kc·(1 + τD/τI)`, `TI = τI + τD`, `TD = τI·τD/(τI + τD)`.

use serde::Serialize;

/// A FOPDT process in the loop's units: `K·e^(−θs)/(1 + τs)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Process {
    /// Static gain K in %PV (of RH − RL) per %MV.
    pub gain: f64,
    /// Time constant τ, s.
    pub tau: f64,
    /// Dead time θ, s.
    pub dead_time: f64,
}

/// A tuning rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rule {
    /// Ziegler–Nichols reaction curve, P only.
    ZnP,
    /// Ziegler–Nichols reaction curve, PI.
    ZnPi,
    /// Ziegler–Nichols reaction curve, PID.
    ZnPid,
    /// Chien–Hrones–Reswick, set-point response with 0 % overshoot, PI.
    ChrPi,
    /// Chien–Hrones–Reswick, set-point response with 0 % overshoot, PID.
    ChrPid,
    /// Skogestad's SIMC PI.
    SimcPi,
    /// Skogestad's improved SIMC PID for FOPDT (series form, converted).
    SimcPid,
    /// IMC-PID with a first-order Padé dead time (Rivera, Morari, Skogestad).
    ImcPid,
}

impl Rule {
    /// Every rule, in table order.
    pub const ALL: [Rule; 8] = [
        Rule::ZnP,
        Rule::ZnPi,
        Rule::ZnPid,
        Rule::ChrPi,
        Rule::ChrPid,
        Rule::SimcPi,
        Rule::SimcPid,
        Rule::ImcPid,
    ];

    /// The command-line name (`zn-pid`, `simc-pi`, …).
    pub fn name(self) -> &'static str {
        match self {
            Rule::ZnP => "zn-p",
            Rule::ZnPi => "zn-pi",
            Rule::ZnPid => "zn-pid",
            Rule::ChrPi => "chr-pi",
            Rule::ChrPid => "chr-pid",
            Rule::SimcPi => "simc-pi",
            Rule::SimcPid => "simc-pid",
            Rule::ImcPid => "imc-pid",
        }
    }

    /// Parses a command-line name.
    pub fn parse(s: &str) -> Result<Rule, String> {
        Rule::ALL
            .into_iter()
            .find(|r| r.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                let names: Vec<&str> = Rule::ALL.iter().map(|r| r.name()).collect();
                format!("unknown rule `{s}` (known: {})", names.join(", "))
            })
    }

    /// Whether the rule has derivative action.
    pub fn has_derivative(self) -> bool {
        matches!(
            self,
            Rule::ZnPid | Rule::ChrPid | Rule::SimcPid | Rule::ImcPid
        )
    }
}

/// One row of the tuning table, in the instruction's units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tuning {
    pub rule: Rule,
    /// P (+52), dimensionless on % of range.
    pub p: f64,
    /// TI (+54), s; 0 = no integral action.
    pub ti: f64,
    /// TD (+56), s.
    pub td: f64,
    /// η = 1/MTD for rows with derivative action, else `None`.
    pub eta: Option<f64>,
}

/// Parameters of the rules.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RuleOptions {
    /// The closed-loop time constant τc (λ) of SIMC and IMC, s; `None` = θ
    /// (Skogestad's default for tight but robust control).
    pub tau_c: Option<f64>,
    /// The derivative gain MTD of the PID instruction (S2+0), > 0.
    pub mtd: f64,
}

impl Default for RuleOptions {
    fn default() -> Self {
        RuleOptions {
            tau_c: None,
            mtd: 8.0,
        }
    }
}

/// Series (interacting) PID `Kc·(1 + 1/(τI·s))·(1 + τD·s)` as the parallel
/// form of S.PID: `(P, TI, TD)`.
pub fn series_to_parallel(kc: f64, ti: f64, td: f64) -> (f64, f64, f64) {
    if ti <= 0.0 || td <= 0.0 {
        return (kc, ti, td);
    }
    (kc * (1.0 + td / ti), ti + td, ti * td / (ti + td))
}

/// The settings of `rule` for `process`. Errors when the process has no dead
/// time or time constant the rule needs, or a gain of 0 (a negative gain is
/// tuned on |K|: the loop then needs forward action, PN = 1).
pub fn tune(rule: Rule, process: &Process, opts: &RuleOptions) -> Result<Tuning, String> {
    let Process {
        gain,
        tau,
        dead_time: theta,
    } = *process;
    let k = gain.abs();
    if !(k > 0.0 && k.is_finite()) {
        return Err(format!(
            "process gain {gain}: cannot tune a loop without gain"
        ));
    }
    if !(tau.is_finite() && tau >= 0.0 && theta.is_finite() && theta >= 0.0) {
        return Err(format!("process τ = {tau} s, θ = {theta} s: not a FOPDT"));
    }
    let needs_theta = matches!(
        rule,
        Rule::ZnP | Rule::ZnPi | Rule::ZnPid | Rule::ChrPi | Rule::ChrPid
    );
    if needs_theta && theta <= 0.0 {
        return Err(format!(
            "{}: the reaction-curve rules need a dead time > 0 (θ = {theta} s)",
            rule.name()
        ));
    }
    let tau_c = opts.tau_c.unwrap_or(theta);
    let (p, ti, td) = match rule {
        // Ziegler–Nichols reaction curve: the S.AT1 table (spec §4.37 step 11)
        // with R·L/(|STEP|/100) = K·θ/τ for a FOPDT (the maximum slope of the
        // step response is R' = K·STEP/τ and the tangent meets y0 at θ).
        Rule::ZnP => (tau / (k * theta), 0.0, 0.0),
        Rule::ZnPi => (0.9 * tau / (k * theta), 3.33 * theta, 0.0),
        Rule::ZnPid => (1.2 * tau / (k * theta), 2.0 * theta, 0.5 * theta),
        // Chien, Hrones, Reswick (1952), set-point response, 0 % overshoot,
        // with a = K·θ/τ: PI 0.35/a, TI = 1.2·τ; PID 0.6/a, TI = τ, TD = 0.5·θ.
        Rule::ChrPi => (0.35 * tau / (k * theta), 1.2 * tau, 0.0),
        Rule::ChrPid => (0.6 * tau / (k * theta), tau, 0.5 * theta),
        // SIMC (Skogestad 2003): Kc = τ/(K·(τc + θ)), τI = min(τ, 4·(τc + θ)).
        Rule::SimcPi => {
            let sum = tau_c + theta;
            if sum <= 0.0 {
                return Err("simc-pi: τc + θ must be > 0 (give --tau-c)".into());
            }
            (tau / (k * sum), tau.min(4.0 * sum), 0.0)
        }
        // Improved SIMC for FOPDT (Grimholt & Skogestad 2012): series PID
        // with τD = θ/3 and τ replaced by τ + θ/3:
        // Kc = (τ + θ/3)/(K·(τc + θ)), τI = min(τ + θ/3, 4·(τc + θ)),
        // then converted to the parallel form ([`series_to_parallel`]).
        Rule::SimcPid => {
            let sum = tau_c + theta;
            if sum <= 0.0 {
                return Err("simc-pid: τc + θ must be > 0 (give --tau-c)".into());
            }
            let t1 = tau + theta / 3.0;
            series_to_parallel(t1 / (k * sum), t1.min(4.0 * sum), theta / 3.0)
        }
        // IMC-PID with e^(−θs) ≈ (1 − θs/2)/(1 + θs/2), λ = τc (parallel form):
        // P = (2τ + θ)/(K·(2λ + θ)), TI = τ + θ/2, TD = τ·θ/(2τ + θ).
        Rule::ImcPid => {
            if 2.0 * tau_c + theta <= 0.0 || 2.0 * tau + theta <= 0.0 {
                return Err("imc-pid: λ and θ cannot both be 0 (give --tau-c)".into());
            }
            (
                (2.0 * tau + theta) / (k * (2.0 * tau_c + theta)),
                tau + theta / 2.0,
                tau * theta / (2.0 * tau + theta),
            )
        }
    };
    let eta = (rule.has_derivative() && td > 0.0).then(|| 1.0 / opts.mtd);
    Ok(Tuning {
        rule,
        p,
        ti,
        td,
        eta,
    })
}

/// The whole table: every rule that applies (rules needing θ > 0 are left out
/// when θ = 0).
pub fn table(process: &Process, opts: &RuleOptions) -> Vec<Tuning> {
    Rule::ALL
        .iter()
        .filter_map(|r| tune(*r, process, opts).ok())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * b.abs().max(1.0)
    }

    /// K = 0.5 %/%, τ = 60 s, θ = 10 s: τ/(Kθ) = 12.
    const PLANT: Process = Process {
        gain: 0.5,
        tau: 60.0,
        dead_time: 10.0,
    };

    fn row(rule: Rule) -> Tuning {
        tune(rule, &PLANT, &RuleOptions::default()).unwrap()
    }

    #[test]
    fn ziegler_nichols_by_hand() {
        let r = row(Rule::ZnP);
        assert!(close(r.p, 12.0) && r.ti == 0.0 && r.td == 0.0 && r.eta.is_none());
        let r = row(Rule::ZnPi);
        assert!(close(r.p, 10.8) && close(r.ti, 33.3) && r.td == 0.0);
        let r = row(Rule::ZnPid);
        assert!(close(r.p, 14.4) && close(r.ti, 20.0) && close(r.td, 5.0));
        assert_eq!(r.eta, Some(0.125));
    }

    #[test]
    fn zn_matches_the_s_at1_table_written_with_r_and_l() {
        // S.AT1 (§4.37): R' = K·STEP/τ %/s, R = |R'|/100, L = θ;
        // PID Kp = 1.2/(R·L)·|STEP|/100.
        let step = 10.0;
        let r = PLANT.gain * step / PLANT.tau / 100.0;
        let l = PLANT.dead_time;
        let kp = 1.2 / (r * l) * step / 100.0;
        assert!(close(row(Rule::ZnPid).p, kp));
    }

    #[test]
    fn chr_by_hand() {
        let r = row(Rule::ChrPi);
        assert!(close(r.p, 4.2) && close(r.ti, 72.0) && r.td == 0.0);
        let r = row(Rule::ChrPid);
        assert!(close(r.p, 7.2) && close(r.ti, 60.0) && close(r.td, 5.0));
    }

    #[test]
    fn simc_by_hand() {
        // τc = θ = 10: Kc = 60/(0.5·20) = 6, τI = min(60, 80) = 60.
        let r = row(Rule::SimcPi);
        assert!(close(r.p, 6.0) && close(r.ti, 60.0) && r.td == 0.0);
        // iSIMC: τ + θ/3 = 63.333…, Kc = 63.333/(0.5·20) = 6.3333, τI = 63.333,
        // τD = 3.3333; parallel: P = 6.3333·(1 + 3.3333/63.333) = 6.6667,
        // TI = 66.667, TD = 63.333·3.3333/66.667 = 3.16667.
        let r = row(Rule::SimcPid);
        assert!(close(r.p, 20.0 / 3.0), "{r:?}");
        assert!(close(r.ti, 200.0 / 3.0) && close(r.td, 19.0 / 6.0), "{r:?}");
        // Short τ: τI = 4(τc + θ) is not the limit, τ is.
        let fast = Process {
            gain: 2.0,
            tau: 5.0,
            dead_time: 10.0,
        };
        let r = tune(Rule::SimcPi, &fast, &RuleOptions::default()).unwrap();
        assert!(close(r.p, 0.125) && close(r.ti, 5.0));
        // A slow process: τI = 4(τc + θ) = 80 s.
        let slow = Process {
            tau: 1000.0,
            ..PLANT
        };
        assert!(close(
            tune(Rule::SimcPi, &slow, &RuleOptions::default())
                .unwrap()
                .ti,
            80.0
        ));
        // τc given.
        let o = RuleOptions {
            tau_c: Some(30.0),
            ..RuleOptions::default()
        };
        assert!(close(tune(Rule::SimcPi, &PLANT, &o).unwrap().p, 3.0));
    }

    #[test]
    fn imc_by_hand() {
        // λ = 10: P = 130/(0.5·30) = 8.6667, TI = 65, TD = 600/130 = 4.6154.
        let r = row(Rule::ImcPid);
        assert!(close(r.p, 26.0 / 3.0) && close(r.ti, 65.0) && close(r.td, 60.0 / 13.0));
    }

    #[test]
    fn series_to_parallel_by_hand() {
        let (p, ti, td) = series_to_parallel(2.0, 10.0, 2.5);
        assert!(close(p, 2.5) && close(ti, 12.5) && close(td, 2.0));
        assert_eq!(series_to_parallel(2.0, 10.0, 0.0), (2.0, 10.0, 0.0));
    }

    #[test]
    fn degenerate_processes() {
        let no_dead = Process {
            dead_time: 0.0,
            ..PLANT
        };
        assert!(tune(Rule::ZnPid, &no_dead, &RuleOptions::default())
            .unwrap_err()
            .contains("dead time"));
        // τc defaults to θ = 0: SIMC and IMC need τc given.
        assert!(table(&no_dead, &RuleOptions::default()).is_empty());
        let o = RuleOptions {
            tau_c: Some(5.0),
            ..RuleOptions::default()
        };
        let t = table(&no_dead, &o);
        let names: Vec<&str> = t.iter().map(|r| r.rule.name()).collect();
        assert_eq!(names, ["simc-pi", "simc-pid", "imc-pid"]);
        // θ = 0, τc = 5: SIMC PI Kc = 60/(0.5·5) = 24, τI = min(60, 20) = 20.
        assert!(close(t[0].p, 24.0) && close(t[0].ti, 20.0));
        let dead_only = Process {
            gain: 1.0,
            tau: 0.0,
            dead_time: 0.0,
        };
        assert!(tune(Rule::SimcPi, &dead_only, &RuleOptions::default()).is_err());
        let flat = Process { gain: 0.0, ..PLANT };
        assert!(table(&flat, &RuleOptions::default()).is_empty());
        // A negative gain is tuned on |K|.
        let neg = Process {
            gain: -0.5,
            ..PLANT
        };
        assert_eq!(
            tune(Rule::ZnPid, &neg, &RuleOptions::default()).unwrap(),
            row(Rule::ZnPid)
        );
    }

    #[test]
    fn names_round_trip() {
        for r in Rule::ALL {
            assert_eq!(Rule::parse(r.name()).unwrap(), r);
        }
        assert!(Rule::parse("zn").unwrap_err().contains("simc-pi"));
    }
}
