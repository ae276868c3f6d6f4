//! `softplc serve --time-scale F` and `--lockstep` (contract §7): the
//! options' errors name them, and a served program and a multi-CPU system
//! advance in virtual time.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::Command;

mod serve_support;
use serve_support::{start, Serve};

const TOKEN: &str = "t0ken";

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

/// A program file in a temporary directory.
fn program(dir: &std::path::Path) -> String {
    let p = dir.join("main.il");
    std::fs::write(&p, "LD SM400\nINC D0\nEND\n").unwrap();
    p.to_str().unwrap().to_string()
}

/// `serve ARGS` that must refuse to start: its stderr.
fn refused(args: &[&str]) -> String {
    let out = softplc().arg("serve").args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    String::from_utf8_lossy(&out.stderr).to_string()
}

#[test]
fn bad_options_are_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path());
    for bad in ["0.001", "1001", "fast", "NaN", "inf"] {
        let err = refused(&[&p, "--time-scale", bad]);
        assert!(err.contains("--time-scale"), "{bad}: {err}");
        assert!(err.contains("0.01 to 1000"), "{bad}: {err}");
    }
    // Only the web monitor's advance moves a held CPU.
    let err = refused(&[&p, "--lockstep"]);
    assert!(
        err.contains("--lockstep") && err.contains("--http"),
        "{err}"
    );
    let err = refused(&[&p, "--lockstep", "--http", "127.0.0.1:0"]);
    assert!(err.contains("--lockstep") && err.contains("token"), "{err}");
}

fn serve(args: &[&str]) -> Serve {
    let mut cmd = softplc();
    cmd.arg("serve").args(args).args([
        "--http",
        "127.0.0.1:0",
        "--http-token",
        TOKEN,
        "--no-realtime",
    ]);
    start(cmd)
}

fn http(port: u16, method: &str, path: &str, body: &str) -> (u16, serde_json::Value) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\nAuthorization: Bearer {TOKEN}\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let code = out.split_whitespace().nth(1).unwrap().parse().unwrap();
    let body = out.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    (code, serde_json::from_str(body).unwrap_or_default())
}

#[test]
fn a_lockstep_program_runs_when_advanced() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path());
    let s = serve(&[&p, "--lockstep", "--scan-time", "20ms"]);
    assert!(s.banner.contains("lockstep"), "{}", s.banner);
    let (code, st) = http(s.port, "GET", "/api/v1/status", "");
    assert_eq!(
        (code, &st["scan"], &st["time_ms"]),
        (200, &0.into(), &0.0.into())
    );
    let (code, done) = http(s.port, "POST", "/api/v1/sim/advance", r#"{"ms": 50}"#);
    assert_eq!(
        (code, done),
        (200, serde_json::json!({"scan": 3, "time_ms": 60.0}))
    );
    let (_, d) = http(s.port, "GET", "/api/v1/devices?names=D0,SD520", "");
    assert_eq!(d["devices"], serde_json::json!({"D0": 3, "SD520": 20}));
}

#[test]
fn a_multi_cpu_system_advances_by_scans_of_cpu_1() {
    let dir = tempfile::tempdir().unwrap();
    for (i, scan) in [(1, "10ms"), (2, "30ms")] {
        let d = dir.path().join(format!("cpu{i}"));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!(
                "[[program]]\nfile = \"main.il\"\n[ras]\nconstant_scan = \"{scan}\"\n\
                 [multi_cpu]\ncpus = 2\n"
            ),
        )
        .unwrap();
        std::fs::write(d.join("main.il"), "LD SM400\nINC D0\nEND\n").unwrap();
    }
    std::fs::write(
        dir.path().join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    let s = serve(&[dir.path().to_str().unwrap(), "--lockstep"]);
    let (code, done) = http(s.port, "POST", "/api/v1/sim/advance", r#"{"scans": 10}"#);
    assert_eq!(
        (code, done),
        (200, serde_json::json!({"scan": 10, "time_ms": 100.0}))
    );
    // CPU 2 scanned at 30, 60 and 90 ms.
    let (_, st) = http(s.port, "GET", "/api/v1/status", "");
    let cpus = st["cpus"].as_array().unwrap();
    let scans: Vec<_> = cpus.iter().map(|c| c["scans"].clone()).collect();
    assert_eq!(scans, [serde_json::json!(10), serde_json::json!(3)]);
    assert_eq!(cpus[1]["time_ms"], 100.0);
}

#[test]
fn bad_real_time_options_are_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path());
    let err = refused(&[&p, "--cpu", "100000"]);
    assert!(
        err.contains("--cpu 100000: CPU 100000 is not one this process may run on"),
        "{err}"
    );
    let err = refused(&[&p, "--realtime", "--no-realtime"]);
    assert!(
        err.contains("--no-realtime") && err.contains("--realtime"),
        "{err}"
    );
    let err = refused(&[&p, "--spin-us", "1000001"]);
    assert!(err.contains("--spin-us"), "{err}");
    let err = refused(&[&p, "--spin-us=-5"]);
    assert!(err.contains("--spin-us"), "{err}");
}
