//! `softplc run`/`check` of a GX Works2 export whose PLC Information row
//! names a Universal model (QnU): the file runs on that model.

use std::process::{Command, Output};

fn softplc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args(args)
        .output()
        .expect("softplc runs")
}

/// A UTF-16LE export naming `plc`: `LD X0 / ANDFI X1 / OUT Y0 / END`.
fn export(dir: &tempfile::TempDir, plc: &str) -> String {
    let text = format!(
        "\"MAIN\"\r\n\"PLC Information:\"\t\"{plc}\"\r\n\
         \"Step No.\"\t\"Line Statement\"\t\"Instruction\"\t\"I/O(Device)\"\t\"Blank\"\t\"PI Statement\"\t\"Note\"\r\n\
         \"0\"\t\"\"\t\"LD\"\t\"X0\"\t\"\"\t\"\"\t\"\"\r\n\
         \"1\"\t\"\"\t\"ANDFI\"\t\"X1\"\t\"\"\t\"\"\t\"\"\r\n\
         \"2\"\t\"\"\t\"OUT\"\t\"Y0\"\t\"\"\t\"\"\t\"\"\r\n\
         \"3\"\t\"\"\t\"END\"\t\"\"\t\"\"\t\"\"\t\"\"\r\n"
    );
    let mut bytes = vec![0xFF, 0xFE];
    bytes.extend(text.encode_utf16().flat_map(u16::to_le_bytes));
    let path = dir.path().join("main.csv");
    std::fs::write(&path, bytes).unwrap();
    path.display().to_string()
}

#[test]
fn an_export_naming_a_q04udeh_runs_on_it() {
    let dir = tempfile::tempdir().unwrap();
    let csv = export(&dir, "QCPU (Q mode) Q04UDEH");
    let out = softplc(&[
        "run", &csv, "--scans", "3", "--set", "X0=1", "--show", "Y0", "--json",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stderr: {stderr}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["state"], "RUN");
    // X1 stays OFF: ANDFI is ON (no falling edge).
    assert_eq!(v["devices"]["Y0"], true);
    assert!(softplc(&["check", &csv]).status.success());

    // --model takes precedence: on a Q06HCPU ANDFI is refused.
    let out = softplc(&["check", &csv, "--model", "Q06HCPU"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("unsupported instruction `ANDFI`: a Universal model instruction"),
        "{stderr}"
    );
}

#[test]
fn an_export_naming_an_unknown_model_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let csv = export(&dir, "FXCPU FX3U/FX3UC");
    let out = softplc(&["check", &csv]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(":2:27: the PLC Information row names the CPU model `FX3U/FX3UC`"),
        "{stderr}"
    );
    assert!(softplc(&["check", &csv, "--model", "Q26UDEHCPU"])
        .status
        .success());
}
