//! Golden tests of the basic instructions (transfer, BIN and real arithmetic,
//! conversion, comparison contacts, index modification). Every expected value is
//! worked out by hand in the comment next to it (004 §2.8 numeric formats,
//! programming manual ch. 6).
//!
//! This file: BIN 16/32-bit and real arithmetic, INC/DEC and the FLT/INT
//! conversions.

mod common;
use common::{assert_running, assert_stopped, Plc};
use softplc_core::engine::CpuState;

// ---------------------------------------------------------------- BIN 16

#[test]
fn add_sub_16_bit_wrap_and_two_operand_forms() {
    let mut p = Plc::new(
        "LD SM400\n\
         + K32767 K1 D0\n\
         - K-32768 K1 D1\n\
         + K100 K-250 D2\n\
         + D10 D11\n\
         - D12 D13\n\
         END\n",
    );
    p.set("D10", "5").set("D11", "7");
    p.set("D12", "3").set("D13", "10");
    p.scan();
    assert_running(&p);
    // 32767 + 1 = 8000H = −32768 (wraps, no error).
    assert_eq!(p.int("D0"), -32768);
    // −32768 − 1 = 7FFFH = 32767.
    assert_eq!(p.int("D1"), 32767);
    assert_eq!(p.int("D2"), -150);
    // `+ S D`: D = D + S → D11 = 7 + 5 = 12.
    assert_eq!(p.int("D11"), 12);
    // `- S D`: D = D − S → D13 = 10 − 3 = 7 (not 3 − 10).
    assert_eq!(p.int("D13"), 7);
    // A second scan adds again: 12 + 5 = 17, 7 − 3 = 4.
    p.scan();
    assert_eq!(p.int("D11"), 17);
    assert_eq!(p.int("D13"), 4);
}

#[test]
fn mul_16_bit_gives_32_bit_product() {
    let mut p = Plc::new(
        "LD SM400\n\
         * K300 K300 D10\n\
         * K-2 K3 D20\n\
         * K-32768 K-32768 D30\n\
         * D40 D41\n\
         END\n",
    );
    p.set("D40", "1000").set("D41", "-100").scan();
    assert_running(&p);
    // 300 × 300 = 90000 = 15F90H: D10 = 5F90H = 24464, D11 = 1.
    assert_eq!(p.int("D10:i32"), 90000);
    assert_eq!(p.int("D10:u16"), 0x5F90);
    assert_eq!(p.int("D11"), 1);
    // −6 = FFFFFFFAH: the high word D21 is FFFFH = −1.
    assert_eq!(p.int("D20:i32"), -6);
    assert_eq!(p.int("D21"), -1);
    // (−32768)² = 2³⁰ = 1073741824.
    assert_eq!(p.int("D30:i32"), 1 << 30);
    // `* S D`: D,D+1 = D × S = −100 × 1000 = −100000.
    assert_eq!(p.int("D41:i32"), -100000);
}

#[test]
fn div_16_bit_quotient_and_remainder() {
    let mut p = Plc::new(
        "LD SM400\n\
         / K-7 K2 D0\n\
         / K7 K-2 D2\n\
         / K-5 K-3 D4\n\
         / K2000 K600 D6\n\
         / D10 D11\n\
         END\n",
    );
    p.set("D10", "4").set("D11", "30").scan();
    assert_running(&p);
    // −7 / 2: quotient truncated toward 0 = −3; remainder has the dividend's
    // sign: −7 = 2·(−3) + (−1).
    assert_eq!(p.int("D0"), -3);
    assert_eq!(p.int("D1"), -1);
    // 7 / −2 = −3 remainder 1 (7 = −2·−3 + 1).
    assert_eq!(p.int("D2"), -3);
    assert_eq!(p.int("D3"), 1);
    // −5 / −3 = 1 remainder −2 (programming manual example).
    assert_eq!(p.int("D4"), 1);
    assert_eq!(p.int("D5"), -2);
    // 2000 / 600 = 3 remainder 200 (manual example).
    assert_eq!(p.int("D6"), 3);
    assert_eq!(p.int("D7"), 200);
    // `/ S D`: D = D / S → 30 / 4 = 7 remainder 2 in D11, D12.
    assert_eq!(p.int("D11"), 7);
    assert_eq!(p.int("D12"), 2);
}

