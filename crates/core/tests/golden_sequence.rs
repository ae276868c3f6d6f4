//! Golden tests for sequence instructions, timers, counters, master control and
//! the system relays/registers. Every expected value is worked out by hand from
//! the manual's rules (004 §10.2.10-10.2.11, App. 1/2; notes in qcpu.md §5.2, §6,
//! §8.1) in the comment next to it.
//!
//! Virtual time in the harness: power-on is time 0, the clock is advanced by the
//! scan time before each scan, so scan k (10 ms scans) reads 10·k ms, and the
//! first scan is measured at its END as 10 ms (from power-on).

mod common;
use common::{diagnostics, Plc};
use softplc_core::device::DeviceKind;
use softplc_core::engine::CpuConfig;

/// Sets X0, X1, … from a string of '0'/'1', X0 first.
fn inputs(p: &mut Plc, bits: &str) {
    for (i, c) in bits.chars().enumerate() {
        p.set(&format!("X{i}"), if c == '1' { "1" } else { "0" });
    }
}

/// Reads Y0, Y1, … Y(n-1) as a '0'/'1' string, Y0 first.
fn outputs(p: &Plc, n: usize) -> String {
    (0..n)
        .map(|i| if p.bit(&format!("Y{i}")) { '1' } else { '0' })
        .collect()
}

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

// ---------------------------------------------------------------- timers

#[test]
fn low_speed_timer_10ms_scans() {
    let mut p = Plc::new(
        "\
LD X0
OUT T0 K10
LD T0
OUT Y0
END
",
    );
    // Base 100 ms, 10 ms scans. The coil turns ON in scan 1 (adds nothing); each
    // later scan adds 10 ms, so TN0 = n at scan 10n+1 and reaches K10 at scan 101.
    p.set("X0", "1").scan();
    assert_eq!(p.int("TN0"), 0);
    p.scans(9); // scan 10: 90 ms accumulated
    assert_eq!(p.int("TN0"), 0);
    p.scan(); // scan 11: 100 ms
    assert_eq!(p.int("TN0"), 1);
    p.scans(89); // scan 100
    assert_eq!(p.int("TN0"), 9);
    assert!(!p.bit("T0") && !p.bit("Y0"));
    p.scan(); // scan 101
    assert_eq!(p.int("TN0"), 10);
    assert!(p.bit("T0") && p.bit("Y0"));
    // Timed out: stays at the set value.
    p.scans(20);
    assert_eq!(p.int("TN0"), 10);
    assert!(p.bit("T0"));
    // Coil OFF → current value 0 and contact OFF at once.
    p.set("X0", "0").scan();
    assert_eq!(p.int("TN0"), 0);
    assert!(!p.bit("T0") && !p.bit("Y0"));
    // Coil ON again: counts from 0 again, time-up 100 scans after the ON scan.
    p.set("X0", "1").scans(100);
    assert_eq!(p.int("TN0"), 9);
    assert!(!p.bit("T0"));
    p.scan();
    assert!(p.bit("T0"));
}

#[test]
fn high_speed_timer_10ms_scans() {
    let mut p = Plc::new(
        "\
LD X0
OUTH T1 K10
END
",
    );
    // Base 10 ms, 10 ms scans: scan 1 (coil ON) 0, scan k → k-1, K10 at scan 11.
    p.set("X0", "1").scan();
    assert_eq!(p.int("TN1"), 0);
    p.scans(9); // scan 10
    assert_eq!(p.int("TN1"), 9);
    assert!(!p.bit("T1"));
    p.scan(); // scan 11
    assert_eq!(p.int("TN1"), 10);
    assert!(p.bit("T1"));
}

