//! The input refresh of an APLC-TCP program: skipped when no program may
//! write X (`Program::may_write_x`), and a skip never hides an input.

mod common;
use common::plc;

fn may_write_x(src: &str) -> bool {
    softplc_aplc::load_bytes("t.apl", src.as_bytes())
        .unwrap_or_else(|d| panic!("load failed:\n{d}"))
        .may_write_x
}

#[test]
fn contacts_read_x_and_a_box_naming_x_counts_as_a_writer() {
    assert!(!may_write_x("LD X0\nAND X1\nOUT Y0\n"));
    // The APLC refuses X as a destination; a source outside a contact is
    // still counted (the rule is the operand's place, not its direction).
    assert!(may_write_x("LD M0\nMOV K1X0 D0\n"));
}

#[test]
fn a_reader_follows_the_inputs() {
    let mut p = plc("LD X0\nOUT Y0\nLD X17\nOUT Y1\n");
    p.scans(2);
    assert!(!p.bit("Y0"));
    p.set("X0", "1").scan();
    assert!(p.bit("Y0"));
    p.set("X17", "1").set("X0", "0").scan();
    assert!(!p.bit("Y0") && p.bit("Y1"));
}
