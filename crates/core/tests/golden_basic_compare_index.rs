//! Golden tests of the basic instructions (transfer, BIN and real arithmetic,
//! conversion, comparison contacts, index modification). Every expected value is
//! worked out by hand in the comment next to it (004 §2.8 numeric formats,
//! programming manual ch. 6).
//!
//! This file: comparison contacts and index modification.

mod common;
use common::{assert_running, assert_stopped, Plc};

// ---------------------------------------------------------------- compare

fn compare_program() -> Plc {
    Plc::new(
        "LD= D0 K5\nOUT M0\n\
         LD<> D0 K5\nOUT M1\n\
         LD> D0 K5\nOUT M2\n\
         LD<= D0 K5\nOUT M3\n\
         LD< D0 K5\nOUT M4\n\
         LD>= D0 K5\nOUT M5\n\
         END\n",
    )
}

fn flags(p: &Plc) -> [bool; 6] {
    ["M0", "M1", "M2", "M3", "M4", "M5"].map(|m| p.bit(m))
}

#[test]
fn compare_16_bit_all_operators() {
    let mut p = compare_program();
    //                 =      <>     >      <=     <      >=
    p.set("D0", "5").scan();
    assert_eq!(flags(&p), [true, false, false, true, false, true]);
    p.set("D0", "6").scan();
    assert_eq!(flags(&p), [false, true, true, false, false, true]);
    p.set("D0", "4").scan();
    assert_eq!(flags(&p), [false, true, false, true, true, false]);
    // Signed: −1 (FFFFH) < 5, not 65535 > 5.
    p.set("D0", "-1").scan();
    assert_eq!(flags(&p), [false, true, false, true, true, false]);
}

#[test]
fn compare_16_bit_is_signed() {
    let mut p = Plc::new(
        "LD< H8000 K0\nOUT M0\n\
         LD> D0 K0\nOUT M1\n\
         LD< D0 D1\nOUT M2\n\
         END\n",
    );
    // H8000 = −32768 < 0 → ON. D0 = 8000H → not > 0. D0 = −32768 < D1 = 32767.
    p.set("D0:u16", "32768").set("D1", "32767").scan();
    assert!(p.bit("M0"));
    assert!(!p.bit("M1"));
    assert!(p.bit("M2"));
}

#[test]
fn compare_and_or_forms() {
    let mut p = Plc::new(
        "LD X0\nAND= D0 K5\nOUT M10\n\
         LD X0\nOR> D0 K5\nOUT M11\n\
         LD X0\nAND<> D0 K5\nOUT M12\n\
         LD X0\nOR<= D0 K5\nOUT M13\n\
         LD X0\nAND< D0 K5\nOUT M14\n\
         LD X0\nOR>= D0 K5\nOUT M15\n\
         END\n",
    );
    // X0 ON, D0 = 5: AND= ON, OR> ON (X0), AND<> OFF, OR<= ON, AND< OFF, OR>= ON.
    p.set("X0", "1").set("D0", "5").scan();
    let got = ["M10", "M11", "M12", "M13", "M14", "M15"].map(|m| p.bit(m));
    assert_eq!(got, [true, true, false, true, false, true]);
    // X0 OFF, D0 = 9: ANDs all OFF; OR> 9>5 ON, OR<= OFF, OR>= ON.
    p.set("X0", "0").set("D0", "9").scan();
    let got = ["M10", "M11", "M12", "M13", "M14", "M15"].map(|m| p.bit(m));
    assert_eq!(got, [false, true, false, false, false, true]);
}

#[test]
fn compare_32_bit_forms() {
    let mut p = Plc::new(
        "LDD> D10 K65535\nOUT M0\n\
         LDD< D12 K0\nOUT M1\n\
         LD X0\nANDD= D10 K65536\nOUT M2\n\
         LDI X0\nORD<> D10 K65536\nOUT M3\n\
         LDD>= D10 H10000\nOUT M4\n\
         LDD<= D12 K-2\nOUT M5\n\
         END\n",
    );
    // D10,D11 = 65536 = 00010000H: the low word alone is 0, so a 16-bit
    // compare would say 0 > 65535 is false; the 32-bit one says 65536 > 65535.
    // D12,D13 = −1 < 0.
    p.set("D10:i32", "65536")
        .set("D12:i32", "-1")
        .set("X0", "1");
    p.scan();
    assert!(p.bit("M0"));
    assert!(p.bit("M1"));
    assert!(p.bit("M2")); // X0 ∧ 65536 = 65536
    assert!(!p.bit("M3")); // ¬X0 ∨ 65536 ≠ 65536 = false
    assert!(p.bit("M4")); // 65536 ≥ 10000H
    assert!(!p.bit("M5")); // −1 ≤ −2 is false
}

