//! `softplc serve --http` (contract §3, §3.1): the token from `--http-token`
//! or `[http] token`, read-only without one, and the bad-option errors.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

struct Serve {
    child: Child,
    port: u16,
}

impl Drop for Serve {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn serve(args: &[&str]) -> Serve {
    let mut child = Command::new(env!("CARGO_BIN_EXE_softplc"))
        .arg("serve")
        .args(args)
        .args(["--http", "127.0.0.1:0", "--no-realtime"])
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    let port = loop {
        line.clear();
        assert!(err.read_line(&mut line).unwrap() > 0, "serve exited");
        if let Some(rest) = line.split("web monitor on 127.0.0.1:").nth(1) {
            break rest
                .trim()
                .trim_end_matches(|c: char| !c.is_ascii_digit())
                .parse()
                .unwrap();
        }
    };
    std::thread::spawn(move || std::io::copy(&mut err, &mut std::io::sink()));
    Serve { child, port }
}

fn post(port: u16, path: &str, token: Option<&str>, body: &str) -> (u16, String) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    let auth = token.map_or(String::new(), |t| format!("Authorization: Bearer {t}\r\n"));
    write!(
        s,
        "POST {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n{auth}Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let code = out.split_whitespace().nth(1).unwrap().parse().unwrap();
    (code, out)
}

#[test]
fn the_token_comes_from_plc_toml_or_the_option() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("main.il"), "LD X0\nOUT Y0\nEND\n").unwrap();
    std::fs::write(
        dir.path().join("plc.toml"),
        "[[program]]\nfile = \"main.il\"\n\n[http]\ntoken = \"from-toml\"\n",
    )
    .unwrap();
    let state = dir.path().join("st");
    let p = dir.path().to_str().unwrap();
    {
        let s = serve(&[p, "--state", state.to_str().unwrap()]);
        assert_eq!(post(s.port, "/api/v1/devices", None, r#"{"D0": 1}"#).0, 401);
        assert_eq!(
            post(s.port, "/api/v1/devices", Some("from-toml"), r#"{"D0": 1}"#).0,
            200
        );
    }
    {
        let s = serve(&[
            p,
            "--state",
            state.to_str().unwrap(),
            "--http-token",
            "from-cli",
        ]);
        assert_eq!(
            post(s.port, "/api/v1/devices", Some("from-toml"), r#"{"D0": 1}"#).0,
            401
        );
        assert_eq!(
            post(s.port, "/api/v1/cpu/stop", Some("from-cli"), "").0,
            200
        );
    }
    let il = dir.path().join("main.il");
    let s = serve(&[il.to_str().unwrap()]);
    assert_eq!(post(s.port, "/api/v1/cpu/stop", Some("x"), "").0, 403);
}

#[test]
fn bad_http_options_are_refused() {
    for (args, want) in [
        (vec!["--http", "nowhere"], "--http"),
        (
            vec!["--http", "8080", "--http-token", "has space"],
            "--http-token",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_softplc"))
            .args([
                "serve",
                concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/blink.il"),
            ])
            .args(&args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(want),
            "{args:?}"
        );
    }
}
