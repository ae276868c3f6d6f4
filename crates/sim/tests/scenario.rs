//! The scenario runner: file format and validation, timing of models, the
//! timeline and the assertions in virtual time, failure reports, traces and
//! plots, and the shipped examples (examples/sim/*.toml).

use std::path::{Path, PathBuf};

use softplc_core::device::DeviceConfig;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_sim::plot;
use softplc_sim::scenario::{ExpectKind, Outcome, Scenario};

/// Parses `scenario` (without the `program` line) and builds it against the
/// inline program text.
fn build(program: &str, scenario: &str) -> Result<softplc_sim::scenario::Run, String> {
    let sc = parse(scenario)?;
    let clock = VirtualClock::new();
    let prog =
        compile_il("inline.il", program, &DeviceConfig::default()).map_err(|d| d.to_string())?;
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(clock.clone()),
    );
    sc.build_with(cpu, clock)
}

fn parse(scenario: &str) -> Result<Scenario, String> {
    Scenario::parse(
        &format!("program = \"inline.il\"\n{scenario}"),
        Path::new("inline.toml"),
    )
}

fn run(program: &str, scenario: &str) -> Outcome {
    build(program, scenario)
        .unwrap_or_else(|e| panic!("{e}"))
        .run(&mut |_| {})
}

fn parse_err(scenario: &str) -> String {
    match parse(scenario) {
        Ok(_) => panic!("expected an error for:\n{scenario}"),
        Err(e) => e,
    }
}

#[track_caller]
fn assert_all_pass(o: &Outcome) {
    let report = o.report(false);
    assert_eq!(o.failed(), 0, "{report}");
    assert!(o.passed() > 0, "{report}");
}

const HEAD: &str = "scan_time = \"10ms\"\nduration = \"2s\"\n";

// ---------------------------------------------------------------- format

/// `cpu` names a MELSEC model or the APLC-TCP, and must fit the program's
/// dialect: the APLC-TCP runs `.apl` files only.
#[test]
fn the_cpu_model_must_run_the_program_file() {
    assert!(parse(&format!("{HEAD}cpu = \"Q06HCPU\"\n")).is_ok());
    let e = parse_err(&format!("{HEAD}cpu = \"aplc-tcp\"\n"));
    assert!(
        e.contains("cpu: APLC-TCP does not run") && e.contains("inline.il"),
        "{e}"
    );
    let e = parse_err(&format!("{HEAD}cpu = \"Q99CPU\"\n"));
    assert!(
        e.contains("unknown CPU model \"Q99CPU\"") && e.contains("or APLC-TCP"),
        "{e}"
    );
    let apl = Scenario::parse(
        &format!("program = \"a.apl\"\n{HEAD}cpu = \"APLC-TCP\"\n"),
        Path::new("a.toml"),
    );
    assert!(apl.is_ok(), "{:?}", apl.err());
    let e = Scenario::parse(
        &format!("program = \"a.apl\"\n{HEAD}cpu = \"Q06HCPU\"\n"),
        Path::new("a.toml"),
    )
    .err()
    .unwrap_or_default();
    assert!(
        e.contains("cpu: Q06HCPU does not run") && e.contains("a.apl"),
        "{e}"
    );
}

