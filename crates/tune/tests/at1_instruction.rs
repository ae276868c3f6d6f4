//! The real S.AT1 against `softplc tune` on the same plant: the shipped
//! example (`examples/process/fopdt_loop.toml`: FOPDT K = 0.8 °C/% = 0.4 %/%,
//! τ = 90 s, θ = 15 s, 0.05 °C of noise, AT1ST = 10 s from its timeline) and
//! its program (`temperature_loop.il`, where S.AT1 runs before S.OUT1 on the
//! loop tag R1000, AT1STEPMV = 10 % = `--step`).
//!
//! The S.AT1 run repeats the tuner's session scan for scan up to its MV step
//! (the same writes in the same scans, so the plant and its seeded noise
//! give the same PV), then sets S.AT1's start bit for the scan in which the
//! tuner stepped MV. S.AT1 then steps MV by the same 10 % in that scan and
//! samples the same PVs, so the P, I, D it writes must be the report's `at1`
//! rows up to float32 arithmetic.

use std::path::{Path, PathBuf};

use softplc_core::access::{DeviceSpec, Value};
use softplc_sim::scenario::Scenario;
use softplc_tune::driver::{tune_scenario, Options, Report};
use softplc_tune::loop_tag::{offset, MODE_MAN};
use softplc_tune::rules::Rule;
use softplc_tune::session::Session;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/process/fopdt_loop.toml")
}

/// S.AT1's S1 +2 (e1, b0 = start) and D1 (BB, b15 = BB16 complete) in
/// temperature_loop.il.
const AT1_START: &str = "D1382";
const AT1_BB: &str = "D1384";

fn word(s: &Session, dev: &str) -> u16 {
    match s
        .run
        .cpu()
        .read_device(&DeviceSpec::parse(dev).unwrap())
        .unwrap()
    {
        Value::Int(v) => v as u16,
        v => panic!("{dev}: {v:?}"),
    }
}

