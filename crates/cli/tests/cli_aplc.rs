//! `softplc run`/`check` on APLC programs (contract §1.1, §2): `.apl` by
//! name, `--dialect`, APLC device names, projects with `[cpu] model =
//! "APLC-TCP"`.

use std::path::PathBuf;
use std::process::{Command, Output};

fn softplc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args(args)
        .current_dir(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .output()
        .expect("softplc runs")
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// The example machine: start, ten boxes, the batch lamp, the 3 s restart.
#[test]
fn conveyor_example() {
    let mut args: Vec<String> = [
        "run",
        "examples/aplc/conveyor.apl",
        "--scan-time",
        "100ms",
        "--json",
    ]
    .map(String::from)
    .to_vec();
    args.extend([
        "--at".into(),
        "1:X0=1".into(),
        "--at".into(),
        "2:X0=0".into(),
    ]);
    for k in 0..10 {
        args.extend(["--at".into(), format!("{}:X2=1", 3 + 2 * k)]);
        args.extend(["--at".into(), format!("{}:X2=0", 4 + 2 * k)]);
    }
    for d in ["Y0", "Y1", "CN0", "D10:i32", "M10"] {
        args.extend(["--show".into(), d.into()]);
    }
    let run = |scans: &str| {
        let mut a = args.clone();
        a.extend(["--scans".into(), scans.into()]);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        json(&softplc(&a))
    };
    let v = run("20");
    assert_eq!(v["devices"]["Y0"], true);
    assert_eq!(v["devices"]["CN0"], 9);
    let v = run("40");
    assert_eq!(v["state"], "RUN");
    assert_eq!(v["devices"]["Y0"], false, "a full batch stops the conveyor");
    assert_eq!(v["devices"]["Y1"], true);
    assert_eq!(v["devices"]["D10:i32"], 1000);
    assert_eq!(v["devices"]["M10"], true);
    let v = run("52");
    assert_eq!(v["devices"]["CN0"], 0);
    assert_eq!(v["devices"]["Y1"], false);
}

/// Octal names, `--dialect aplc` on another file name, 32-bit high word first.
#[test]
fn dialect_option_and_names() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        &dir,
        "prog.txt",
        "LD X10\nOUT Y10\nLD SM0\nDMOV 100000 D0\n",
    );
    let v = json(&softplc(&[
        "run",
        &p,
        "--dialect",
        "aplc",
        "--set",
        "X10=1",
        "--show",
        "Y10",
        "--show",
        "D0:i32",
        "--show",
        "D1:u16",
        "--json",
    ]));
    assert_eq!(v["devices"]["Y10"], true);
    assert_eq!(v["devices"]["D0:i32"], 100000);
    assert_eq!(v["devices"]["D1:u16"], 100000 & 0xFFFF);
    let bad = softplc(&["run", &p, "--dialect", "aplc", "--show", "X8"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("`X8`: X is numbered in octal"));
    let v = json(&softplc(&[
        "run",
        &p,
        "--dialect",
        "aplc",
        "--set",
        "D5=16#1F",
        "--show",
        "D5",
        "--json",
    ]));
    assert_eq!(v["devices"]["D5"], 31);
}

/// A run error keeps the CPU in RUN and is reported with its Appendix 6 code.
#[test]
fn run_error_json() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "div.apl", "LD SM0\nDIV 10 D0 D2\nINC D4\n");
    let v = json(&softplc(&[
        "run", &p, "--scans", "3", "--show", "D4", "--show", "SD20", "--json",
    ]));
    assert_eq!(v["state"], "RUN");
    assert_eq!(v["error"]["code"], 69);
    assert_eq!(v["error"]["line"], 2);
    assert!(v["error"]["step"].is_null());
    assert_eq!(v["devices"]["D4"], 3);
    assert_eq!(v["devices"]["SD20"], 69);
}

/// `check` reports file:line:column naming the token, non-zero exit.
#[test]
fn check_diagnostics() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "bad.apl", "LD X8\nMOV 70000 D0\nTRD D0\n");
    let out = softplc(&["check", &p]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.apl:1:4: `X8`: X is numbered in octal"),
        "{err}"
    );
    assert!(
        err.contains("bad.apl:2:5: constant `70000` does not fit a 16-bit operand"),
        "{err}"
    );
    assert!(
        err.contains("bad.apl:3:1: unsupported instruction `TRD`: not available on APLC-TCP"),
        "{err}"
    );
    let ok = softplc(&["check", "examples/aplc/conveyor.apl"]);
    assert!(ok.status.success());
}

/// `[cpu] model = "APLC-TCP"` reads the program as `.apl` with APLC names.
#[test]
fn aplc_project() {
    let dir = tempfile::tempdir().unwrap();
    write(
        &dir,
        "plc.toml",
        "[cpu]\nmodel = \"APLC-TCP\"\n\n[[program]]\nfile = \"main.prg\"\n",
    );
    write(&dir, "main.prg", "LD X10\nOUT Y10\n");
    let d = dir.path().display().to_string();
    let v = json(&softplc(&[
        "run", &d, "--set", "X10=1", "--show", "Y10", "--json",
    ]));
    assert_eq!(v["devices"]["Y10"], true);
    write(
        &dir,
        "plc.toml",
        "[cpu]\nmodel = \"APLC-TCP\"\n[latch]\nlatch1 = []\n[[program]]\nfile = \"main.prg\"\n",
    );
    let out = softplc(&["check", &d]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("[latch] in an APLC-TCP project"));
    // [ras]: the watchdog in effect shows in SD34 (below 100 ms acts as 100,
    // D4), the constant scan in SD33 with SM8; above 1000 ms is an error.
    write(&dir, "plc.toml", "[cpu]\nmodel = \"APLC-TCP\"\n[ras]\nwatchdog = \"50ms\"\nconstant_scan = \"20ms\"\n[[program]]\nfile = \"main.prg\"\n");
    let v = json(&softplc(&[
        "run", &d, "--show", "SD34", "--show", "SD33", "--show", "SM8", "--json",
    ]));
    assert_eq!(
        (
            v["devices"]["SD34"].clone(),
            v["devices"]["SD33"].clone(),
            v["devices"]["SM8"].clone()
        ),
        (100.into(), 20.into(), true.into())
    );
    write(&dir, "plc.toml", "[cpu]\nmodel = \"APLC-TCP\"\n[ras]\nwatchdog = \"1500ms\"\n[[program]]\nfile = \"main.prg\"\n");
    let out = softplc(&["check", &d]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("watchdog: APLC-TCP allows 0-1000 ms"));
    let v = json(&softplc(&[
        "run",
        "examples/aplc/conveyor.apl",
        "--show",
        "SD34",
        "--json",
    ]));
    assert_eq!(v["devices"]["SD34"], 200);
}