#[test]
fn compare_real_forms() {
    let mut p = Plc::new(
        "LDE> D20 E1.5\nOUT M0\n\
         LDE= D20 E1.75\nOUT M1\n\
         LDE< D20 E-2.0\nOUT M2\n\
         LD X0\nORE<= D20 E1.75\nOUT M3\n\
         LD X0\nANDE<> D20 E1.75\nOUT M4\n\
         LDE>= D22 D20\nOUT M5\n\
         END\n",
    );
    p.set("D20:f32", "1.75").set("D22:f32", "-3.5").scan();
    assert!(p.bit("M0")); // 1.75 > 1.5
    assert!(p.bit("M1")); // 1.75 = 1.75
    assert!(!p.bit("M2")); // 1.75 < −2 false
    assert!(p.bit("M3")); // X0 OFF ∨ 1.75 ≤ 1.75
    assert!(!p.bit("M4")); // X0 OFF ∧ …
    assert!(!p.bit("M5")); // −3.5 ≥ 1.75 false
}

#[test]
fn compare_real_with_infinite_operand_stops_with_4100() {
    let mut p = Plc::new("LDE> D0 E1.0\nOUT M0\nEND\n");
    p.set("D0:u32", "H7F800000").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn compare_mixed_with_anb_orb() {
    // Y0 = (D0 = 1 ∨ X0) ∧ (D1 > 10 ∨ D2,D3 < 0)
    // Y1 = (X1 ∧ D0 ≠ 0) ∨ (D4 ≥ 0.5 ∧ ¬X2)
    let mut p = Plc::new(
        "LD= D0 K1\n\
         OR X0\n\
         LD> D1 K10\n\
         ORD< D2 K0\n\
         ANB\n\
         OUT Y0\n\
         LD X1\n\
         AND<> D0 K0\n\
         LDE>= D4 E0.5\n\
         ANI X2\n\
         ORB\n\
         OUT Y1\n\
         END\n",
    );
    // D0 = 1, D1 = 0, D2,D3 = 0: (T ∨ F) ∧ (F ∨ F) = F.
    // Y1: (F ∧ T) ∨ (0.0 ≥ 0.5 = F ∧ T) = F.
    p.set("D0", "1").scan();
    assert!(!p.bit("Y0"));
    assert!(!p.bit("Y1"));
    // D2,D3 = −70000 < 0 → second block T → Y0 ON.
    // D4 = 0.5 → (T ∧ ¬X2 = T) → Y1 ON.
    p.set("D2:i32", "-70000").set("D4:f32", "0.5").scan();
    assert!(p.bit("Y0"));
    assert!(p.bit("Y1"));
    // D0 = 2, X0 OFF → first block F → Y0 OFF. X2 ON and X1 OFF → Y1 OFF.
    p.set("D0", "2").set("X2", "1").scan();
    assert!(!p.bit("Y0"));
    assert!(!p.bit("Y1"));
    // X0 ON → first block T again, D1 = 11 → Y0 ON; X1 ON and D0 = 2 ≠ 0 → Y1 ON.
    p.set("X0", "1")
        .set("D1", "11")
        .set("D2:i32", "0")
        .set("X1", "1");
    p.scan();
    assert!(p.bit("Y0"));
    assert!(p.bit("Y1"));
}

// ---------------------------------------------------------------- index

#[test]
fn negative_index_modification() {
    let mut p = Plc::new("LD SM400\nMOV K-3 Z0\nMOV K7 D10Z0\nMOV D10Z0 D20\nEND\n");
    p.scan();
    assert_running(&p);
    // D10Z0 with Z0 = −3 is D7.
    assert_eq!(p.int("D7"), 7);
    assert_eq!(p.int("D10"), 0);
    assert_eq!(p.int("D20"), 7);
}

#[test]
fn index_modification_out_of_range_stops_with_4101() {
    let mut p = Plc::new("LD SM400\nMOV K-11 Z0\nMOV K7 D10Z0\nEND\n");
    // D10 − 11 = D−1: outside D0-D12287.
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn index_modification_32_bit_past_last_device_stops_with_4101() {
    let mut p = Plc::new("LD SM400\nMOV K1 Z1\nDMOV K1 D12286Z1\nEND\n");
    // D12286 + 1 = D12287; a 32-bit operand also needs D12288, which does not exist.
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn index_modification_of_bits_and_digits() {
    let mut p = Plc::new(
        "LD SM400\n\
         MOV K5 Z3\n\
         MOV K-4 Z4\n\
         LD X0Z3\n\
         OUT Y10Z4\n\
         LD SM400\n\
         MOV K1M0Z3 D0\n\
         END\n",
    );
    // X0Z3 = X5; Y10Z4 = Y(10H − 4) = YC. K1M0Z3 = M5-M8.
    p.set("X5", "1").set("M5", "1").set("M8", "1").scan();
    assert_running(&p);
    assert!(p.bit("YC"));
    assert!(!p.bit("Y10"));
    // M5 → bit 0, M8 → bit 3: 1001b = 9.
    assert_eq!(p.int("D0"), 9);
}

#[test]
fn digit_destination_of_multiply_and_divide() {
    // `*` with K8M0: the 32-bit product 300 × 300 = 90000 = 0x15F90 in M0-M31.
    // `/` with K4M100: only the quotient 100 / 7 = 14 is stored, no remainder.
    let mut p = Plc::new("LD SM400\n* K300 K300 K8M0\n/ K100 K7 K4M100\nEND\n");
    p.scan();
    assert_eq!(p.int("K8M0"), 90000);
    assert_eq!(p.int("K4M100"), 14);
    assert_eq!(p.int("K4M116"), 0);
}
