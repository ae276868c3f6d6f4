//! COMPATIBILITY.md's instruction tables are generated from the instruction
//! definitions (`softplc_melsec::DEFS`). This test regenerates them: when the file is
//! stale it is rewritten and the test fails, so the change shows in the diff
//! (commit the file). Also checks that every implemented instruction is named
//! by at least one golden test.

use softplc_lang::isa;

const BEGIN: &str =
    "<!-- generated from the instruction definitions by crates/melsec/tests/compat.rs: begin -->\n";
const END: &str = "<!-- end of generated part -->\n";

#[test]
fn compatibility_md_is_current() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../COMPATIBILITY.md");
    let text = std::fs::read_to_string(path).expect("COMPATIBILITY.md");
    let (Some(a), Some(b)) = (text.find(BEGIN), text.find(END)) else {
        panic!("COMPATIBILITY.md lacks the generated-part markers");
    };
    let fresh = format!(
        "{}{BEGIN}{}{}",
        &text[..a],
        isa::compat_markdown(softplc_melsec::isa()),
        &text[b..]
    );
    if fresh != text {
        std::fs::write(path, &fresh).expect("write COMPATIBILITY.md");
        panic!("COMPATIBILITY.md was stale and has been regenerated: review and commit it");
    }
}

#[test]
fn every_documented_family_row_has_a_golden_test() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../core/tests");
    let mut corpus = String::new();
    for e in std::fs::read_dir(dir).expect("tests dir").flatten() {
        let p = e.path();
        if p.extension().is_some_and(|x| x == "rs") {
            corpus += &std::fs::read_to_string(&p).unwrap_or_default();
        }
    }
    // A mnemonic counts as tested when a program line of a test starts with it
    // (`\nMOV `, `"MOV `, `LD= ` …), in any of its spellings. Each row of the
    // generated table (instructions sharing a manual section and notes) must
    // have at least one tested mnemonic.
    let tested = |name: &str| {
        let forms = [
            format!("{name} "),
            format!("{name}P "),
            format!("{name}\\n"),
        ];
        ["\\n", "\"", "\n", "{"]
            .iter()
            .any(|pre| forms.iter().any(|f| corpus.contains(&format!("{pre}{f}"))))
    };
    let mut rows: Vec<(&str, &str, bool)> = Vec::new();
    for d in softplc_melsec::isa().all() {
        let Some(doc) = d.doc else { continue };
        let t = tested(d.name);
        match rows
            .iter_mut()
            .find(|(f, c, _)| *f == doc.family && *c == doc.cite)
        {
            Some(row) => row.2 |= t,
            None => rows.push((doc.family, doc.cite, t)),
        }
    }
    let untested: Vec<_> = rows.iter().filter(|r| !r.2).collect();
    assert!(
        untested.is_empty(),
        "no golden test names an instruction of {untested:?}"
    );
}
