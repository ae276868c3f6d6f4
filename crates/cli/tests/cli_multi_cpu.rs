//! `softplc run` and `check` of a multi-CPU system (contract §6): the
//! report's `cpus`, `CPUn/` names, CPU 1's scans counting, a module's input
//! set through its control CPU, and clear refusals.

use std::path::Path;
use std::process::{Command, Output};

fn softplc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args(args)
        .output()
        .expect("softplc runs")
}

/// CPU 1 counts D0 up and sends it by auto refresh as D100; CPU 2 (constant
/// scan 20 ms) adds 1000 to what it receives. An input slot X0-XF is
/// controlled by CPU 2, which copies X0 to Y20.
fn write_system(dir: &Path) {
    let params = "[multi_cpu]\ncpus = 2\n\
        [[multi_cpu.refresh]]\ndevice = \"D100\"\nwords = [2, 2]\n\
        [[slot]]\ntype = \"input\"\npoints = 16\ncontrol_cpu = 2\n\
        [[slot]]\ntype = \"output\"\npoints = 16\n";
    let cpus = [
        ("cpu1", "", "LD SM400\nINC D0\nMOV D0 D100\nEND\n"),
        (
            "cpu2",
            "[ras]\nconstant_scan = \"20ms\"\n",
            "LD SM400\n+ K1000 D100 D102\nLD X0\nOUT Y10\nEND\n",
        ),
    ];
    std::fs::write(
        dir.join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    for (d, extra, il) in cpus {
        let p = dir.join(d);
        std::fs::create_dir(&p).unwrap();
        let toml = format!("[[program]]\nfile = \"main.il\"\n{params}{extra}");
        std::fs::write(p.join("plc.toml"), toml).unwrap();
        std::fs::write(p.join("main.il"), il).unwrap();
    }
}

#[test]
fn check_lists_every_cpu() {
    let dir = tempfile::tempdir().unwrap();
    write_system(dir.path());
    let out = softplc(&["check", dir.path().to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("OK, 2 CPUs"), "{text}");
    assert!(text.contains("CPU 2: Q06HCPU, 1 program"), "{text}");
}

/// 10 scans of CPU 1 (10 ms each, to 100 ms) are 5 of CPU 2 (20 ms), which
/// scans after CPU 1 at equal times. CPU 1's D100 = 10. CPU 2's scan at
/// 100 ms uses the D100 it imported at its END at 80 ms (8): D102 = 1008.
/// CPU 1's END at 100 ms comes before that scan, so CPU 1 holds what CPU 2
/// published at 80 ms: 1000 + 6.
#[test]
fn run_reports_every_cpu() {
    let dir = tempfile::tempdir().unwrap();
    write_system(dir.path());
    let out = softplc(&[
        "run",
        dir.path().to_str().unwrap(),
        "--scans",
        "10",
        "--show",
        "D100",
        "--show",
        "CPU2/D102",
        "--show",
        "D102",
        "--show",
        "CPU2/Y10",
        "--set",
        "CPU1/X0=1",
        "--json",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text} {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
    assert_eq!(v["scans"], 10);
    assert_eq!(v["time_ms"], 100.0);
    assert_eq!(v["state"], "RUN");
    assert_eq!(v["cpus"][0]["cpu"], 1);
    assert_eq!(v["cpus"][1]["scans"], 5);
    assert_eq!(v["cpus"][1]["error"], serde_json::Value::Null);
    assert_eq!(v["devices"]["D100"], 10);
    assert_eq!(v["devices"]["CPU2/D102"], 1008);
    assert_eq!(v["devices"]["D102"], 1006);
    // X0 belongs to CPU 2's input module: `CPU1/X0` set the module's input.
    assert_eq!(v["devices"]["CPU2/Y10"], true);
}

#[test]
fn refusals_are_clear() {
    let dir = tempfile::tempdir().unwrap();
    write_system(dir.path());
    let d = dir.path().to_str().unwrap();
    let out = softplc(&["run", d, "--show", "CPU3/D0"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("there is no CPU 3"), "{err}");
    let out = softplc(&["run", d, "--trace", "D0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--trace does not apply"));
    // A CPU whose program does not compile names the CPU and the place.
    std::fs::write(dir.path().join("cpu2/main.il"), "LD SM400\nFOO D0\nEND\n").unwrap();
    let out = softplc(&["check", d]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("main.il:2:1: CPU 2:"), "{err}");
}
