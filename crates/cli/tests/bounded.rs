//! Bounded inputs (issue 11 item 7, in part): oversized files fail fast with a
//! clear message, diagnostics never echo huge tokens or raw control
//! characters, and plc.toml diagnostics stay linear in the file size.

use std::process::Command;

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

#[test]
fn dev_zero_fails_fast_with_a_size_message() {
    let out = softplc().args(["check", "/dev/zero"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        err.contains("/dev/zero") && err.contains("larger than 16 MiB"),
        "{err}"
    );
    // A project whose plc.toml is endless, and a scenario file.
    let t = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/dev/zero", t.path().join("plc.toml")).unwrap();
    let out = softplc()
        .arg("check")
        .arg(t.path().join("plc.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(0));
    assert!(
        err.contains("larger than 4 MiB, the limit for plc.toml"),
        "{err}"
    );
    let out = softplc().args(["test", "/dev/zero"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stdout);
    assert_ne!(out.status.code(), Some(0));
    assert!(err.contains("the limit for a scenario file"), "{err}");
}

#[test]
fn diagnostics_cut_long_tokens_and_escape_control_characters() {
    let t = tempfile::tempdir().unwrap();
    let p = t.path().join("bad.il");
    let long = "Q".repeat(50_000);
    std::fs::write(&p, format!("{long}\nLD X0\x1b[2J\nEND\n")).unwrap();
    let out = softplc().arg("check").arg(&p).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(err.len() < 2_000, "{} bytes of diagnostics", err.len());
    assert!(err.contains("(50000 characters)"), "{err}");
    assert!(!err.contains('\x1b'), "raw escape echoed: {err:?}");
}

#[test]
fn sixteen_thousand_program_tables_are_all_diagnosed() {
    let t = tempfile::tempdir().unwrap();
    let mut toml = String::new();
    for i in 0..16_000 {
        toml += &format!("[[program]]\nfile = \"p{i}.il\"\ntype = \"scan\"\n\n");
    }
    std::fs::write(t.path().join("plc.toml"), toml).unwrap();
    let out = softplc().arg("check").arg(t.path()).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        err.contains("plc.toml:63998:8: program file \"p15999.il\" not found"),
        "{}",
        &err[err.len().saturating_sub(300)..]
    );
    assert!(err.contains("too many programs (16000)"));
}
