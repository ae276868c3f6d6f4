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

#[test]
fn toml_syntax_errors_are_one_line_with_line_and_column() {
    let t = tempfile::tempdir().unwrap();
    std::fs::write(
        t.path().join("plc.toml"),
        "[cpu]\nmodel = \"Q06HCPU\"\n[[program\nfile = \"m.il\"\n",
    )
    .unwrap();
    let out = softplc().arg("check").arg(t.path()).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let line = err.lines().next().unwrap_or_default();
    assert!(
        line.ends_with(
            "plc.toml:3:10: TOML syntax error: invalid table header; expected `.`, `]]`"
        ),
        "{err}"
    );
    // A scenario file: position and message on one line too.
    std::fs::write(
        t.path().join("s.toml"),
        "program = \"x.il\"\n\n[[model]\nkind = 3\n",
    )
    .unwrap();
    let out = softplc()
        .arg("test")
        .arg(t.path().join("s.toml"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("s.toml: 3:8: invalid table header; expected `.`, `]]`\n"),
        "{text}"
    );
    std::fs::write(t.path().join("s2.toml"), "program = \"x.il\"\nbogus = 1\n").unwrap();
    let out = softplc()
        .arg("test")
        .arg(t.path().join("s2.toml"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("s2.toml: 2:1: unknown field `bogus`"),
        "{text}"
    );
}

#[test]
fn a_program_larger_than_the_program_memory_is_rejected() {
    // Q06HCPU: 60k = 61,440 steps, of which a file header takes 34 (004 Table 3.1).
    // 30,703 rungs of LD + OUT + END = 61,407 steps + 34 = 61,441: one too many.
    let t = tempfile::tempdir().unwrap();
    let big = t.path().join("big.il");
    std::fs::write(&big, "LD X0\nOUT Y0\n".repeat(30_703) + "END\n").unwrap();
    let out = softplc().arg("check").arg(&big).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("the programs take 61441 steps")
            && err.contains("program memory of 61440 steps"),
        "{err}"
    );
    // One rung less fits exactly.
    std::fs::write(&big, "LD X0\nOUT Y0\n".repeat(30_702) + "END\n").unwrap();
    let out = softplc().arg("check").arg(&big).output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
