//! The tuning workflow on a scenario (program + plant) in virtual time:
//!
//! 1. the scenario's timeline is played (e.g. the write that starts the
//!    program), then the loop is put in MAN (MODE +1 := 8H) and MV held until
//!    PV is steady;
//! 2. **open-loop step test**: MV (+12) := MV + step; PV is recorded every scan
//!    until it has settled (or for a given time);
//! 3. **FOPDT fit** of the response ([`crate::fit`]), the gain expressed in %
//!    of the range RH−RL (+22/+24) per %MV, and what S.AT1 would identify
//!    from the same record ([`crate::at1`]);
//! 4. **tuning table** ([`crate::rules`]);
//! 5. **closed-loop verification** with one rule: P, I, D (+52/+54/+56)
//!    written, SV (+14) := PV, MODE := AUT (10H), then SV stepped; PV, SV and
//!    MV recorded and the step metrics computed ([`crate::metrics`]).
//!
//! Only the loop-tag words are touched (plus, optionally, the PID's operation
//! constants MTD and PN), so the driver works unchanged on any loop built
//! from S.IN → S.PHPL → S.PID → S.OUT1 (or S.2PID, …) with the standard
//! loop-tag layout.

use serde::Serialize;
use softplc_core::access::{DeviceSpec, Value};
use softplc_sim::scenario::{Scenario, TraceData};

use crate::at1::{self, ReactionCurve};
use crate::fit::{fit_fopdt, FopdtFit, StepResponse};
use crate::loop_tag::{device_at, offset, ALM_SPA, MODE_AUT, MODE_MAN};
use crate::metrics::{step_metrics, StepMetrics};
use crate::rules::{self, Process, Rule, RuleOptions, Tuning};
use crate::session::Session;

/// What to do.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Head device of the loop tag (e.g. `R1000`).
    pub loop_head: String,
    /// Read PV from this device instead of the loop tag's +10.
    pub pv_device: Option<String>,
    /// The `pv_device` holds PV in % of RH − RL (as S.IN's BW), not in
    /// engineering units.
    pub pv_percent: bool,
    /// MV step of the open-loop test, % (signed).
    pub step_pct: f64,
    /// MV to hold before the step, % (default: the loop's MV as found).
    pub initial_mv: Option<f64>,
    /// Shortest hold before the step, s.
    pub min_hold_s: f64,
    /// Longest wait for a steady PV before the step, s.
    pub max_hold_s: f64,
    /// Record the step response for exactly this long, s (default: until
    /// PV has settled, at most `max_record_s`).
    pub record_s: Option<f64>,
    /// Longest step record, s.
    pub max_record_s: f64,
    /// The rule of the verification run.
    pub rule: Rule,
    pub rule_options: RuleOptions,
    /// Run the closed-loop verification.
    pub verify: bool,
    /// SV step of the verification, engineering units (default: the PV
    /// change of the step test, so MV moves on by about the test's step, in
    /// the same direction unless that leaves the range).
    pub sv_step: Option<f64>,
    /// Length of the verification after the SV step, s (default
    /// 10·τ + 20·θ + 10·CT).
    pub verify_s: Option<f64>,
    /// Settling band of the metrics, % of the SV step.
    pub band_pct: f64,
    /// Width of the centred moving average applied to PV before the
    /// verification metrics, s (0 = none), so that measurement noise does
    /// not count as leaving the band.
    pub smooth_s: f64,
    /// Head of the PID instruction's operation constants (S2): MTD (+0, float)
    /// and PN (+4) are written before the verification when given.
    pub pid_constants: Option<String>,
    /// Sampling period of the S.AT1 comparison, s (default: AT1ST, +72).
    pub at1_period: Option<f64>,
}