/// Runs S.AT1 with the loop's I and D set to `(ti, td)` (which select its
/// P, PI or PID row), stepping MV in the scan the tuner stepped it in `r`;
/// returns the P, I, D it wrote.
fn run_s_at1(sc: &Scenario, r: &Report, ti: f64, td: f64) -> (f64, f64, f64) {
    let mut s = Session::start(sc, "R1000", None, false).unwrap();
    // What the driver does before the step: the timeline, MAN, MV0 = 25 %.
    while s.run.steps_done() < s.timeline_scans.max(1) {
        s.scan().unwrap();
    }
    s.tag.set_mode(s.run.cpu_mut(), MODE_MAN).unwrap();
    s.write(offset::MV, 25.0).unwrap();
    s.scan().unwrap();
    let step_scan = (r.step_test.at_s / s.scan_s).round() as u64;
    while s.run.steps_done() + 1 < step_scan {
        s.scan().unwrap();
    }
    assert_eq!(s.read(offset::MV).unwrap(), r.step_test.mv_before);
    assert_eq!(s.read(offset::AT1ST).unwrap(), 10.0);
    s.write(offset::I, ti).unwrap();
    s.write(offset::D, td).unwrap();
    let start = DeviceSpec::parse(AT1_START).unwrap();
    s.run.cpu_mut().write_value(&start, &Value::Int(1)).unwrap();
    let s0 = s.scan().unwrap();
    assert_eq!(s0.mv, r.step_test.mv_after, "S.AT1 steps MV in that scan");
    // S.AT1 ends AT1TOUT2 (100 s) after the maximum slope.
    let mut n = 0;
    while word(&s, AT1_BB) & 0x8000 == 0 {
        s.scan().unwrap();
        n += 1;
        assert!(n < 20_000, "S.AT1 did not complete");
    }
    assert_eq!(word(&s, AT1_BB), 0x8000, "BB16 alone: no alarm");
    // The step is taken back (DEC-34).
    assert_eq!(s.read(offset::MV).unwrap(), r.step_test.mv_before);
    (
        s.read(offset::P).unwrap(),
        s.read(offset::I).unwrap(),
        s.read(offset::D).unwrap(),
    )
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

#[test]
fn s_at1_writes_the_reports_at1_rows() {
    let sc = Scenario::load(&example()).unwrap();
    let mut o = Options::new("R1000");
    o.initial_mv = Some(25.0);
    o.verify = false;
    let r = tune_scenario(&sc, &o).unwrap();
    let c = r.at1.curve.expect("S.AT1 identifies the plant");
    assert_eq!(c.sample_period, 10.0);
    // S.AT1 picks its row by the loop's I and D: I = 0 → P, D = 0 → PI,
    // both set → PID.
    for (rule, ti, td) in [
        (Rule::ZnP, 0.0, 0.0),
        (Rule::ZnPi, 10.0, 0.0),
        (Rule::ZnPid, 10.0, 1.0),
    ] {
        let want = r.at1.rows.iter().find(|t| t.rule == rule).unwrap();
        let (p, i, d) = run_s_at1(&sc, &r, ti, td);
        // float32 (S.AT1) against f64 (the report): a few ulps of f32
        // (measured: at most 5.4e-8 relative).
        assert!(rel(p, want.p) < 5e-7, "{rule:?}: P {p} vs {want:?}");
        if want.ti == 0.0 {
            assert_eq!(i, 0.0, "{rule:?}");
        } else {
            assert!(rel(i, want.ti) < 5e-7, "{rule:?}: I {i} vs {want:?}");
        }
        if want.td == 0.0 {
            assert_eq!(d, 0.0, "{rule:?}");
        } else {
            assert!(rel(d, want.td) < 5e-7, "{rule:?}: D {d} vs {want:?}");
        }
    }
}

#[test]
fn s_at1_differs_from_the_fits_zn_rows_by_its_sampling() {
    // The known difference (crates/tune/src/at1.rs): S.AT1's L is the
    // tangent of the steepest secant over h = AT1ST, so θ ≤ L ≤ θ + h, and
    // its TI, TD are L/θ times the fit's ZN TI, TD; its R′ is that secant's
    // slope, at most K·STEP·(1 − e^(−h/τ))/h ≤ K·STEP/τ without noise, and
    // its P is (K·STEP/τ)/R′ · θ/L times the fit's.
    let sc = Scenario::load(&example()).unwrap();
    let mut o = Options::new("R1000");
    o.initial_mv = Some(25.0);
    o.verify = false;
    let r = tune_scenario(&sc, &o).unwrap();
    let c = r.at1.curve.unwrap();
    let p = &r.identification.process;
    let h = c.sample_period;
    assert!(
        c.l >= p.dead_time && c.l <= p.dead_time + h,
        "L = {} vs θ = {}",
        c.l,
        p.dead_time
    );
    let tangent = p.gain * 10.0 / p.tau;
    let secant = tangent * (1.0 - (-h / p.tau).exp()) * p.tau / h;
    // 0.05 °C of noise is 0.025 % of range: over h = 10 s it may steepen a
    // secant by 2·3σ/h = 0.015 %/s at most; here it does not.
    assert!(
        c.slope <= secant + 2.0 * 3.0 * 0.025 / h && c.slope >= 0.85 * tangent,
        "R' = {} vs K·STEP/τ = {tangent}, secant {secant}",
        c.slope
    );
    for at1 in &r.at1.rows {
        let fit = r.table.iter().find(|t| t.rule == at1.rule).unwrap();
        let p_ratio = tangent / c.slope * p.dead_time / c.l;
        assert!(rel(at1.p / fit.p, p_ratio) < 1e-9, "{at1:?} vs {fit:?}");
        if fit.ti > 0.0 {
            assert!(rel(at1.ti / fit.ti, c.l / p.dead_time) < 1e-9);
        }
        if fit.td > 0.0 {
            assert!(rel(at1.td / fit.td, c.l / p.dead_time) < 1e-9);
        }
    }
}
