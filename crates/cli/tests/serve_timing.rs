//! `softplc serve`'s real-time options at work (their refusals are in
//! serve_time.rs) and its scan timing (`GET /api/v1/timing`, `POST /api/v1/timing/reset`,
//! `--timing-report`). Counts are checked against the elapsed time with a
//! wide margin (the machine may be loaded); no time is asserted.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

mod serve_support;
use serve_support::start;

const TOKEN: &str = "t0ken";

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

fn program(dir: &Path) -> String {
    let p = dir.join("main.il");
    std::fs::write(&p, "LD SM400\nINC D0\nEND\n").unwrap();
    p.to_str().unwrap().to_string()
}

fn http(port: u16, method: &str, path: &str, token: Option<&str>) -> (u16, Value) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    let auth = token.map_or(String::new(), |t| format!("Authorization: Bearer {t}\r\n"));
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n{auth}Content-Length: 0\r\n\r\n"
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let code = out.split_whitespace().nth(1).unwrap().parse().unwrap();
    let body = out.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    (code, serde_json::from_str(body).unwrap_or_default())
}

/// The percentiles of a distribution are in order and the mean within them.
fn ordered(d: &Value, what: &str) {
    let f = |k: &str| d[k].as_f64().unwrap_or_else(|| panic!("{what}.{k}: {d}"));
    assert!(f("p50") <= f("p99"), "{what}: {d}");
    assert!(f("p99") <= f("p999"), "{what}: {d}");
    assert!(f("p999") <= f("max"), "{what}: {d}");
    assert!(f("mean") <= f("max") && f("p50") >= 0.0, "{what}: {d}");
}

/// `count` scans over `seconds` at `period_us`: at most one more than the
/// periods that fit (a scan never starts before its deadline), at least a
/// quarter of them (a loaded machine delays and skips some).
fn count_fits(t: &Value) {
    let count = t["count"].as_f64().unwrap();
    let periods = t["seconds"].as_f64().unwrap() * 1e6 / t["period_us"].as_f64().unwrap();
    assert!(count <= periods + 2.0, "{t}");
    assert!(count >= periods / 4.0, "{t}");
}

#[test]
fn the_timing_endpoint_counts_the_scans_and_resets() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path());
    let mut cmd = softplc();
    cmd.args(["serve", &p, "--scan-time", "2ms", "--spin-us", "100"])
        .args(["--http", "127.0.0.1:0", "--http-token", TOKEN]);
    let s = start(cmd);
    std::thread::sleep(Duration::from_millis(1000));
    let (code, t) = http(s.port, "GET", "/api/v1/timing", None);
    assert_eq!(code, 200, "{t}");
    assert_eq!(t["period_us"], 2000, "{t}");
    assert_eq!(t["realtime"]["spin_us"], 100, "{t}");
    assert_eq!(t["realtime"]["memory_locked"], false, "{t}");
    assert_eq!(t["realtime"]["cpu"], Value::Null, "{t}");
    count_fits(&t);
    assert!(t["count"].as_u64().unwrap() >= 100, "{t}");
    for d in ["lateness_us", "period_jitter_us", "scan_time_us"] {
        ordered(&t[d], d);
    }
    // Every scan started is counted; CPU 1's periods are one fewer than its
    // starts; a scan in RUN executed.
    assert_eq!(t["lateness_us"]["count"], t["count"], "{t}");
    let starts = t["count"].as_u64().unwrap();
    let periods = t["period_jitter_us"]["count"].as_u64().unwrap();
    assert!(periods < starts && periods + 2 >= starts, "{t}");
    assert!(
        t["scan_time_us"]["count"].as_u64().unwrap() >= starts - 1,
        "{t}"
    );

    // A reset needs the token, like every request that changes something.
    let (code, _) = http(s.port, "POST", "/api/v1/timing/reset", None);
    assert_eq!(code, 401);
    let (code, before) = http(s.port, "POST", "/api/v1/timing/reset", Some(TOKEN));
    assert_eq!(code, 200, "{before}");
    assert!(before["count"].as_u64().unwrap() >= starts, "{before}");
    let (_, after) = http(s.port, "GET", "/api/v1/timing", None);
    assert!(
        after["count"].as_u64().unwrap() < starts,
        "started over: {after}"
    );
    assert!(after["seconds"].as_f64().unwrap() < before["seconds"].as_f64().unwrap());
    // The contract's endpoints are unchanged.
    let (code, st) = http(s.port, "GET", "/api/v1/status", None);
    assert_eq!(code, 200);
    assert_eq!(st["state"], "RUN");
}

