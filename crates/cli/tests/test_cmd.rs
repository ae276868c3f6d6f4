//! `softplc test` end to end (issue 7): the shipped scenarios pass, a wrong
//! expectation fails with a useful message and a non-zero exit status, and
//! --trace/--plot write their files.

use std::path::PathBuf;
use std::process::{Command, Output};

fn softplc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args(args)
        .current_dir(workspace())
        .output()
        .expect("softplc runs")
}

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

const PROGRAM: &str = "\
; X0 starts the motor, X4 is its running feedback, C0 counts parts on X2.
LD X0
OR Y0
OUT Y0
LD X4
AND X2
OUT C0 K3
LD C0
OUT Y1
END
";

/// A conveyor scenario; `expect` is appended.
fn scenario(dir: &tempfile::TempDir, name: &str, expect: &str) -> String {
    std::fs::write(dir.path().join("conv.il"), PROGRAM).unwrap();
    let text = format!(
        r#"program = "conv.il"
scan_time = "10ms"
duration = "5s"

[[model]]
type = "motor"
params = {{ accel_time = "1s", threshold = 90 }}
inputs.run = "Y0"
outputs.running = "X4"
outputs.speed = "D20"

[[timeline]]
at = "0.5s"
set = {{ X0 = 1 }}

[[timeline]]
at = "2s"
every = "500ms"
count = 3
set = {{ X2 = 1 }}

[[timeline]]
at = "2.1s"
every = "500ms"
count = 3
set = {{ X2 = 0 }}

{expect}
"#
    );
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

const GOOD: &str = r#"
[[expect]]
device = "X4"
equals = true
within = "1.5s"
after = "0.5s"

[[expect]]
device = "Y1"
equals = true
within = "100ms"
after = "3s"
"#;

/// Y1 comes on at 3 s (third part), not within 0.5 s of the first part.
const WRONG: &str = r#"
[[expect]]
device = "X4"
equals = true
within = "1.5s"
after = "0.5s"

[[expect]]
device = "Y1"
equals = true
within = "500ms"
after = "2s"
show = ["X2", "CN0"]
"#;

#[test]
fn passing_scenario_reports_and_exits_zero() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scenario(&dir, "good.toml", GOOD);
    let out = softplc(&["test", &sc]);
    let text = stdout(&out);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("PASS X4 becomes true within 1.5 s after 500 ms: at 1.4 s (scan 140)"),
        "{text}"
    );
    assert!(
        text.contains("PASS Y1 becomes true within 100 ms after 3 s: at 3 s (scan 300)"),
        "{text}"
    );
    assert_eq!(text.lines().last(), Some("2 passed, 0 failed"), "{text}");
}

#[test]
fn wrong_expectation_fails_with_first_failing_scan_and_history() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scenario(&dir, "wrong.toml", WRONG);
    let out = softplc(&["test", &sc]);
    let text = stdout(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("PASS X4 becomes true"), "{text}");
    assert!(
        text.contains(
            "FAIL Y1 becomes true within 500 ms after 2 s: still false at 2.5 s (scan 250)"
        ),
        "{text}"
    );
    assert!(
        text.contains("first failing scan 250 (t = 2.500 s)"),
        "{text}"
    );
    // The history table: a header with the devices, 5 samples up to the
    // failing scan (marked) and 3 after.
    let lines: Vec<&str> = text.lines().collect();
    let h = lines
        .iter()
        .position(|l| {
            l.contains("scan") && l.contains("Y1") && l.contains("X2") && l.contains("CN0")
        })
        .unwrap_or_else(|| panic!("no history header in\n{text}"));
    let rows = &lines[h + 1..h + 9];
    assert!(rows[0].trim_start().starts_with("246"), "{text}");
    assert!(rows[4].trim_start().starts_with("> 250"), "{text}");
    assert!(
        rows[4].contains("false") && rows[4].ends_with('2'),
        "{text}"
    );
    assert!(rows[7].trim_start().starts_with("253"), "{text}");
    assert_eq!(lines.last(), Some(&"1 passed, 1 failed"), "{text}");
}