impl Options {
    /// The defaults for a loop tag at `loop_head`.
    pub fn new(loop_head: &str) -> Options {
        Options {
            loop_head: loop_head.to_string(),
            pv_device: None,
            pv_percent: false,
            step_pct: 10.0,
            initial_mv: None,
            min_hold_s: 30.0,
            max_hold_s: 3600.0,
            record_s: None,
            max_record_s: 4.0 * 3600.0,
            rule: Rule::SimcPi,
            rule_options: RuleOptions::default(),
            verify: true,
            sv_step: None,
            verify_s: None,
            band_pct: 2.0,
            smooth_s: 2.0,
            pid_constants: None,
            at1_period: None,
        }
    }
}

/// The open-loop step test.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StepTest {
    /// Virtual time of the step, s.
    pub at_s: f64,
    pub mv_before: f64,
    pub mv_after: f64,
    /// Steady PV before the step, and PV at the end of the record.
    pub pv_before: f64,
    pub pv_after: f64,
    /// Length of the record, s.
    pub record_s: f64,
    /// Whether PV was judged settled at the end of the record.
    pub settled: bool,
    pub samples: usize,
}

/// The identified process.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Identification {
    /// The fit in engineering units (gain: PV units per %MV).
    pub fit: FopdtFit,
    /// The process in the loop's units (gain: % of range per %MV).
    pub process: Process,
    /// RMS residual, % of range.
    pub rms_pct_of_range: f64,
}

/// The S.AT1 comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct At1Comparison {
    pub curve: Option<ReactionCurve>,
    /// Why S.AT1 would fail (its BB8 identification alarm).
    pub error: Option<String>,
    /// The ZN rows S.AT1 would write (P, PI, PID).
    pub rows: Vec<Tuning>,
}

/// The closed-loop run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verification {
    pub tuning: Tuning,
    /// Virtual time of the SV step, s.
    pub at_s: f64,
    pub sv_before: f64,
    pub sv_after: f64,
    pub duration_s: f64,
    pub metrics: StepMetrics,
    pub mv_min: f64,
    pub mv_max: f64,
    /// PV stays within the band from the settling time to the end of the
    /// run (a sustained oscillation through the band never settles).
    pub settled: bool,
}

/// Everything the workflow found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    pub scenario: String,
    pub loop_tag: String,
    pub scan_time_s: f64,
    pub range_low: f64,
    pub range_high: f64,
    pub control_cycle_s: f64,
    pub step_test: StepTest,
    pub identification: Identification,
    pub at1: At1Comparison,
    pub table: Vec<Tuning>,
    pub verification: Option<Verification>,
    pub warnings: Vec<String>,
    /// PV, SV and MV over the whole session, for the plot.
    #[serde(skip)]
    pub trend: TraceData,
    #[serde(skip)]
    pub trend_labels: Vec<String>,
}

