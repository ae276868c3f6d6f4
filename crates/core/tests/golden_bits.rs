//! Golden tests of the bit processing instructions BSET, BRST, TEST, DTEST,
//! BKRST (programming manual §7.4), and of ZRST being rejected (not a QnH
//! instruction). Every expected value is worked out by hand in the comment
//! next to it.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};

// ------------------------------------------------------------ BSET / BRST

#[test]
fn bset_brst_set_and_reset_one_bit() {
    let mut p = Plc::new(
        "LD SM400\n\
         BSET D0 K3\n\
         BRST D1 K15\n\
         BSET D2 K17\n\
         BSET D3 D10\n\
         BSET D4 K-1\n\
         BRST D5 K0\n\
         END\n",
    );
    p.set("D1", "-1").set("D10", "4").set("D5", "3").scan();
    assert_running(&p);
    // Bit 3 → 8.
    assert_eq!(p.int("D0"), 8);
    // FFFFH with b15 OFF = 7FFFH = 32767.
    assert_eq!(p.int("D1"), 32767);
    // n = 17: low 4 bits = 1 → bit 1 → 2.
    assert_eq!(p.int("D2"), 2);
    // n from D10 = 4 → 16.
    assert_eq!(p.int("D3"), 16);
    // K-1 = FFFFH, low 4 bits = 15 → 8000H.
    assert_eq!(p.int("D4:u16"), 0x8000);
    // 3 with b0 OFF = 2.
    assert_eq!(p.int("D5"), 2);
}

#[test]
fn bsetp_runs_once_per_rising_edge() {
    // BRST clears b0 every scan; BSETP sets it again only on a rising edge.
    let mut p = Plc::new("LD SM400\nBRST D0 K0\nLD X0\nBSETP D0 K0\nEND\n");
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 1);
    p.scan();
    // Held ON: BSETP does not run, BRST did → 0 (BSET would keep it 1).
    assert_eq!(p.int("D0"), 0);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 1);
}

#[test]
fn bset_digit_specified_and_indexed() {
    let mut p = Plc::new("LD SM400\nBSET K4M0 K5\nBRST K4M0 K0\nBSET D0Z0 K0\nEND\n");
    p.set("M0", "1").set("Z0", "7").scan();
    // K4M0 bit 5 = M5 ON; bit 0 = M0 OFF.
    assert!(p.bit("M5") && !p.bit("M0"));
    // D0Z0 with Z0 = 7 → D7 = 1; D0 untouched.
    assert_eq!([p.int("D0"), p.int("D7")], [0, 1]);
    // Z0 = 20000: D20000 does not exist (D0-D12287) → 4101.
    p.set("Z0", "20000").scan();
    assert_stopped(&p, 4101);
}

// ------------------------------------------------------------ TEST / DTEST

#[test]
fn test_copies_one_bit_to_a_bit_device() {
    let mut p = Plc::new(
        "LD SM400\n\
         TEST D0 K5 M0\n\
         TEST D0 K4 M1\n\
         TEST D0 K21 M2\n\
         TEST D0 K5 D10.3\n\
         TEST K4X0 K2 M6\n\
         TEST D0 D11 M0Z0\n\
         END\n",
    );
    p.set("D0", "H0020").set("M1", "1").set("X2", "1");
    p.set("D11", "5").set("Z0", "30").scan();
    assert_running(&p);
    // 0020H = bit 5 ON.
    assert!(p.bit("M0"));
    // Bit 4 is OFF: M1 turned OFF.
    assert!(!p.bit("M1"));
    // 21 → low 4 bits 5 → ON.
    assert!(p.bit("M2"));
    // D10 bit 3 ON → 8.
    assert_eq!(p.int("D10"), 8);
    // K4X0 bit 2 = X2 ON.
    assert!(p.bit("M6"));
    // S2 = D11 = 5 → ON into M0Z0 = M30.
    assert!(p.bit("M30"));
}