#[test]
fn several_files_run_in_parallel_and_sum_up() {
    let dir = tempfile::tempdir().unwrap();
    let a = scenario(&dir, "a.toml", GOOD);
    let b = scenario(&dir, "b.toml", WRONG);
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "program = \"conv.il\"\nscan_time = \"10ms\"\n").unwrap();
    let bad = bad.display().to_string();
    let out = softplc(&["test", "-q", &a, &b, &bad, "--jobs", "3"]);
    let text = stdout(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    // Reports in argument order; -q leaves out passing lines.
    let ia = text.find("a.toml").unwrap();
    let ib = text.find("b.toml").unwrap();
    let ibad = text.find("bad.toml").unwrap();
    assert!(ia < ib && ib < ibad, "{text}");
    assert!(!text.contains("PASS"), "{text}");
    assert!(text.contains("FAIL") && text.contains("duration"), "{text}");
    assert_eq!(text.lines().last(), Some("3 passed, 2 failed"), "{text}");
}

#[test]
fn trace_and_plot_files() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scenario(&dir, "good.toml", GOOD);
    let csv = dir.path().join("trend.csv").display().to_string();
    let svg = dir.path().join("trend.svg").display().to_string();
    let out = softplc(&[
        "test",
        &sc,
        "--trace",
        "D20,Y0,X4",
        "--trace-file",
        &csv,
        "--trace-interval",
        "100ms",
        "--plot",
        &svg,
    ]);
    let text = stdout(&out);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("trace: ") && text.contains("plot: "),
        "{text}"
    );
    let data = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = data.lines().collect();
    assert_eq!(lines[0], "scan,time_s,D20,Y0,X4");
    assert_eq!(lines[1], "1,0.010,0,0,0");
    assert_eq!(lines.len(), 1 + 51, "scan 1 and every 10th scan");
    assert_eq!(lines[50], "490,4.900,100,1,1");
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert!(plot.starts_with("<svg") && plot.contains("D20") && plot.contains("X4"));
}

#[test]
fn shipped_examples_pass() {
    // Plots go to a scratch directory, not over the committed SVGs.
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("plot.svg").display().to_string();
    let out = softplc(&[
        "test",
        "examples/sim/conveyor.toml",
        "examples/sim/fill_drain.toml",
        "examples/sim/heated_tank.toml",
        // The process CPU's loops (Q06PHCPU): S.PID flow loop, S.2PID/S.PID
        // cascade, S.AT1 auto-tuning, S.R ratio, and the loop `softplc
        // tune` runs on (at rest in MAN).
        "examples/process/flow_loop.toml",
        "examples/process/cascade.toml",
        "examples/process/autotune.toml",
        "examples/process/ratio.toml",
        "examples/process/fopdt_loop.toml",
        // The APLC-TCP conveyor (seed 002 dialect, APLC device names).
        "examples/aplc/conveyor.toml",
        // APLC ports in virtual time: a Modbus master polling a drive and
        // a meter on RTU, a free-port barcode reader (issue #14).
        "examples/aplc/modbus_poll.toml",
        "examples/aplc/barcode.toml",
        // The APLC examples of seed 002 §8: subroutines, SFC branches,
        // PID set-up, a batch mixer (`cpu = "APLC-TCP"`).
        "examples/aplc/subroutine.toml",
        "examples/aplc/sfc.toml",
        "examples/aplc/pid_setup.toml",
        "examples/aplc/batch_mix.toml",
        // The rack (issue #26): a Q64AD, a Q64DA and a QI60 emergency stop.
        "examples/rack/tank.toml",
        // A multi-CPU system: CPU 1's batch sequence, CPU 2's loop.
        "examples/multi_cpu/line.toml",
        // A fleet: two APLC-TCPs on a Modbus RTU link, a Q supervisor
        // fed by a SCADA client over Modbus TCP.
        "examples/fleet/serial_line.toml",
        "--plot",
        &svg,
    ]);
    let text = stdout(&out);
    // With several scenarios each plot file gets the scenario's name.
    for name in [
        "conveyor",
        "fill_drain",
        "heated_tank",
        "flow_loop",
        "cascade",
        "autotune",
        "ratio",
        "fopdt_loop",
        "line",
        "serial_line",
    ] {
        assert!(
            dir.path().join(format!("plot-{name}.svg")).is_file(),
            "no plot for {name}: {text}"
        );
    }
    assert!(out.status.success(), "{text}");
    assert!(!text.contains("FAIL"), "{text}");
    assert!(
        text.lines().last().unwrap().ends_with(" passed, 0 failed"),
        "{text}"
    );
}

