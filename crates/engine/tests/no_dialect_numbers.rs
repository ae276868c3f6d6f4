//! The engine and softplc-ir hold no dialect's numbers: no special relay or
//! register (SM/SD) and no error number in their non-test code. A family's
//! system devices and error codes are its `System`'s (softplc-melsec's
//! `system/`, softplc-aplc's `system.rs`).
//!
//! `crates/ir/src/device/` is left out: it defines the device kinds
//! themselves (SM and SD among them) and the MELSEC operand syntax.

use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            if !p.ends_with("device") || !p.parent().is_some_and(|d| d.ends_with("ir/src")) {
                sources(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") && !p.ends_with("tests.rs") {
            out.push(p);
        }
    }
}

/// The code of a file: comments dropped, and everything from a `#[cfg(test)]`
/// module on (test modules close the files).
fn code(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("#[cfg(test)]") {
            break;
        }
        let code = line.split("//").next().unwrap_or("");
        out.push((n + 1, code.to_string()));
    }
    out
}

/// What in a line of code names a system device or an error number.
fn offence(line: &str) -> Option<String> {
    let tokens = line.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'));
    for t in tokens {
        if t == "SM" || t == "SD" || t.starts_with("SM_") || t.starts_with("SD_") {
            return Some(format!("names the system device `{t}`"));
        }
    }
    let compact: String = line.chars().filter(|c| !c.is_whitespace()).collect();
    if let Some(at) = compact.find("ErrorCode(") {
        if compact[at + "ErrorCode(".len()..].starts_with(|c: char| c.is_ascii_digit()) {
            return Some("writes an error number".into());
        }
    }
    None
}

#[test]
fn engine_and_ir_name_no_system_device_and_no_error_number() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    sources(&root.join("engine/src"), &mut files);
    sources(&root.join("ir/src"), &mut files);
    assert!(
        files.len() > 20,
        "sources not found under {}",
        root.display()
    );
    let mut problems = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap_or_default();
        for (n, line) in code(&text) {
            if let Some(why) = offence(&line) {
                problems.push(format!("{}:{n}: {why}: {}", f.display(), line.trim()));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_scan_finds_what_it_looks_for() {
    assert!(offence("let _ = mem.set_bit(DeviceKind::SM, 400, true);").is_some());
    assert!(offence("if matches!(k, X | SD | R) {").is_some());
    assert!(offence("sd(mem, softplc_ir::access::SD_R_BLOCK as i64, 0);").is_some());
    assert!(offence("return Err(ErrorCode( 4100 ));").is_some());
    assert!(offence("let s = SMALL; code: ErrorCode(u16::from_le_bytes(b))").is_none());
    assert_eq!(code("a // SD0\n#[cfg(test)]\nSD").len(), 1);
}
