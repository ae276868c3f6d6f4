//! Golden tests for sequence instructions, timers, counters, master control and
//! the system relays/registers. Every expected value is worked out by hand from
//! the manual's rules (004 §10.2.10-10.2.11, App. 1/2; notes in qcpu.md §5.2, §6,
//! §8.1) in the comment next to it.
//!
//! Virtual time in the harness: power-on is time 0, the clock is advanced by the
//! scan time before each scan, so scan k (10 ms scans) reads 10·k ms, and the
//! first scan is measured at its END as 10 ms (from power-on).
//!
//! This file: contacts, block and branch instructions, edges, coils and master
//! control.

mod common;
use common::{inputs, outputs, Plc};

// ---------------------------------------------------------------- contacts

#[test]
fn contact_truth_tables() {
    let mut p = Plc::new(
        "\
LD X0
AND X1
OUT Y0
LD X0
ANI X1
OUT Y1
LD X0
OR X1
OUT Y2
LD X0
ORI X1
OUT Y3
LDI X0
AND X1
OUT Y4
LDI X0
ORI X1
OUT Y5
LD X0
AND X1
INV
OUT Y6
END
",
    );
    // Columns: Y0 = X0·X1, Y1 = X0·/X1, Y2 = X0+X1, Y3 = X0+/X1,
    // Y4 = /X0·X1, Y5 = /X0+/X1, Y6 = /(X0·X1).
    for (x, want) in [
        // X0=0 X1=0: 0 0 0 (0+1)=1 (1·0)=0 (1+1)=1 /(0)=1
        ("00", "0001011"),
        // X0=0 X1=1: 0 0 1 (0+0)=0 (1·1)=1 (1+0)=1 1
        ("01", "0010111"),
        // X0=1 X1=0: 0 (1·1)=1 1 1 0 (0+1)=1 1
        ("10", "0111011"),
        // X0=1 X1=1: 1 0 1 1 0 (0+0)=0 /(1)=0
        ("11", "1011000"),
    ] {
        inputs(&mut p, x);
        p.scan();
        assert_eq!(outputs(&p, 7), want, "X0X1 = {x}");
    }
}

#[test]
fn anb_orb_blocks() {
    let mut p = Plc::new(
        "\
LD X0
OR X1
LD X2
OR X3
ANB
OUT Y0
LD X0
AND X1
LD X2
AND X3
ORB
LD X4
LD X5
AND X6
ORB
ANB
OUT Y1
END
",
    );
    // Y0 = (X0+X1)·(X2+X3)
    // Y1 = ((X0·X1)+(X2·X3)) · (X4+(X5·X6))   (two levels of blocks)
    for (x, want) in [
        ("0000000", "00"),
        // left block of Y0 ON, right OFF: an AND gives 0 (an OR would give 1)
        ("1000000", "00"),
        // (0+1)·(0+1) = 1; Y1: (0·1)+(0·1) = 0
        ("0101000", "10"),
        // (1+0)·(1+0) = 1; Y1: (1·0)+(1·0) = 0
        ("1010000", "10"),
        // Y0: (1+1)·(0+0) = 0; Y1: (1·1)·(1+0) = 1
        ("1100100", "01"),
        // Y1: (1·1)·(0+(0·0)) = 0
        ("1100000", "00"),
        // Y0: 0·(1+1) = 0; Y1: (0+(1·1))·(0+(1·1)) = 1
        ("0011011", "01"),
        // Y1: 1·(0+(1·0)) = 0
        ("0011010", "00"),
        // Y0: (1+0)·(0+1) = 1; Y1: ((1·0)+(0·1))·1 = 0
        ("1001100", "10"),
        // Y1: 0·(1+1) = 0
        ("0000111", "00"),
    ] {
        inputs(&mut p, x);
        p.scan();
        assert_eq!(outputs(&p, 2), want, "X0..X6 = {x}");
    }
}

#[test]
fn mps_mrd_mpp_branches() {
    let mut p = Plc::new(
        "\
LD X0
MPS
AND X1
OUT Y0
MRD
AND X2
OUT Y1
MPP
AND X3
OUT Y2
LD X0
MPS
AND X1
MPS
AND X2
OUT Y3
MPP
AND X3
OUT Y4
MPP
AND X4
OUT Y5
END
",
    );
    // Y0 = X0·X1, Y1 = X0·X2 (MRD restores X0, not X0·X1), Y2 = X0·X3;
    // Y3 = X0·X1·X2, Y4 = X0·X1·X3, Y5 = X0·X4 (two MPS levels).
    for (x, want) in [
        // X0 X2 X3: Y1 = 1 only if MRD restored X0; Y2 likewise for MPP.
        ("10110", "011000"),
        // X0 off: nothing.
        ("01111", "000000"),
        ("11000", "100000"),
        // X0 X1 X3 X4: Y0 = 1, Y2 = X0·X3 = 1, Y4 = 1 (inner MPP gives X0·X1),
        // Y5 = 1 (outer MPP gives X0)
        ("11011", "101011"),
        // X0 X2 X4: Y1 = 1, Y3 = 0 (X1 off), Y5 = 1
        ("10101", "010001"),
    ] {
        inputs(&mut p, x);
        p.scan();
        assert_eq!(outputs(&p, 6), want, "X0..X4 = {x}");
    }
}