/// Runs the workflow on a loaded scenario.
pub fn tune_scenario(sc: &Scenario, opts: &Options) -> Result<Report, String> {
    check_options(opts)?;
    if opts.pv_percent && opts.pv_device.is_none() {
        return Err("--pv-percent goes with --pv DEV".into());
    }
    let mut s = Session::start(
        sc,
        &opts.loop_head,
        opts.pv_device.as_deref(),
        opts.pv_percent,
    )?;
    let head = s.tag.head.clone();
    let mut warnings = Vec::new();

    // 1. The timeline (the program's start), then MAN.
    while s.run.steps_done() < s.timeline_scans.max(1) {
        s.scan()?;
    }
    let (rl, rh) = (s.read(offset::RL)?, s.read(offset::RH)?);
    let span = rh - rl;
    if !(span.is_finite() && span != 0.0) {
        return Err(format!(
            "loop {head}: the engineering range RH ({}) = {rh}, RL ({}) = {rl} is empty",
            s.tag.name_at(offset::RH),
            s.tag.name_at(offset::RL)
        ));
    }
    let ct = s.read(offset::CT)?;
    s.set_mode(MODE_MAN)?;
    if let Some(mv) = opts.initial_mv {
        s.write(offset::MV, mv)?;
    }
    s.scan()?;
    expect_mode(&s, MODE_MAN, "MAN")?;
    let tol = 0.0002 * span.abs();
    let (pv_before, _) = hold_until_steady(&mut s, opts, tol)?;

    // 2. The step.
    let mv_before = s.read(offset::MV)?;
    let mv_after = mv_before + opts.step_pct;
    let (mh, ml) = (s.read(offset::MH)?, s.read(offset::ML)?);
    if mv_after > mh.max(ml) || mv_after < ml.min(mh) {
        warnings.push(format!(
            "the stepped MV {mv_after:.2} % is outside ML..MH ({ml}..{mh} %); S.AT1 would refuse it (BB4/BB5)"
        ));
    }
    s.write(offset::MV, mv_after)?;
    let at_s = s.now() + s.scan_s;
    let (resp, settled) = record_step(&mut s, opts, pv_before, tol)?;
    if !settled {
        warnings.push(format!(
            "PV had not settled {:.0} s after the step: the fit extrapolates (give --record-for)",
            resp.t.last().copied().unwrap_or(0.0)
        ));
    }
    let step_test = StepTest {
        at_s,
        mv_before,
        mv_after,
        pv_before,
        pv_after: resp.y.last().copied().unwrap_or(pv_before),
        record_s: resp.t.last().copied().unwrap_or(0.0),
        settled,
        samples: resp.t.len(),
    };

    // 3. Identification.
    let fit = fit_fopdt(&resp).map_err(|e| format!("loop {head}: {e}"))?;
    let process = Process {
        gain: fit.gain * 100.0 / span,
        tau: fit.tau,
        dead_time: fit.dead_time,
    };
    let identification = Identification {
        fit,
        process,
        rms_pct_of_range: fit.rms * 100.0 / span.abs(),
    };
    if fit.r2 < 0.98 {
        warnings.push(format!(
            "the FOPDT fit is poor (R² = {:.4}): the process is not first order plus dead time",
            fit.r2
        ));
    }
    let at1_period = match opts.at1_period {
        Some(p) => p,
        None => s
            .read(offset::AT1ST)
            .ok()
            .filter(|p| *p > 0.0)
            .unwrap_or(1.0),
    };
    let at1 = at1_compare(&resp, rl, span, at1_period, process.gain, opts);
    if let Some(c) = &at1.curve {
        // S.AT1's Kp = c·|STEP|/100/(R·L); the fit's ZN Kp = c·τ/(K·θ).
        let zn_ratio = c.r * c.l * 100.0
            / (opts.step_pct.abs() * process.gain.abs() * process.dead_time / process.tau);
        if !(0.75..=1.33).contains(&zn_ratio) {
            warnings.push(format!(
                "S.AT1's R·L is {zn_ratio:.2}× the fit's K·θ/τ: its maximum-slope method is \
                 sensitive to noise and sampling (try a longer AT1ST, --at1-period)"
            ));
        }
    }
    let table = rules::table(&process, &opts.rule_options);
    if ct > 0.0 && process.dead_time > 0.0 && ct > process.dead_time / 2.0 {
        warnings.push(format!(
            "the control cycle CT = {ct} s is long against θ = {:.2} s: the rules assume continuous control",
            process.dead_time
        ));
    }

    // 4. Verification.
    let verification = if opts.verify {
        let pv_change = step_test.pv_after - step_test.pv_before;
        Some(verify(
            &mut s,
            opts,
            &process,
            ct,
            (rl, rh),
            pv_change,
            &mut warnings,
        )?)
    } else {
        None
    };
    Ok(Report {
        scenario: sc.file.display().to_string(),
        loop_tag: head,
        scan_time_s: s.scan_s,
        range_low: rl,
        range_high: rh,
        control_cycle_s: ct,
        step_test,
        identification,
        at1,
        table,
        verification,
        warnings,
        trend: s.trace(),
        trend_labels: s.labels().to_vec(),
    })
}

