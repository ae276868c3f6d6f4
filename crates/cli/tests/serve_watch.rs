//! `softplc serve --watch` (contract §7): a program file rewritten on disk
//! is written during RUN and reported; a changed plc.toml is reported as
//! needing a restart; `PUT /api/v1/program` writes a single program file.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::Command;
use std::time::{Duration, Instant};

mod serve_support;
use serve_support::{start, Serve};

fn serve(args: &[&str]) -> Serve {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_softplc"));
    cmd.arg("serve").args(args).args([
        "--http",
        "127.0.0.1:0",
        "--http-token",
        "tok",
        "--no-realtime",
    ]);
    start(cmd)
}

fn request(port: u16, method: &str, path: &str, body: &str) -> (u16, String) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\nAuthorization: Bearer tok\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let code = out.split_whitespace().nth(1).unwrap().parse().unwrap();
    (code, out)
}

#[test]
fn a_rewritten_program_file_is_written_during_run_and_plc_toml_needs_a_restart() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("main.il"), "LD SM400\nMOV K1 D0\nEND\n").unwrap();
    std::fs::write(
        dir.path().join("plc.toml"),
        "[[program]]\nfile = \"main.il\"\n",
    )
    .unwrap();
    let state = dir.path().join("st");
    let s = serve(&[
        dir.path().to_str().unwrap(),
        "--watch",
        "--state",
        state.to_str().unwrap(),
    ]);
    // An editor's save: a new file renamed over the old one.
    let tmp = dir.path().join(".main.il.new");
    std::fs::write(&tmp, "LD SM400\nMOV K2 D0\nLD X0\nOUT Y0\nEND\n").unwrap();
    std::fs::rename(&tmp, dir.path().join("main.il")).unwrap();
    let l = s.expect("main.il written during RUN");
    // LD SM400 and END kept; MOV K2 D0 (3 steps), LD X0, OUT Y0 added.
    let what = "2 instructions kept, 3 added, 1 removed (5 steps written, 7 in all)";
    assert!(l.contains(what), "{l}");
    // The swap came after an END; the scan after it moves 2.
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let (code, body) = request(s.port, "GET", "/api/v1/devices?names=D0", "");
        assert_eq!(code, 200);
        if body.contains(r#""D0":2"#) {
            break;
        }
        assert!(Instant::now() < deadline, "{body}");
        std::thread::sleep(Duration::from_millis(20));
    }
    // A text that does not compile: reported, the program stays.
    std::fs::write(dir.path().join("main.il"), "LD SM400\nMOVE K3 D0\nEND\n").unwrap();
    s.expect("main.il not written, the running program is unchanged");
    s.expect("main.il:2:1: unknown instruction `MOVE`");
    std::fs::write(
        dir.path().join("plc.toml"),
        "[[program]]\nfile = \"main.il\"\n[ras]\nwatchdog = \"100ms\"\n",
    )
    .unwrap();
    s.expect("plc.toml changed; its settings take effect when serve is restarted");
}

#[test]
fn put_program_writes_a_single_program_file() {
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("main.il");
    std::fs::write(&main, "LD SM400\nMOV K1 D0\nEND\n").unwrap();
    let state = dir.path().join("st");
    let s = serve(&[main.to_str().unwrap(), "--state", state.to_str().unwrap()]);
    let body = r#"{"file": "main.il", "text": "LD SM400\nMOV K7 D0\nEND\n"}"#;
    let (code, out) = request(s.port, "PUT", "/api/v1/program", body);
    assert_eq!(code, 200, "{out}");
    assert!(out.contains(r#""kept":2"#), "{out}");
    let (_, out) = request(s.port, "GET", "/api/v1/devices?names=D0", "");
    assert!(out.contains(r#""D0":7"#), "{out}");
    assert_eq!(
        std::fs::read_to_string(&main).unwrap(),
        "LD SM400\nMOV K7 D0\nEND\n"
    );
}
