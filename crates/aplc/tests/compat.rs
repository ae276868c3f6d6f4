//! COMPATIBILITY.md's APLC-TCP section is generated from the APLC
//! definitions (`softplc_aplc::DEFS`). When it is stale this test rewrites it
//! and fails, so the change shows in the diff (commit the file). Every
//! documented family must be named by a golden test of this crate.

use softplc_lang::isa;

const BEGIN: &str =
    "<!-- generated from the APLC definitions by crates/aplc/tests/compat.rs: begin -->\n";
const END: &str = "<!-- end of the APLC generated part -->\n";

#[test]
fn compatibility_md_is_current() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../COMPATIBILITY.md");
    let text = std::fs::read_to_string(path).expect("COMPATIBILITY.md");
    let table = isa::compat_markdown(softplc_aplc::isa()).replace(
        "\n## Rejected at load\n",
        "\n### APLC-TCP: rejected at load\n",
    );
    let fresh = match (text.find(BEGIN), text.find(END)) {
        (Some(a), Some(b)) => format!("{}{BEGIN}{table}{}", &text[..a], &text[b..]),
        _ => format!(
            "{}\n## APLC-TCP (seed 002)\n\nThe `.apl` dialect (contract §1.1; `softplc run prog.apl`). Its instruction\ntable, generated like the MELSEC one:\n\n{BEGIN}{table}{END}",
            text.trim_end()
        ),
    };
    if fresh != text {
        std::fs::write(path, &fresh).expect("write COMPATIBILITY.md");
        panic!("COMPATIBILITY.md was stale and has been regenerated: review and commit it");
    }
}

#[test]
fn every_documented_family_has_a_golden_test() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests");
    let mut corpus = String::new();
    for e in std::fs::read_dir(dir).expect("tests dir").flatten() {
        let p = e.path();
        if p.extension().is_some_and(|x| x == "rs") && !p.ends_with("compat.rs") {
            corpus += &std::fs::read_to_string(&p).unwrap_or_default();
        }
    }
    let tested = |name: &str| {
        ["\\n", "\"", "\n"].iter().any(|pre| {
            corpus.contains(&format!("{pre}{name} ")) || corpus.contains(&format!("{pre}{name}\\n"))
        })
    };
    let mut rows: Vec<(&str, bool)> = Vec::new();
    for d in softplc_aplc::isa().all() {
        let Some(doc) = d.doc else { continue };
        let t = tested(d.name);
        match rows.iter_mut().find(|(f, _)| *f == doc.family) {
            Some(row) => row.1 |= t,
            None => rows.push((doc.family, t)),
        }
    }
    let untested: Vec<_> = rows.iter().filter(|r| !r.1).collect();
    assert!(
        untested.is_empty(),
        "no golden test names an instruction of {untested:?}"
    );
}
