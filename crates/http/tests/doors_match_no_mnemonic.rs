//! The doors (web monitor, OPC UA, the servers, the CLI, the simulator,
//! tuning) never recognise an instruction by its mnemonic: what an
//! instruction is comes from the compiled program (`Program::listing`: ladder
//! roles, loop memories and their layouts). This test fails when a door's
//! source (outside its tests and comments) holds a string literal that is a
//! mnemonic of either dialect, as `m == "OUT"`, `"ANB" | "ORB" =>`,
//! `strip_prefix("LD")` or a list of instruction names would.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use softplc_core::program::isa::{Isa, Pulse};

/// The crates that show or serve a program.
const DOORS: &[&str] = &[
    "http", "opcua", "serve", "mc", "modbus", "cli", "sim", "tune",
];

/// Every mnemonic of `isas` as it may be written: the name, its `P` form and
/// its `SP.` form. One-character operators (`+`, `/`, `*`) are left out: as
/// text they are everywhere (paths, separators) and no door classifies by them.
fn mnemonics(isas: &[&Isa]) -> HashSet<String> {
    let mut out = HashSet::new();
    for d in isas.iter().flat_map(|i| i.all()) {
        if d.name.chars().count() < 2 {
            continue;
        }
        out.insert(d.name.to_string());
        match d.pulse {
            Pulse::Suffix => {
                out.insert(format!("{}P", d.name));
            }
            Pulse::SPrefix => {
                out.insert(format!("SP.{}", &d.name[2..]));
            }
            Pulse::None => {}
        }
    }
    out
}

/// The string literals of Rust source before its first `#[cfg(test)]`, as
/// (line, text), comments skipped. Raw strings count; escapes are kept as
/// written (no mnemonic has one).
fn literals(src: &str) -> Vec<(usize, String)> {
    let code = src.split("#[cfg(test)]").next().unwrap_or("");
    let b: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let (mut k, mut line) = (0, 1);
    while k < b.len() {
        let c = b[k];
        let next = b.get(k + 1).copied();
        if c == '\n' {
            line += 1;
            k += 1;
        } else if c == '/' && next == Some('/') {
            while k < b.len() && b[k] != '\n' {
                k += 1;
            }
        } else if c == '/' && next == Some('*') {
            k += 2;
            while k < b.len() && !(b[k] == '*' && b.get(k + 1) == Some(&'/')) {
                line += usize::from(b[k] == '\n');
                k += 1;
            }
            k += 2;
        } else if c == '\'' {
            // A character literal ('"', '\'', 'x') or a lifetime.
            match (next, b.get(k + 2), b.get(k + 3)) {
                (Some('\\'), _, _) => {
                    k += 2;
                    while k < b.len() && b[k] != '\'' {
                        k += 1;
                    }
                    k += 1;
                }
                (Some(_), Some('\''), _) => k += 3,
                _ => k += 1,
            }
        } else if c == 'r' && (next == Some('"') || next == Some('#')) {
            let hashes = b[k + 1..].iter().take_while(|&&h| h == '#').count();
            let open = k + 1 + hashes;
            if b.get(open) != Some(&'"') {
                k += 1;
                continue;
            }
            let (start, first) = (open + 1, line);
            let mut end = start;
            while end < b.len()
                && !(b[end] == '"' && b[end + 1..].iter().take(hashes).all(|&h| h == '#'))
            {
                line += usize::from(b[end] == '\n');
                end += 1;
            }
            out.push((first, b[start..end.min(b.len())].iter().collect()));
            k = end + 1 + hashes;
        } else if c == '"' {
            let (start, first) = (k + 1, line);
            let mut end = start;
            while end < b.len() && b[end] != '"' {
                if b[end] == '\\' {
                    end += 1;
                }
                line += usize::from(b.get(end) == Some(&'\n'));
                end += 1;
            }
            out.push((first, b[start..end.min(b.len())].iter().collect()));
            k = end + 1;
        } else if c.is_alphanumeric() || c == '_' {
            // An identifier (so the `r` of `bar"` is not a raw string).
            while k < b.len() && (b[k].is_alphanumeric() || b[k] == '_') {
                k += 1;
            }
        } else {
            k += 1;
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

fn all_mnemonics() -> HashSet<String> {
    mnemonics(&[
        softplc_core::instructions::isa(),
        softplc_core::instructions::process_isa(),
        softplc_aplc::isa(),
    ])
}

#[test]
fn no_door_compares_a_mnemonic() {
    let names = all_mnemonics();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut found = Vec::new();
    let mut scanned = 0;
    for door in DOORS {
        let mut files = Vec::new();
        rust_files(&root.join(door).join("src"), &mut files);
        assert!(!files.is_empty(), "no sources found for crates/{door}");
        for f in files {
            let src = std::fs::read_to_string(&f).unwrap();
            scanned += 1;
            for (line, text) in literals(&src) {
                if names.contains(&text) {
                    let at = f.strip_prefix(&root).unwrap_or(&f).display().to_string();
                    found.push(format!("crates/{at}:{line}: \"{text}\""));
                }
            }
        }
    }
    assert!(scanned > 50, "only {scanned} files scanned");
    assert!(
        found.is_empty(),
        "door code names instructions by their mnemonics (read the program's \
         listing: roles, loop memories):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_scan_finds_what_it_looks_for() {
    let names = all_mnemonics();
    let src = r####"
        // A comment naming "LDI" is fine.
        fn f(m: &str) -> bool {
            let c = '"';
            let lt: &'static str = "x";
            /* "ANB" in a block comment */
            let raw = r#"a "quoted" OUT"#;
            match m { "ANB" | "ORB" => true, _ => m.strip_prefix("LD").is_some() }
                || ["S.IN", "SP.PIDCONT"].contains(&m) || m == "MOVP"
        }
        #[cfg(test)]
        mod tests { const A: &str = "OUT"; }
    "####;
    let hits: Vec<(usize, String)> = literals(src)
        .into_iter()
        .filter(|(_, t)| names.contains(t))
        .collect();
    let want: Vec<(usize, String)> = [
        (8, "ANB"),
        (8, "ORB"),
        (8, "LD"),
        (9, "S.IN"),
        (9, "SP.PIDCONT"),
        (9, "MOVP"),
    ]
    .iter()
    .map(|(l, t)| (*l, t.to_string()))
    .collect();
    assert_eq!(hits, want);
}