#[test]
fn rung_continues_after_output() {
    // LD X0 / OUT Y0 / AND X1 / OUT Y1: Y0 = X0, Y1 = X0·X1.
    let mut p = Plc::new(
        "\
LD X0
OUT Y0
AND X1
OUT Y1
END
",
    );
    for (x, want) in [("10", "10"), ("11", "11"), ("01", "00"), ("00", "00")] {
        inputs(&mut p, x);
        p.scan();
        assert_eq!(outputs(&p, 2), want, "X0X1 = {x}");
    }
}

// ---------------------------------------------------------------- edges

#[test]
fn pulse_contacts_on_for_one_scan() {
    let mut p = Plc::new(
        "\
LDP X0
OUT Y0
LDF X0
OUT Y1
LD SM400
ANDP X0
OUT Y2
LD SM400
ANDF X0
OUT Y3
LD SM401
ORP X0
OUT Y4
LD SM401
ORF X0
OUT Y5
END
",
    );
    // Rising-edge contacts (Y0, Y2, Y4) are ON only in the scan where X0 goes
    // OFF→ON; falling-edge ones (Y1, Y3, Y5) only where it goes ON→OFF.
    for (x0, want) in [
        ("0", "000000"),
        ("1", "101010"), // OFF→ON
        ("1", "000000"), // stays ON: no edge
        ("0", "010101"), // ON→OFF
        ("0", "000000"),
        ("1", "101010"), // a second rising edge
    ] {
        inputs(&mut p, x0);
        p.scan();
        assert_eq!(outputs(&p, 6), want);
    }
}

#[test]
fn mep_mef_on_operation_result_edges() {
    let mut p = Plc::new(
        "\
LD X0
AND X1
MEP
OUT Y0
LD X0
AND X1
MEF
OUT Y1
END
",
    );
    // MEP/MEF act on the operation result X0·X1, not on one device.
    for (x, want) in [
        ("10", "00"), // result 0
        ("11", "10"), // result 0→1: MEP
        ("11", "00"), // stays 1
        ("01", "01"), // result 1→0 (X0 went OFF): MEF
        ("01", "00"),
        ("11", "10"), // result 0→1 again (X0 went ON)
    ] {
        inputs(&mut p, x);
        p.scan();
        assert_eq!(outputs(&p, 2), want, "X0X1 = {x}");
    }
}

#[test]
fn egp_egf_edge_relays() {
    let mut p = Plc::new(
        "\
LD X0
EGP V0
OUT Y0
LD X0
EGF V1
OUT Y1
END
",
    );
    // V stores the operation result up to that point (004 L6299-6328), so V0 and
    // V1 follow X0 after each scan; EGP is ON on 0→1, EGF on 1→0.
    for (x0, want) in [
        ("1", "10"),
        ("1", "00"),
        ("0", "01"),
        ("0", "00"),
        ("1", "10"),
    ] {
        inputs(&mut p, x0);
        p.scan();
        assert_eq!(outputs(&p, 2), want);
        assert_eq!(p.bit("V0"), x0 == "1");
        assert_eq!(p.bit("V1"), x0 == "1");
    }
}

// ---------------------------------------------------------------- coils

#[test]
fn out_set_rst() {
    let mut p = Plc::new(
        "\
LD X0
OUT Y0
LD X1
SET M0
LD X2
RST M0
LD M0
OUT Y1
END
",
    );
    // OUT follows its condition; SET/RST hold; the later RST wins in one scan.
    p.set("X0", "1").scan();
    assert!(p.bit("Y0"));
    p.set("X0", "0").scan();
    assert!(!p.bit("Y0"));
    p.set("X1", "1").scan();
    assert!(p.bit("M0") && p.bit("Y1"));
    p.set("X1", "0").scans(3);
    assert!(
        p.bit("M0") && p.bit("Y1"),
        "SET holds after its condition goes OFF"
    );
    p.set("X2", "1").scan();
    assert!(!p.bit("M0") && !p.bit("Y1"));
    p.set("X2", "0").scan();
    assert!(!p.bit("M0"), "RST holds too");
    p.set("X1", "1").set("X2", "1").scan();
    assert!(
        !p.bit("M0"),
        "SET then RST in the same scan: RST (later) wins"
    );
}

#[test]
fn pls_plf_one_scan() {
    let mut p = Plc::new(
        "\
LD X0
PLS M0
LD X0
PLF M1
END
",
    );
    // PLS: ON for the one scan after the condition rises; PLF after it falls.
    for (x0, m0, m1) in [
        ("1", true, false),
        ("1", false, false),
        ("1", false, false),
        ("0", false, true),
        ("0", false, false),
        ("1", true, false),
    ] {
        inputs(&mut p, x0);
        p.scan();
        assert_eq!((p.bit("M0"), p.bit("M1")), (m0, m1));
    }
}