#[test]
fn low_speed_timer_7ms_scans_carries_remainder() {
    let mut p = Plc::new(
        "\
LD X0
OUT T2 K5
END
",
    );
    p.scan_time_us(7_000);
    p.scans(3); // coil OFF
    assert_eq!(p.int("TN2"), 0);
    // Coil ON in scan 1 (of this count); scan k adds 7 ms from k = 2, so after
    // scan k the timer holds 7·(k-1) ms and TN2 = floor(7·(k-1) / 100):
    //   k=15:  98 → 0    k=16: 105 → 1
    //   k=29: 196 → 1    k=30: 203 → 2
    //   k=43: 294 → 2    k=44: 301 → 3
    //   k=58: 399 → 3    k=59: 406 → 4
    //   k=72: 497 → 4    k=73: 504 → 5 = K5: time-up
    let expect = [
        (15, 0),
        (16, 1),
        (29, 1),
        (30, 2),
        (43, 2),
        (44, 3),
        (58, 3),
        (59, 4),
        (72, 4),
        (73, 5),
    ];
    p.set("X0", "1");
    let mut k = 0;
    for (at, tn) in expect {
        while k < at {
            p.scan();
            k += 1;
        }
        assert_eq!(p.int("TN2"), tn, "scan {k}");
        assert_eq!(p.bit("T2"), tn == 5, "scan {k}");
    }
    // Coil OFF resets the timer, the 4 ms left over from 504 ms included: timing
    // restarts from the next coil-ON exactly as above (0 at scan 15, 1 at 16; a
    // kept 4 ms would give 4 + 7·14 = 102 ms → 1 already at scan 15).
    p.set("X0", "0").scan();
    assert_eq!(p.int("TN2"), 0);
    p.set("X0", "1").scans(15);
    assert_eq!(p.int("TN2"), 0);
    p.scan();
    assert_eq!(p.int("TN2"), 1);
}

#[test]
fn timer_set_value_zero_and_from_d() {
    let mut p = Plc::new(
        "\
LD X0
OUT T3 K0
LD X1
OUTH T4 D0
END
",
    );
    p.set("D0", "3");
    // Set value 0: contact ON at the first execution with the coil ON (L6507).
    p.set("X0", "1").scan();
    assert!(p.bit("T3"));
    assert_eq!(p.int("TN3"), 0);
    // OUTH T4 D0, D0 = 3: 0, 1, 2, then 3 at the 4th scan.
    p.set("X1", "1").scans(3);
    assert_eq!(p.int("TN4"), 2);
    assert!(!p.bit("T4"));
    p.scan();
    assert_eq!(p.int("TN4"), 3);
    assert!(p.bit("T4"));
}

#[test]
fn raising_set_value_after_time_up_keeps_contact() {
    let mut p = Plc::new(
        "\
LD X0
OUTH T5 D1
END
",
    );
    p.set("D1", "2");
    // 0, 1, 2: timed out at scan 3.
    p.set("X0", "1").scans(3);
    assert!(p.bit("T5"));
    assert_eq!(p.int("TN5"), 2);
    // Set value raised above the current value: stays timed out, no further
    // timing (L6509-6510).
    p.set("D1", "5").scans(5);
    assert!(p.bit("T5"));
    assert_eq!(p.int("TN5"), 2);
}

#[test]
fn timer_and_counter_update_at_out_not_at_end() {
    let mut p = Plc::new(
        "\
LD T6
OUT Y0
LD C2
OUT Y2
LD X0
OUTH T6 K2
LD X0
OUT C2 K1
LD T6
OUT Y1
LD C2
OUT Y3
END
",
    );
    // Coil, current value and contact are processed when OUT T/OUT C executes,
    // never at END (L6474-6490, 10.2.11 (2)(a)): a contact read before the OUT
    // sees the new state one scan later than one read after it.
    // T6 (10 ms base, K2): 0, 1, 2 → ON in scan 3. C2 (K1): ON in scan 1.
    p.set("X0", "1").scan();
    assert_eq!(outputs(&p, 4), "0001");
    p.scan();
    assert_eq!(outputs(&p, 4), "0011");
    p.scan();
    assert_eq!(outputs(&p, 4), "0111");
    p.scan();
    assert_eq!(outputs(&p, 4), "1111");
}

#[test]
fn timer_out_twice_per_scan_adds_twice() {
    let mut p = Plc::new(
        "\
LD X0
OUTH T7 K100
LD X0
OUTH T7 K100
END
",
    );
    // Each OUT T with the coil ON adds the last scan time (L6495-6497). Scan 1:
    // the first OUT turns the coil ON (adds nothing), the second adds the scan
    // time measured at the previous END; there was none yet, so 0. Later scans
    // add 10 ms twice: scan k → 2·(k-1).
    p.set("X0", "1").scan();
    assert_eq!(p.int("TN7"), 0);
    p.scans(2);
    assert_eq!(p.int("TN7"), 4);
}

