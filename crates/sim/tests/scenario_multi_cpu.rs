//! Scenarios of multi-CPU systems (contract §6): a system directory as the
//! scenario's project, `CPUn/` names in bindings, timeline, expectations
//! and traces, the CPUs at their own constant scans in one virtual time,
//! the auto refresh seen from a scenario, stop errors, determinism and the
//! errors of bad names. Values worked out by hand.

use std::path::{Path, PathBuf};

use softplc_sim::scenario::{Outcome, Scenario};

/// A system in a temporary directory: `cpus` are (extra plc.toml, main.il)
/// of CPU 1, 2, … (each plc.toml has `[multi_cpu] cpus = N`).
fn system(cpus: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let mut manifest = String::new();
    for (i, (toml, il)) in cpus.iter().enumerate() {
        let d = dir.path().join(format!("cpu{}", i + 1));
        std::fs::create_dir(&d).unwrap();
        let toml = format!(
            "{toml}\n[[program]]\nfile = \"main.il\"\n\n[multi_cpu]\ncpus = {}\n{REFRESH}",
            cpus.len()
        );
        std::fs::write(d.join("plc.toml"), toml).unwrap();
        std::fs::write(d.join("main.il"), il).unwrap();
        manifest += &format!("[[cpu]]\nproject = \"cpu{}\"\n", i + 1);
    }
    std::fs::write(dir.path().join("system.toml"), manifest).unwrap();
    dir
}

/// Every CPU sends 2 words from D1000 (CPU 1: D1000-D1001, CPU 2:
/// D1002-D1003).
const REFRESH: &str = "[[multi_cpu.refresh]]\ndevice = \"D1000\"\nwords = [2, 2]\n";

const IDLE: &str = "LD SM400\nOUT M0\nEND\n";

/// Writes `text` (after `project = "."` and a 10 ms scan) as the scenario
/// file of the system in `dir` and loads it.
fn load(dir: &Path, text: &str) -> Result<Scenario, String> {
    let path = dir.join("scenario.toml");
    std::fs::write(
        &path,
        format!("project = \".\"\nscan_time = \"10ms\"\n{text}"),
    )
    .unwrap();
    Scenario::load(&path)
}

fn run(dir: &Path, text: &str) -> Outcome {
    load(dir, text)
        .unwrap_or_else(|e| panic!("{e}"))
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
        .run(&mut |_| {})
}

/// Runs the scenario `text` (as [`load`] writes it) on a new system of
/// `cpus` (as [`system`] builds it).
fn run_on(cpus: &[(&str, &str)], text: &str) -> Outcome {
    let dir = system(cpus);
    run(dir.path(), text)
}

#[track_caller]
fn assert_all_pass(o: &Outcome) {
    let report = o.report(false);
    assert_eq!(o.failed(), 0, "{report}");
    assert!(o.passed() > 0, "{report}");
}

/// The integrator reads CPU 2's D820 (1000 from its program: 50/s through
/// the D/A range) and writes CPU 2's D10:f32; before step 1 it reads 0, so
/// after step n it holds 50·(n−1)·0.01. CPU 1's D820 and D10 stay 0. The
/// timeline's CPU2/X0 at 0.5 s reaches CPU 2's program in that step.
#[test]
fn a_model_the_timeline_and_checks_on_cpu2() {
    let o = run_on(
        &[
            ("", IDLE),
            ("", "LD SM400\nMOV K1000 D820\nLD X0\nOUT Y0\nEND\n"),
        ],
        r#"duration = "1s"

[[model]]
type = "integrator"
inputs.u = { device = "CPU2/D820", raw = [0, 2000], eng = [0, 100] }
outputs.y = "CPU2/D10:f32"

[[timeline]]
at = "0.5s"
set = { "CPU2/X0" = 1 }

[[expect]]
device = "CPU2/D10:f32"
equals = 49.5
tolerance = 1e-4
at = "1s"

[[expect]]
device = "CPU2/Y0"
equals = true
within = "10ms"
after = "0.5s"

[[expect]]
device = "CPU2/Y0"
never = true
equals = true
to = "0.5s"

[[expect]]
device = "D820"
always = true
equals = 0

[[expect]]
device = "CPU1/D10:f32"
always = true
equals = 0

[[expect]]
device = "CPU1/Y0"
never = true
equals = true

[trace]
devices = ["CPU2/D10:f32", "CPU1/D10:f32", "cpu2/Y0"]
interval = "0.5s"
"#,
    );
    assert_all_pass(&o);
    assert_eq!(o.results[1].detail, "at 500 ms (scan 50)");
    assert_eq!(o.scans, 100);
    assert_eq!(o.steps, 100);
    let t = o.trace.unwrap();
    let names: Vec<&str> = t.devices.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["CPU2/D10:f32", "CPU1/D10:f32", "cpu2/Y0"]);
    assert_eq!(t.scans, [1, 50, 100]);
    // Sample 50: 50·49·0.01 = 24.5, CPU 1's D10 0, Y0 ON.
    assert!((t.values[3] - 24.5).abs() < 1e-4, "{:?}", t.values);
    assert_eq!(t.values[4], 0.0);
    assert_eq!(t.values[5], 1.0);
    assert_eq!(t.column_of("CPU2/Y0"), Some(2));
}