#[test]
fn ff_toggles_per_rising_edge() {
    let mut p = Plc::new(
        "\
LD X0
FF Y0
END
",
    );
    // Y0 inverts on every OFF→ON of X0 and holds otherwise.
    for (x0, y0) in [
        ("1", true),  // rise: OFF→ON
        ("1", true),  // no edge
        ("0", true),  // fall: no change
        ("1", false), // rise: ON→OFF
        ("1", false),
        ("0", false),
        ("1", true), // rise
    ] {
        inputs(&mut p, x0);
        p.scan();
        assert_eq!(p.bit("Y0"), y0);
    }
}

#[test]
fn bit_of_word_coils() {
    let mut p = Plc::new(
        "\
LD X0
OUT D0.3
LD X1
SET D1.F
LD X2
RST D1.F
END
",
    );
    p.set("D0", "1");
    // D0 = 1; OUT D0.3 ON → 1 + 8 = 9; OFF → back to 1 (bit 0 untouched).
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 9);
    p.set("X0", "0").scan();
    assert_eq!(p.int("D0"), 1);
    // SET D1.F on D1 = 0 → 0x8000 = -32768 as a signed word; holds.
    p.set("X1", "1").scan();
    assert_eq!(p.int("D1"), -32768);
    p.set("X1", "0").scan();
    assert_eq!(p.int("D1"), -32768);
    p.set("X2", "1").scan();
    assert_eq!(p.int("D1"), 0);
}

#[test]
fn index_modified_coil() {
    let mut p = Plc::new(
        "\
LD SM400
MOV K5 Z0
LD SM400
MOV K16 Z1
LD X0
OUT Y0Z0
LD X0
OUT Y0Z1
END
",
    );
    // Y0Z0 with Z0 = 5 is Y5; Y0Z1 with Z1 = 16 is Y10 (Y is numbered in hex).
    p.set("X0", "1").scan();
    assert!(p.bit("Y5"));
    assert!(p.bit("Y10"));
    assert!(!p.bit("Y0"));
    assert!(!p.bit("Y16"));
    p.set("X0", "0").scan();
    assert!(!p.bit("Y5") && !p.bit("Y10"));
}

// ---------------------------------------------------------------- MC/MCR

#[test]
fn master_control_off() {
    let mut p = Plc::new(
        "\
LD X0
MC N0 M10
LD X1
OUT Y0
LD X1
OUTH T0 K100
LD X1
SET M0
LD X1
OUT C0 K5
MCR N0
LD X1
OUT Y1
END
",
    );
    // MC ON, X1 ON for 5 scans: Y0 ON; T0 (10 ms base) 0 at the coil-ON scan then
    // +1 per scan → 4; M0 SET; C0 counted the one rising edge → 1.
    p.set("X0", "1").set("X1", "1").scans(5);
    assert!(p.bit("M10") && p.bit("Y0") && p.bit("M0"));
    assert_eq!(p.int("TN0"), 4);
    assert_eq!(p.int("CN0"), 1);
    // MC OFF (X1 still ON): OUT coils OFF, timer reset to 0, SET device and
    // counter value held; the rung after MCR runs normally.
    p.set("X0", "0").scan();
    assert!(!p.bit("M10"));
    assert!(!p.bit("Y0"));
    assert_eq!(p.int("TN0"), 0);
    assert!(!p.bit("T0"));
    assert!(p.bit("M0"));
    assert_eq!(p.int("CN0"), 1);
    assert!(p.bit("Y1"));
    p.scans(3);
    assert_eq!(p.int("TN0"), 0);
    assert_eq!(p.int("CN0"), 1);
    // MC ON again: the counter coil was turned OFF under MC, so X1 (still ON)
    // is a new rising edge → 2; the timer restarts from 0.
    p.set("X0", "1").scan();
    assert!(p.bit("Y0"));
    assert_eq!(p.int("CN0"), 2);
    assert_eq!(p.int("TN0"), 0);
}

#[test]
fn master_control_nested() {
    let mut p = Plc::new(
        "\
LD X0
MC N0 M10
LD X1
OUT Y0
LD X2
MC N1 M11
LD X1
OUT Y1
MCR N1
LD X1
OUT Y2
MCR N0
LD X1
OUT Y3
END
",
    );
    // Outer ON, inner OFF: only the coil between MC N1 and MCR N1 is forced OFF.
    inputs(&mut p, "110");
    p.scan();
    assert_eq!(outputs(&p, 4), "1011");
    assert!(p.bit("M10") && !p.bit("M11"));
    // Both ON: everything follows X1.
    inputs(&mut p, "111");
    p.scan();
    assert_eq!(outputs(&p, 4), "1111");
    // Outer OFF (inner condition ON): the inner MC is OFF as well, so Y0-Y2 OFF;
    // Y3 after MCR N0 still follows X1.
    inputs(&mut p, "011");
    p.scan();
    assert_eq!(outputs(&p, 4), "0001");
    assert!(!p.bit("M10") && !p.bit("M11"));
}
