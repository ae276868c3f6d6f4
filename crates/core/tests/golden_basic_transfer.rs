//! Golden tests of the basic instructions (transfer, BIN and real arithmetic,
//! conversion, comparison contacts, index modification). Every expected value is
//! worked out by hand in the comment next to it (004 §2.8 numeric formats,
//! programming manual ch. 6).
//!
//! This file: transfer (MOV, DMOV, EMOV; digit-specified and bit-of-word operands).

mod common;
use common::{assert_running, Plc};

// ---------------------------------------------------------------- transfer

#[test]
fn mov_constants_and_words() {
    let mut p = Plc::new(
        "LD SM400\n\
         MOV K1234 D0\n\
         MOV D0 D1\n\
         MOV K-1 D2\n\
         MOV HABCD D3\n\
         MOV K-32768 D4\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), 1234);
    // MOV D0 D1 runs after MOV K1234 D0 in the same scan.
    assert_eq!(p.int("D1"), 1234);
    // K-1 is FFFFH: -1 signed, 65535 unsigned.
    assert_eq!(p.int("D2"), -1);
    assert_eq!(p.int("D2:u16"), 65535);
    // ABCDH = 10·4096 + 11·256 + 12·16 + 13 = 43981; signed 43981 − 65536 = −21555.
    assert_eq!(p.int("D3:u16"), 43981);
    assert_eq!(p.int("D3"), -21555);
    // K-32768 = 8000H.
    assert_eq!(p.int("D4:u16"), 0x8000);
}

#[test]
fn mov_condition_off_does_nothing() {
    let mut p = Plc::new("LD X0\nMOV K5 D0\nEND\n");
    p.set("D0", "99").scan();
    // X0 OFF: D0 keeps the 99 written before the scan.
    assert_eq!(p.int("D0"), 99);
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 5);
}

#[test]
fn movp_runs_once_per_rising_edge_mov_every_scan() {
    let mut p = Plc::new("LD X0\nMOVP D5 D6\nLD X0\nMOV D5 D7\nEND\n");
    // Scan 1: X0 rises, D5 = 7 → both copy 7.
    p.set("X0", "1").set("D5", "7").scan();
    assert_eq!(p.int("D6"), 7);
    assert_eq!(p.int("D7"), 7);
    // Scan 2: X0 still ON, D5 = 9 → MOVP does not run again, MOV does.
    p.set("D5", "9").scan();
    assert_eq!(p.int("D6"), 7);
    assert_eq!(p.int("D7"), 9);
    // Scan 3 OFF, scan 4 ON again: a new rising edge → MOVP copies 9.
    p.set("X0", "0").scan();
    assert_eq!(p.int("D6"), 7);
    p.set("X0", "1").scan();
    assert_eq!(p.int("D6"), 9);
}