/// Each CPU scans at its own constant scan, the others at the scenario's
/// scan time, in one time: over 1 s with 10 ms steps, CPU 2 at 30 ms scans
/// at 30, 60, … 990 ms: 33 times, once by 50 ms and twice by 60 ms. The
/// report's `scans` are CPU 1's.
#[test]
fn cpus_scan_at_their_own_constant_scans() {
    let count = "LD SM400\nINC D0\nEND\n";
    let o = run_on(
        &[("", count), ("[ras]\nconstant_scan = \"30ms\"\n", count)],
        r#"duration = "1s"

[[expect]]
device = "CPU2/D0"
equals = 1
at = "50ms"

[[expect]]
device = "CPU2/D0"
equals = 2
at = "60ms"

[[expect]]
device = "CPU2/D0"
equals = 33
at = "1s"

[[expect]]
device = "CPU1/D0"
equals = 100
at = "1s"
"#,
    );
    assert_all_pass(&o);
    assert_eq!((o.scans, o.steps), (100, 100));

    // CPU 1 at 20 ms: 50 of its scans in the 100 steps of 1 s.
    let o = run_on(
        &[("[ras]\nconstant_scan = \"20ms\"\n", count), ("", count)],
        "duration = \"1s\"\n[[expect]]\ndevice = \"CPU2/D0\"\nequals = 100\nat = \"1s\"\n\
         [[expect]]\ndevice = \"D0\"\nequals = 50\nat = \"1s\"\n",
    );
    assert_all_pass(&o);
    assert_eq!((o.scans, o.steps), (50, 100));
    assert!(
        o.header().contains(": 50 scans, 1 s simulated"),
        "{}",
        o.header()
    );
}

/// The auto refresh as the scenario sees it: the timeline writes CPU 1's
/// D1000 before step 50; CPU 1's END publishes it and CPU 2's END (same
/// time, after CPU 1's) takes it into CPU 2's D1000; CPU 2's program copies
/// it to D1 in its next scan. CPU 2's D1002 goes back to CPU 1 alike.
#[test]
fn the_auto_refresh_between_steps() {
    let o = run_on(
        &[
            ("", IDLE),
            ("", "LD SM400\nMOV D1000 D1\nMOV K7 D1002\nEND\n"),
        ],
        r#"duration = "1s"

[[timeline]]
at = "0.5s"
set = { "CPU1/D1000" = 5 }

[[expect]]
device = "CPU2/D1000"
equals = 5
at = "0.5s"

[[expect]]
device = "CPU2/D1"
equals = 0
at = "0.5s"

[[expect]]
device = "CPU2/D1"
equals = 5
at = "0.51s"

[[expect]]
device = "CPU1/D1002"
equals = 0
at = "10ms"

[[expect]]
device = "CPU1/D1002"
equals = 7
at = "20ms"

[[expect]]
device = "CPU2/U3E0\\G2048"
equals = 5
at = "0.5s"
"#,
    );
    assert_all_pass(&o);
}

