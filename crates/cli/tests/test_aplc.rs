//! `softplc test` on APLC programs (contract §2 APLC names, docs/scenarios.md):
//! model bindings, timeline writes, expectations and the trace in the APLC's
//! names (`X10` is input 8, `D20:f32` and `D30:i32` high word first, `CN201`
//! 32-bit), the run-error report (code 69, file:line) and name diagnostics.
//! Every expected value is worked out by hand in the comments.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn softplc(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("softplc runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The program: line 18 is the DIV.
const PROGRAM: &str = r#"// X10 is input 8: it drives Y10 (output 8).
LD X10
OUT Y10
// REAL, high word first: D20 = D10 x 2.0.
LD SM0
RMUL D10 2.0 D20
// The 32-bit counter value C201 (written by the plant) into D30/D31.
DMOV C201 D30
LDD>= D30 100000
OUT Y1
// A 32-bit up counter on X0's rising edges.
LD X0
DCNT C200 3
LD C200
OUT Y2
// Divide by zero while M1: run error 69, the CPU keeps running.
LD M1
DIV D0 D1 D2
// STOP with power flow ends the run (L3743).
LD M2
STOP
"#;

/// Hand-worked values (scan time 10 ms, scan n at n·10 ms):
/// - the integrator (gain 1000) reads D20:f32 before each scan; D20 = 2 × 25.0
///   = 50.0 from scan 1 on, so before scan n ≥ 2 it writes CN201 = 500·(n−1)
///   (over 65535 from n = 133: a true 32-bit value);
/// - DMOV C201 D30: D30:i32 reaches 100000 at scan 201 (2.01 s), D30 = 1
///   (high word), D31 = 100000 − 65536 = 34464; Y1 = D30:i32 ≥ 100000;
/// - 50.0f32 = 16#42480000: D20 = 16#4248 = 16968;
/// - X10 (input 8) → Y10 (output 8) = bit 8 of K4Y0 (Y0-Y7, Y10-Y17), plus Y2
///   (bit 2) after the third X0 edge: K4Y0 = 256 + 4 = 260;
/// - X0 rises at 0.1, 0.3, 0.5 s: CN200 = 3 and Y2 ON at 0.5 s.
const SCENARIO: &str = r#"program = "t.apl"
scan_time = "10ms"
duration = "3s"

[[model]]
type = "integrator"
params = { gain = 1000 }
inputs.u = "D20:f32"
outputs.y = "CN201"

[[timeline]]
at = 0
set = { "D10:f32" = 25.0 }

[[timeline]]
at = "0.5s"
set = { X10 = true }

[[timeline]]
at = "0.1s"
every = "200ms"
count = 3
set = { X0 = true }

[[timeline]]
at = "0.2s"
every = "200ms"
count = 3
set = { X0 = false }

[[expect]]
device = "Y10"
equals = true
within = "10ms"
after = "0.5s"

[[expect]]
device = "K4Y0"
equals = 260
at = "0.6s"

[[expect]]
device = "D20:f32"
equals = 50.0
at = "1s"

[[expect]]
device = "D20"
equals = 16968
at = "1s"

[[expect]]
device = "Y1"
equals = true
within = "10ms"
after = "2s"

[[expect]]
device = "D30:i32"
equals = 100000
at = "2.01s"

[[expect]]
device = "D30"
equals = 1
at = "2.01s"

[[expect]]
device = "D31:u16"
equals = 34464
at = "2.01s"

[[expect]]
device = "CN200"
equals = 3
at = "0.6s"

[[expect]]
device = "Y2"
equals = true
within = "10ms"
after = "0.5s"

[trace]
devices = ["CN201", "D30:i32", "X10", "D20:f32"]
interval = "1s"
"#;

/// M1 at 1 s divides by zero each scan (error 69, the CPU runs on, L11278);
/// M2 at 2 s executes STOP: the run ends at scan 200 and the report gives the
/// latest error with its file and line (no step numbers on the APLC).
const ERRORS: &str = r#"program = "t.apl"
scan_time = "10ms"
duration = "3s"

[[timeline]]
at = "1s"
set = { M1 = true }

[[timeline]]
at = "2s"
set = { M2 = true }

[[expect]]
device = "SD20"
equals = 69
at = "1.5s"

[[expect]]
device = "SM20"
equals = true
at = "1.5s"
"#;

fn setup() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("t.apl"), PROGRAM).unwrap();
    std::fs::write(dir.path().join("t.toml"), SCENARIO).unwrap();
    std::fs::write(dir.path().join("e.toml"), ERRORS).unwrap();
    let p = dir.path().to_path_buf();
    (dir, p)
}