#[test]
fn retentive_timer_keeps_value() {
    let mut cfg = CpuConfig::default();
    cfg.devices.set_points(DeviceKind::STS, 16);
    let mut p = Plc::with_config(
        "\
LD X0
OUTH ST0 K5
LD X1
RST ST0
END
",
        cfg,
    );
    // 10 ms base, 10 ms scans: 0, 1, 2.
    p.set("X0", "1").scans(3);
    assert_eq!(p.int("STN0"), 2);
    // Coil OFF: value kept (a plain timer would go to 0).
    p.set("X0", "0").scans(2);
    assert_eq!(p.int("STN0"), 2);
    assert!(!p.bit("ST0"));
    // Coil ON again: resumes from 2. The coil-ON execution adds nothing, then
    // +1 per scan: 2, 3, 4, 5 → time-up at the 4th scan.
    p.set("X0", "1").scans(3);
    assert_eq!(p.int("STN0"), 4);
    assert!(!p.bit("ST0"));
    p.scan();
    assert_eq!(p.int("STN0"), 5);
    assert!(p.bit("ST0"));
    // Coil OFF: contact and value kept.
    p.set("X0", "0").scans(2);
    assert!(p.bit("ST0"));
    assert_eq!(p.int("STN0"), 5);
    // RST ST0 clears both.
    p.set("X1", "1").scan();
    assert!(!p.bit("ST0"));
    assert_eq!(p.int("STN0"), 0);
}

#[test]
fn retentive_timer_needs_points() {
    // The default configuration has 0 ST points (004: retentive timers need
    // points assigned), so the program must not load.
    let d = diagnostics(
        "\
LD X0
OUT ST0 K10
END
",
    );
    assert!(
        d.iter()
            .any(|m| m.starts_with("2:") && m.contains("0 points")),
        "{d:?}"
    );
}

// ---------------------------------------------------------------- counters

#[test]
fn counter_counts_rising_edges() {
    let mut p = Plc::new(
        "\
LD X1
RST C0
LD X0
OUT C0 K3
LD C0
OUT Y0
LD X2
OUT C1 D0
END
",
    );
    // C1's set value, in D0, is given before the first scan.
    p.set("D0", "2");
    // +1 only on OFF→ON of the coil (not ON→ON, ON→OFF, OFF→OFF).
    for (x0, cn, c) in [
        ("1", 1, false), // rise
        ("1", 1, false), // ON→ON
        ("0", 1, false), // ON→OFF: value kept
        ("1", 2, false), // rise
        ("0", 2, false),
        ("1", 3, true), // rise: 3 = K3, contact ON
        ("0", 3, true), // coil OFF: value and contact kept
        ("1", 3, true), // counted out: no further counting
    ] {
        inputs(&mut p, x0);
        p.scan();
        assert_eq!(p.int("CN0"), cn);
        assert_eq!(p.bit("C0"), c);
        assert_eq!(p.bit("Y0"), c);
    }
    // RST C0 clears value and contact at once.
    inputs(&mut p, "01");
    p.scan();
    assert_eq!(p.int("CN0"), 0);
    assert!(!p.bit("C0") && !p.bit("Y0"));
    inputs(&mut p, "10");
    p.scan();
    assert_eq!(p.int("CN0"), 1);

    // Set value in D0 = 2: the second rising edge of X2 turns C1 ON.
    assert_eq!(p.int("CN1"), 0);
    assert!(!p.bit("C1"));
    p.set("X2", "1").scan();
    assert_eq!(p.int("CN1"), 1);
    assert!(!p.bit("C1"));
    p.set("X2", "0").scan();
    p.set("X2", "1").scan();
    assert_eq!(p.int("CN1"), 2);
    assert!(p.bit("C1"));
}

// ---------------------------------------------------------------- SM / SD

#[test]
fn sm400_to_sm403_first_scans() {
    let mut p = Plc::new(
        "\
LD SM400
OUT M0
LD SM401
OUT M1
LD SM402
OUT M2
LD SM403
OUT M3
END
",
    );
    // Scan 1: SM400 ON, SM401 OFF, SM402 ON (first scan only), SM403 OFF.
    p.scan();
    assert_eq!(
        [p.bit("M0"), p.bit("M1"), p.bit("M2"), p.bit("M3")],
        [true, false, true, false]
    );
    // Scan 2 and later: SM402 OFF, SM403 ON.
    for _ in 0..2 {
        p.scan();
        assert_eq!(
            [p.bit("M0"), p.bit("M1"), p.bit("M2"), p.bit("M3")],
            [true, false, false, true]
        );
    }
}