/// An input of a module goes to the module's control CPU whichever CPU
/// names it, as `--set X…` (contract §6): the input module X0-XF is
/// CPU 2's, so CPU 1's X0 from the timeline and CPU 1's X1 from a model
/// reach CPU 2's program; CPU 1 does not load the inputs of a module it
/// does not control.
#[test]
fn inputs_of_a_module_go_to_its_control_cpu() {
    let rack = "[[slot]]\ntype = \"input\"\npoints = 16\ncontrol_cpu = 2\n";
    let o = run_on(
        &[
            (rack, "LD X0\nOUT M0\nEND\n"),
            (rack, "LD X0\nOUT M1\nLD X1\nOUT M2\nEND\n"),
        ],
        r#"duration = "1s"

[[model]]
type = "integrator"
params = { gain = 0, initial = 1 }
inputs.u = 0
outputs.y = "X1"

[[timeline]]
at = "0.5s"
set = { X0 = 1 }

[[expect]]
device = "CPU2/M1"
equals = true
at = "0.5s"

[[expect]]
device = "CPU2/M1"
never = true
equals = true
to = "0.5s"

[[expect]]
device = "CPU2/M2"
equals = true
at = "10ms"

[[expect]]
device = "CPU1/M0"
never = true
equals = true

[[expect]]
device = "X1"
never = true
equals = true
"#,
    );
    assert_all_pass(&o);
}

/// A stop error of CPU 2 stops CPU 1 too (MULTI CPU DOWN, 7000, by
/// default): the run ends at that step with one failed line per CPU.
#[test]
fn a_stop_error_of_cpu2_stops_the_system_and_the_run() {
    let o = run_on(
        &[("", IDLE), ("", "LD X0\n/ K1 K0 D0\nEND\n")],
        r#"duration = "1s"

[[timeline]]
at = "0.3s"
set = { "CPU2/X0" = 1 }

[[expect]]
device = "CPU1/M0"
always = true
equals = true
"#,
    );
    assert_eq!(o.steps, 30, "{}", o.report(false));
    // CPU 1 scanned at 300 ms before CPU 2 (CPU-number order), then
    // stopped at CPU 2's END.
    assert_eq!(o.scans, 30);
    let texts: Vec<&str> = o.results.iter().map(|r| r.text.as_str()).collect();
    assert_eq!(
        texts,
        [
            "CPU1/M0 always true",
            "CPU 1 keeps running (stopped at 300 ms, scan 30)",
            "CPU 2 keeps running (stopped at 300 ms, scan 30)",
        ]
    );
    assert!(o.results[0].detail.contains("every CPU stopped"), "{o:?}");
    assert!(o.results[1].detail.starts_with("error 7000 "), "{o:?}");
    assert!(o.results[2].detail.starts_with("error 4100 "), "{o:?}");
}

/// With `stop_all = { 2 = false }` CPU 1 goes on (7010): the run goes on,
/// CPU 1's checks are decided to the end and CPU 2's stop is one failed
/// line.
#[test]
fn cpu1_goes_on_when_cpu2_stops_without_stopping_all() {
    let go_on = "stop_all = { 2 = false }\n";
    let dir = system(&[
        ("", "LD SM400\nINC D0\nEND\n"),
        ("", "LD X0\n/ K1 K0 D0\nEND\n"),
    ]);
    // The operation mode is in both CPUs' [multi_cpu] (it must be the same).
    for cpu in ["cpu1", "cpu2"] {
        let p = dir.path().join(cpu).join("plc.toml");
        let t = std::fs::read_to_string(&p).unwrap();
        std::fs::write(&p, t.replace("cpus = 2\n", &format!("cpus = 2\n{go_on}"))).unwrap();
    }
    let o = run(
        dir.path(),
        r#"duration = "1s"

[[timeline]]
at = "0.3s"
set = { "CPU2/X0" = 1 }

[[expect]]
device = "CPU1/D0"
equals = 100
at = "1s"
"#,
    );
    assert_eq!(o.steps, 100, "{}", o.report(false));
    assert!(o.results[0].passed, "{}", o.report(false));
    assert_eq!(o.results.len(), 2, "{}", o.report(false));
    assert_eq!(
        o.results[1].text,
        "CPU 2 keeps running (stopped at 300 ms, scan 30)"
    );
}

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/multi_cpu/line.toml")
}

/// The same scenario gives the same results every run, sample for sample.
#[test]
fn a_system_scenario_is_deterministic() {
    let once = || {
        let mut sc = Scenario::load(&example()).unwrap();
        sc.plot = None; // do not rewrite the committed SVG
        sc.trace.interval_us = Some(100_000);
        sc.build().unwrap().run(&mut |_| {})
    };
    let (a, b) = (once(), once());
    assert_all_pass(&a);
    assert_eq!(a.results, b.results);
    assert_eq!(a.trace, b.trace);
    assert_eq!((a.scans, a.steps), (b.scans, b.steps));
    assert!(a.trace.unwrap().len() > 4000);
}

