//! Golden tests of the basic instructions, timers, counters and flow, values
//! from the manual's examples (spec aplc.md §3.2, §8.1) or worked by hand.

mod common;
use common::plc;

/// §8.1 #5, Example 1, the LAD→IL listing (L2185-2208): Y0 = (X0∨X1)∧X14, Y1 = Y0∧X1,
/// Y2 = …∧X2, Y3 = …∧X2∧X3∧X4, Y4 = …∧X2∧(X5∧X6 ∨ X7∧X10), Y5 = …∧X2.
#[test]
fn mps_mrd_mpp_listing() {
    let src = "LD X0\nOR X1\nAND X14\nMPS\nOUT Y0\nAND X1\nOUT Y1\nMPP\nAND X2\nMPS\nOUT Y2\nAND X3\nAND X4\nOUT Y3\nMRD\nLD X5\nAND X6\nLD X7\nAND X10\nORB\nANB\nOUT Y4\nMPP\nOUT Y5\n";
    let mut p = plc(src);
    p.set("X0", "1").set("X14", "1").set("X1", "1").scan();
    assert!(p.bit("Y0") && p.bit("Y1"));
    assert!(!p.bit("Y2") && !p.bit("Y5"));
    p.set("X1", "0")
        .set("X2", "1")
        .set("X7", "1")
        .set("X10", "1")
        .scan();
    assert!(p.bit("Y0") && !p.bit("Y1") && p.bit("Y2") && !p.bit("Y3"));
    assert!(p.bit("Y4") && p.bit("Y5"));
    p.set("X10", "0").scan();
    assert!(!p.bit("Y4"));
    p.set("X3", "1").set("X4", "1").scan();
    assert!(p.bit("Y3"));
}

/// §8.1 #3, Example 2 (L2798-2803): Y0 = (M1∧M2) ∨ (M3∧M4).
#[test]
fn orb() {
    let mut p = plc("LD  M1\nAND M2\nLD  M3\nAND M4\nORB\nOUT Y0\n");
    p.scan();
    assert!(!p.bit("Y0"));
    p.set("M3", "1").set("M4", "1").scan();
    assert!(p.bit("Y0"));
    p.set("M4", "0").set("M1", "1").scan();
    assert!(!p.bit("Y0"));
    p.set("M2", "1").scan();
    assert!(p.bit("Y0"));
}

/// §8.1 #4, ANB (L2774): Y0 = (M0∨M1)∧(M2∨M3); ANI/ORI/LDI.
#[test]
fn anb_and_negations() {
    let mut p = plc(
        "LD M0\nOR M1\nLD M2\nOR M3\nANB\nOUT Y0\nLDI M0\nANI M1\nOUT Y1\nLD M5\nORI M6\nOUT Y2\n",
    );
    p.scan();
    assert!(!p.bit("Y0") && p.bit("Y1") && p.bit("Y2"));
    p.set("M1", "1").set("M3", "1").set("M6", "1").scan();
    assert!(p.bit("Y0") && !p.bit("Y1") && !p.bit("Y2"));
}

/// §8.1 #6: EU/ED on M2 (L2872-2876): Y2 ON one scan at OFF→ON, Y3 one scan at ON→OFF.
#[test]
fn eu_ed() {
    let mut p = plc("LD M2\nEU\nOUT Y2\nLD M2\nED\nOUT Y3\nLD M2\nINV\nOUT Y4\n");
    p.scan();
    assert!(!p.bit("Y2") && !p.bit("Y3") && p.bit("Y4"));
    p.set("M2", "1").scan();
    assert!(p.bit("Y2") && !p.bit("Y4"));
    p.scan();
    assert!(!p.bit("Y2"));
    p.set("M2", "0").scan();
    assert!(p.bit("Y3"));
    p.scan();
    assert!(!p.bit("Y3"));
}

/// SET/RST, and RST of a timer and a 32-bit counter clears the value.
#[test]
fn set_rst() {
    let mut p = plc("LD M0\nSET Y0\nLD M1\nRST Y0\nLD M2\nRST C200\nRST T3\n");
    p.set("M0", "1").scan();
    p.set("M0", "0").scan();
    assert!(p.bit("Y0"));
    p.set("M1", "1").scan();
    assert!(!p.bit("Y0"));
    p.set("CN200", "100000")
        .set("TN3", "7")
        .set("M2", "1")
        .scan();
    assert_eq!((p.int("CN200"), p.int("TN3")), (0, 0));
}