#[test]
fn parses_times_models_timeline_and_expectations() {
    let sc = parse(&format!(
        "{HEAD}
[[model]]
type = \"motor\"
params = {{ accel_time = \"1s\" }}
inputs.run = \"Y0\"
outputs.running = \"X4\"
outputs.speed = {{ device = \"D20\", eng = [0, 100], raw = [0, 4000] }}

[[timeline]]
at = \"0.5s\"
set = {{ X0 = true, \"D10:f32\" = 1.5 }}

[[timeline]]
scan = 3
every = \"100ms\"
count = 4
set = {{ X1 = 1 }}

[[expect]]
device = \"Y0\"
equals = true
at = \"1s\"
"
    ))
    .unwrap();
    assert_eq!(sc.scan_us, 10_000);
    assert_eq!(sc.scans, 200);
    assert_eq!(sc.models.len(), 1);
    assert_eq!(sc.models[0].name, "motor");
    assert_eq!(sc.models[0].outputs.len(), 2);
    // 0.5 s is scan 50; the repeated entry expands to scans 3, 13, 23, 33.
    let scans: Vec<u64> = sc.timeline.iter().map(|e| e.scan).collect();
    assert_eq!(scans, vec![3, 13, 23, 33, 50]);
    assert_eq!(
        sc.timeline[4].set,
        vec![("D10:f32".into(), "1.5".into()), ("X0".into(), "1".into())]
    );
    assert_eq!(sc.expects[0].text, "Y0 = true at 1 s");
    assert!(matches!(
        sc.expects[0].kind,
        ExpectKind::At { scan: 100, .. }
    ));
}

#[test]
fn rejects_bad_scenarios_with_useful_messages() {
    let cases: &[(&str, &str)] = &[
        ("scan_time = \"10ms\"\n", "duration"),
        (&format!("{HEAD}bogus = 1\n"), "unknown field `bogus`"),
        ("scan_time = \"0s\"\nduration = \"1s\"\n", "scan_time"),
        (
            &format!("{HEAD}[[model]]\ntype = \"pump\"\n"),
            "unknown model type `pump`",
        ),
        (
            &format!("{HEAD}[[model]]\ntype = \"motor\"\ninputs.speed = \"D0\"\n"),
            "has no input `speed` (inputs: run)",
        ),
        (
            &format!("{HEAD}[[model]]\ntype = \"motor\"\nparams = {{ acel_time = 1 }}\n"),
            "unknown parameter `acel_time`",
        ),
        (
            &format!("{HEAD}[[model]]\ntype = \"motor\"\noutputs.running = {{ device = \"X4\", raw = [0, 1] }}\n"),
            "a bit device takes no `raw` range",
        ),
        (
            &format!("{HEAD}[[model]]\ntype = \"fopdt\"\noutputs.y = {{ device = \"D0\", raw = [0, 4000] }}\n"),
            "give both `raw` and `eng`",
        ),
        (
            &format!("{HEAD}[[model]]\ntype = \"fopdt\"\noutputs.y = \"Q7\"\n"),
            "output `y`",
        ),
        (
            &format!("{HEAD}[[timeline]]\nset = {{ X0 = 1 }}\n"),
            "give exactly one of `at` (a time) or `scan`",
        ),
        (
            &format!("{HEAD}[[timeline]]\nat = \"2.5s\"\nset = {{ X0 = 1 }}\n"),
            "scan 250 is after the end of the run (200 scans)",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"Y0\"\nequals = true\nat = \"3s\"\n"),
            "at 3 s is after the end of the run (2 s)",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"Y0\"\nequals = true\nwithin = \"2s\"\nafter = \"1s\"\n"),
            "after the end of the run",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"Y0\"\nequals = true\n"),
            "give exactly one of `at`, `within`",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"Y0\"\nat = \"1s\"\n"),
            "give a condition",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"Y0\"\nabove = 1\nat = \"1s\"\n"),
            "a bit device takes `equals = true/false`",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"D0\"\nsetpoint = 5\nband = 2\n"),
            "give `settle_within` and/or `max_overshoot`",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"D0\"\nequals = 1\nat = \"1s\"\nfrmo = 1\n"),
            "unknown key `frmo`",
        ),
        (
            &format!("{HEAD}[[expect]]\ndevice = \"D0:str\"\nequals = 1\nat = \"1s\"\n"),
            "strings cannot be",
        ),
    ];
    for (text, want) in cases {
        let e = parse_err(text);
        assert!(e.contains(want), "error `{e}` should contain `{want}`");
        assert!(e.starts_with("inline.toml: "), "{e}");
    }
    // Both program and project.
    let e = Scenario::parse(
        &format!("program = \"a.il\"\nproject = \"p\"\n{HEAD}"),
        Path::new("x.toml"),
    )
    .unwrap_err();
    assert!(e.contains("exactly one of `program`"), "{e}");
    // Device range and value errors surface when building against the CPU.
    let e = build(
        "END\n",
        &format!("{HEAD}[[timeline]]\nat = 0\nset = {{ D0 = 70000 }}\n"),
    )
    .err()
    .unwrap();
    assert!(e.contains("`D0`: `70000` is not a valid"), "{e}");
    let e = build(
        "END\n",
        &format!("{HEAD}[[expect]]\ndevice = \"D99999\"\nequals = 0\nat = \"1s\"\n"),
    )
    .err()
    .unwrap();
    assert!(e.contains("D99999"), "{e}");
}