/// A name of a CPU the system does not have, or a `CPUn/` name in a
/// single-CPU scenario, fails at load naming the entry.
#[test]
fn names_of_missing_cpus_fail_at_load() {
    let dir = system(&[("", IDLE), ("", IDLE)]);
    let err = |text: &str| load(dir.path(), text).unwrap_err();
    let e = err("duration = \"1s\"\n[[expect]]\ndevice = \"CPU5/D0\"\nequals = 0\nat = \"1s\"\n");
    assert!(
        e.contains("expect #1 (CPU5/D0)") && e.contains("there is no CPU 5"),
        "{e}"
    );
    let e = err("duration = \"1s\"\n[[timeline]]\nat = 0\nset = { \"CPU3/X0\" = 1 }\n");
    assert!(
        e.contains("timeline #1") && e.contains("no CPU 3 (the system has CPU 1-2)"),
        "{e}"
    );
    let e = err("duration = \"1s\"\n[[model]]\ntype = \"integrator\"\ninputs.u = \"CPU3/D0\"\n");
    assert!(
        e.contains("model #1 `integrator`: input `u`") && e.contains("no CPU 3"),
        "{e}"
    );
    let e = err("duration = \"1s\"\n[trace]\ndevices = [\"CPU0/D0\"]\n");
    assert!(e.contains("trace") && e.contains("no CPU 0"), "{e}");
    let e = err("duration = \"1s\"\n[[expect]]\ndevice = \"CPUX/D0\"\nequals = 0\nat = \"1s\"\n");
    assert!(e.contains("a CPU prefix is CPU1/ to CPU4/"), "{e}");
    let e = err("cpu = \"Q06PHCPU\"\nduration = \"1s\"\n");
    assert!(e.contains("cpu: each CPU of a multi-CPU system"), "{e}");

    // A single CPU: CPU1/ is its own, CPU2/ is an error.
    let single = tempfile::tempdir().unwrap();
    std::fs::write(single.path().join("main.il"), "LD X0\nOUT Y0\nEND\n").unwrap();
    let path = single.path().join("one.toml");
    let text = |dev: &str| {
        format!(
            "program = \"main.il\"\nscan_time = \"10ms\"\nduration = \"1s\"\n\
             [[timeline]]\nat = \"0.5s\"\nset = {{ X0 = 1 }}\n\
             [[expect]]\ndevice = \"{dev}\"\nequals = true\nat = \"1s\"\n"
        )
    };
    std::fs::write(&path, text("CPU2/Y0")).unwrap();
    let e = Scenario::load(&path).unwrap_err();
    assert!(
        e.contains("expect #1 (CPU2/Y0)")
            && e.contains("there is no CPU 2 (the scenario runs one CPU"),
        "{e}"
    );
    std::fs::write(&path, text("CPU1/Y0")).unwrap();
    let o = Scenario::load(&path)
        .unwrap()
        .build()
        .unwrap()
        .run(&mut |_| {});
    assert_all_pass(&o);
    assert_eq!(o.results[0].text, "CPU1/Y0 = true at 1 s");
}

/// `Run::step` (the tuning driver's loop) on a system, with CPU 2 reached
/// by `cpu_at` and names split by `split_name`.
#[test]
fn stepping_a_system() {
    let dir = system(&[("", IDLE), ("", "LD SM400\nINC D0\nEND\n")]);
    let sc = load(dir.path(), "duration = \"1s\"\n").unwrap();
    let mut run = sc.build().unwrap();
    assert_eq!(run.cpu_count(), 2);
    assert_eq!(run.split_name("CPU2/D0"), Ok((1, "D0")));
    assert_eq!(run.split_name("D0"), Ok((0, "D0")));
    assert!(run.split_name("CPU3/D0").is_err());
    for _ in 0..3 {
        run.step().unwrap();
    }
    let d0 = run
        .cpu_at(1)
        .read_device(&softplc_core::access::DeviceSpec::parse("D0").unwrap())
        .unwrap();
    assert_eq!(d0, softplc_core::access::Value::Int(3));
    assert_eq!(run.steps_done(), 3);
}