fn check_options(o: &Options) -> Result<(), String> {
    let pos = |v: f64, what: &str| {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(format!("{what} must be > 0 (got {v})"))
        }
    };
    if !(o.step_pct.is_finite() && o.step_pct != 0.0) {
        return Err(format!("--step must be a non-zero % (got {})", o.step_pct));
    }
    pos(o.max_hold_s, "the longest hold")?;
    pos(o.max_record_s, "the longest record")?;
    pos(o.band_pct, "--band")?;
    pos(o.rule_options.mtd, "--mtd")?;
    if let Some(r) = o.record_s {
        pos(r, "--record-for")?;
    }
    if let Some(v) = o.verify_s {
        pos(v, "--verify-for")?;
    }
    if !(o.smooth_s >= 0.0 && o.smooth_s.is_finite()) {
        return Err(format!("--smooth must be ≥ 0 (got {})", o.smooth_s));
    }
    if let Some(p) = o.at1_period {
        pos(p, "--at1-period")?;
    }
    if let Some(t) = o.rule_options.tau_c {
        pos(t, "--tau-c")?;
    }
    if o.sv_step.is_some_and(|v| !v.is_finite() || v == 0.0) {
        return Err("--sv-step must be a non-zero number".into());
    }
    Ok(())
}

fn expect_mode(s: &Session, want: u16, name: &str) -> Result<(), String> {
    let mode = s.tag.mode(s.cpu())?;
    if mode == want {
        return Ok(());
    }
    let alm = s.tag.alarms(s.cpu())?;
    let why = if alm & ALM_SPA != 0 {
        format!(
            "; the loop is stopped (ALM {} = {alm:04X}H has SPA, b14): the program must start it",
            s.tag.name_at(offset::ALM)
        )
    } else {
        String::new()
    };
    Err(format!(
        "loop {}: MODE {} reads {mode:X}H after writing {want:X}H ({name}){why}",
        s.tag.head,
        s.tag.name_at(offset::MODE)
    ))
}

/// Mean of `v[a..b]` from prefix sums.
fn mean(prefix: &[f64], a: usize, b: usize) -> f64 {
    (prefix[b] - prefix[a]) / (b - a).max(1) as f64
}

/// Holds MV until PV is steady: at least `min_hold_s`, and the drift over
/// the last quarter of the hold (the difference of the means of its two
/// halves) is either below `tol` when carried over a time as long as the hold
/// so far, or not significant against the noise (within 3 standard errors of
/// that difference). Returns the steady PV (mean of the last tenth) and the
/// hold time.
fn hold_until_steady(s: &mut Session, o: &Options, tol: f64) -> Result<(f64, f64), String> {
    let start = s.now();
    let mut sum = vec![0.0];
    let mut sum_sq = vec![0.0];
    loop {
        let x = s.scan()?;
        sum.push(sum[sum.len() - 1] + x.pv);
        sum_sq.push(sum_sq[sum_sq.len() - 1] + x.pv * x.pv);
        let n = sum.len() - 1;
        let held = s.now() - start;
        if held >= o.min_hold_s && n >= 8 {
            let w = (n / 4).max(4);
            let half = w / 2;
            let a = mean(&sum, n - w, n - half);
            let b = mean(&sum, n - half, n);
            let m = mean(&sum, n - w, n);
            let var = (mean(&sum_sq, n - w, n) - m * m).max(0.0);
            let noise = 3.0 * (var * 2.0 / half as f64).sqrt();
            let carried = (b - a).abs() * held / (half as f64 * s.scan_s);
            // (The noise test needs enough samples: on a noise-free drift the
            // spread of the window alone would pass it with few samples.)
            if carried <= tol || (half >= 25 && (b - a).abs() <= noise) {
                let tail = (n / 10).max(1);
                return Ok((mean(&sum, n - tail, n), held));
            }
        }
        if held >= o.max_hold_s {
            return Err(format!(
                "loop {}: PV did not become steady in {} s of MAN with MV held (give --mv0 or a longer hold)",
                s.tag.head, o.max_hold_s
            ));
        }
    }
}

