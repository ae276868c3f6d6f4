//! `softplc serve --opcua` (contract §3.2) from the command line: refused
//! with the way to build it when the `opcua` feature is off; with it, the
//! `[opcua]` table's errors and the served endpoint.

use std::process::Command;

fn program(dir: &std::path::Path) -> std::path::PathBuf {
    let p = dir.join("p.il");
    std::fs::write(&p, "LD X0\nOUT Y0\nEND\n").unwrap();
    p
}

#[cfg(not(feature = "opcua"))]
#[test]
fn without_the_feature_opcua_is_refused_with_the_build_command() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_softplc"))
        .arg("serve")
        .arg(program(dir.path()))
        .args(["--opcua", "127.0.0.1:0", "--no-realtime"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("built without the OPC UA server"), "{err}");
    assert!(err.contains("--features opcua"), "{err}");
}

#[cfg(feature = "opcua")]
#[test]
fn bad_opcua_tables_name_the_key_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    program(dir.path());
    for (table, want) in [
        (
            "[opcua]\naddress = \"127.0.0.1:0\"\nport = 1\n",
            "unknown key `port`",
        ),
        (
            "[opcua]\naddress = \"127.0.0.1:0\"\nnodes = [\"QX9\"]\n",
            "`QX9`",
        ),
        (
            "[opcua]\naddress = \"127.0.0.1:0\"\npassword = \"x\"\n",
            "go together",
        ),
    ] {
        std::fs::write(
            dir.path().join("plc.toml"),
            format!("[[program]]\nfile = \"p.il\"\n{table}"),
        )
        .unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_softplc"))
            .arg("serve")
            .arg(dir.path())
            .arg("--no-realtime")
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{table}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{table}: {err}");
    }
}

#[cfg(feature = "opcua")]
#[test]
fn serve_reports_the_opcua_endpoint() {
    use std::io::{BufRead, BufReader};
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_softplc"))
        .arg("serve")
        .arg(program(dir.path()))
        .args(["--opcua", "127.0.0.1:0", "--no-realtime", "--opcua-pki"])
        .arg(dir.path().join("pki"))
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    err.read_line(&mut line).unwrap();
    let _ = child.kill();
    let _ = child.wait();
    assert!(line.contains("OPC UA on 127.0.0.1:"), "{line}");
}

/// Without `--opcua-pki` or `[opcua] pki` the certificate store is in the
/// user's data directory: nothing is written into the current directory.
#[cfg(feature = "opcua")]
#[test]
fn the_default_certificate_store_is_in_the_user_data_directory() {
    let dir = tempfile::tempdir().unwrap();
    let home = tempfile::tempdir().unwrap();
    let cwd = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_softplc"))
        .current_dir(cwd.path())
        .env("HOME", home.path())
        .env_remove("XDG_DATA_HOME")
        .arg("serve")
        .arg(program(dir.path()))
        .args(["--opcua", "127.0.0.1:0", "--no-realtime"])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let cert = home
        .path()
        .join(".local/share/softplc/opcua-pki/own/cert.der");
    let end = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !cert.exists() && std::time::Instant::now() < end {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let _ = child.kill();
    let _ = child.wait();
    assert!(cert.exists(), "no certificate at {}", cert.display());
    let written: Vec<_> = std::fs::read_dir(cwd.path()).unwrap().collect();
    assert!(
        written.is_empty(),
        "written into the current directory: {written:?}"
    );
}
