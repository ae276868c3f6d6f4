//! The `softplc run` / `softplc check` contract (contract §2), end to end.

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

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

#[test]
fn run_blink_json() {
    // blink.il: T0 K5 (100 ms base) times out at scan 51 with 10 ms scans, and
    // Y0 follows T0; C0 counts Y0's rising edges.
    let out = softplc(&[
        "run",
        "examples/blink.il",
        "--scans",
        "100",
        "--set",
        "X0=1",
        "--show",
        "Y0",
        "--show",
        "TN0",
        "--show",
        "CN0",
        "--show",
        "D0",
        "--json",
    ]);
    let v = json(&out);
    assert_eq!(v["scans"], 100);
    assert_eq!(v["time_ms"], 1000.0);
    assert_eq!(v["state"], "RUN");
    assert_eq!(v["error"], serde_json::Value::Null);
    assert_eq!(v["devices"]["Y0"], true);
    assert_eq!(v["devices"]["TN0"], 5);
    assert_eq!(v["devices"]["CN0"], 1);
    assert_eq!(v["devices"]["D0"], 0);
    // Keys in the contract's order.
    let keys: Vec<_> = v.as_object().unwrap().keys().cloned().collect();
    assert_eq!(keys, ["scans", "time_ms", "state", "error", "devices"]);
}

#[test]
fn csv_export_runs_like_the_list() {
    let out = softplc(&[
        "run",
        "examples/csv/blink.csv",
        "--scans",
        "51",
        "--set",
        "X0=1",
        "--show",
        "Y0",
        "--json",
    ]);
    assert_eq!(json(&out)["devices"]["Y0"], true);
    let out = softplc(&[
        "run",
        "examples/csv/blink.csv",
        "--scans",
        "50",
        "--set",
        "X0=1",
        "--show",
        "Y0",
        "--json",
    ]);
    assert_eq!(json(&out)["devices"]["Y0"], false);
}

#[test]
fn at_writes_before_the_given_scan_and_types() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        &dir,
        "t.il",
        "LD X0\nINCP D0\nLD SM400\nFLT D0 D10\nDMOV K100000 D20\nEMOV E1.5 D30\nEND\n",
    );
    // X0 rises at scans 1 and 3 (off at 2): D0 = 2.
    let out = softplc(&[
        "run", &p, "--scans", "4", "--set", "X0=1", "--at", "2:X0=0", "--at", "3:X0=1", "--show",
        "D0", "--show", "D10:f32", "--show", "D20:i32", "--show", "D20", "--show", "D30:f32",
        "--show", "D31:u16", "--json",
    ]);
    let v = json(&out);
    assert_eq!(v["devices"]["D0"], 2);
    assert_eq!(v["devices"]["D10:f32"], 2.0);
    assert_eq!(v["devices"]["D20:i32"], 100000);
    // 100000 = 0x186A0: low word 0x86A0 = -31072 as i16.
    assert_eq!(v["devices"]["D20"], -31072);
    assert_eq!(v["devices"]["D30:f32"], 1.5);
    assert_eq!(v["devices"]["D31:u16"], 0x3FC0);
}

#[test]
fn stop_error_is_reported_in_json() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "main.il", "LD SM400\nMOV K1 D0\n/ D0 D1 D2\nEND\n");
    let out = softplc(&["run", &p, "--scans", "5", "--json", "--show", "D0"]);
    let v = json(&out);
    assert_eq!(v["state"], "STOP");
    assert_eq!(v["scans"], 1);
    assert_eq!(v["error"]["code"], 4100);
    assert_eq!(v["error"]["line"], 3);
    assert_eq!(v["error"]["step"], 4);
    assert!(v["error"]["file"].as_str().unwrap().ends_with("main.il"));
    assert_eq!(v["devices"]["D0"], 1);
}

#[test]
fn check_reports_every_diagnostic_with_position() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "bad.il", "LD X0\nOUT Q1\nMOV K70000 D0\nFOO\n");
    let out = softplc(&["check", &p]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert!(
        lines[0].ends_with("bad.il:2:5: `Q1` is not a device or constant"),
        "{err}"
    );
    assert!(
        lines[1].contains("bad.il:3:5: constant `K70000` does not fit a 16-bit operand"),
        "{err}"
    );
    assert!(
        lines[2].contains("bad.il:4:1: unknown instruction `FOO`"),
        "{err}"
    );
    assert!(lines[3].contains("bad.il:4:1: missing END"), "{err}");
    // run refuses to start on the same file, with the same diagnostics.
    let out = softplc(&["run", &p]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown instruction `FOO`"));
}

#[test]
fn check_ok() {
    let out = softplc(&["check", "examples/conveyor.il"]);
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("OK"));
}