/// `--shard`, `--jsonl` and `--merge` (issue 16): two shards split the files,
/// their JSON lines merge to the totals of the unsharded run.
#[test]
fn shards_partition_the_files_and_their_lines_merge_to_the_plain_totals() {
    let dir = tempfile::tempdir().unwrap();
    let good = scenario(&dir, "a_good.toml", GOOD);
    let wrong = scenario(&dir, "b_wrong.toml", WRONG);
    let good2 = scenario(&dir, "c_good.toml", GOOD);
    let plain = softplc(&["test", &wrong, &good2, &good]);
    assert_eq!(
        stdout(&plain).lines().last(),
        Some("5 passed, 1 failed"),
        "{}",
        stdout(&plain)
    );
    // Ranked by path a, b, c: shard 0/2 gets a and c, 1/2 gets b, whatever
    // the argument order.
    let mut files = Vec::new();
    for (i, expected) in [(0, vec![&good2, &good]), (1, vec![&wrong])] {
        let out = softplc(&[
            "test",
            "--jsonl",
            "--shard",
            &format!("{i}/2"),
            &wrong,
            &good2,
            &good,
        ]);
        let text = stdout(&out);
        let lines: Vec<serde_json::Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
            .collect();
        let got: Vec<&str> = lines.iter().map(|l| l["file"].as_str().unwrap()).collect();
        assert_eq!(got, expected, "{text}");
        for l in &lines {
            assert_eq!(l["scans"], 500, "{l}");
            assert_eq!(l["simulated_s"], 5.0, "{l}");
        }
        let f = dir.path().join(format!("shard{i}.jsonl"));
        std::fs::write(&f, text).unwrap();
        files.push(f.display().to_string());
    }
    let wrong_line: serde_json::Value =
        serde_json::from_str(std::fs::read_to_string(&files[1]).unwrap().trim()).unwrap();
    assert_eq!(wrong_line["passed"], false);
    assert_eq!(wrong_line["assertions"]["passed"], 1);
    assert_eq!(wrong_line["assertions"]["failed"], 1);
    assert_eq!(
        wrong_line["results"][1]["text"],
        "Y1 becomes true within 500 ms after 2 s"
    );

    let merged = softplc(&["test", "--merge", &files[0], &files[1]]);
    let text = stdout(&merged);
    assert_eq!(merged.status.code(), Some(1), "{text}");
    assert_eq!(text.lines().last(), Some("5 passed, 1 failed"), "{text}");
    let order: Vec<usize> = [&good, &wrong, &good2]
        .iter()
        .map(|f| text.find(f.as_str()).unwrap())
        .collect();
    assert!(order[0] < order[1] && order[1] < order[2], "{text}");
    assert!(
        text.contains(
            "  FAIL Y1 becomes true within 500 ms after 2 s: still false at 2.5 s (scan 250)"
        ),
        "{text}"
    );
}

