//! SFC in IL: steps, transitions, the clearing pass of a deactivated step,
//! jumps, parallel merges, RET (spec aplc.md §3.4, decision D16).

mod common;
use common::{errors, plc};

const SEQ: &str =
    "LD SM1\nSET S0\nSTL S0\nOUT Y0\nLD X0\nSET S20\nSTL S20\nOUT Y1\nTON T0 3\nLD T0\nSET S21\n\
STL S21\nOUT Y2\nLD X1\nOUT S0\nRET\nLD SM0\nOUT Y7\n";

#[test]
fn simple_sequence() {
    let mut p = plc(SEQ);
    p.scan_us = 100_000;
    p.scan();
    assert!(p.bit("S0") && p.bit("Y0") && !p.bit("Y1") && p.bit("Y7"));
    p.set("X0", "1").scan();
    assert!(!p.bit("S0") && p.bit("S20") && p.bit("Y1"));
    assert!(
        p.bit("Y0"),
        "the old step's output goes OFF one scan late (L9906-9925)"
    );
    p.set("X0", "0").scan();
    assert!(!p.bit("Y0") && p.bit("Y1"));
    p.scans(3);
    assert!(p.bit("S21") && p.bit("Y2"));
    p.scan();
    assert!(
        !p.bit("Y1") && p.int("TN0") == 0,
        "TON in the left step is reset"
    );
    p.set("X1", "1").scan();
    assert!(p.bit("S0") && !p.bit("S21"));
    p.set("X1", "0").scan();
    assert!(p.bit("Y0") && !p.bit("Y2"));
}

/// The manual's parallel example (S30 and S31 merge into S32 on M31,
/// L9731-9735) in D16's form.
#[test]
fn parallel_merge() {
    let src =
        "LD SM1\nSET S20\nSTL S20\nLD M20\nSET S30\nSET S31\nSTL S30\nOUT Y0\nSTL S31\nOUT Y1\n\
STL S30\nSTL S31\nLD M31\nSET S32\nSTL S32\nOUT Y2\nRET\n";
    let mut p = plc(src);
    p.scan();
    p.set("M20", "1").scan();
    assert!(p.bit("S30") && p.bit("S31") && !p.bit("S20"));
    p.scan();
    assert!(p.bit("Y0") && p.bit("Y1"));
    p.set("M31", "1").scan();
    assert!(!p.bit("S30") && !p.bit("S31") && p.bit("S32") && p.bit("Y2"));
    p.set("M31", "0").scan().scan();
    assert!(!p.bit("Y0") && !p.bit("Y1"));
}

#[test]
fn sfc_diagnostics() {
    let e = errors("STL S20\nOUT Y0\nSTL S21\nOUT Y1\nSTL S20\nOUT Y2\n");
    assert!(
        e.contains("t.apl:5:5: S20 opens a second step body (first at line 1)"),
        "{e}"
    );
    let e = errors("STL M0\nOUT Y0\n");
    assert!(e.contains("`M0`: STL takes a step S0-S1023"), "{e}");
    let e = errors("STL S20\nLD M0\nMC 0\nOUT Y0\n");
    assert!(e.contains("t.apl:3:1: `MC` in an SFC step"), "{e}");
    let e = errors("POU MAIN\nLD M0\nOUT Y0\nPOU SBR_1\nSTL S20\nOUT Y1\nRET\n");
    assert!(e.contains("t.apl:7:1: RET outside MAIN"), "{e}");
    // Outside steps SET/OUT/RST S are ordinary coils.
    let mut p = plc("LD M0\nOUT S5\nLD M1\nSET S6\nLD M2\nRST S6\n");
    p.set("M0", "1").set("M1", "1").scan();
    assert!(p.bit("S5") && p.bit("S6"));
}