/// §8.1 #7: MC 0 with M0 OFF (L3006): Y0 forced OFF; SET holds.
#[test]
fn master_control() {
    let mut p = plc("LD M0\nMC 0\nLD SM0\nOUT Y0\nLD M1\nSET Y1\nMCR 0\nLD SM0\nOUT Y2\n");
    p.set("M0", "1").scan();
    assert!(p.bit("Y0") && p.bit("Y2"));
    p.set("M1", "1").scan();
    p.set("M0", "0").scan();
    assert!(!p.bit("Y0") && p.bit("Y1") && p.bit("Y2"));
}

/// TON T0 5 (100 ms base): ON after 0.5 s; value saturates at 32767 only;
/// OFF resets.
#[test]
fn ton_100ms() {
    let mut p = plc("LD X0\nTON T0 5\nLD T0\nOUT Y0\n");
    p.scan_us = 100_000;
    p.set("X0", "1").scans(5);
    // D21: housekeeping added 5 × 100 ms; the coil is compared when TON runs.
    assert_eq!(p.int("TN0"), 5);
    assert!(!p.bit("Y0"));
    p.scan();
    assert!(p.bit("Y0"));
    assert_eq!(p.int("TN0"), 6);
    p.scans(3);
    assert_eq!(p.int("TN0"), 9, "TON keeps counting past the preset");
    p.set("X0", "0").scan();
    assert!(!p.bit("T0"));
    assert_eq!(p.int("TN0"), 0);
}

/// T210-T251 count 10 ms, T252-T255 1 ms (L1667-1677).
#[test]
fn time_bases_by_number() {
    let mut p = plc("LD SM0\nTON T210 1000\nTON T252 1000\nTON T1 1000\n");
    p.scan_us = 10_000;
    p.scans(11);
    assert_eq!(p.int("TN210"), 11);
    assert_eq!(p.int("TN252"), 110);
    assert_eq!(p.int("TN1"), 1);
}

/// §8.1 #8, Example 3, TONR (L3161-3169): M0 ON 0.5 s in total, in two pieces.
#[test]
fn tonr_accumulates() {
    let mut p = plc("LD M0\nTONR T1 5\nLD T1\nOUT Y0\n");
    p.scan_us = 100_000;
    p.set("M0", "1").scans(4);
    assert_eq!(p.int("TN1"), 4);
    p.set("M0", "0").scans(3);
    assert_eq!(p.int("TN1"), 4);
    p.set("M0", "1").scans(3);
    assert!(p.bit("Y0"));
    p.set("M0", "0").scan();
    assert!(p.bit("Y0"), "TONR holds its coil with PF OFF");
}

/// TOF: PF ON → coil ON, value 0; the falling edge starts timing; at the
/// preset coil OFF, value held.
#[test]
fn tof_off_delay() {
    let mut p = plc("LD M0\nTOF T2 3\n");
    p.scan_us = 100_000;
    p.scan();
    assert!(!p.bit("T2"), "never started: nothing");
    p.set("M0", "1").scan();
    assert!(p.bit("T2"));
    p.set("M0", "0").scans(3);
    assert!(p.bit("T2"));
    p.scan();
    assert!(!p.bit("T2"));
    assert_eq!(p.int("TN2"), 3);
}

/// §8.1 #9: TMON, a 0.5 s pulse, not retriggerable (L3227-3235).
#[test]
fn tmon_one_shot() {
    let mut p = plc("LD M0\nTMON T3 5\n");
    p.scan_us = 100_000;
    p.set("M0", "1").scan();
    assert!(p.bit("T3"));
    p.set("M0", "0").scans(2);
    p.set("M0", "1").scans(2);
    assert!(p.bit("T3"));
    p.scan();
    assert!(!p.bit("T3"));
    assert_eq!(p.int("TN3"), 0);
}

/// CTU counts rising edges, coil at ≥ preset, saturates; CTR rings.
#[test]
fn ctu_ctr() {
    let mut p = plc("LD M0\nCTU C0 3\nLD M0\nCTR C1 2\n");
    for k in 1..=4 {
        p.set("M0", "1").scan();
        p.set("M0", "0").scan();
        assert_eq!(p.int("CN0"), k);
        assert_eq!(p.bit("C0"), k >= 3);
    }
    // CTR: 1, 2 (ON), 1, 2 (ON).
    assert_eq!(p.int("CN1"), 2);
    assert!(p.bit("C1"));
    p.set("CN0", "32767").set("M0", "1").scan();
    assert_eq!(p.int("CN0"), 32767);
    assert_eq!(p.int("CN1"), 1);
    assert!(!p.bit("C1"));
}

