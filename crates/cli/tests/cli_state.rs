//! `softplc run --save-state FILE` / `--load-state FILE` (contract §7):
//! N+M scans equal N scans, a save, a load and M scans (inputs written
//! before the cut come back from the file); `scans` counts the run's scans,
//! `time_ms` the time since power-on; a file of another program or a
//! damaged one is refused with a clear error and a non-zero exit.

use std::path::{Path, PathBuf};
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

const SHOW: [&str; 10] = [
    "--show", "Y0", "--show", "TN0", "--show", "TN1", "--show", "CN0", "--json", "--show",
];

fn blink(scans: &str, extra: &[&str]) -> Output {
    let mut args = vec!["run", "examples/blink.il", "--scans", scans];
    args.extend_from_slice(&SHOW);
    args.push("T0");
    args.extend_from_slice(extra);
    softplc(&args)
}

/// blink.il with X0 ON: 130 scans of 10 ms in one run, or 47 then 83. X0 is
/// set only in the first part: it comes back from the file. X1 resets C0
/// at scan 100 (the second part's 53). Y0 is ON for 50 scans from scan 51
/// (T0 up after 500 ms), then T1 restarts the cycle at scan 101: C0 counted
/// the rise at 51 and, reset at 100, nothing since; TN0 is 2 at scan 130
/// (T0 restarted at 102, 28 scans of 10 ms = 280 ms).
#[test]
fn n_plus_m_scans_equal_n_save_load_m() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("blink.state");
    let f = file.to_str().unwrap();
    let whole = json(&blink("130", &["--set", "X0=1", "--at", "100:X1=1"]));
    let first = json(&blink("47", &["--set", "X0=1", "--save-state", f]));
    assert_eq!(first["scans"], 47);
    let second = json(&blink("83", &["--load-state", f, "--at", "53:X1=1"]));
    assert_eq!(second["devices"], whole["devices"]);
    assert_eq!(second["state"], "RUN");
    assert_eq!(second["scans"], 83);
    assert_eq!(second["time_ms"], 1300.0);
    assert_eq!(whole["devices"]["CN0"], 0);
    assert_eq!(whole["devices"]["TN0"], 2);
    assert_eq!(whole["devices"]["Y0"], false);
}

#[test]
fn another_program_a_damaged_or_a_missing_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("blink.state");
    let f = file.to_str().unwrap();
    json(&blink("5", &["--set", "X0=1", "--save-state", f]));
    let other = dir.path().join("other.il");
    std::fs::write(&other, "LD X0\nOUT Y0\nEND\n").unwrap();
    let out = softplc(&["run", other.to_str().unwrap(), "--load-state", f]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!(
            "--load-state {f}: the state file was saved from other programs"
        )),
        "{err}"
    );
    let mut bytes = std::fs::read(&file).unwrap();
    let at = bytes.len() - 3;
    bytes[at] ^= 1;
    std::fs::write(&file, &bytes).unwrap();
    let out = blink("5", &["--load-state", f]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("the state file is damaged: its checksum"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
    let missing = dir.path().join("none.state");
    let out = blink("5", &["--load-state", missing.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("none.state"));
}

/// Two CPUs (CPU 2 every 20 ms) exchanging D100 by auto refresh: 10 + 14
/// scans of CPU 1 equal 24; CPU 1 counted D0 to 24 and CPU 2 adds 1000 to
/// what CPU 1 published at its last END.
fn write_system(dir: &Path) {
    let params =
        "[multi_cpu]\ncpus = 2\n[[multi_cpu.refresh]]\ndevice = \"D100\"\nwords = [2, 2]\n";
    std::fs::write(
        dir.join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    for (d, extra, il) in [
        ("cpu1", "", "LD SM400\nINC D0\nMOV D0 D100\nEND\n"),
        (
            "cpu2",
            "[ras]\nconstant_scan = \"20ms\"\n",
            "LD SM400\n+ K1000 D100 D102\nEND\n",
        ),
    ] {
        let p = dir.join(d);
        std::fs::create_dir(&p).unwrap();
        let toml = format!("[[program]]\nfile = \"main.il\"\n{params}{extra}");
        std::fs::write(p.join("plc.toml"), toml).unwrap();
        std::fs::write(p.join("main.il"), il).unwrap();
    }
}

#[test]
fn a_system_continues_from_its_file() {
    let dir = tempfile::tempdir().unwrap();
    write_system(dir.path());
    let sys = dir.path().to_str().unwrap();
    let file = dir.path().join("sys.state");
    let f = file.to_str().unwrap();
    let show = ["--show", "D0", "--show", "CPU2/D102", "--json"];
    let run = |scans: &str, extra: &[&str]| {
        let mut a = vec!["run", sys, "--scans", scans];
        a.extend_from_slice(&show);
        a.extend_from_slice(extra);
        json(&softplc(&a))
    };
    let whole = run("24", &[]);
    run("10", &["--save-state", f]);
    let second = run("14", &["--load-state", f]);
    assert_eq!(second["devices"], whole["devices"]);
    assert_eq!(second["devices"]["D0"], 24);
    assert_eq!(second["scans"], 14);
    assert_eq!(second["cpus"][1]["scans"], 7);
    assert_eq!(second["time_ms"], 240.0);
    // A single CPU's file is not the system's.
    let one = dir.path().join("one.state");
    json(&blink("1", &["--save-state", one.to_str().unwrap()]));
    let out = softplc(&["run", sys, "--load-state", one.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("holds 1 CPU(s); this is 2"));
}
