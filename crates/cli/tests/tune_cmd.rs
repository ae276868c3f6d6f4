//! `softplc tune` on the shipped example (examples/process/fopdt_loop.toml):
//! it prints the tuning table, writes the SVG trend, recovers the plant's
//! K, τ, θ and verifies a loop that settles.

use std::path::Path;
use std::process::{Command, Output};

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

fn example() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/process/fopdt_loop.toml")
}

/// The JSON a run printed; the run must succeed (else its stderr is shown).
#[track_caller]
fn json_of(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn within(v: f64, want: f64, rel: f64) -> bool {
    (v - want).abs() <= rel * want.abs()
}

#[test]
fn tune_the_example_prints_a_table_and_writes_an_svg() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("loop.svg");
    let out = softplc()
        .arg("tune")
        .arg(example())
        .args(["--loop", "R1000", "--mv0", "25", "--svg"])
        .arg(&svg)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for row in [
        "zn-p ",
        "zn-pi ",
        "zn-pid ",
        "chr-pi ",
        "chr-pid ",
        "simc-pi ",
        "simc-pid ",
        "imc-pid ",
    ] {
        assert!(text.contains(row), "no {row} in\n{text}");
    }
    assert!(text.contains("FOPDT fit: K = 0.80"), "{text}");
    assert!(text.contains("— settled"), "{text}");
    let drawn = std::fs::read_to_string(&svg).unwrap();
    assert!(
        drawn.starts_with("<svg") && drawn.contains("PV R1010"),
        "{}",
        &drawn[..100]
    );
}

#[test]
fn tune_the_example_as_json() {
    let out = softplc()
        .arg("tune")
        .arg(example())
        .args([
            "--loop",
            "R1000",
            "--mv0",
            "25",
            "--pid-constants",
            "D1200",
            "--json",
        ])
        .output()
        .unwrap();
    let j = json_of(&out);
    // The plant: K = 0.8 C/% = 0.4 %/% of 0..200 C, τ = 90 s, θ = 15 s, with
    // 0.05 C of noise on the measurement (measured: K 0.8008, τ 90.01 s,
    // θ 14.97 s).
    let id = &j["identification"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert!(within(f(&id["fit"]["gain"]), 0.8, 0.01), "{id}");
    assert!(within(f(&id["process"]["gain"]), 0.4, 0.01), "{id}");
    assert!(within(f(&id["fit"]["tau"]), 90.0, 0.01), "{id}");
    assert!(within(f(&id["fit"]["dead_time"]), 15.0, 0.01), "{id}");
    // S.AT1's view of the same record (AT1ST = 10 s from the scenario): its
    // tangent dead time lies between θ and θ + AT1ST, and its three ZN rows.
    let at1 = &j["at1"];
    assert_eq!(f(&at1["curve"]["sample_period"]), 10.0, "{at1}");
    let l = f(&at1["curve"]["l"]);
    let theta = f(&id["fit"]["dead_time"]);
    assert!(l >= theta && l <= theta + 10.0, "{at1}");
    assert_eq!(at1["rows"].as_array().unwrap().len(), 3, "{at1}");
    // Closed loop with simc-pi: settles, modest overshoot, no sustained
    // oscillation (few crossings of the band).
    let v = &j["verification"];
    assert_eq!(v["tuning"]["rule"], "simc-pi");
    assert_eq!(v["settled"], true);
    let m = &v["metrics"];
    // (measured: 5.7 % overshoot, settled in 94 s)
    assert!(f(&m["overshoot_pct"]) < 8.0, "{m}");
    assert!(f(&m["settling_time"]) < 120.0, "{m}");
    assert!(m["band_crossings"].as_u64().unwrap() <= 3, "{m}");
}

#[test]
fn the_example_scenario_passes_softplc_test() {
    let out = softplc().arg("test").arg(example()).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains("2 passed, 0 failed"),
        "{text}"
    );
}

