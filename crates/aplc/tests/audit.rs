//! The audit of issue #13's "Done when" beyond §8 (worked_examples.rs has
//! those): each execution error code 60-80 of Appendix 6 (L11266-11289, spec
//! aplc.md §7.5) and each load diagnostic the issue lists names the golden
//! test that produces it, and that test's text shows it (the code, or the
//! message). Codes no APLC-TCP program can raise in softplc say why, and the
//! instructions that would raise them must be load errors.

use softplc_lang::isa::Kind;

/// How an error code is covered.
enum Cover {
    /// A run-time error: the test (file in tests/, function) raises it and
    /// asserts the code.
    Run(&'static str, &'static str),
    /// The manual's execution error is a load error in softplc (D14, D18):
    /// the test asserts the diagnostic that replaces it (a fragment of it).
    Load(&'static str, &'static str, &'static str),
    /// No program that loads can raise it: why, and the mnemonics (rejected
    /// at load) whose execution would.
    Never(&'static str, &'static [&'static str]),
}
use Cover::*;

static CODES: &[(u16, Cover)] = &[
    (
        60,
        Load(
            "diagnostics.rs",
            "devices",
            "t.apl:1:4: `X8`: X is numbered in octal",
        ),
    ),
    (61, Run("golden_logic.rs", "watchdog_is_error_61")),
    (
        62,
        Load(
            "diagnostics.rs",
            "instructions",
            "unsupported instruction `TRD`",
        ),
    ),
    (
        63,
        Load(
            "diagnostics.rs",
            "devices",
            "`X0` cannot be written by this instruction",
        ),
    ),
    (64, Run("golden_data.rs", "block_transfer_examples")),
    (65, Run("golden_data.rs", "divide_by_zero_is_error_69")),
    (
        66,
        Load(
            "golden_call.rs",
            "call_diagnostics",
            "more than 6 (APLC programming manual §4.4.2)",
        ),
    ),
    (67, Run("golden_interrupt.rs", "queue_overflow_is_error_67")),
    (
        68,
        Load(
            "golden_call.rs",
            "call_diagnostics",
            "CJ 1: no LBL 1 in this POU",
        ),
    ),
    (69, Run("golden_data.rs", "divide_by_zero_is_error_69")),
    (70, Run("golden_more.rs", "push_fifo_lifo")),
    (71, Never("reserved (L11279)", &[])),
    (
        72,
        Load(
            "golden_call.rs",
            "call_diagnostics",
            "no POU SBR_3 in the program",
        ),
    ),
    (73, Run("golden_data.rs", "from_to_raise_73")),
    (
        74,
        Never(
            "APLC-TCP has no special module: FROM/TO raise 73 before any access (D7)",
            &[],
        ),
    ),
    (
        75,
        Load(
            "golden_more.rs",
            "ref_reff_rsum",
            "REF starts at X or Y, a multiple of 8",
        ),
    ),
    (
        76,
        Never(
            "the clock instructions are not on APLC-TCP (D6)",
            &["TWR", "TADD", "TSUB"],
        ),
    ),
    (77, Never("no high-speed I/O on APLC-TCP (D7)", &["PLSR"])),
    (
        78,
        Never(
            "marked not-TCP in Appendix 6 (L11287); FROM/TO raise 73 (D7)",
            &[],
        ),
    ),
    (
        79,
        Never(
            "no instruction of seed 002 reads ABS data (L11288)",
            &["ABSD", "DABSD"],
        ),
    ),
    (
        80,
        Never(
            "no instruction of seed 002 reads ABS data (L11289)",
            &["ABSD", "DABSD"],
        ),
    ),
];

/// The load diagnostics of issue #13 item 1: (what, test file, function, a
/// fragment of the message the test asserts).
static DIAGNOSTICS: &[(&str, &str, &str, &str)] = &[
    (
        "X8 is not an octal device",
        "diagnostics.rs",
        "devices",
        "`X8`: X is numbered in octal",
    ),
    (
        "a constant that does not fit its operand",
        "diagnostics.rs",
        "constants",
        "does not fit a 16-bit operand",
    ),
    (
        "CALL argument of the wrong type",
        "golden_call.rs",
        "call_diagnostics",
        "REAL constant `1.5` where an integer operand is needed",
    ),
    (
        "CSRET outside a subroutine",
        "golden_call.rs",
        "call_diagnostics",
        "CSRET outside a subroutine",
    ),
    (
        "recursion",
        "golden_call.rs",
        "call_diagnostics",
        "recursive call: SBR_0 → SBR_1 → SBR_0",
    ),
    (
        "more than 6 nesting levels",
        "golden_call.rs",
        "call_diagnostics",
        "calls nested 7 levels deep from MAIN, more than 6",
    ),
    (
        "an instruction APLC-TCP does not have",
        "diagnostics.rs",
        "instructions",
        "not available on APLC-TCP",
    ),
    (
        "GB18030 text accepted",
        "golden_data.rs",
        "variables_and_gb18030",
        "encoding_rs::GB18030.encode",
    ),
    (
        "global and local variables with #NAME",
        "golden_data.rs",
        "variables_and_gb18030",
        "OUT #FLAG",
    ),
];

/// The text of `#[test] fn name` in tests/`file` (doc comment to closing
/// brace), or None.
fn test_text(file: &str, name: &str) -> Option<String> {
    let path = format!("{}/tests/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).ok()?;
    let start = text.find(&format!("#[test]\nfn {name}("))?;
    let end = text[start..]
        .find("\n}\n")
        .map_or(text.len(), |e| start + e);
    Some(text[start..end].to_string())
}

fn rejected(name: &str) -> bool {
    softplc_aplc::isa()
        .all()
        .any(|d| d.name == name && matches!(d.kind, Kind::Rejected(_)))
}

/// The code as a whole number in the text (not part of a longer number).
fn names_code(text: &str, code: u16) -> bool {
    let c = code.to_string();
    text.match_indices(&c).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + c.len()..].chars().next();
        !before.is_some_and(|b| b.is_ascii_digit()) && !after.is_some_and(|a| a.is_ascii_digit())
    })
}

#[test]
fn every_error_code_is_covered() {
    let codes: Vec<u16> = CODES.iter().map(|c| c.0).collect();
    assert_eq!(codes, (60..=80).collect::<Vec<_>>());
    let mut problems = Vec::new();
    for (code, cover) in CODES {
        match cover {
            Run(file, name) => match test_text(file, name) {
                Some(t) if names_code(&t, *code) => {}
                Some(_) => problems.push(format!("{code}: {file}::{name} does not assert {code}")),
                None => problems.push(format!("{code}: no #[test] fn {name} in {file}")),
            },
            Load(file, name, fragment) => match test_text(file, name) {
                Some(t) if t.contains(fragment) => {}
                _ => problems.push(format!(
                    "{code}: {file}::{name} does not assert `{fragment}`"
                )),
            },
            Never(why, names) => {
                for n in *names {
                    if !rejected(n) {
                        problems.push(format!(
                            "{code} ({why}): {n} loads now: name the test raising {code}"
                        ));
                    }
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_listed_diagnostic_is_covered() {
    let mut problems = Vec::new();
    for (what, file, name, fragment) in DIAGNOSTICS {
        match test_text(file, name) {
            Some(t) if t.contains(fragment) => {}
            _ => problems.push(format!(
                "{what}: {file}::{name} does not assert `{fragment}`"
            )),
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn codes_are_matched_as_whole_numbers() {
    assert!(names_code("Some(64))", 64));
    assert!(!names_code("D6400", 64));
    assert!(!names_code("164", 64));
}
