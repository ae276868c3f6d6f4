//! `softplc serve --http` (contract §3, §3.1): the token from `--http-token`
//! or `[http] token`, read-only without one, and the bad-option errors.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::Command;

mod serve_support;
use serve_support::{start, Serve};

fn serve(args: &[&str]) -> Serve {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_softplc"));
    cmd.arg("serve")
        .args(args)
        .args(["--http", "127.0.0.1:0", "--no-realtime"]);
    start(cmd)
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

fn get(port: u16, path: &str) -> (u16, serde_json::Value) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let code = out.split_whitespace().nth(1).unwrap().parse().unwrap();
    let body = out.split("\r\n\r\n").nth(1).unwrap_or("");
    // A chunked body: the JSON object is between the first `{` and last `}`.
    let json = match (body.find('{'), body.rfind('}')) {
        (Some(a), Some(b)) => serde_json::from_str(&body[a..=b]).unwrap(),
        _ => serde_json::Value::Null,
    };
    (code, json)
}

/// The JSON API of an APLC program speaks APLC names (contract §3.1, §2):
/// octal X/Y, `D10:i32` high word first, LM/V read only, `16#` values, and
/// the status names the model and reports errors without step numbers.
#[test]
fn the_api_of_an_aplc_program_uses_aplc_names() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("t.apl");
    std::fs::write(
        &p,
        "VAR_GLOBAL\n    灯 Y10\nEND_VAR\nLD X10\nOUT Y10\nLD M1\nDIV 1 D0 D2\n",
    )
    .unwrap();
    let s = serve(&[p.to_str().unwrap(), "--http-token", "t"]);
    let body = r#"{"D10:i32": 100000, "X10": true, "D20": "16#1F"}"#;
    assert_eq!(post(s.port, "/api/v1/devices", Some("t"), body).0, 200);
    // 100000 = 16#0001_86A0: D10 = 1 (high), D11 = 34464; X10 is input 8.
    let (code, v) = get(
        s.port,
        "/api/v1/devices?names=D10,D11:u16,D10:i32,Y10,X10,D20,K4Y0,%E7%81%AF",
    );
    assert_eq!(code, 200, "{v}");
    let d = &v["devices"];
    assert_eq!(d["D10"], 1);
    assert_eq!(d["D11:u16"], 34464);
    assert_eq!(d["D10:i32"], 100000);
    assert_eq!(d["Y10"], true);
    assert_eq!(d["X10"], true);
    assert_eq!(d["D20"], 31);
    // Y10 is bit 8 of K4Y0 (Y0-Y7, Y10-Y17).
    assert_eq!(d["K4Y0"], 256);
    // The program's global name 灯 is Y10.
    assert_eq!(d["灯"], true, "{v}");
    // X8 is not an APLC device; V0 is MAIN's local: both 400, nothing written.
    let (code, v) = get(s.port, "/api/v1/devices?names=X8");
    assert_eq!(code, 400);
    assert!(v["error"].as_str().unwrap().contains("X8"), "{v}");
    let (code, out) = post(
        s.port,
        "/api/v1/devices",
        Some("t"),
        r#"{"D30": 5, "V0": 1}"#,
    );
    assert_eq!(code, 400, "{out}");
    assert_eq!(
        get(s.port, "/api/v1/devices?names=D30").1["devices"]["D30"],
        0
    );
    // Forces name X/Y in octal.
    assert_eq!(
        post(s.port, "/api/v1/force", Some("t"), r#"{"Y17": true}"#).0,
        200
    );
    assert_eq!(get(s.port, "/api/v1/force").1["forced"]["Y17"], true);
    // The status: the model, and error 69 with its line and no step.
    let (_, st) = get(s.port, "/api/v1/status");
    assert_eq!(st["model"], "APLC-TCP");
    assert!(st["error"].is_null(), "{st}");
    assert_eq!(
        post(s.port, "/api/v1/devices", Some("t"), r#"{"M1": true}"#).0,
        200
    );
    let (_, st) = get(s.port, "/api/v1/status");
    assert_eq!(st["error"]["code"], 69, "{st}");
    assert_eq!(st["error"]["line"], 7);
    assert!(st["error"]["step"].is_null());
    assert_eq!(st["state"], "RUN");
}