// ---------------------------------------------------------------- timing

#[test]
fn timeline_writes_before_the_scan_at_or_after_their_time() {
    // X0 at 1 s = before scan 100; Y0 follows in that scan, M0 (PLS) is ON
    // for exactly that scan.
    let o = run(
        "LD X0\nOUT Y0\nLD X0\nPLS M0\nEND\n",
        &format!(
            "{HEAD}
[[timeline]]
at = \"1s\"
set = {{ X0 = 1 }}

[[expect]]
device = \"Y0\"
never = true
equals = true
to = \"1s\"

[[expect]]
device = \"Y0\"
equals = true
within = \"0s\"
after = \"1s\"

[[expect]]
device = \"M0\"
equals = true
at = \"1s\"

[[expect]]
device = \"M0\"
equals = false
at = \"1.01s\"
"
        ),
    );
    assert_all_pass(&o);
    assert_eq!(o.results[0].detail, "99 scans checked");
    assert_eq!(o.results[1].detail, "at 1 s (scan 100)");
}

#[test]
fn models_step_before_each_scan_and_see_the_last_scans_outputs() {
    // The program writes D820 = 1000 in every scan; the integrator reads it
    // through a D/A range 0..2000 -> 0..100, i.e. 50/s. Before scan 1 it still
    // reads 0, so at scan n its output is 50·(n−1)·dt. The output goes to
    // D10:f32 unscaled and, with an A/D range, to D0.
    let o = run(
        "LD SM400\nMOV K1000 D820\nEND\n",
        &format!(
            "{HEAD}
[[model]]
type = \"integrator\"
inputs.u = {{ device = \"D820\", raw = [0, 2000], eng = [0, 100] }}
outputs.y = \"D10:f32\"

[[model]]
name = \"copy\"
type = \"integrator\"
params = {{ gain = 0 }}
inputs.u = 1

[[model]]
name = \"adc\"
type = \"fopdt\"
params = {{ tau = 0 }}
inputs.u = \"D10:f32\"
outputs.y = {{ device = \"D0\", eng = [0, 100], raw = [0, 4000] }}

[[expect]]
device = \"D10:f32\"
equals = 49.5
tolerance = 1e-4
at = \"1s\"

[[expect]]
device = \"D0\"
equals = 1980
at = \"1s\"

[[expect]]
device = \"D10:f32\"
equals = 99.5
tolerance = 1e-4
at = \"2s\"
"
        ),
    );
    assert_all_pass(&o);
}

#[test]
fn x_outputs_go_through_the_input_image() {
    // The motor's running contact drives X4 (the program only reads it); the
    // feedback needs 0.5 s to reach 50 % plus 0.2 s debounce.
    let o = run(
        "LD X0\nOUT Y0\nLD X4\nOUT Y4\nEND\n",
        &format!(
            "{HEAD}
[[model]]
type = \"motor\"
params = {{ accel_time = \"1s\", feedback_delay = \"200ms\" }}
inputs.run = \"Y0\"
outputs.running = \"X4\"
outputs.speed = \"D20\"

[[timeline]]
scan = 1
set = {{ X0 = 1 }}

[[expect]]
device = \"Y4\"
equals = true
within = \"2s\"
show = [\"D20\"]

[[expect]]
device = \"D20\"
equals = 100
at = \"1.5s\"
"
        ),
    );
    assert_all_pass(&o);
    // Y0 is ON after scan 1, the motor starts in the step before scan 2:
    // 50 % after 0.5 s (scan 51), the contact 0.2 s later (step before scan
    // 71), Y4 in scan 71.
    assert_eq!(o.results[0].detail, "at 710 ms (scan 71)");
}

/// Bindings and expectations resolve plain names once (a bit, a bit of a
/// word, one or two words) and read digit-specified names through the name:
/// every kind reads and writes the value its name means.
#[test]
fn bindings_and_checks_read_each_kind_of_name_by_value() {
    // The ramp (1/s) goes to D10:f32; the counter (100/s: 1 a scan, exact)
    // to K4M0, which the program copies to D20; the flag (0.8/s, ON above
    // 0.5 from scan 63) to bit 3 of D1, which the timeline sets to 5 at scan
    // 1 and the program copies to D2. D0 = 10 is 1010b; D30:i32 = 100000 is
    // 0001 86A0, a low word alone would read 86A0. D18Z0 is D20 (Z0 = 2),
    // read through its name at every scan.
    let o = run(
        "LD SM400\nMOV K10 D0\nDMOV K100000 D30\nMOV K4M0 D20\nMOV D1 D2\nMOV K2 Z0\nEND\n",
        &format!(
            "{HEAD}
[[model]]
name = \"ramp\"
type = \"integrator\"
inputs.u = 1
outputs.y = \"D10:f32\"

[[model]]
name = \"counter\"
type = \"integrator\"
params = {{ gain = 100 }}
inputs.u = 1
outputs.y = \"K4M0\"

[[model]]
name = \"flag\"
type = \"integrator\"
params = {{ gain = 0.8 }}
inputs.u = 1
outputs.y = \"D1.3\"

[[timeline]]
scan = 1
set = {{ D1 = 5 }}

[[expect]]
device = \"D10:f32\"
equals = 0.5
tolerance = 1e-6
at = \"0.5s\"

[[expect]]
device = \"D10:f32\"
equals = 1.0
tolerance = 1e-6
at = \"1s\"

[[expect]]
device = \"K4M0\"
equals = 100
at = \"1s\"

[[expect]]
device = \"D20\"
equals = 100
at = \"1s\"

[[expect]]
device = \"M2\"
equals = true
at = \"1s\"

[[expect]]
device = \"M3\"
equals = false
at = \"1s\"

[[expect]]
device = \"D1.3\"
equals = false
at = \"0.62s\"

[[expect]]
device = \"D1.3\"
equals = true
at = \"0.63s\"

[[expect]]
device = \"D2\"
equals = 5
at = \"0.62s\"

[[expect]]
device = \"D2\"
equals = 13
at = \"0.63s\"

[[expect]]
device = \"D0.3\"
always = true
equals = true

[[expect]]
device = \"D0.2\"
never = true
equals = true

[[expect]]
device = \"D30:i32\"
equals = 100000
at = \"1s\"

[[expect]]
device = \"D18Z0\"
equals = 100
at = \"1s\"
"
        ),
    );
    assert_all_pass(&o);
    assert_eq!(o.passed(), 14);
}

/// A model writing X that the program reads: the write reaches the input
/// image (it survives the input refresh) and its rising edge is seen once.
#[test]
fn a_model_output_on_x_is_an_input_the_program_reads() {
    // y = 0.008·n before scan n: above 0.5 from scan 63 on.
    let o = run(
        "LDP X5\nINC D0\nLD X5\nOUT Y0\nEND\n",
        &format!(
            "{HEAD}
[[model]]
type = \"integrator\"
params = {{ gain = 0.8 }}
inputs.u = 1
outputs.y = \"X5\"

[[expect]]
device = \"Y0\"
equals = true
within = \"2s\"

[[expect]]
device = \"X5\"
equals = false
at = \"0.62s\"

[[expect]]
device = \"X5\"
equals = true
at = \"0.63s\"

[[expect]]
device = \"D0\"
equals = 1
at = \"2s\"
"
        ),
    );
    assert_all_pass(&o);
    assert_eq!(o.results[0].detail, "at 630 ms (scan 63)");
}

/// A model writing a forced X: the forced value wins, for the program and
/// for a later model reading it in the same step; the written value is the
/// one under the force and comes back at release.
#[test]
fn a_model_output_on_a_forced_x_keeps_the_force() {
    // "off" writes X5 OFF before every scan; "count" integrates X5 (1/s)
    // into D10:f32, after "off" in the same step.
    let scenario = parse(&format!(
        "{HEAD}
[[model]]
name = \"off\"
type = \"integrator\"
params = {{ gain = 0 }}
inputs.u = 1
outputs.y = \"X5\"

[[model]]
name = \"count\"
type = \"integrator\"
inputs.u = \"X5\"
outputs.y = \"D10:f32\"
"
    ))
    .unwrap();
    let clock = VirtualClock::new();
    let prog = compile_il(
        "inline.il",
        "LD X5\nOUT Y0\nEND\n",
        &DeviceConfig::default(),
    )
    .unwrap();
    let mut cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(clock.clone()),
    );
    cpu.force(softplc_core::device::DeviceKind::X, 5, true)
        .unwrap();
    let mut run = scenario.build_with(cpu, clock).unwrap();
    for _ in 0..100 {
        run.step().unwrap();
    }
    let read = |run: &softplc_sim::scenario::Run, d: &str| {
        let spec = softplc_core::access::DeviceSpec::parse(d).unwrap();
        run.cpu().read_device(&spec).unwrap()
    };
    use softplc_core::access::Value;
    // 100 steps of 1·0.01 s: 1.0 as an f32.
    assert_eq!(read(&run, "D10:f32"), Value::Float(1.0));
    assert_eq!(read(&run, "X5"), Value::Bool(true));
    assert_eq!(read(&run, "Y0"), Value::Bool(true));
    // Released, X5 is what "off" wrote: OFF.
    assert!(run
        .cpu_mut()
        .release(softplc_core::device::DeviceKind::X, 5));
    assert_eq!(read(&run, "X5"), Value::Bool(false));
    run.step().unwrap();
    assert_eq!(read(&run, "Y0"), Value::Bool(false));
    // Scan 101's step read X5 OFF: D10 stays 1.0.
    assert_eq!(read(&run, "D10:f32"), Value::Float(1.0));
}

// ---------------------------------------------------------------- failures

#[test]
fn a_wrong_value_reports_the_first_failing_scan_and_history() {
    let o = run(
        "LD SM400\nINC D0\nEND\n",
        &format!(
            "{HEAD}
[[expect]]
device = \"D0\"
equals = 7
at = \"1s\"
show = [\"SM400\"]
"
        ),
    );
    assert_eq!((o.passed(), o.failed()), (0, 1));
    let r = &o.results[0];
    assert_eq!(r.text, "D0 = 7 at 1 s");
    assert_eq!(r.detail, "got 100 at 1 s (scan 100)");
    let f = r.failure.as_ref().unwrap();
    assert_eq!((f.scan, f.time_us), (100, 1_000_000));
    assert_eq!(f.columns[0].0, "D0");
    assert_eq!(f.columns[1].0, "SM400");
    // 5 samples up to the failing scan, 3 after.
    let scans: Vec<u64> = f.rows.iter().map(|r| r.0).collect();
    assert_eq!(scans, vec![96, 97, 98, 99, 100, 101, 102, 103]);
    assert_eq!(f.rows[4].1, vec![100.0, 1.0]);
    let report = o.report(false);
    assert!(report.contains("FAIL D0 = 7 at 1 s: got 100"), "{report}");
    assert!(
        report.contains("first failing scan 100 (t = 1.000 s)"),
        "{report}"
    );
    assert!(report.contains("> 100"), "{report}");
    assert!(report.contains("scan"), "{report}");
}

#[test]
fn within_fails_at_the_deadline_and_never_at_the_first_violation() {
    let o = run(
        "LD X0\nOUT T0 K10\nLD T0\nOUT Y0\nLD SM400\nMOV TN0 D5\nEND\n",
        &format!(
            "{HEAD}
[[timeline]]
at = \"0.5s\"
set = {{ X0 = 1 }}

[[expect]]
device = \"Y0\"
equals = true
within = \"0.5s\"
after = \"0.5s\"

[[expect]]
device = \"Y0\"
equals = true
within = \"1s\"
after = \"0.5s\"

[[expect]]
device = \"D5\"
never_exceeds = 4
show = [\"X0\"]

[[expect]]
device = \"D5\"
always = true
at_most = 10
"
        ),
    );
    // T0 (100 ms, K10) times out 1 s after X0: Y0 at 1.5 s.
    assert_eq!(o.failed(), 2, "{}", o.report(false));
    assert!(!o.results[0].passed);
    assert_eq!(o.results[0].detail, "still false at 1 s (scan 100)");
    assert_eq!(o.results[0].failure.as_ref().unwrap().scan, 100);
    assert!(o.results[1].passed);
    assert_eq!(o.results[1].detail, "at 1.5 s (scan 150)");
    // TN0 reaches 5 at 1 s (scan 100: 50 scans = 0.5 s = 5 counts).
    assert!(!o.results[2].passed);
    let f = o.results[2].failure.as_ref().unwrap();
    assert_eq!(f.scan, 100, "{}", o.report(false));
    assert_eq!(o.results[2].detail, "5 at 1 s (scan 100)");
    assert!(o.results[3].passed);
    assert_eq!(o.results[3].detail, "min 0, max 10");
}

#[test]
fn settle_time_and_overshoot() {
    // A first-order lag (τ = 10 s) driven to 100 enters the ±2 % band at
    // t = 10·ln 50 = 39.12 s (the sample at 39.13 s); a second-order lag with ζ = 0.5 overshoots by
    // e^(−πζ/√(1−ζ²)) = 16.3 %.
    let scenario = |settle: &str, overshoot: f64| {
        format!(
            "scan_time = \"10ms\"
duration = \"60s\"

[[model]]
type = \"fopdt\"
params = {{ tau = \"10s\" }}
inputs.u = 100
outputs.y = \"D0:f32\"

[[model]]
type = \"second_order\"
params = {{ zeta = 0.5, omega = 1 }}
inputs.u = 100
outputs.y = \"D2:f32\"

[[expect]]
device = \"D0:f32\"
setpoint = 100
band = 2
settle_within = \"{settle}\"

[[expect]]
device = \"D2:f32\"
setpoint = 100
band = 2
max_overshoot = {overshoot}
"
        )
    };
    let o = run("END\n", &scenario("40s", 17.0));
    assert_all_pass(&o);
    assert_eq!(
        o.results[0].detail,
        "settled after 39.13 s, overshoot 0.0 %",
        "{}",
        o.report(false)
    );
    assert!(
        o.results[1].detail.contains("overshoot 16.3 %"),
        "{}",
        o.results[1].detail
    );

    let o = run("END\n", &scenario("30s", 15.0));
    assert_eq!(o.failed(), 2);
    assert!(
        // The step is taken from the first sample (y = 0.0999 after 10 ms).
        o.results[0].detail
            == "95.02129 is outside the band 98.002…101.998 at the deadline, 30 s (scan 3000)",
        "{}",
        o.results[0].detail
    );
    assert!(
        o.results[1]
            .detail
            .starts_with("overshoot 15.1 % > 15 % at 3.26 s (scan 326)"),
        "{}",
        o.results[1].detail
    );
}

#[test]
fn a_cpu_stop_error_fails_the_scenario() {
    let o = run(
        "LD X0\n/ D0 D1 D2\nEND\n",
        &format!(
            "{HEAD}
[[timeline]]
at = \"0.5s\"
set = {{ X0 = 1 }}

[[expect]]
device = \"D2\"
equals = 0
at = \"0.2s\"

[[expect]]
device = \"D2\"
equals = 0
at = \"1s\"
"
        ),
    );
    assert_eq!(o.scans, 50);
    assert_eq!((o.passed(), o.failed()), (1, 2), "{}", o.report(false));
    assert_eq!(
        o.results[1].detail,
        "not decided: the CPU stopped at 500 ms (scan 50)"
    );
    assert!(o.results[2].text.contains("the CPU keeps running"));
    assert!(
        o.results[2].detail.contains("4100"),
        "{}",
        o.results[2].detail
    );
}

#[test]
fn stepping_scan_by_scan_matches_the_run_and_reports_a_stop() {
    // The integrator of `models_step_before_each_scan…` driven by `Run::step`
    // gives the values `Run::run` gives (50·(n−1)·dt at scan n); the timeline
    // is applied, the CPU is reachable between scans, and a stop is an error
    // naming the scan and the error code.
    let scenario = format!(
        "{HEAD}
[[model]]
type = \"integrator\"
inputs.u = {{ device = \"D820\", raw = [0, 2000], eng = [0, 100] }}
outputs.y = \"D10:f32\"

[[timeline]]
at = \"0.5s\"
set = {{ X0 = 1 }}
"
    );
    let program = "LD SM400\nMOV K1000 D820\nLD X0\n/ D0 D1 D2\nEND\n";
    let mut run = build(program, &scenario).unwrap();
    assert_eq!(run.scan_us(), 10_000);
    for n in 1..=49u64 {
        assert_eq!(run.step().unwrap(), n * 10_000);
    }
    assert_eq!(run.steps_done(), 49);
    let spec = softplc_core::access::DeviceSpec::parse("D10:f32").unwrap();
    let y = run.cpu().read_device(&spec).unwrap();
    assert_eq!(
        y,
        softplc_core::access::Value::Float(f64::from(48.0f32 * 0.5))
    );
    // Between scans the driver may write devices: D1 = 0 stays a division
    // by zero at scan 50, when the timeline turns X0 on.
    let d1 = softplc_core::access::DeviceSpec::parse("D1").unwrap();
    run.cpu_mut().write_device(&d1, "0").unwrap();
    let e = run.step().unwrap_err();
    assert!(e.contains("scan 50") && e.contains("4100"), "{e}");
    assert!(run.step().unwrap_err().contains("stopped"));
}

// ---------------------------------------------------------------- trace, plot, progress

#[test]
fn trace_samples_csv_plot_and_progress() {
    let run = build(
        "LD SM400\nINC D0\nLD SM412\nOUT Y0\nEND\n",
        "scan_time = \"1ms\"
duration = \"40s\"

[trace]
devices = [\"D0\", \"Y0\"]
interval = \"100ms\"

[plot]
file = \"x.svg\"
",
    )
    .unwrap();
    assert_eq!(run.total_scans(), 40_000);
    let mut calls = Vec::new();
    let o = run.run(&mut |n| calls.push(n));
    assert_eq!(calls.len(), 3, "{calls:?}"); // 16384, 32768, and the end
    assert_eq!(*calls.last().unwrap(), 40_000);
    let t = o.trace.as_ref().unwrap();
    // Scan 1, every 100th scan, and the last (which is a 100th).
    assert_eq!(t.len(), 401);
    assert_eq!(t.scans[..3], [1, 100, 200]);
    let csv = t.to_csv();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("scan,time_s,D0,Y0"));
    assert_eq!(lines.next(), Some("1,0.001,1,0"));
    assert_eq!(lines.next(), Some("100,0.100,100,0"));
    let svg = plot::render_svg(t, &["D0".into(), "Y0".into()], "test plot").unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..100]);
    assert!(svg.contains("test plot") && svg.contains("D0") && svg.contains("Y0"));
    assert!(svg.len() < 200_000, "{}", svg.len());
    assert!(plot::render_svg(t, &["D7".into()], "x")
        .unwrap_err()
        .contains("D7"));
}

#[test]
fn long_traces_are_capped_by_default() {
    let sc = parse(
        "scan_time = \"1ms\"
duration = \"100s\"
[trace]
devices = [\"SD520\"]
",
    )
    .unwrap();
    let clock = VirtualClock::new();
    let prog = compile_il("inline.il", "END\n", &DeviceConfig::default()).unwrap();
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(clock.clone()),
    );
    let o = sc.build_with(cpu, clock).unwrap().run(&mut |_| {});
    let t = o.trace.unwrap();
    assert!(t.len() <= 10_002 && t.len() > 9_000, "{}", t.len());
}

// ---------------------------------------------------------------- examples

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/sim")
}

#[test]
fn the_examples_pass() {
    let mut n = 0;
    for entry in std::fs::read_dir(examples()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let mut sc = Scenario::load(&path).unwrap();
            sc.plot = None; // do not rewrite the committed SVGs
            let o = sc.build().unwrap().run(&mut |_| {});
            assert_all_pass(&o);
            n += 1;
        }
    }
    assert!(n >= 3, "{n} example scenarios");
    // The soak scenario parses (it is run in release mode only).
    let soak = Scenario::load(&examples().join("soak/heated_tank_24h.toml")).unwrap();
    assert_eq!(soak.scans, 8_640_000);
}