#[test]
fn bad_options_fail_before_running() {
    for args in [
        &["run", "examples/blink.il", "--show", "Q0"][..],
        &["run", "examples/blink.il", "--set", "D0"],
        &["run", "examples/blink.il", "--at", "0:X0=1"],
        &["run", "examples/blink.il", "--scan-time", "10"],
        &["run", "examples/blink.il", "--set", "D0=70000"],
    ] {
        let out = softplc(args);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(!out.stderr.is_empty());
    }
}

#[test]
fn trace_to_csv_file() {
    let dir = tempfile::tempdir().unwrap();
    let out_csv = dir.path().join("trace.csv");
    let out = softplc(&[
        "run",
        "examples/blink.il",
        "--scans",
        "60",
        "--set",
        "X0=1",
        "--trace",
        "Y0,TN0",
        "--trace-every",
        "25",
        "--trace-file",
        out_csv.to_str().unwrap(),
        "--json",
    ]);
    json(&out);
    // Samples at scans 1, 26, 51: T0 (0.5 s) times out at scan 51, Y0 follows.
    let csv = std::fs::read_to_string(&out_csv).unwrap();
    assert_eq!(
        csv,
        "scan,time_ms,Y0,TN0\n1,10,0,0\n26,260,0,2\n51,510,1,5\n"
    );
}

/// `--exec` and `--stats` (issue #17): both tiers give the same report, the
/// JIT says how much it compiled, `--exec` outranks `SOFTPLC_EXEC`, and a
/// wrong name is an error naming it.
#[test]
fn exec_tiers_report_the_same_and_stats_name_the_tier() {
    let args = |tier: &'static str| {
        [
            "run",
            "examples/blink.il",
            "--scans",
            "100",
            "--set",
            "X0=1",
            "--show",
            "Y0",
            "--show",
            "CN0",
            "--json",
            "--stats",
            "--exec",
            tier,
        ]
    };
    let (jit, interp) = (softplc(&args("jit")), softplc(&args("interp")));
    assert_eq!(json(&jit), json(&interp));
    // blink.il: 12 ops; all but END (contacts, coils, timers, the counter
    // and its RST) are one native run of 11.
    let stderr = String::from_utf8_lossy(&jit.stderr);
    assert!(
        stderr.starts_with("exec: jit, 11 of 12 ops native, compiled in "),
        "{stderr}"
    );
    // Ten contacts and coils in a row are one native run; END is interpreted.
    let dir = tempfile::tempdir().unwrap();
    let bits = write(
        &dir,
        "bits.il",
        "LD X0\nAND X1\nOR X2\nANI X3\nOUT Y0\nLD X4\nOUT Y1\nLD Y0\nAND Y1\nOUT Y2\nEND\n",
    );
    let run = |tier| {
        softplc(&[
            "run", &bits, "--scans", "2", "--set", "X0=1", "--set", "X1=1", "--set", "X4=1",
            "--show", "Y2", "--json", "--stats", "--exec", tier,
        ])
    };
    let (jit, interp) = (run("jit"), run("interp"));
    assert_eq!(json(&jit), json(&interp));
    assert_eq!(
        json(&jit)["devices"]["Y2"],
        serde_json::json!(true),
        "{}",
        json(&jit)
    );
    let stderr = String::from_utf8_lossy(&jit.stderr);
    assert!(
        stderr.starts_with("exec: jit, 10 of 11 ops native, compiled in "),
        "{stderr}"
    );
    // At the end, the wall time of the scans alone.
    let interp_err = String::from_utf8_lossy(&interp.stderr);
    let lines: Vec<&str> = interp_err.lines().collect();
    assert_eq!(lines.len(), 2, "{interp_err}");
    assert_eq!(lines[0], "exec: interp");
    for last in [lines[1], stderr.lines().last().unwrap()] {
        assert!(
            last.starts_with("run: 2 scans in ") && last.ends_with(" µs per scan"),
            "{last}"
        );
    }
    // `softplc check examples/blink.il --stats EXTRA…` with one variable set.
    let check_with = |extra: &[&str], var: &str, value: &str| {
        Command::new(env!("CARGO_BIN_EXE_softplc"))
            .args(["check", "examples/blink.il", "--stats"])
            .args(extra)
            .env(var, value)
            .current_dir(workspace())
            .output()
            .unwrap()
    };
    let env = check_with(&["--exec", "interp"], "SOFTPLC_EXEC", "jit");
    assert!(env.status.success());
    assert!(String::from_utf8_lossy(&env.stderr).contains("exec: interp"));
    let bad = check_with(&[], "SOFTPLC_EXEC", "fast");
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&bad.stderr)
            .contains("SOFTPLC_EXEC: exec \"fast\" is not one of auto, jit, interp"),
        "{}",
        String::from_utf8_lossy(&bad.stderr)
    );
    // SOFTPLC_JIT_MIN_RUN=12: blink's one native run of 11 is too short,
    // so nothing is native; 0 is refused.
    let min_run = |n: &str| check_with(&["--exec", "jit"], "SOFTPLC_JIT_MIN_RUN", n);
    let twelve = min_run("12");
    let stderr = String::from_utf8_lossy(&twelve.stderr);
    assert!(
        stderr.starts_with("exec: jit, 0 of 12 ops native, compiled in "),
        "{stderr}"
    );
    let zero = min_run("0");
    assert_eq!(zero.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&zero.stderr)
            .contains("SOFTPLC_JIT_MIN_RUN=0: not a number from 1"),
        "{}",
        String::from_utf8_lossy(&zero.stderr)
    );
}