#[test]
fn dtest_reads_32_bits() {
    let mut p = Plc::new(
        "LD SM400\n\
         DTEST D20 K16 M3\n\
         DTEST D20 K48 M4\n\
         DTEST D20 K0 M5\n\
         TEST D20 K16 M7\n\
         END\n",
    );
    p.set("D20:i32", "65536")
        .set("M5", "1")
        .set("M7", "1")
        .scan();
    // 65536 = 00010000H: bit 16 (D21 bit 0) ON.
    assert!(p.bit("M3"));
    // 48 → low 5 bits 16 → ON.
    assert!(p.bit("M4"));
    // Bit 0 OFF.
    assert!(!p.bit("M5"));
    // 16-bit TEST of D20 with 16 → bit 0 of D20 = 0 → OFF.
    assert!(!p.bit("M7"));
}

#[test]
fn testp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nTESTP D0 K0 M0\nEND\n");
    p.set("D0", "1").set("X0", "1").scan();
    assert!(p.bit("M0"));
    p.set("D0", "0").scan();
    // Held: not executed again, M0 stays ON (TEST would turn it OFF).
    assert!(p.bit("M0"));
}

#[test]
fn test_constant_data_is_a_load_error() {
    let d = diagnostics("LD SM400\nTEST K5 K0 M0\nTEST D0 K0 D1\nEND\n");
    assert_eq!(d.len(), 2, "{d:?}");
    // S1 constant; D a word device where a bit is needed.
    assert!(d[0].starts_with("2:6:"), "{d:?}");
    assert!(d[1].starts_with("3:12:"), "{d:?}");
}

// ------------------------------------------------------------------ BKRST

#[test]
fn bkrst_resets_n_bits() {
    let mut p = Plc::new("LD SM400\nBKRST M2 K5\nBKRST Y10 D0\nEND\n");
    for i in 0..10 {
        p.set(&format!("M{i}"), "1");
    }
    for y in ["Y10", "Y11", "Y12"] {
        p.set(y, "1");
    }
    p.set("D0", "2").scan();
    assert_running(&p);
    // M2-M6 OFF; M0, M1, M7-M9 ON.
    let m: Vec<bool> = (0..10).map(|i| p.bit(&format!("M{i}"))).collect();
    assert_eq!(
        m,
        [true, true, false, false, false, false, false, true, true, true]
    );
    // n = D0 = 2: Y10, Y11 OFF, Y12 ON.
    assert!(!p.bit("Y10") && !p.bit("Y11") && p.bit("Y12"));
}

#[test]
fn bkrst_timers_and_counters_clear_value_and_contact() {
    let mut p = Plc::new("LD SM400\nBKRST T0 K2\nBKRST C5 K1\nBKRST TN10 K2\nEND\n");
    for t in 0..3 {
        p.set(&format!("TN{t}"), "7").set(&format!("T{t}"), "1");
    }
    p.set("CN5", "3")
        .set("C5", "1")
        .set("CN6", "4")
        .set("C6", "1");
    p.set("TN10", "9").set("TN11", "9").set("T10", "1").scan();
    // T0, T1: value 0, contact OFF; T2 (third timer) unchanged.
    assert_eq!([p.int("TN0"), p.int("TN1"), p.int("TN2")], [0, 0, 7]);
    assert!(!p.bit("T0") && !p.bit("T1") && p.bit("T2"));
    // C5 reset, C6 unchanged.
    assert_eq!([p.int("CN5"), p.int("CN6")], [0, 4]);
    assert!(!p.bit("C5") && p.bit("C6"));
    // TN10 is the word device: only the current values are cleared, the
    // contact T10 stays ON.
    assert_eq!([p.int("TN10"), p.int("TN11")], [0, 0]);
    assert!(p.bit("T10"));
}

#[test]
fn bkrst_running_timer_restarts() {
    // T0 (100 ms timer, set value 2 = 200 ms) with its coil ON, scans of 10 ms.
    let mut p = Plc::new("LD X0\nOUT T0 K2\nLD X1\nBKRST T0 K1\nEND\n");
    p.set("X0", "1").scans(25);
    // Scan 1 adds nothing, scans 2-21 add 10 ms each = 200 ms → value 2 = set
    // value, contact ON (and it stays there).
    assert_eq!(p.int("TN0"), 2);
    assert!(p.bit("T0"));
    p.set("X1", "1").scan();
    // BKRST ran after OUT T0 in this scan: value 0, contact OFF.
    assert_eq!(p.int("TN0"), 0);
    assert!(!p.bit("T0"));
}

