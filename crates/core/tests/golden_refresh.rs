//! COM (004 §4.2, L1504-1575): the END's refresh in mid-scan, in softplc the
//! input refresh (the input image into X, forced inputs kept forced).

mod common;

use common::Plc;
use softplc_core::device::DeviceKind;

/// The program clears X0-X15 (K4X0), reads X0 into Y0, runs COM, reads X0
/// into Y1: only after COM does X0 show the input module's ON again.
const PROGRAM: &str = "LD SM400\nMOV K0 K4X0\nLD X0\nOUT Y0\nLD M0\nCOM\nLD X0\nOUT Y1\nEND\n";

#[test]
fn com_refreshes_the_inputs_in_mid_scan() {
    let mut p = Plc::new(PROGRAM);
    p.set("X0", "1").set("M0", "1").scan();
    assert!(!p.bit("Y0"), "X0 as the program left it before COM");
    assert!(p.bit("Y1"), "X0 from the input image after COM");
}

#[test]
fn com_runs_only_while_its_condition_is_on() {
    let mut p = Plc::new(PROGRAM);
    p.set("X0", "1").set("M0", "0").scan();
    assert!(!p.bit("Y1"));
}

#[test]
fn com_keeps_forced_inputs_forced() {
    let mut p = Plc::new(PROGRAM);
    p.set("M0", "1");
    p.cpu.force(DeviceKind::X, 0, true).unwrap();
    p.scan();
    assert!(!p.bit("Y0"));
    assert!(p.bit("Y1"), "forced X0 is ON again after COM");
}

#[test]
fn com_takes_no_operand() {
    let d = common::diagnostics("LD SM400\nCOM K1\nEND\n");
    assert!(d.iter().any(|m| m.contains("COM")), "{d:?}");
}
