//! A soft PLC stays controllable (issue 11 item 6): an endless loop that
//! contains WDT never faults (WDT resets the watchdog, as on the CPU), but
//! `run --timeout`, Ctrl-C/SIGTERM to `run` and SIGTERM to `serve` stop it,
//! commit latched data, and `serve` reports the stalled scan.

use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

/// R0 += 1 (latched: a file register), then loop forever resetting the watchdog.
const LOOP: &str = "LD SM400\nINC R0\nP0\nLD SM400\nWDT\nLD SM400\nCJ P0\nEND\n";

fn r0(prog: &Path, state: &Path) -> i64 {
    let out = softplc()
        .arg("run")
        .arg(prog)
        .arg("--state")
        .arg(state)
        .args(["--scans", "0", "--json", "--show", "R0"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["devices"]["R0"].as_i64().unwrap()
}

/// Waits for the child to exit, at most 20 s (then kills it and fails).
fn wait(child: &mut Child, what: &str) -> std::process::ExitStatus {
    let t = Instant::now();
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            return s;
        }
        if t.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            panic!("{what} did not stop");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn sigterm(child: &Child) {
    let ok = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
}

#[test]
fn run_timeout_stops_an_endless_scan_and_commits() {
    let t = tempfile::tempdir().unwrap();
    let prog = t.path().join("loop.il");
    std::fs::write(&prog, LOOP).unwrap();
    let state = t.path().join("state");
    let mut child = softplc()
        .arg("run")
        .arg(&prog)
        .arg("--state")
        .arg(&state)
        .args([
            "--scans",
            "5",
            "--timeout",
            "500ms",
            "--json",
            "--show",
            "R0",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let status = wait(&mut child, "run --timeout");
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    assert!(status.success());
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["state"], "STOP");
    assert_eq!(v["stopped"], "timeout");
    assert!(v["error"].is_null(), "WDT keeps the watchdog quiet: {v}");
    assert_eq!(v["devices"]["R0"], 1);
    assert_eq!(r0(&prog, &state), 1, "committed at the stop");
}

#[test]
fn sigterm_stops_run_and_serve_inside_an_endless_scan() {
    let t = tempfile::tempdir().unwrap();
    let prog = t.path().join("loop.il");
    std::fs::write(&prog, LOOP).unwrap();
    let state = t.path().join("state");

    let mut child = softplc()
        .arg("run")
        .arg(&prog)
        .arg("--state")
        .arg(&state)
        .args(["--scans", "5"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(300));
    sigterm(&child);
    let status = wait(&mut child, "run after SIGTERM");
    assert_eq!(status.code(), Some(143), "128 + SIGTERM");
    assert_eq!(r0(&prog, &state), 1);

    let mut child = softplc()
        .arg("serve")
        .arg(&prog)
        .arg("--state")
        .arg(&state)
        .arg("--no-realtime") // an endless loop at SCHED_FIFO would hog a core
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The stall is reported after 1 s.
    std::thread::sleep(Duration::from_millis(1600));
    sigterm(&child);
    let status = wait(&mut child, "serve after SIGTERM");
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(status.success(), "{err}");
    assert!(err.contains("has not reached END"), "stall reported: {err}");
    assert_eq!(r0(&prog, &state), 2, "serve committed its scan's INC");
}
