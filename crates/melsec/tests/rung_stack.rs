//! The rung-stack rules (`softplc_lang::rung::Compiler::rung_stack`) as the
//! MELSEC driver reports them (PM §3.5-§3.6); the APLC's are in its
//! `diagnostics.rs`.

use softplc_ir::device::DeviceConfig;
use softplc_lang::compile;
use softplc_lang::il::parse_il;
use softplc_melsec::dialect;

fn errors(src: &str) -> String {
    let src = parse_il("t.il", src).expect("parses");
    match compile(&src, &DeviceConfig::default(), dialect(), None) {
        Ok(_) => String::new(),
        Err(d) => d.to_string(),
    }
}

#[test]
fn mps_nests_sixteen_deep() {
    let ok = format!(
        "LD X0\n{}OUT Y0\n{}END\n",
        "MPS\n".repeat(16),
        "MPP\nOUT Y1\n".repeat(16)
    );
    assert_eq!(errors(&ok), "");
    let deep = format!(
        "LD X0\n{}OUT Y0\n{}END\n",
        "MPS\n".repeat(17),
        "MPP\nOUT Y1\n".repeat(17)
    );
    let e = errors(&deep);
    assert!(e.starts_with("t.il:18:1: more than 16 nested MPS"), "{e}");
}

#[test]
fn read_and_pop_need_a_push_and_combining_needs_a_block() {
    assert_eq!(
        errors("LD X0\nMRD\nOUT Y0\nEND\n"),
        "t.il:2:1: `MRD` without MPS"
    );
    assert_eq!(
        errors("LD X0\nMPP\nOUT Y0\nEND\n"),
        "t.il:2:1: `MPP` without MPS"
    );
    assert_eq!(
        errors("LD X0\nANB\nOUT Y0\nEND\n"),
        "t.il:2:1: `ANB` has no block to combine (no LD opened one)"
    );
    assert_eq!(errors("MPS\nEND\n"), "t.il:1:1: `MPS` needs a preceding LD");
    let e = errors("LD X0\nMPS\nOUT Y0\nLD X1\nOUT Y1\nEND\n");
    assert!(e.contains("MPS without MPP"), "{e}");
}
