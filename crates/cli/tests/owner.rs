//! One owner per state directory (issue 11 item 2): a second `softplc run` on
//! the directory of a running `softplc serve` is refused with a message naming
//! the directory and the owner's PID, and the lock does not outlive kill -9.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

#[test]
fn second_owner_is_refused_and_lock_dies_with_the_owner() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("count.il");
    std::fs::write(&prog, "LD SM400\nINC R0\nEND\n").unwrap();
    let state = dir.path().join("state");
    let state_s = state.to_str().unwrap();
    let mut server = softplc()
        .args(["serve", prog.to_str().unwrap(), "--state", state_s])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until it serves (the state directory is open by then).
    let mut err = BufReader::new(server.stderr.take().unwrap());
    let mut line = String::new();
    while !line.contains("serving") {
        line.clear();
        assert!(err.read_line(&mut line).unwrap() > 0, "serve exited early");
    }
    let out = softplc()
        .args([
            "run",
            prog.to_str().unwrap(),
            "--state",
            state_s,
            "--scans",
            "5",
        ])
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "second owner must fail: {msg}");
    assert!(msg.contains(state_s), "names the directory: {msg}");
    assert!(
        msg.contains(&format!("PID {}", server.id())),
        "names the owner: {msg}"
    );
    // A second server is refused too.
    let out = softplc()
        .args(["serve", prog.to_str().unwrap(), "--state", state_s])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("in use"));

    server.kill().unwrap(); // SIGKILL: no cleanup runs
    server.wait().unwrap();
    let out = softplc()
        .args([
            "run",
            prog.to_str().unwrap(),
            "--state",
            state_s,
            "--scans",
            "5",
        ])
        .args(["--json", "--show", "R0"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "the lock is gone with its owner: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["devices"]["R0"].as_i64().unwrap() >= 5);
}

#[test]
fn bad_remote_passwords_are_rejected_at_start() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("p.il");
    std::fs::write(&prog, "LD X0\nOUT Y0\nEND\n").unwrap();
    for pw in ["", "abc", "abcde", "ab 1", "ab\u{e9}1"] {
        let out = softplc()
            .args(["serve", prog.to_str().unwrap(), "--mc", "127.0.0.1:0"])
            .args(["--password", pw])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{pw:?}: {err}");
        assert!(err.contains("--password"), "{err}");
    }
}