fn sigterm(child: &Child) {
    let ok = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
}

/// Runs `cmd` (a `serve --timing-report`) for a while, stops it with SIGTERM
/// and returns the report it wrote.
fn report_of(cmd: Command, report: &Path) -> Value {
    let mut s = start(cmd);
    std::thread::sleep(Duration::from_millis(500));
    sigterm(&s.child);
    let t = Instant::now();
    let status = loop {
        if let Some(st) = s.child.try_wait().unwrap() {
            break st;
        }
        assert!(t.elapsed() < Duration::from_secs(20), "serve did not stop");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "{status:?}");
    serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap()
}

fn root() -> bool {
    // SAFETY: geteuid has no preconditions.
    unsafe { libc::geteuid() == 0 }
}

/// The soft RLIMIT_RTPRIO a child inherits (0: SCHED_FIFO needs CAP_SYS_NICE).
fn rtprio_limit() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max realtime priority"))?;
    line.split_whitespace().nth(3)?.parse().ok()
}

#[test]
fn realtime_runs_with_or_without_the_privilege() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path());
    let report = dir.path().join("timing.json");
    let mut cmd = softplc();
    cmd.args([
        "serve",
        &p,
        "--scan-time",
        "1ms",
        "--realtime",
        "--cpu",
        "0",
    ])
    .arg("--timing-report")
    .arg(&report);
    let t = report_of(cmd, &report);
    let rt = &t["realtime"];
    let note = rt["note"].as_str().unwrap();
    assert_eq!(t["period_us"], 1000, "{t}");
    assert_eq!(rt["spin_us"], 200, "the default spin: {t}");
    count_fits(&t);
    ordered(&t["lateness_us"], "lateness_us");
    if rt["sched_fifo"] == true {
        assert!(note.starts_with("SCHED_FIFO priority"), "{note}");
    } else {
        assert!(note.starts_with("not granted"), "{note}");
    }
    if rt["memory_locked"] == true {
        assert!(note.contains("; memory locked"), "{note}");
    } else {
        assert!(note.contains("; memory not locked ("), "{note}");
    }
    // CPU 0 is allowed (`--cpu` was checked at start).
    assert_eq!(rt["cpu"], 0, "{note}");
    assert!(note.ends_with("; pinned to CPU 0"), "{note}");
    if !root() {
        return;
    }
    // As root everything is granted …
    assert_eq!(rt["sched_fifo"], true, "{note}");
    assert_eq!(rt["memory_locked"], true, "{note}");
    // … and as an unprivileged user (setpriv to nobody, where it can run
    // the binary) the server still runs, saying what it did not get.
    let nobody = |cmd: &mut Command| {
        cmd.args(["--reuid=65534", "--regid=65534", "--clear-groups", "--"])
            .arg(env!("CARGO_BIN_EXE_softplc"));
    };
    let mut probe = Command::new("setpriv");
    nobody(&mut probe);
    let usable = probe
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !usable {
        eprintln!("setpriv or the binary is not usable as nobody here: unprivileged run skipped");
        return;
    }
    let open = tempfile::tempdir().unwrap();
    let mut perm = std::fs::metadata(open.path()).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perm, 0o777);
    std::fs::set_permissions(open.path(), perm).unwrap();
    let p = program(open.path());
    let report = open.path().join("timing.json");
    let mut cmd = Command::new("setpriv");
    nobody(&mut cmd);
    cmd.args(["serve", &p, "--scan-time", "1ms", "--realtime"])
        .arg("--timing-report")
        .arg(&report);
    let t = report_of(cmd, &report);
    let rt = &t["realtime"];
    let note = rt["note"].as_str().unwrap();
    if rtprio_limit() == Some(0) {
        assert_eq!(rt["sched_fifo"], false, "{note}");
        assert!(note.starts_with("not granted ("), "{note}");
    }
    count_fits(&t);
    ordered(&t["lateness_us"], "lateness_us");
}
