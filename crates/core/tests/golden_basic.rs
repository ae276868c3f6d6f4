//! Golden tests of the basic instructions (transfer, BIN and real arithmetic,
//! conversion, comparison contacts, index modification). Every expected value is
//! worked out by hand in the comment next to it (004 §2.8 numeric formats,
//! programming manual ch. 6).

mod common;
use common::{assert_running, assert_stopped, Plc};
use softplc_core::engine::CpuState;

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