#[test]
fn dmov_32_bit() {
    let mut p = Plc::new(
        "LD SM400\n\
         DMOV K100000 D0\n\
         DMOV K-2 D10\n\
         DMOV D0 D20\n\
         DMOV HFFFFFFFF D30\n\
         DMOV K-2147483648 D40\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    // 100000 = 186A0H: low word 86A0H = 34464, high word 1.
    assert_eq!(p.int("D0:u16"), 0x86A0);
    assert_eq!(p.int("D1"), 1);
    assert_eq!(p.int("D0:i32"), 100000);
    // −2 = FFFFFFFEH: D10 = FFFEH, D11 = FFFFH.
    assert_eq!(p.int("D10:u16"), 0xFFFE);
    assert_eq!(p.int("D11:u16"), 0xFFFF);
    assert_eq!(p.int("D20:i32"), 100000);
    assert_eq!(p.int("D30:i32"), -1);
    // −2147483648 = 80000000H.
    assert_eq!(p.int("D40:u16"), 0);
    assert_eq!(p.int("D41:u16"), 0x8000);
}

#[test]
fn emov_copies_real_bits() {
    let mut p = Plc::new(
        "LD SM400\n\
         EMOV E10.0 D0\n\
         EMOV D0 D2\n\
         EMOV E-2.5 D4\n\
         EMOV E1.234+3 D6\n\
         EMOV E-2.5-1 D8\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    // 10.0 = 1.25·2³: sign 0, exponent 3+127 = 82H, mantissa 0100…0 → 41200000H
    // (004 §2.8 worked example).
    assert_eq!(p.int("D0:u16"), 0x0000);
    assert_eq!(p.int("D1:u16"), 0x4120);
    assert_eq!(p.real("D0"), 10.0);
    assert_eq!(p.int("D2:u32"), 0x4120_0000);
    // −2.5 = −1.25·2¹: sign 1, exponent 128 = 80H, mantissa 0100…0
    // → 1 10000000 0100… = C0200000H.
    assert_eq!(p.int("D4:u16"), 0);
    assert_eq!(p.int("D5:u16"), 0xC020);
    // E1.234+3 = 1.234·10³ = 1234.0 (exactly representable).
    assert_eq!(p.real("D6"), 1234.0);
    // E-2.5-1 = −2.5·10⁻¹ = −0.25 = −1·2⁻²: exponent 125 = 7DH → BE800000H.
    assert_eq!(p.int("D8:u32"), 0xBE80_0000);
}

#[test]
fn mov_digit_specified_source_k4x0() {
    let mut p = Plc::new("LD SM400\nMOV K4X0 D0\nMOV K1X0 D1\nEND\n");
    // 1234H = 0001 0010 0011 0100b: bits 2, 4, 5, 9 and 12 → X2, X4, X5, X9, XC.
    for x in ["X2", "X4", "X5", "X9", "XC"] {
        p.set(x, "1");
    }
    // X10 is outside K4X0 (X0-XF) and must not be read.
    p.set("X10", "1");
    p.scan();
    assert_eq!(p.int("D0"), 0x1234);
    // K1X0 = X0-X3 = 0100b = 4, zero-extended.
    assert_eq!(p.int("D1"), 4);
}

#[test]
fn mov_digit_specified_destination_k2y10() {
    let mut p = Plc::new("LD SM400\nMOV H1234 K2Y10\nMOV K-1 K1Y0\nEND\n");
    // Y10 was ON before: inside K2Y10, so it is overwritten. Y18 is outside
    // (K2Y10 = Y10-Y17) and keeps its ON state.
    p.set("Y10", "1").set("Y18", "1").set("Y4", "1").scan();
    // Only the low 8 bits of 1234H are written: 34H = 0011 0100b
    // → Y12, Y14, Y15 ON; Y10, Y11, Y13, Y16, Y17 OFF.
    let on = ["Y12", "Y14", "Y15"];
    for y in ["Y10", "Y11", "Y12", "Y13", "Y14", "Y15", "Y16", "Y17"] {
        assert_eq!(p.bit(y), on.contains(&y), "{y}");
    }
    assert!(p.bit("Y18"));
    assert_eq!(p.int("K2Y10"), 0x34);
    // K-1 = FFFFH, low 4 bits → Y0-Y3 ON; Y4 (outside K1Y0) untouched (was ON).
    for y in ["Y0", "Y1", "Y2", "Y3"] {
        assert!(p.bit(y), "{y}");
    }
    assert!(p.bit("Y4"));
}

#[test]
fn mov_digit_specified_indexed_k4m0z2() {
    let mut p = Plc::new("LD SM400\nMOV K16 Z2\nMOV K4M0Z2 D0\nEND\n");
    // Z2 = 16 → K4M16 = M16-M31. M17 and M31 ON → bits 1 and 15 → 8002H.
    // M0 (the unindexed start) must not be read.
    p.set("M0", "1").set("M17", "1").set("M31", "1").scan();
    assert_running(&p);
    assert_eq!(p.int("D0:u16"), 0x8002);
    // 8002H as signed 16-bit: 32770 − 65536 = −32766.
    assert_eq!(p.int("D0"), -32766);
}

#[test]
fn dmov_k8m0_32_bits() {
    let mut p = Plc::new("LD SM400\nDMOV K8M0 D0\nDMOV H12345678 K8M100\nEND\n");
    // M0 and M31 ON → 80000001H.
    p.set("M0", "1").set("M31", "1").scan();
    assert_eq!(p.int("D0:u32"), 0x8000_0001);
    assert_eq!(p.int("D0"), 1);
    assert_eq!(p.int("D1:u16"), 0x8000);
    // 12345678H into M100-M131: M103 is bit 3 of 8H → ON; M100 bit 0 → OFF;
    // the top digit 1H puts bit 28 → M128 ON, M131 OFF.
    assert_eq!(p.int("K8M100:u32"), 0x1234_5678);
    assert!(p.bit("M103"));
    assert!(!p.bit("M100"));
    assert!(p.bit("M128"));
    assert!(!p.bit("M131"));
}

#[test]
fn dmov_k4_source_is_zero_extended() {
    let mut p = Plc::new("LD SM400\nDMOV K4M0 D0\nEND\n");
    // K4M0 with M15 ON = 8000H; a 32-bit read of 4 digits is not sign-extended:
    // D0,D1 = 00008000H = 32768. M16 (outside K4M0) is ignored.
    p.set("D1", "-1").set("M15", "1").set("M16", "1").scan();
    assert_eq!(p.int("D0:i32"), 32768);
}

#[test]
fn mov_timer_and_counter_current_values() {
    let mut p = Plc::new(
        "LD X0\n\
         OUT T0 K100\n\
         LD X1\n\
         OUT C0 K10\n\
         LD SM400\n\
         MOV T0 D0\n\
         MOV C0 D1\n\
         MOV K7 T5\n\
         MOV TN5 D2\n\
         END\n",
    );
    // T0 (100 ms base) with the coil ON from scan 1: scan 1 adds nothing, scans
    // 2..21 add the 10 ms scan time each → 200 ms → current value 2 after scan 21.
    p.set("X0", "1");
    // C0: X1 ON, OFF, ON, OFF, ON over the first 5 scans → 3 rising edges.
    for i in 0..21 {
        let x1 = i < 5 && i % 2 == 0;
        p.set("X1", if x1 { "1" } else { "0" }).scan();
    }
    assert_running(&p);
    // `MOV T0 D0` in a word operand means the current value of T0.
    assert_eq!(p.int("D0"), 2);
    assert_eq!(p.int("D1"), 3);
    // `MOV K7 T5` writes the current value of T5.
    assert_eq!(p.int("TN5"), 7);
    assert_eq!(p.int("D2"), 7);
    // The contacts: T0 not timed out (2 < 100), C0 not counted out (3 < 10).
    assert!(!p.bit("T0"));
    assert!(!p.bit("C0"));
}

#[test]
fn bit_of_word_contact_and_coil() {
    let mut p = Plc::new(
        "LD D0.3\n\
         OUT Y0\n\
         LD D0.2\n\
         OUT Y1\n\
         LD SM400\n\
         SET D1.F\n\
         OUT D2.0\n\
         LD X0\n\
         OUT D3.A\n\
         END\n",
    );
    // D0 = 8 = 1000b: bit 3 ON, bit 2 OFF.
    p.set("D0", "8").set("D3", "-1").scan();
    assert!(p.bit("Y0"));
    assert!(!p.bit("Y1"));
    // SET D1.F: bit 15 → 8000H = −32768.
    assert_eq!(p.int("D1"), -32768);
    assert_eq!(p.int("D2"), 1);
    // OUT D3.A with X0 OFF clears bit 10 only: FFFFH − 400H = FBFFH.
    assert_eq!(p.int("D3:u16"), 0xFBFF);
}