/// Records PV after the step: for `record_s`, or until the mean PV over the
/// last 5 % of the record and over the 5 % ending at three quarters of it
/// differ by at most 0.5 % of the change (and the change exceeds `tol`).
fn record_step(
    s: &mut Session,
    o: &Options,
    pv0: f64,
    tol: f64,
) -> Result<(StepResponse, bool), String> {
    let t0 = s.now();
    let mut t = Vec::new();
    let mut y = Vec::new();
    let mut prefix = vec![0.0];
    let limit = o.record_s.unwrap_or(o.max_record_s);
    loop {
        let x = s.scan()?;
        // The first scan after the write is t = 0: the plant sees the new MV
        // from that scan's output.
        t.push(x.t - t0 - s.scan_s);
        y.push(x.pv);
        prefix.push(prefix[prefix.len() - 1] + x.pv);
        let n = y.len();
        let elapsed = x.t - t0;
        if o.record_s.is_none() && n >= 40 {
            let w = (n / 20).max(2);
            let end = mean(&prefix, n - w, n);
            let q = 3 * n / 4;
            let mid = mean(&prefix, q - w, q);
            let change = (end - pv0).abs();
            if change > tol && (end - mid).abs() <= 0.005 * change {
                return Ok((finish(t, y, pv0, o), true));
            }
        }
        if elapsed >= limit {
            let settled = o.record_s.is_some();
            return Ok((finish(t, y, pv0, o), settled));
        }
    }
}

fn finish(t: Vec<f64>, y: Vec<f64>, y0: f64, o: &Options) -> StepResponse {
    StepResponse {
        t,
        y,
        y0,
        du: o.step_pct,
    }
}

/// What S.AT1 would identify from the record, resampled every `period`
/// (sample k = the scan k·period after the step's scan).
fn at1_compare(
    resp: &StepResponse,
    rl: f64,
    span: f64,
    period: f64,
    gain_pct: f64,
    o: &Options,
) -> At1Comparison {
    let dt = if resp.t.len() > 1 {
        resp.t[1] - resp.t[0]
    } else {
        1.0
    };
    let pct = |v: f64| (v - rl) * 100.0 / span;
    // Sample 0 is PV in the scan of the step (S.AT1's PV0, DEC-32), not the
    // steady PV of the hold: S.AT1 executed before S.OUT1 in that scan sees
    // exactly these samples.
    let mut pv = vec![pct(resp.y.first().copied().unwrap_or(resp.y0))];
    let mut k = 1;
    loop {
        let i = ((k as f64 * period - resp.t[0]) / dt).round();
        if i < 0.0 || i as usize >= resp.y.len() {
            break;
        }
        pv.push(pct(resp.y[i as usize]));
        k += 1;
    }
    let rising = gain_pct * o.step_pct > 0.0;
    match at1::identify(&pv, period, rising) {
        Ok(c) => At1Comparison {
            rows: [Rule::ZnP, Rule::ZnPi, Rule::ZnPid]
                .iter()
                .filter_map(|r| c.zn(*r, o.step_pct, o.rule_options.mtd))
                .collect(),
            curve: Some(c),
            error: None,
        },
        Err(e) => At1Comparison {
            curve: None,
            error: Some(e),
            rows: Vec::new(),
        },
    }
}