#[test]
fn the_text_report_gives_the_virtual_time_exactly() {
    // 510 scans of 10 ms: 5100 ms, without the float noise of 510 × 0.01 s.
    let out = softplc(&["run", "examples/blink.il", "--scans", "510"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.lines()
            .next()
            .is_some_and(|l| l.starts_with("scans: 510  time: 5100 ms  ")),
        "{text}"
    );
    let out = softplc(&["run", "examples/blink.il", "--scans", "3", "--json"]);
    assert_eq!(json(&out)["time_ms"], 30.0);
}

#[test]
fn a_reader_that_goes_away_ends_the_run_quietly() {
    // `softplc run … --trace Y0 | head -1`: stdout is closed before the trace
    // is printed; the run stops with a shell's broken-pipe status (141), not
    // a panic.
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args([
            "run",
            "examples/blink.il",
            "--scans",
            "2000",
            "--trace",
            "Y0",
        ])
        .current_dir(workspace())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("softplc runs");
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "stderr: {stderr}");
}

/// Issue #31, a newcomer's first hour: a directory without plc.toml says
/// that a project needs one (naming the directory and a program file in
/// it); `--stats` says why ops are not native; `run --help` lists `.apl`.
#[test]
fn newcomer_messages_say_what_to_do() {
    for cmd in ["check", "run"] {
        let o = softplc(&[cmd, "examples/aplc/"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(
            err.contains("examples/aplc/: no plc.toml in this directory: a project directory needs a plc.toml"),
            "{err}"
        );
        assert!(err.contains("e.g. examples/aplc/"), "{err}");
        assert!(!err.contains("os error"), "{err}");
    }
    // Two runs of native-capable ops (LD/OUT, LD; LD) between an FF, a
    // multiplication and END, which have no native form.
    let dir = tempfile::tempdir().unwrap();
    let short = write(
        &dir,
        "short.il",
        "LD X0\nOUT Y0\nLD X1\nFF Y1\nLD X2\n* D0 K2 D2\nEND\n",
    );
    let o = softplc(&["check", &short, "--stats", "--exec", "jit"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("; interpreted: 4 in runs shorter than 8 native ops in a row"),
        "{err}"
    );
    assert!(err.contains("3 with no native form"), "{err}");
    for help in [
        &["run", "--help"][..],
        &["--help"][..],
        &["serve", "--help"][..],
    ] {
        let o = softplc(help);
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains(".apl"), "{help:?}: {text}");
        for label in ["seed 0", "(000)", "(002)", "DEC-", "004 L"] {
            assert!(!text.contains(label), "{help:?} says {label}: {text}");
        }
    }
}