#[test]
fn div_16_bit_into_digit_destination_stores_quotient() {
    let mut p = Plc::new("LD SM400\n/ K-7 K2 K4M0\nEND\n");
    // Quotient −3 = FFFDH into M0-M15; M16 (outside K4M0) is untouched.
    p.scan();
    assert_eq!(p.int("K4M0:u16"), 0xFFFD);
    assert!(!p.bit("M16"));
}

#[test]
fn div_16_bit_by_zero_stops_with_4100() {
    let mut p = Plc::new("LD SM400\n/ K5 D1 D2\nMOV K1 D10\nEND\n");
    p.set("D2", "42").scan();
    assert_stopped(&p, 4100);
    // The instruction is not executed and the CPU stops at once: D2 keeps 42 and
    // the MOV after it never runs.
    assert_eq!(p.int("D2"), 42);
    assert_eq!(p.int("D10"), 0);
    // In STOP further scans execute nothing.
    p.scan();
    assert_eq!(p.int("D10"), 0);
    assert_eq!(p.state(), CpuState::Stop);
}

// ---------------------------------------------------------------- BIN 32

#[test]
fn add_sub_32_bit_wrap() {
    let mut p = Plc::new(
        "LD SM400\n\
         D+ K2147483647 K1 D0\n\
         D- K-2147483648 K1 D2\n\
         D+ K100000 K-1 D4\n\
         D+ K1 D6\n\
         D- K70000 D8\n\
         END\n",
    );
    p.set("D6:u32", "65535").set("D8:i32", "5").scan();
    assert_running(&p);
    // 2147483647 + 1 wraps to −2147483648.
    assert_eq!(p.int("D0:i32"), -2147483648);
    // −2147483648 − 1 wraps to 2147483647.
    assert_eq!(p.int("D2:i32"), 2147483647);
    assert_eq!(p.int("D4:i32"), 99999);
    // 65535 + 1 = 65536 = 10000H: carry into the high word, D6 = 0, D7 = 1.
    assert_eq!(p.int("D6"), 0);
    assert_eq!(p.int("D7"), 1);
    // 5 − 70000 = −69995.
    assert_eq!(p.int("D8:i32"), -69995);
}

#[test]
fn mul_32_bit_gives_64_bit_product() {
    let mut p = Plc::new(
        "LD SM400\n\
         D* K100000 K100000 D10\n\
         D* K-1 K1 D20\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    // 100000² = 10¹⁰ = 2·2³² + 1410065408 = 2_540B_E400H
    // → D10 = E400H, D11 = 540BH, D12 = 0002H, D13 = 0000H.
    assert_eq!(p.int("D10:u16"), 0xE400);
    assert_eq!(p.int("D11:u16"), 0x540B);
    assert_eq!(p.int("D12:u16"), 0x0002);
    assert_eq!(p.int("D13:u16"), 0x0000);
    // −1 in 64 bits: all four words FFFFH.
    for d in ["D20", "D21", "D22", "D23"] {
        assert_eq!(p.int(&format!("{d}:u16")), 0xFFFF, "{d}");
    }
}

#[test]
fn div_32_bit_quotient_and_remainder() {
    let mut p = Plc::new(
        "LD SM400\n\
         D/ K-100001 K10 D30\n\
         D/ K5500 K-540 D40\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    // −100001 / 10 = −10000 remainder −1 (−100001 = 10·−10000 − 1);
    // quotient in D30,D31, remainder in D32,D33.
    assert_eq!(p.int("D30:i32"), -10000);
    assert_eq!(p.int("D32:i32"), -1);
    // 5500 / −540 = −10 remainder 100 (5500 = −540·−10 + 100).
    assert_eq!(p.int("D40:i32"), -10);
    assert_eq!(p.int("D42:i32"), 100);
}

#[test]
fn div_32_bit_by_zero_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nD/ K1 D0 D10\nEND\n");
    // D0,D1 = 00000000H = 0.
    p.scan();
    assert_stopped(&p, 4100);
}

#[test]
fn div_32_bit_divisor_with_only_high_word_is_not_zero() {
    let mut p = Plc::new("LD SM400\nD/ K131072 D0 D10\nEND\n");
    // D0,D1 = 65536 = 10000H: low word 0 but the divisor is not 0.
    // 131072 / 65536 = 2 remainder 0.
    p.set("D0:i32", "65536").scan();
    assert_running(&p);
    assert_eq!(p.int("D10:i32"), 2);
    assert_eq!(p.int("D12:i32"), 0);
}

// ---------------------------------------------------------------- real

#[test]
fn real_arithmetic_exact_values() {
    let mut p = Plc::new(
        "LD SM400\n\
         E+ E1.5 E2.25 D0\n\
         E- E1.5 E2.25 D2\n\
         E* E1.5 E-4.0 D4\n\
         E/ E1.0 E8.0 D6\n\
         E+ E0.5 D8\n\
         E- E0.25 D10\n\
         E* E2.0 D12\n\
         E/ E4.0 D14\n\
         END\n",
    );
    p.set("D8:f32", "1.0").set("D10:f32", "1.0");
    p.set("D12:f32", "3.0").set("D14:f32", "3.0");
    p.scan();
    assert_running(&p);
    // All operands and results are sums of powers of two: exact in binary.
    // 1.5 + 2.25 = 3.75; 1.5 − 2.25 = −0.75; 1.5 × −4 = −6; 1 / 8 = 0.125.
    assert_eq!(p.real("D0"), 3.75);
    assert_eq!(p.real("D2"), -0.75);
    assert_eq!(p.real("D4"), -6.0);
    assert_eq!(p.real("D6"), 0.125);
    // Two-operand forms, D = D op S: 1.0 + 0.5 = 1.5; 1.0 − 0.25 = 0.75;
    // 3.0 × 2 = 6; 3.0 / 4 = 0.75.
    assert_eq!(p.real("D8"), 1.5);
    assert_eq!(p.real("D10"), 0.75);
    assert_eq!(p.real("D12"), 6.0);
    assert_eq!(p.real("D14"), 0.75);
    // 3.75 = 1.875·2¹: exponent 128, mantissa .111 → 40700000H.
    assert_eq!(p.int("D0:u32"), 0x4070_0000);
}

#[test]
fn real_division_by_zero_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nE/ E1.0 D0 D10\nEND\n");
    // D0,D1 = 0 = 0.0.
    p.scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D10:u32"), 0);
}