/// DCNT C200: up, then down with SM200 ON; wraps at the 32-bit limits.
#[test]
fn dcnt_32_bit() {
    let mut p = plc("LD M0\nDCNT C200 100000\nLD M0\nDCNT C201 0\n");
    p.set("CN200", "99999");
    p.set("M0", "1").scan();
    assert_eq!(p.int("CN200"), 100000);
    assert!(p.bit("C200"));
    p.set("SM200", "1")
        .set("M0", "0")
        .scan()
        .set("M0", "1")
        .scan();
    assert_eq!(p.int("CN200"), 99999);
    assert!(!p.bit("C200"));
    p.set("CN201", "2147483647")
        .set("M0", "0")
        .scan()
        .set("M0", "1")
        .scan();
    assert_eq!(p.int("CN201"), -2147483648);
    // C200's pair: high word first in CN storage, shown as one value.
    assert_eq!(p.int("CN200:u32"), 99998);
}

/// §8.1 #10, Example 4, the CJ listing with `LD SM0` (L3655-3666).
#[test]
fn cj_and_cfend() {
    let src = "LD M0\nCJ 0\nLD SM0\nMOV 100 D0\nCFEND\nLBL 0\nLD M1\nMOV 200 D0\n";
    let mut p = plc(src);
    p.set("M1", "1").scan();
    assert_eq!(p.int("D0"), 100);
    p.set("M0", "1").scan();
    assert_eq!(p.int("D0"), 200);
}

/// §8.1 #11: CFEND with M0 (L3682-3687): OFF: Y0 follows SM12 (1 s clock); ON: the
/// rest of MAIN is skipped.
#[test]
fn cfend_stops_the_blink() {
    let mut p = plc("LD M0\nCFEND\nLD SM12\nOUT Y0\n");
    p.scan_us = 100_000;
    // Scan n runs at n × 100 ms of virtual time: SM12 is ON from 500 ms.
    p.scans(4);
    assert!(!p.bit("Y0"));
    p.scan();
    assert!(p.bit("Y0"));
    p.set("M0", "1").scans(5);
    assert!(p.bit("Y0"), "frozen");
}

/// SM0 always ON, SM1 the first scan only, SM15 toggles from 0.
#[test]
fn system_relays() {
    let mut p = plc("LD SM1\nOUT M1\nLD SM0\nOUT M0\nLD SM15\nOUT M15\n");
    p.scan();
    assert!(p.bit("M0") && p.bit("M1") && !p.bit("M15"));
    p.scan();
    assert!(p.bit("M0") && !p.bit("M1") && p.bit("M15"));
}

/// An endless CJ loop is error 61 (watchdog, 200 ms): SD20 = 61, STOP (D14).
#[test]
fn watchdog_is_error_61() {
    let mut p = plc("LBL 0\nLD SM0\nCJ 0\n");
    p.scan();
    assert!(!p.running());
    assert_eq!(p.error_code(), Some(61));
    assert_eq!(p.int("SD20"), 61);
    assert!(p.bit("SM20"));
}

/// STOP with power flow stops the user program (L3735-3743); NOP does nothing.
#[test]
fn stop_instruction() {
    let mut p = plc("NOP\nLD SM0\nOUT Y0\nLD M0\nSTOP\nWDT\n");
    p.scan();
    assert!(p.running() && p.bit("Y0"));
    p.set("M0", "1").scan();
    assert!(!p.running());
    assert_eq!(p.error_code(), None);
}

/// §8.1 #12: on M2's rising edge `FOR 100` with `INC D0` → D0 = 100
/// (L3568-3570); PF OFF or S ≤ 0 skips the body; nesting multiplies.
#[test]
fn for_next() {
    let src = "LD M2\nEU\nFOR 100\nLD SM0\nINC D0\nNEXT\nLD M3\nFOR D10\nLD SM0\nFOR 3\nLD SM0\nINC D1\nNEXT\nNEXT\nLD SM0\nINC D2\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!((p.int("D0"), p.int("D1"), p.int("D2")), (0, 0, 1));
    p.set("M2", "1").scan();
    assert_eq!(p.int("D0"), 100);
    p.scan();
    assert_eq!(p.int("D0"), 100, "EU: once");
    p.set("M3", "1").set("D10", "-2").scan();
    assert_eq!(p.int("D1"), 0, "S ≤ 0 skips");
    p.set("D10", "4").scan();
    assert_eq!(p.int("D1"), 12);
    assert_eq!(p.int("D2"), 5);
}