#[test]
fn fit_csv_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("step.csv");
    let mut s = String::from("t,u,y\n");
    for i in 0..400 {
        let t = f64::from(i);
        let u = if t >= 50.0 { 1.0 } else { 0.0 };
        let y = if t > 60.0 {
            2.0 * (1.0 - (-(t - 60.0) / 40.0).exp())
        } else {
            0.0
        };
        s += &format!("{t},{u},{y}\n");
    }
    std::fs::write(&csv, s).unwrap();
    let out = softplc()
        .args(["tune", "--json", "--fit-csv"])
        .arg(&csv)
        .output()
        .unwrap();
    let j = json_of(&out);
    assert!(within(j["fit"]["gain"].as_f64().unwrap(), 2.0, 1e-6), "{j}");
    assert!(within(j["fit"]["tau"].as_f64().unwrap(), 40.0, 1e-4), "{j}");
    assert!(
        within(j["fit"]["dead_time"].as_f64().unwrap(), 10.0, 1e-4),
        "{j}"
    );

    std::fs::write(&csv, "t,u,y\n0,0,0\nx,1,1\n").unwrap();
    let out = softplc()
        .args(["tune", "--fit-csv"])
        .arg(&csv)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("step.csv:3: `x` is not a number"), "{err}");

    let out = softplc()
        .arg("tune")
        .arg(example())
        .args(["--loop", "R1000", "--rule", "pid"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown rule `pid`"));
}

/// Issue #31 defect 8: a fit whose numbers are not finite (K = inf from a
/// step of 1e-300, R² = NaN from outputs near 1e200) is a failed fit, exit
/// status 2, with or without --json; nothing is printed as a result.
#[test]
fn a_non_finite_fit_is_a_failed_fit() {
    let dir = tempfile::tempdir().unwrap();
    for (name, du, scale) in [
        ("tiny_step.csv", 1e-300, 1e10),
        ("huge_output.csv", 1.0, 1e200),
    ] {
        let csv = dir.path().join(name);
        let mut s = String::from("t,u,y\n");
        for i in 0..100 {
            let t = f64::from(i) * 0.5;
            let (u, y) = if t < 10.0 {
                (0.0, 0.0)
            } else {
                (du, scale * (1.0 - (-(t - 10.0) / 5.0).exp()))
            };
            s += &format!("{t},{u},{y}\n");
        }
        std::fs::write(&csv, s).unwrap();
        for json in [false, true] {
            let mut cmd = softplc();
            cmd.arg("tune");
            if json {
                cmd.arg("--json");
            }
            let out = cmd.arg("--fit-csv").arg(&csv).output().unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(
                out.status.code(),
                Some(2),
                "{name}: {}{err}",
                String::from_utf8_lossy(&out.stdout)
            );
            assert!(out.stdout.is_empty(), "{name}");
            assert!(
                err.contains(name) && err.contains("not finite"),
                "{name}: {err}"
            );
        }
    }
}

/// The example's loop on CPU 2 of a multi-CPU system (CPU 1 idle): with
/// `CPU2/` names for the loop, the plant and `--pid-constants` the session
/// is the single CPU's, scan for scan (CPU 2 scans at the scenario's
/// 100 ms), so the identification is exactly the same.
#[test]
fn tune_a_loop_on_cpu2_of_a_system() {
    let dir = tempfile::tempdir().unwrap();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/process");
    let multi = "[multi_cpu]\ncpus = 2\n";
    for (cpu, model, program) in [
        ("cpu1", "Q06HCPU", "LD SM400\nOUT M0\nEND\n".to_string()),
        (
            "cpu2",
            "Q06PHCPU",
            std::fs::read_to_string(examples.join("temperature_loop.il")).unwrap(),
        ),
    ] {
        let d = dir.path().join(cpu);
        std::fs::create_dir(&d).unwrap();
        std::fs::write(d.join("main.il"), program).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!("[cpu]\nmodel = \"{model}\"\n[[program]]\nfile = \"main.il\"\n{multi}"),
        )
        .unwrap();
    }
    std::fs::write(
        dir.path().join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    // The example's scenario with its program replaced by the system and
    // its names by CPU 2's.
    let single = std::fs::read_to_string(example()).unwrap();
    let mut text = String::new();
    for line in single.lines() {
        let line = match line {
            l if l.starts_with("program =") => "project = \".\"".to_string(),
            l if l.starts_with("cpu =") => continue,
            l => l.replace("\"D", "\"CPU2/D").replace("\"R1", "\"CPU2/R1"),
        };
        text += &line;
        text.push('\n');
    }
    assert!(text.contains("\"CPU2/D820\"") && text.contains("\"CPU2/R1072:f32\""));
    let scenario = dir.path().join("loop.toml");
    std::fs::write(&scenario, text).unwrap();
    let svg = dir.path().join("trend.svg");
    let tune = |path: &Path, prefix: &str| {
        let out = softplc()
            .arg("tune")
            .arg(path)
            .args(["--loop", &format!("{prefix}R1000"), "--mv0", "25"])
            .args(["--pid-constants", &format!("{prefix}D1200"), "--json"])
            .arg("--svg")
            .arg(&svg)
            .output()
            .unwrap();
        json_of(&out)
    };
    let (one, sys) = (tune(&example(), ""), tune(&scenario, "CPU2/"));
    assert_eq!(sys["loop_tag"], "CPU2/R1000");
    assert_eq!(one["identification"], sys["identification"]);
    assert_eq!(one["step_test"], sys["step_test"]);
    assert_eq!(sys["verification"]["settled"], true);
    let drawn = std::fs::read_to_string(&svg).unwrap();
    assert!(
        drawn.contains("PV CPU2/R1010") && drawn.contains("MV CPU2/R1012"),
        "{}",
        &drawn[..200]
    );

    // The loop's CPU must exist.
    let out = softplc()
        .arg("tune")
        .arg(&scenario)
        .args(["--loop", "CPU3/R1000"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--loop: `CPU3/R1000`: there is no CPU 3"),
        "{err}"
    );
}