#[test]
fn clock_relays_in_virtual_time() {
    let prog = "\
LD SM409
OUT M9
LD SM410
OUT M10
LD SM412
OUT M12
END
";
    // 10 ms scans, scan k at t = 10·k ms. The clocks start OFF at power-on and
    // toggle every half period: SM410 (50 ms) ON when floor(t / 50) is odd (t in
    // [50, 100), [150, 200) … ms), SM412 (500 ms) ON for t in [500, 1000) ms.
    let mut p = Plc::new(prog);
    for k in 1..=120u32 {
        p.scan();
        let t = 10 * k;
        let m10 = (t / 50) % 2 == 1;
        let m12 = (t / 500) % 2 == 1;
        assert_eq!(p.bit("M10"), m10, "SM410 at scan {k}");
        assert_eq!(p.bit("M12"), m12, "SM412 at scan {k}");
    }
    // Spot checks of the same, written out: scans 4/5/9/10 and 49/50/99/100.
    let mut p = Plc::new(prog);
    p.scans(4);
    assert!(!p.bit("M10"));
    p.scan();
    assert!(p.bit("M10"));
    p.scans(4); // scan 9, 90 ms
    assert!(p.bit("M10"));
    p.scan(); // scan 10, 100 ms
    assert!(!p.bit("M10"));
    p.scans(39); // scan 49, 490 ms
    assert!(!p.bit("M12"));
    p.scan(); // 500 ms
    assert!(p.bit("M12"));
    p.scans(49); // 990 ms
    assert!(p.bit("M12"));
    p.scan(); // 1000 ms
    assert!(!p.bit("M12"));

    // SM409 (5 ms ON / 5 ms OFF) with 3 ms scans, t = 3, 6, 9, …:
    // floor(t/5) = 0 1 1 2 3 3 4 4 5 6 → ON when odd.
    let mut p = Plc::new(prog);
    p.scan_time_us(3_000);
    for (k, want) in [
        false, true, true, false, true, true, false, false, true, false,
    ]
    .into_iter()
    .enumerate()
    {
        p.scan();
        assert_eq!(p.bit("M9"), want, "SM409 at t = {} ms", 3 * (k + 1));
    }
}

#[test]
fn scan_time_registers() {
    let mut p = Plc::new(
        "\
LD SM400
MOV SD420 D0
END
",
    );
    // Scan 1: 50 ms (measured from power-on).
    p.scan_time_us(50_000).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (50, 0));
    assert_eq!((p.int("SD524"), p.int("SD525")), (50, 0));
    // Scan 2: 10 ms. Minimum 10; maximum excludes the first scan → 10, not 50.
    p.scan_time_us(10_000).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (10, 0));
    assert_eq!((p.int("SD524"), p.int("SD525")), (10, 0));
    assert_eq!((p.int("SD526"), p.int("SD527")), (10, 0));
    // Scan 3: 23.6 ms → SD520 = 23, SD521 = 600 µs (L10445-10447); new maximum.
    p.scan_time_us(23_600).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (23, 600));
    assert_eq!((p.int("SD524"), p.int("SD525")), (10, 0));
    assert_eq!((p.int("SD526"), p.int("SD527")), (23, 600));
    // Scan 4: 15.03 ms: 100 µs resolution → 15 / 0; neither min nor max changes.
    p.scan_time_us(15_030).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (15, 0));
    assert_eq!((p.int("SD524"), p.int("SD525")), (10, 0));
    assert_eq!((p.int("SD526"), p.int("SD527")), (23, 600));
    // SD420 counts scans at END: 4 after 4 scans; the program read it in scan 4
    // before END, i.e. 3.
    assert_eq!(p.int("SD420"), 4);
    assert_eq!(p.int("D0"), 3);
}

#[test]
fn one_second_counter_sd412() {
    let mut p = Plc::new(
        "\
LD SM400
OUT Y0
END
",
    );
    // +1 per second after RUN (RUN at power-on, time 0); 10 ms scans.
    p.scans(99); // 990 ms
    assert_eq!(p.int("SD412"), 0);
    p.scan(); // 1000 ms
    assert_eq!(p.int("SD412"), 1);
    p.scans(99); // 1990 ms
    assert_eq!(p.int("SD412"), 1);
    p.scan(); // 2000 ms
    assert_eq!(p.int("SD412"), 2);
    p.scans(50);
    assert_eq!(p.int("SD420"), 250);
    // SD420 wraps 32767 → -32768 → … → -1 → 0 (App. 2, L10431-10437).
    p.set("SD420", "32767").scan();
    assert_eq!(p.int("SD420"), -32768);
    p.set("SD420", "-1").scan();
    assert_eq!(p.int("SD420"), 0);
}

#[test]
fn counter_set_value_zero_counts_as_one() {
    // Set value 0 is processed as 1: nothing before the first count, ON at it.
    let mut p = Plc::new("LD X0\nOUT C1 D0\nEND\n");
    p.scan();
    assert!(!p.bit("C1"));
    p.set("X0", "1").scan();
    assert!(p.bit("C1"));
    assert_eq!(p.int("CN1"), 1);
}
