//! `softplc tune`: offline loop tuning in virtual time (issue 12 item 5; the
//! workflow is `softplc_tune::driver`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Args;
use softplc_sim::plot;
use softplc_sim::scenario::Scenario;
use softplc_tune::csv_fit::fit_csv_file;
use softplc_tune::driver::{tune_scenario, Options};
use softplc_tune::report::num;
use softplc_tune::rules::{Rule, RuleOptions};

use crate::run::parse_duration;
use crate::stdout::{out, outln};

#[derive(Args, Debug)]
pub struct TuneArgs {
    /// Scenario file (TOML, docs/scenarios.md): the program and its plant.
    /// Its timeline is played first; its duration and [[expect]]s are not used.
    #[arg(value_name = "SCENARIO", required_unless_present = "fit_csv")]
    pub scenario: Option<PathBuf>,
    /// Head device of the loop tag (the D2 of S.IN/S.PID/S.OUT1), e.g. R1000;
    /// in a multi-CPU system with its CPU's prefix, e.g. CPU2/R1000.
    #[arg(long = "loop", value_name = "DEV", required_unless_present = "fit_csv")]
    pub loop_head: Option<String>,
    /// Read PV from this device instead of the loop tag's PV (+10; written by
    /// S.PHPL), e.g. a float of engineering units.
    #[arg(long, value_name = "DEV")]
    pub pv: Option<String>,
    /// The --pv device holds PV in % of the range RH−RL (e.g. S.IN's BW).
    #[arg(long, requires = "pv")]
    pub pv_percent: bool,
    /// MV step of the open-loop test, % (negative steps down).
    #[arg(
        long,
        value_name = "PCT",
        default_value_t = 10.0,
        allow_negative_numbers = true
    )]
    pub step: f64,
    /// MV to hold in MAN before the step, % (default: the loop's MV).
    #[arg(long, value_name = "PCT", allow_negative_numbers = true)]
    pub mv0: Option<f64>,
    /// Shortest MAN hold before the step, then until PV is steady (make it
    /// longer than the dead time after a --mv0 change).
    #[arg(long, value_name = "DUR", value_parser = parse_duration, default_value = "30s")]
    pub hold: Duration,
    /// Record the step response this long (default: until PV settles, at most 4 h).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub record_for: Option<Duration>,
    /// Rule of the closed-loop verification: zn-p, zn-pi, zn-pid, chr-pi,
    /// chr-pid, simc-pi, simc-pid, imc-pid.
    #[arg(long, value_name = "RULE", default_value = "simc-pi", value_parser = Rule::parse)]
    pub rule: Rule,
    /// Closed-loop time constant τc (λ) of SIMC/IMC (default: θ).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub tau_c: Option<Duration>,
    /// Derivative gain MTD of the PID instruction (η = 1/MTD).
    #[arg(long, value_name = "X", default_value_t = 8.0)]
    pub mtd: f64,
    /// SV step of the verification, engineering units (default: the PV change
    /// of the step test).
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub sv_step: Option<f64>,
    /// Length of the verification after the SV step (default 10·τ + 20·θ + 10·CT).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub verify_for: Option<Duration>,
    /// Skip the closed-loop verification.
    #[arg(long)]
    pub no_verify: bool,
    /// Settling band of the metrics, % of the SV step.
    #[arg(long, value_name = "PCT", default_value_t = 2.0)]
    pub band: f64,
    /// Centred moving average over PV before the verification metrics (0s = none).
    #[arg(long, value_name = "DUR", value_parser = parse_duration, default_value = "2s")]
    pub smooth: Duration,
    /// Head of the PID's operation constants (S2): MTD (+0) and PN (+4) are
    /// written before the verification.
    #[arg(long, value_name = "DEV")]
    pub pid_constants: Option<String>,
    /// Sampling period of the S.AT1 comparison (default: the loop's AT1ST, +72).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub at1_period: Option<Duration>,
    /// Write the trend of PV, SV and MV over the session to this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    pub svg: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Only fit a recorded step test: CSV with columns t, u, y (or time, mv, pv).
    #[arg(long, value_name = "FILE", conflicts_with = "scenario")]
    pub fit_csv: Option<PathBuf>,
}

fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}

fn fail(msg: String) -> ExitCode {
    eprintln!("softplc tune: {msg}");
    ExitCode::from(2)
}

pub fn run(args: TuneArgs) -> ExitCode {
    if let Some(csv) = &args.fit_csv {
        return match fit_csv_file(csv) {
            Ok(f) if args.json => {
                outln!("{}", serde_json::to_string_pretty(&f).unwrap_or_default());
                ExitCode::SUCCESS
            }
            Ok(f) => {
                outln!(
                    "{}: step {} → {} at t = {} s; FOPDT K = {}, τ = {} s, θ = {} s; \
                     RMS error {}, R² = {:.6} ({} samples)",
                    f.file,
                    num(f.u_before),
                    num(f.u_after),
                    num(f.step_at),
                    num(f.fit.gain),
                    num(f.fit.tau),
                    num(f.fit.dead_time),
                    num(f.fit.rms),
                    f.fit.r2,
                    f.fit.samples
                );
                ExitCode::SUCCESS
            }
            Err(e) => fail(e),
        };
    }
    let (Some(path), Some(head)) = (&args.scenario, &args.loop_head) else {
        return fail("give SCENARIO and --loop DEV (or --fit-csv FILE)".into());
    };
    let sc = match Scenario::load(path) {
        Ok(s) => s,
        Err(e) => return fail(e),
    };
    let mut o = Options::new(head);
    o.pv_device = args.pv.clone();
    o.pv_percent = args.pv_percent;
    o.step_pct = args.step;
    o.initial_mv = args.mv0;
    o.min_hold_s = secs(args.hold);
    o.record_s = args.record_for.map(secs);
    o.rule = args.rule;
    o.rule_options = RuleOptions {
        tau_c: args.tau_c.map(secs),
        mtd: args.mtd,
    };
    o.verify = !args.no_verify;
    o.sv_step = args.sv_step;
    o.verify_s = args.verify_for.map(secs);
    o.band_pct = args.band;
    o.smooth_s = secs(args.smooth);
    o.pid_constants = args.pid_constants.clone();
    o.at1_period = args.at1_period.map(secs);
    let report = match tune_scenario(&sc, &o) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    let mut notes = String::new();
    if let Some(svg) = &args.svg {
        let title = format!(
            "{}: loop {} step test and {} verification",
            sc.name,
            report.loop_tag,
            report
                .verification
                .as_ref()
                .map_or("no", |v| v.tuning.rule.name())
        );
        if let Err(e) = plot::write_svg(svg, &report.trend, &report.trend_labels, &title) {
            return fail(e);
        }
        notes = format!("trend: {}\n", svg.display());
    }
    if args.json {
        outln!("{}", report.json());
    } else {
        out!("{}{notes}", report.text());
    }
    match &report.verification {
        Some(v) if !v.settled => ExitCode::from(1),
        _ => ExitCode::SUCCESS,
    }
}