#[test]
fn bkrst_words() {
    let mut p = Plc::new("LD SM400\nBKRST D0 K3\nBKRST D10Z0 K2\nEND\n");
    for i in 0..4 {
        p.set(&format!("D{i}"), "5");
    }
    p.set("Z0", "2")
        .set("D12", "1")
        .set("D13", "1")
        .set("D14", "1")
        .scan();
    assert_eq!(
        [p.int("D0"), p.int("D1"), p.int("D2"), p.int("D3")],
        [0, 0, 0, 5]
    );
    // D10Z0 with Z0 = 2 → D12, D13.
    assert_eq!([p.int("D12"), p.int("D13"), p.int("D14")], [0, 0, 1]);
}

#[test]
fn bkrst_n_zero_and_index() {
    let mut p = Plc::new("LD SM400\nBKRST M0 K0\nBKRST M0Z0 K2\nBKRST T0Z0 K1\nEND\n");
    p.set("M0", "1")
        .set("M50", "1")
        .set("M51", "1")
        .set("M52", "1");
    p.set("Z0", "50").set("TN50", "3").set("T50", "1").scan();
    assert!(p.bit("M0"), "n = 0 resets nothing");
    // M0Z0 = M50, 2 points: M50, M51 OFF, M52 ON.
    assert!(!p.bit("M50") && !p.bit("M51") && p.bit("M52"));
    // T0Z0 = T50.
    assert_eq!(p.int("TN50"), 0);
    assert!(!p.bit("T50"));
}

#[test]
fn bkrst_bits_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBKRST M8190 K2\nBKRST M8190 K3\nEND\n");
    p.set("M8190", "1").set("M8191", "1").scan();
    // First: M8190, M8191 (the last two) reset; second needs M8192.
    assert!(!p.bit("M8191"));
    assert_stopped(&p, 4101);
}

#[test]
fn bkrst_timers_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBKRST T2046 K3\nEND\n");
    p.set("TN2046", "1").scan();
    // T0-T2047: T2046 + 3 needs T2048 → 4101; nothing reset.
    assert_stopped(&p, 4101);
    assert_eq!(p.int("TN2046"), 1);
}

#[test]
fn bkrst_words_negative_count_is_4101() {
    let mut p = Plc::new("LD SM400\nBKRST D0 D100\nEND\n");
    p.set("D100", "-1").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bkrstp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD SM400\nSET M0\nLD X0\nBKRSTP M0 K1\nLD M0\nOUT M10\nEND\n");
    p.set("X0", "1").scan();
    // SET M0, then BKRSTP on the edge → OFF when copied to M10.
    assert!(!p.bit("M10"));
    p.scan();
    // Held: BKRSTP does not run again → M0 stays ON.
    assert!(p.bit("M10"));
}

#[test]
fn bkrst_operand_errors_are_reported_at_load() {
    let d = diagnostics("LD SM400\nBKRST K4M0 K2\nBKRST D0.5 K1\nBKRST M0\nEND\n");
    assert_eq!(d.len(), 3, "{d:?}");
    assert!(d[0].starts_with("2:7:"), "{d:?}");
    assert!(d[1].starts_with("3:7:"), "{d:?}");
    assert!(d[2].contains("2 operands"), "{d:?}");
}

// ------------------------------------------------------------------- ZRST

#[test]
fn zrst_is_not_a_qnh_instruction() {
    let d = diagnostics("LD SM400\nZRST M0 M10\nZRSTP D0 D10\nEND\n");
    assert_eq!(d.len(), 2, "{d:?}");
    assert!(
        d[0].starts_with("2:1:") && d[0].contains("not a MELSEC-Q"),
        "{d:?}"
    );
    assert!(d[1].starts_with("3:1:") && d[1].contains("BKRST"), "{d:?}");
}
