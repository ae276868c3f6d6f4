//! No door owns a dialect: the door crates (the CLI, simulator, tuner,
//! protocols, servers, web monitor, OPC UA, the APLC ports) ask the CPU's
//! profile — its naming, doors and program format — or call a
//! `softplc-core` function that does the dialect's part. None declares an
//! enum with a variant per dialect or family, and none compares a model or
//! family name written in its source.

use std::path::{Path, PathBuf};

/// The door crates, under `crates/`.
const DOORS: [&str; 9] = [
    "cli", "sim", "tune", "mc", "modbus", "serve", "ports", "opcua", "http",
];

/// Variant names that stand for a dialect or a family, besides every model
/// and family name of the profiles (compared without case and punctuation).
const DIALECT_WORDS: [&str; 5] = ["melsec", "q", "qnph", "qnu", "aplc"];

/// softplc-core functions that branch on the dialect by name.
const DIALECT_CALLS: [&str; 2] = ["is_aplc(", "is_apl("];

fn normal(name: &str) -> String {
    name.chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

/// What the check looks for: the words of [`DIALECT_WORDS`] and every
/// profile's model and family.
struct Rules {
    /// Normalised names a variant may not have.
    variants: Vec<String>,
    /// String literals (quoted, as spelled by the profiles) code may not hold.
    literals: Vec<String>,
}

impl Rules {
    fn new() -> Rules {
        let mut names: Vec<&str> = Vec::new();
        for p in softplc_core::profile::all() {
            names.push(p.model);
            names.push(p.family);
        }
        names.sort_unstable();
        names.dedup();
        let mut variants: Vec<String> = DIALECT_WORDS.iter().map(|w| normal(w)).collect();
        variants.extend(names.iter().map(|n| normal(n)));
        Rules {
            variants,
            literals: names.iter().map(|n| format!("\"{n}\"")).collect(),
        }
    }

    /// The offences of one source file, as `line: what`.
    fn check(&self, text: &str) -> Vec<String> {
        let code = without_comment_lines(text);
        let mut out = Vec::new();
        for (i, line) in code.lines().enumerate() {
            for lit in &self.literals {
                if line.contains(lit.as_str()) {
                    out.push(format!("{}: the name {lit} written in code", i + 1));
                }
            }
            for call in DIALECT_CALLS {
                if line.contains(call) {
                    out.push(format!("{}: a call of {call}..) by dialect", i + 1));
                }
            }
        }
        for (name, variants) in enums(&code) {
            for v in variants {
                if self.variants.contains(&normal(&v)) {
                    out.push(format!("enum {name} has a dialect variant {v}"));
                }
            }
        }
        out
    }
}

/// The text with every line that is only a comment blanked (line numbers
/// kept).
fn without_comment_lines(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l.trim_start().starts_with("//") {
                ""
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every `enum` of the code: its name and variant names.
fn enums(code: &str) -> Vec<(String, Vec<String>)> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("enum ") {
        let before = rest[..at].chars().next_back();
        rest = &rest[at + 5..];
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        let name: String = rest
            .trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        let Some(open) = rest.find('{') else { break };
        // Variants: the items at depth 1 of the body, attributes skipped.
        let mut variants = Vec::new();
        let (mut depth, mut item, mut end) = (0usize, String::new(), rest.len());
        for (k, c) in rest[open..].char_indices() {
            match c {
                '{' | '(' | '[' => depth += 1,
                '}' | ')' | ']' => depth = depth.saturating_sub(1),
                _ => {}
            }
            if depth == 0 {
                end = open + k;
                break;
            }
            if depth == 1 && c == ',' {
                variants.extend(variant(&item));
                item.clear();
            } else if depth == 1 && !"{}()[]".contains(c) {
                item.push(c);
            }
        }
        variants.extend(variant(&item));
        out.push((name, variants));
        rest = &rest[end..];
    }
    out
}

/// The variant an item of an enum body names (an attribute leaves its `#`).
fn variant(item: &str) -> Option<String> {
    let item = item.trim().trim_start_matches('#').trim();
    let name: String = item
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect();
    (!name.is_empty()).then_some(name)
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_door_owns_a_dialect() {
    let rules = Rules::new();
    let crates = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut offences = Vec::new();
    let mut files = 0;
    for door in DOORS {
        let mut paths = Vec::new();
        sources(&crates.join(door).join("src"), &mut paths);
        for p in paths {
            files += 1;
            let text = std::fs::read_to_string(&p).unwrap();
            for o in rules.check(&text) {
                offences.push(format!("{}:{o}", p.display()));
            }
        }
    }
    assert!(files > 50, "{files} door sources found");
    assert!(
        offences.is_empty(),
        "doors ask the CPU's profile instead (its naming, doors, program format, \
         or a softplc-core function):\n{}",
        offences.join("\n")
    );
}

/// The check finds what it is for.
#[test]
fn the_check_finds_dialect_enums_and_names() {
    let rules = Rules::new();
    let src = r#"
/// A dialect: "APLC-TCP" in a comment is fine.
#[derive(Clone, Copy)]
pub enum Dialect {
    /// MELSEC-Q.
    #[default]
    MelsecQ,
    Aplc { locals: bool },
}
enum Table { Coils, Registers(u8) }
fn f(p: &Profile) -> bool {
    p.model == "APLC-TCP" || softplc_core::profile::is_aplc(p)
}
"#;
    let found = rules.check(src);
    assert_eq!(
        found,
        [
            "12: the name \"APLC-TCP\" written in code",
            "12: a call of is_aplc(..) by dialect",
            "enum Dialect has a dialect variant MelsecQ",
            "enum Dialect has a dialect variant Aplc",
        ],
        "{found:#?}"
    );
    assert_eq!(
        enums("enum Table { Coils, Registers(u8) }"),
        [(
            "Table".to_string(),
            vec!["Coils".to_string(), "Registers".to_string()]
        )]
    );
}