#[test]
fn real_overflow_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nE* E3.0+38 E10 D0\nMOV K1 D10\nEND\n");
    // 3·10³⁸ × 10 = 3·10³⁹ > 3.40282·10³⁸ (the largest single): overflow.
    p.scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0:u32"), 0);
    assert_eq!(p.int("D10"), 0);
}

#[test]
fn real_infinite_input_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nE+ D0 E1.0 D10\nEND\n");
    // 7F800000H = +∞: exponent FFH is "not used" by the CPU (004 §2.8).
    p.set("D0:u32", "H7F800000").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn real_nan_input_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nEMOV E1.0 D10\nE* D0 D10 D20\nEND\n");
    // 7FC00000H = NaN (exponent FFH).
    p.set("D0:u32", "H7FC00000").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn real_underflow_gives_zero() {
    let mut p = Plc::new(
        "LD SM400\n\
         E* E1.0-30 E1.0-30 D0\n\
         E/ E1.0-20 E1.0+20 D2\n\
         END\n",
    );
    p.set("D0:f32", "5.0").set("D2:f32", "5.0").scan();
    assert_running(&p);
    // 10⁻³⁰ × 10⁻³⁰ = 10⁻⁶⁰, far below 1.17549·10⁻³⁸ → 0 without error.
    assert_eq!(p.int("D0:u32"), 0);
    // 10⁻²⁰ / 10²⁰ = 10⁻⁴⁰: a denormal in IEEE single, which the CPU does not
    // have (exponent 00H "not used") → 0.
    assert_eq!(p.int("D2:u32"), 0);
}

// ---------------------------------------------------------------- INC/DEC

#[test]
fn inc_dec_wrap() {
    let mut p = Plc::new(
        "LD SM400\n\
         INC D0\n\
         DEC D1\n\
         DINC D2\n\
         DDEC D4\n\
         INC D6\n\
         DEC D7\n\
         END\n",
    );
    p.set("D0", "32767").set("D1", "-32768");
    p.set("D2:i32", "2147483647").set("D4:i32", "-2147483648");
    p.scan();
    assert_running(&p);
    // 32767 + 1 = −32768; −32768 − 1 = 32767 (no error).
    assert_eq!(p.int("D0"), -32768);
    assert_eq!(p.int("D1"), 32767);
    // 2147483647 + 1 = −2147483648; −2147483648 − 1 = 2147483647.
    assert_eq!(p.int("D2:i32"), -2147483648);
    assert_eq!(p.int("D4:i32"), 2147483647);
    // INC/DEC run every scan while ON: 0 → 1 → 2 and 0 → −1 → −2.
    assert_eq!(p.int("D6"), 1);
    assert_eq!(p.int("D7"), -1);
    p.scan();
    assert_eq!(p.int("D6"), 2);
    assert_eq!(p.int("D7"), -2);
}

