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

/// `--dialect` names a family (any case; `melsec` and `aplc` as before); a
/// `--model` must run the file's language.
#[test]
fn dialect_is_a_family_and_the_model_must_match() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "prog.txt", "LD X10\nOUT Y10\n");
    for family in ["aplc", "APLC", " Aplc"] {
        let v = json(&softplc(&[
            "run",
            &p,
            "--dialect",
            family,
            "--set",
            "X10=1",
            "--show",
            "Y10",
            "--json",
        ]));
        assert_eq!(v["devices"]["Y10"], true, "{family}");
    }
    let m = write(&dir, "prog.il", "LD X10\nOUT Y10\nEND\n");
    for family in ["melsec", "MELSEC-Q", "melsec-qnph"] {
        let v = json(&softplc(&[
            "run",
            &m,
            "--dialect",
            family,
            "--set",
            "X10=1",
            "--show",
            "Y10",
            "--json",
        ]));
        assert_eq!(v["devices"]["Y10"], true, "{family}");
    }
    let bad = softplc(&["run", &p, "--dialect", "fx"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("unknown dialect `fx` (expected melsec, aplc or a family: MELSEC-Q, "),
        "{err}"
    );
    for args in [
        vec!["run", &p, "--dialect", "aplc", "--model", "Q06HCPU"],
        vec!["check", "examples/aplc/conveyor.apl", "--model", "q06hcpu"],
    ] {
        let out = softplc(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--model: Q06HCPU does not run "), "{err}");
    }
    let out = softplc(&["check", &m, "--model", "APLC-TCP"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--model: APLC-TCP does not run "), "{err}");
    let out = softplc(&["check", &p, "--dialect", "aplc", "--model", "aplc-tcp"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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

/// `--trace` samples APLC names: D10:i32 high word first, CN200 32-bit, X10
/// (input 8); `--set`/`--show` take the same names as `softplc test`.
#[test]
fn trace_with_aplc_names() {
    let dir = tempfile::tempdir().unwrap();
    // Each scan: D10:i32 += 70000 (DADD, high word in D10); C200 counts the
    // rising edges of X10.
    let p = write(
        &dir,
        "t.apl",
        "LD SM0\nDADD D10 70000 D10\nLD X10\nDCNT C200 5\n",
    );
    let csv = dir.path().join("t.csv");
    let csv_s = csv.display().to_string();
    let v = json(&softplc(&[
        "run",
        &p,
        "--scans",
        "3",
        "--at",
        "2:X10=1",
        "--trace",
        "D10:i32,D10,D11:u16,CN200,X10",
        "--trace-file",
        &csv_s,
        "--show",
        "CN200",
        "--show",
        "D10:i32",
        "--json",
    ]));
    assert_eq!(v["devices"]["CN200"], 1);
    assert_eq!(v["devices"]["D10:i32"], 210000);
    // 70000 = 16#0001_1170: D10 = 1, D11 = 4464; 140000 = 16#0002_22E0:
    // D10 = 2, D11 = 8928; 210000 = 16#0003_3450: D10 = 3, D11 = 13392.
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap(),
        "scan,time_ms,D10:i32,D10,D11:u16,CN200,X10\n\
         1,10,70000,1,4464,0,0\n\
         2,20,140000,2,8928,1,1\n\
         3,30,210000,3,13392,1,1\n"
    );
    // LM/V cannot be traced into a write, but can be read; X8 is refused.
    let bad = softplc(&["run", &p, "--trace", "X8"]);
    assert!(String::from_utf8_lossy(&bad.stderr).contains("`X8`: X is numbered in octal"));
}

/// Several `[[program]]` files form one user program (contract §1.1 item
/// 10): a global of one file used in another, a subroutine called across
/// files, errors located in their own file.
#[test]
fn multi_file_project() {
    let dir = tempfile::tempdir().unwrap();
    write(
        &dir,
        "plc.toml",
        "[cpu]\nmodel = \"APLC-TCP\"\n\n[[program]]\nfile = \"main.apl\"\n[[program]]\nfile = \"sub.apl\"\n",
    );
    write(
        &dir,
        "main.apl",
        "VAR_GLOBAL\n    灯   Y10\nEND_VAR\nPOU MAIN\nLD SM0\nCALL SBR_0 D0\nLD 按钮\nOUT 灯\n",
    );
    write(
        &dir,
        "sub.apl",
        "// the subroutine, with a global of its own\nVAR_GLOBAL\n    按钮   X10\nEND_VAR\nPOU SBR_0\nVAR\n    N   IN_OUT INT\nEND_VAR\nLD SM0\nINC #N\nLD M1\nDIV 1 D1 D2\n",
    );
    let d = dir.path().display().to_string();
    // Global names of either file are device names outside the program too.
    let v = json(&softplc(&[
        "run", &d, "--scans", "3", "--set", "按钮=1", "--show", "Y10", "--show", "灯", "--show",
        "D0", "--json",
    ]));
    assert_eq!(v["devices"]["Y10"], true);
    assert_eq!(v["devices"]["灯"], true);
    assert_eq!(v["devices"]["D0"], 3);
    assert!(v["error"].is_null());
    // The divide by zero is in sub.apl line 12, not line 20 of the whole.
    let v = json(&softplc(&["run", &d, "--set", "M1=1", "--json"]));
    assert_eq!(v["error"]["code"], 69);
    assert_eq!(v["error"]["line"], 12);
    assert!(
        v["error"]["file"].as_str().unwrap().ends_with("sub.apl"),
        "{v}"
    );
    // Diagnostics name each file: a global and POUs defined twice, with the
    // first definition's place.
    write(
        &dir,
        "more.apl",
        "VAR_GLOBAL\n    灯   Y11\nEND_VAR\nPOU MAIN\nLD SM0\nOUT Y0\nPOU SBR_0\nLD SM0\n",
    );
    write(
        &dir,
        "plc.toml",
        "[cpu]\nmodel = \"APLC-TCP\"\n[[program]]\nfile = \"main.apl\"\n[[program]]\nfile = \"sub.apl\"\n[[program]]\nfile = \"more.apl\"\n",
    );
    let out = softplc(&["check", &d]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let main = dir.path().join("main.apl").display().to_string();
    let sub = dir.path().join("sub.apl").display().to_string();
    let more = dir.path().join("more.apl").display().to_string();
    for line in [
        format!("{more}:2:5: global variable `灯` defined twice"),
        format!("{more}:4:5: POU `MAIN` defined twice (first at {main}:4)"),
        format!("{more}:7:5: POU `SBR_0` defined twice (first at {sub}:5)"),
    ] {
        assert!(err.contains(&line), "missing `{line}` in {err}");
    }
    // Two files without POU headers are two MAINs; none at all is no MAIN.
    write(&dir, "a.apl", "LD SM0\nOUT Y0\n");
    write(&dir, "b.apl", "\nLD X0\nOUT Y1\n");
    let a = dir.path().join("a.apl").display().to_string();
    let b = dir.path().join("b.apl").display().to_string();
    write(
        &dir,
        "plc.toml",
        "[cpu]\nmodel = \"APLC-TCP\"\n[[program]]\nfile = \"a.apl\"\n[[program]]\nfile = \"b.apl\"\n",
    );
    let err = String::from_utf8_lossy(&softplc(&["check", &d]).stderr).into_owned();
    assert!(
        err.contains(&format!(
            "{b}:2:1: POU `MAIN` defined twice (first at {a}:1)"
        )),
        "{err}"
    );
    write(
        &dir,
        "plc.toml",
        "[cpu]\nmodel = \"APLC-TCP\"\n[[program]]\nfile = \"sub.apl\"\n[[program]]\nfile = \"c.apl\"\n",
    );
    write(&dir, "c.apl", "LD SM0\nPOU SBR_1\nLD SM0\n");
    let c = dir.path().join("c.apl").display().to_string();
    let err = String::from_utf8_lossy(&softplc(&["check", &d]).stderr).into_owned();
    assert!(
        err.contains(&format!(
            "{c}:1:1: `LD` before the first POU header of the file"
        )),
        "{err}"
    );
    write(&dir, "c.apl", "POU SBR_1\nLD SM0\n");
    let err = String::from_utf8_lossy(&softplc(&["check", &d]).stderr).into_owned();
    assert!(
        err.contains("the program has no `POU MAIN` (APLC programming manual §4.2.1)"),
        "{err}"
    );
    assert!(err.contains(&sub), "{err}");
}

/// APLC-TCP has no MC protocol: `serve --mc` is refused before anything
/// starts.
#[test]
fn serve_refuses_mc_on_an_aplc_cpu() {
    for flag in ["--mc", "--mc-udp"] {
        let out = softplc(&["serve", "examples/aplc/conveyor.apl", flag, "127.0.0.1:0"]);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&format!("{flag}: an APLC-TCP has no MC protocol")),
            "{err}"
        );
    }
}

/// `run --port1` (contract §3.3): a project's `[port1]` on no device is a
/// silent line, so the manual's poll times out with 0x10 after SD136 (250 ms)
/// in virtual time; a port without settings, or a device that is not a
/// serial line, is refused before the first scan.
#[test]
fn ports_on_run() {
    let dir = tempfile::tempdir().unwrap();
    write(
        &dir,
        "main.apl",
        "LD SM1\nMOV 3 D0\nMOV 3 D1\nMOV 0 D2\nMOV 0 D3\nMOV 0 D4\nMOV 1 D5\nLD X0\nModbus 1 D0 D100\n",
    );
    write(
        &dir,
        "plc.toml",
        "[cpu]\nmodel = \"APLC-TCP\"\n[[program]]\nfile = \"main.apl\"\n[port1]\nprotocol = \"modbus-master\"\ntimeout_ms = 250\n",
    );
    let proj = dir.path().display().to_string();
    let v = json(&softplc(&[
        "run", &proj, "--scans", "30", "--at", "2:X0=1", "--show", "SD139", "--show", "SM136",
        "--show", "SD136", "--json",
    ]));
    assert_eq!(v["devices"]["SD136"], 250);
    assert_eq!(v["devices"]["SD139"], 16);
    assert_eq!(v["devices"]["SM136"], true);
    let out = softplc(&["run", &proj, "--port2", "/dev/null"]);
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("--port2: PORT2 has no settings"), "{e}");
    let prog = dir.path().join("main.apl").display().to_string();
    let out = softplc(&["run", &prog, "--port1", "/dev/null"]);
    assert_eq!(out.status.code(), Some(2));
    let out = softplc(&["run", &proj, "--port1", "/dev/null"]);
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("PORT1: /dev/null"), "{e}");
}