#[test]
fn aplc_scenario_binds_writes_and_checks_in_aplc_names() {
    let (_d, dir) = setup();
    let out = softplc(
        &["test", "t.toml", "--trace-file", "t.csv", "--plot", "t.svg"],
        &dir,
    );
    let text = stdout(&out);
    assert!(out.status.success(), "{text}");
    for line in [
        "PASS Y10 becomes true within 10 ms after 500 ms: at 500 ms (scan 50)",
        "PASS K4Y0 = 260 at 600 ms: got 260",
        "PASS D20:f32 = 50 at 1 s: got 50",
        "PASS D20 = 16968 at 1 s: got 16968",
        "PASS Y1 becomes true within 10 ms after 2 s: at 2.01 s (scan 201)",
        "PASS D30:i32 = 100000 at 2.01 s: got 100000",
        "PASS D30 = 1 at 2.01 s: got 1",
        "PASS D31:u16 = 34464 at 2.01 s: got 34464",
        "PASS CN200 = 3 at 600 ms: got 3",
        "PASS Y2 becomes true within 10 ms after 500 ms: at 500 ms (scan 50)",
    ] {
        assert!(text.contains(line), "missing `{line}` in\n{text}");
    }
    assert!(text.ends_with("10 passed, 0 failed\n"), "{text}");
    // The trace samples every 1 s (100 scans): CN201 = 500·99 at scan 100.
    let csv = std::fs::read_to_string(dir.join("t.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "scan,time_s,CN201,D30:i32,X10,D20:f32");
    assert!(lines.contains(&"100,1.000,49500,49500,1,50"), "{csv}");
    assert!(lines.contains(&"200,2.000,99500,99500,1,50"), "{csv}");
    // The plot draws the same devices, named as given.
    let svg = std::fs::read_to_string(dir.join("t.svg")).unwrap();
    assert!(svg.contains("D30:i32") && svg.contains("CN201"), "{svg}");
    // --trace names are APLC names too: K2Y10 = Y10-Y17, Y10 ON → 1.
    let out = softplc(
        &[
            "test",
            "t.toml",
            "--trace",
            "K2Y10,X10",
            "--trace-file",
            "k.csv",
        ],
        &dir,
    );
    assert!(out.status.success(), "{}", stdout(&out));
    let csv = std::fs::read_to_string(dir.join("k.csv")).unwrap();
    assert!(csv.contains("\n100,1.000,1,1\n"), "{csv}");
}

#[test]
fn aplc_scenario_failure_history_uses_aplc_names() {
    let (_d, dir) = setup();
    // Y10 = Y(octal 10) is output 8: K4Y0 is 260, not 256.
    let wrong = SCENARIO.replace("equals = 260", "equals = 256");
    std::fs::write(dir.join("w.toml"), wrong).unwrap();
    let out = softplc(&["test", "w.toml"], &dir);
    let text = stdout(&out);
    assert!(!out.status.success(), "{text}");
    assert!(
        text.contains("FAIL K4Y0 = 256 at 600 ms: got 260 at 600 ms (scan 60)"),
        "{text}"
    );
    assert!(text.contains("  scan    t/s  K4Y0"), "{text}");
}

#[test]
fn aplc_run_errors_are_reported_with_their_code_file_and_line() {
    let (_d, dir) = setup();
    let out = softplc(&["test", "e.toml"], &dir);
    let text = stdout(&out);
    assert!(!out.status.success(), "{text}");
    assert!(text.contains("PASS SD20 = 69 at 1.5 s: got 69"), "{text}");
    assert!(
        text.contains("PASS SM20 = true at 1.5 s: got true"),
        "{text}"
    );
    assert!(
        text.contains(
            "FAIL the CPU keeps running (stopped at 2 s, scan 200): error 69 divide by zero at ./t.apl:18"
        ),
        "{text}"
    );
}

#[test]
fn aplc_names_are_checked_when_the_scenario_loads() {
    let (_d, dir) = setup();
    for (from, to, why) in [
        // X8 is not octal (L892).
        ("X10 = true", "X8 = true", "`X8`: X is numbered in octal"),
        // MAIN's locals cannot be driven from outside.
        (
            "outputs.y = \"CN201\"",
            "outputs.y = \"V0\"",
            "`V0`: LM and V are POU locals",
        ),
        // C200-C255 are 32-bit.
        (
            "device = \"CN200\"",
            "device = \"CN200:i16\"",
            "C200-C255 are 32-bit",
        ),
        // MELSEC's H prefix is not an APLC value (16#10 is).
        ("\"D10:f32\" = 25.0", "D10 = \"H10\"", "bad value `H10`"),
    ] {
        let bad = SCENARIO.replace(from, to);
        assert_ne!(bad, SCENARIO, "{from}");
        std::fs::write(dir.join("bad.toml"), bad).unwrap();
        let out = softplc(&["test", "bad.toml"], &dir);
        let text = stdout(&out);
        assert!(!out.status.success(), "{to}: {text}");
        assert!(text.contains(why), "{to}: {text}");
    }
}
