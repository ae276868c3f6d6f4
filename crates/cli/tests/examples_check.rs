//! Every shipped example loads as shipped: `softplc check` passes, with no
//! option, on each project directory (one with a plc.toml) and on each
//! program file outside a project under examples/ (a file states its CPU
//! itself: `; PLC Information: Q06PHCPU` in the process-control examples).

use std::path::{Path, PathBuf};
use std::process::Command;

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// The projects and the program files outside them, under `dir`.
fn checkable(dir: &Path, out: &mut Vec<PathBuf>) {
    if dir.join("plc.toml").is_file() {
        out.push(dir.to_path_buf());
        return;
    }
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            checkable(&p, out);
        } else if matches!(
            p.extension().and_then(|e| e.to_str()),
            Some("il" | "csv" | "apl")
        ) {
            out.push(p);
        }
    }
}

#[test]
fn every_shipped_example_passes_check() {
    let mut found = Vec::new();
    checkable(&examples(), &mut found);
    assert!(found.len() >= 20, "{found:?}");
    let mut failed = Vec::new();
    for p in &found {
        let out = Command::new(env!("CARGO_BIN_EXE_softplc"))
            .arg("check")
            .arg(p)
            .output()
            .unwrap();
        if !out.status.success() {
            failed.push(format!(
                "{}: {}",
                p.display(),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