/// The closed-loop verification run.
fn verify(
    s: &mut Session,
    o: &Options,
    process: &Process,
    ct: f64,
    (rl, rh): (f64, f64),
    pv_change: f64,
    warnings: &mut Vec<String>,
) -> Result<Verification, String> {
    let tuning = rules::tune(o.rule, process, &o.rule_options)
        .map_err(|e| format!("--rule {}: {e}", o.rule.name()))?;
    s.write(offset::P, tuning.p)?;
    s.write(offset::I, tuning.ti)?;
    s.write(offset::D, tuning.td)?;
    let reverse = process.gain >= 0.0;
    match &o.pid_constants {
        Some(given) => {
            let (cpu, head) = s
                .run
                .split_name(given)
                .map_err(|e| format!("--pid-constants: {e}"))?;
            let mtd = device_at(head, 0, "f32").map_err(|e| format!("--pid-constants: {e}"))?;
            let pn = device_at(head, 4, "u16").map_err(|e| format!("--pid-constants: {e}"))?;
            write_value(s, cpu, &mtd, Value::Float(o.rule_options.mtd))?;
            write_value(s, cpu, &pn, Value::Int(i64::from(!reverse)))?;
        }
        None if !reverse => warnings.push(
            "the process gain is negative: the PID needs forward action (PN = 1); \
             give --pid-constants to have it written"
                .into(),
        ),
        None => {}
    }
    // SV := PV while still in MAN, for two control cycles, so that the
    // PID's previous deviation (DVn-1, +110) is the one of SV = PV and the
    // switch to AUT is bumpless.
    let pv = s.pv()?;
    s.write(offset::SV, pv)?;
    s.scan_for(2.0 * ct.max(0.0) + 2.0 * s.scan_s)?;
    s.set_mode(MODE_AUT)?;
    s.scan()?;
    expect_mode(s, MODE_AUT, "AUT")?;
    // Let the loop take over bumplessly for a few control cycles.
    s.scan_for((3.0 * ct).max(5.0 * s.scan_s))?;
    let sv_before = s.read(offset::SV)?;
    let step = o.sv_step.unwrap_or_else(|| {
        let min = 0.01 * (rh - rl).abs();
        let step = if pv_change.abs() < min {
            min.copysign(pv_change)
        } else {
            pv_change
        };
        if sv_before + step > rh.max(rl) || sv_before + step < rh.min(rl) {
            -step
        } else {
            step
        }
    });
    let sv_after = sv_before + step;
    s.write(offset::SV, sv_after)?;
    let duration = o
        .verify_s
        .unwrap_or(10.0 * process.tau + 20.0 * process.dead_time + 10.0 * ct)
        .max(50.0 * s.scan_s)
        .min(o.max_record_s);
    let t0 = s.now();
    let n = (duration / s.scan_s).ceil() as usize;
    let (mut t, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut mv_min, mut mv_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for _ in 0..n {
        let x = s.scan()?;
        t.push(x.t - t0 - s.scan_s);
        y.push(x.pv);
        mv_min = mv_min.min(x.mv);
        mv_max = mv_max.max(x.mv);
    }
    let half = (o.smooth_s / 2.0 / s.scan_s).round() as usize;
    let y = centred_mean(&y, half);
    let metrics = step_metrics(&t, &y, y[0], sv_after, o.band_pct);
    let (mh, ml) = (s.read(offset::MH)?, s.read(offset::ML)?);
    if mv_max >= mh.max(ml) || mv_min <= ml.min(mh) {
        warnings.push(format!(
            "MV reached its limit during the verification ({mv_min:.1}..{mv_max:.1} %, ML..MH {ml}..{mh} %): \
             the response is not linear; try a smaller --sv-step"
        ));
    }
    let settled = metrics.settling_time.is_some();
    if !settled {
        warnings.push(format!(
            "the closed loop did not settle within ±{} % in {duration:.0} s with {}",
            o.band_pct,
            o.rule.name()
        ));
    }
    Ok(Verification {
        tuning,
        at_s: t0 + s.scan_s,
        sv_before,
        sv_after,
        duration_s: duration,
        metrics,
        mv_min,
        mv_max,
        settled,
    })
}

/// The centred moving average of `y` over `2·half + 1` samples (fewer at
/// the ends).
fn centred_mean(y: &[f64], half: usize) -> Vec<f64> {
    if half == 0 {
        return y.to_vec();
    }
    let mut prefix = vec![0.0];
    for v in y {
        prefix.push(prefix[prefix.len() - 1] + v);
    }
    (0..y.len())
        .map(|i| mean(&prefix, i.saturating_sub(half), (i + half + 1).min(y.len())))
        .collect()
}

fn write_value(s: &mut Session, cpu: usize, d: &DeviceSpec, v: Value) -> Result<(), String> {
    s.run
        .cpu_at_mut(cpu)
        .write_value(d, &v)
        .map_err(|e| format!("--pid-constants: {e}"))
}