/// Issue #31 defect 7: counts that cannot be a result line's (huge, or not
/// those of its results) are an error naming the file and line, never summed
/// into a wrapped total that passes.
#[test]
fn merge_refuses_counts_that_do_not_match_the_results() {
    let dir = tempfile::tempdir().unwrap();
    let line = |file: &str, failed: &str| {
        format!(
            r#"{{"file":"{file}","name":"n","passed":false,"assertions":{{"passed":1,"failed":{failed}}},"duration_s":0.1,"simulated_s":1.0,"scans":100,"results":[{{"text":"a","passed":true,"detail":""}},{{"text":"b","passed":false,"detail":"x"}}]}}"#
        )
    };
    let huge = "9223372036854775808";
    let a = dir.path().join("a.jsonl");
    let b = dir.path().join("b.jsonl");
    std::fs::write(&a, format!("{}\n", line("x.toml", huge))).unwrap();
    std::fs::write(
        &b,
        format!("{}\n{}\n", line("y.toml", "1"), line("z.toml", huge)),
    )
    .unwrap();
    let (a, b) = (a.display().to_string(), b.display().to_string());
    let o = softplc(&["test", "--merge", &b]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{}{err}", stdout(&o));
    assert!(err.contains(&format!("{b}:2")), "{err}");
    assert!(err.contains("failed"), "{err}");
    let o = softplc(&["test", "--merge", &a, &b]);
    assert_eq!(o.status.code(), Some(2), "{}", stdout(&o));
    for bad in ["-1", "1.5", "18446744073709551616"] {
        let c = dir.path().join("c.jsonl");
        std::fs::write(&c, format!("{}\n", line("w.toml", bad))).unwrap();
        let c = c.display().to_string();
        let o = softplc(&["test", "--merge", &c]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains(&format!("{c}:1")), "{bad}: {err}");
    }
    // The same line with the counts of its results merges.
    let d = dir.path().join("d.jsonl");
    std::fs::write(&d, format!("{}\n", line("v.toml", "1"))).unwrap();
    let o = softplc(&["test", "--merge", &d.display().to_string()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(stdout(&o).lines().last(), Some("1 passed, 1 failed"));
}

/// Issue #31: with several scenarios `--plot out.svg` writes one file per
/// scenario and the output lists them; two scenarios of the same name do
/// not overwrite each other's file.
#[test]
fn several_scenarios_list_the_files_written() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("out.svg").display().to_string();
    let o = softplc(&[
        "test",
        "examples/sim/conveyor.toml",
        "examples/aplc/conveyor.toml",
        "examples/aplc/sfc.toml",
        "--plot",
        &svg,
        "-q",
    ]);
    let text = stdout(&o);
    assert!(o.status.success(), "{text}");
    let files: Vec<String> = ["out-conveyor.svg", "out-aplc-conveyor.svg", "out-sfc.svg"]
        .iter()
        .map(|f| dir.path().join(f).display().to_string())
        .collect();
    let listed = format!(
        "files written (3):\n  {}\n  {}\n  {}\n",
        files[0], files[1], files[2]
    );
    assert!(text.contains(&listed), "{text}");
    for f in &files {
        assert!(std::path::Path::new(f).is_file(), "{f}");
    }
    assert!(text.lines().last().unwrap().ends_with(" passed, 0 failed"));
}

/// A multi-CPU system's scenario on the command line: `--trace` takes
/// `CPUn/` names, a `--jsonl` line counts CPU 1's scans (here at its own
/// 20 ms constant scan: 250 in 5 s) and the simulated time, and shards of
/// system and single-CPU scenarios merge to the plain totals.
#[test]
fn a_multi_cpu_scenario_traces_shards_and_merges() {
    let dir = tempfile::tempdir().unwrap();
    let sys = dir.path().join("line");
    let count = "LD SM400\nINC D0\nEND\n";
    for (cpu, ras) in [("cpu1", "[ras]\nconstant_scan = \"20ms\"\n"), ("cpu2", "")] {
        let d = sys.join(cpu);
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("main.il"), count).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!("{ras}[[program]]\nfile = \"main.il\"\n[multi_cpu]\ncpus = 2\n"),
        )
        .unwrap();
    }
    std::fs::write(
        sys.join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    let multi = dir.path().join("a_multi.toml");
    std::fs::write(
        &multi,
        "program = \"line\"\nscan_time = \"10ms\"\nduration = \"5s\"\n\
         [[expect]]\ndevice = \"CPU1/D0\"\nequals = 250\nat = \"5s\"\n\
         [[expect]]\ndevice = \"CPU2/D0\"\nequals = 500\nat = \"5s\"\n",
    )
    .unwrap();
    let multi = multi.display().to_string();
    let csv = dir.path().join("t.csv").display().to_string();
    let out = softplc(&[
        "test",
        &multi,
        "--jsonl",
        "--trace",
        "CPU2/D0,CPU1/D0",
        "--trace-interval",
        "1s",
        "--trace-file",
        &csv,
    ]);
    let text = stdout(&out);
    assert!(out.status.success(), "{text}");
    let line: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
    assert_eq!(line["passed"], true, "{line}");
    assert_eq!(line["scans"], 250, "{line}");
    assert_eq!(line["simulated_s"], 5.0, "{line}");
    let data = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = data.lines().collect();
    assert_eq!(lines[0], "scan,time_s,CPU2/D0,CPU1/D0");
    assert_eq!(lines[2], "100,1.000,100,50");

    let good = scenario(&dir, "b_good.toml", GOOD);
    let mut files = Vec::new();
    for i in 0..2 {
        let out = softplc(&[
            "test",
            "--jsonl",
            "--shard",
            &format!("{i}/2"),
            &good,
            &multi,
        ]);
        let f = dir.path().join(format!("shard{i}.jsonl"));
        std::fs::write(&f, stdout(&out)).unwrap();
        files.push(f.display().to_string());
    }
    let merged = softplc(&["test", "--merge", &files[0], &files[1]]);
    let text = stdout(&merged);
    assert!(merged.status.success(), "{text}");
    assert_eq!(text.lines().last(), Some("4 passed, 0 failed"), "{text}");
}

/// A fleet on the command line: `--trace` takes `NAME/DEV` names of
/// several PLCs. The master's copy of the tank's level (read over the
/// serial link) follows the tank PLC's own value within a poll.
#[test]
fn a_fleet_traces_devices_of_several_plcs() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("fleet.csv").display().to_string();
    let svg = dir.path().join("fleet.svg").display().to_string();
    let out = softplc(&[
        "test",
        "examples/fleet/serial_line.toml",
        "--trace",
        "tank/D0,master/D302",
        "--trace-interval",
        "30s",
        "--trace-file",
        &csv,
        "--plot",
        &svg,
    ]);
    let text = stdout(&out);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("10 passed, 0 failed"), "{text}");
    let data = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = data.lines().collect();
    assert_eq!(lines[0], "scan,time_s,tank/D0,master/D302");
    assert_eq!(lines[1], "1,0.010,0,0");
    assert_eq!(lines[3], "6000,60.000,1092,1091");
    assert_eq!(lines.len(), 1 + 9, "scan 1 and every 30 s to 4 min");
    for l in &lines[1..] {
        let v: Vec<i64> = l.split(',').skip(2).map(|x| x.parse().unwrap()).collect();
        assert!((v[0] - v[1]).abs() <= 2, "{l}");
    }
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert!(plot.contains("tank/D0") && plot.contains("master/D302"));
    // An unknown PLC in --trace is an error naming it.
    let out = softplc(&[
        "test",
        "examples/fleet/serial_line.toml",
        "--trace",
        "pump/D0",
    ]);
    let text = stdout(&out);
    assert!(!out.status.success(), "{text}");
    assert!(
        text.contains("`pump/D0`: no PLC is named `pump` (PLCs: master, tank, supervisor)"),
        "{text}"
    );
}