#[test]
fn dinc_carries_into_high_word() {
    let mut p = Plc::new("LD SM400\nDINC D0\nDDEC D2\nEND\n");
    // 0000FFFFH + 1 = 00010000H; 00010000H − 1 = 0000FFFFH.
    p.set("D0:u32", "65535").set("D2:u32", "65536").scan();
    assert_eq!(p.int("D0"), 0);
    assert_eq!(p.int("D1"), 1);
    assert_eq!(p.int("D2:u16"), 0xFFFF);
    assert_eq!(p.int("D3"), 0);
}

#[test]
fn incp_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nINCP D0\nEND\n");
    p.scan();
    assert_eq!(p.int("D0"), 0); // X0 OFF
    p.set("X0", "1").scans(3);
    assert_eq!(p.int("D0"), 1); // one rising edge in three ON scans
    p.set("X0", "0").scan();
    assert_eq!(p.int("D0"), 1);
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 2); // second rising edge
}

// ---------------------------------------------------------------- conversion

#[test]
fn flt_and_dflt() {
    let mut p = Plc::new(
        "LD SM400\n\
         FLT K-5 D0\n\
         FLT D10 D2\n\
         DFLT K100000 D4\n\
         DFLT D12 D6\n\
         END\n",
    );
    p.set("D10", "-32768").set("D12:i32", "-2147483648").scan();
    assert_running(&p);
    assert_eq!(p.real("D0"), -5.0);
    assert_eq!(p.real("D2"), -32768.0);
    // 100000 < 2²⁴: exact in single precision.
    assert_eq!(p.real("D4"), 100000.0);
    // −2³¹ is a power of two: exact.
    assert_eq!(p.real("D6"), -2147483648.0);
    // −5.0 = −1.25·2²: exponent 129 = 81H → C0A00000H.
    assert_eq!(p.int("D0:u32"), 0xC0A0_0000);
}

#[test]
fn int_rounds_half_away_from_zero() {
    let mut p = Plc::new(
        "LD SM400\n\
         INT E2.5 D0\n\
         INT E-2.5 D1\n\
         INT E1.4 D2\n\
         INT E1.5 D3\n\
         INT E-1.6 D4\n\
         INT E32767.0 D5\n\
         INT E-32768.0 D6\n\
         INT E-0.4 D7\n\
         DINT E100000.5 D10\n\
         DINT E-100000.5 D12\n\
         DINT E-2.1+9 D14\n\
         END\n",
    );
    p.set("D7", "99").scan();
    assert_running(&p);
    // 2.5 → 3, −2.5 → −3 (away from zero), 1.4 → 1, 1.5 → 2, −1.6 → −2,
    // the limits 32767 and −32768 as they are, −0.4 → 0.
    assert_eq!(p.int("D0"), 3);
    assert_eq!(p.int("D1"), -3);
    assert_eq!(p.int("D2"), 1);
    assert_eq!(p.int("D3"), 2);
    assert_eq!(p.int("D4"), -2);
    assert_eq!(p.int("D5"), 32767);
    assert_eq!(p.int("D6"), -32768);
    assert_eq!(p.int("D7"), 0);
    // 100000.5 needs 18 significant bits: exact in single; rounds to 100001.
    assert_eq!(p.int("D10:i32"), 100001);
    assert_eq!(p.int("D12:i32"), -100001);
    // −2.1·10⁹ lies between −2³¹ and −2³⁰ where singles are spaced 2⁷ = 128;
    // 2100000000 = 16406250·128 with 16406250 < 2²⁴, so it is exact and fits.
    assert_eq!(p.int("D14:i32"), -2_100_000_000);
}

#[test]
fn int_out_of_range_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nINT E40000.0 D0\nEND\n");
    // 40000 > 32767.
    p.set("D0", "5").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0"), 5);
}

#[test]
fn dint_out_of_range_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nDINT E1.0+10 D0\nEND\n");
    // 10¹⁰ > 2147483647.
    p.scan();
    assert_stopped(&p, 4100);
}

#[test]
fn int_of_infinite_source_stops_with_4100() {
    let mut p = Plc::new("LD SM400\nINT D0 D10\nEND\n");
    // FF800000H = −∞.
    p.set("D0:u32", "HFF800000").scan();
    assert_stopped(&p, 4100);
}
