//! Golden tests of the data conversion instructions (PM §6.3: BCD, DBCD, BIN,
//! DBIN, GRY, DGRY, GBIN, DGBIN, DBL, WORD, NEG, DNEG, ENEG, BKBCD, BKBIN) and
//! of RAD/DEG (PM §7.12). Every expected value is worked out by hand in the
//! comment next to it; BCD values are written as hex literals (one decimal digit
//! per nibble) so that the digits can be read off directly.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};
use softplc_core::engine::{CpuConfig, CpuState, ErrorMode};

/// A CPU that skips a failing instruction instead of stopping.
fn continue_mode(src: &str) -> Plc {
    let cfg = CpuConfig {
        operation_error: ErrorMode::Continue,
        ..softplc_core::profile::default_config()
    };
    Plc::with_config(src, cfg)
}

// ---------------------------------------------------------------- BCD / DBCD

#[test]
fn bcd_converts_bin_to_four_bcd_digits() {
    let mut p = Plc::new(
        "LD SM400\n\
         BCD K1234 D0\n\
         BCD K9999 D1\n\
         BCD K0 D2\n\
         BCD D10 D3\n\
         END\n",
    );
    p.set("D2", "77").set("D10", "705").scan();
    assert_running(&p);
    // 1234 → digits 1,2,3,4 → 1234H.
    assert_eq!(p.int("D0:u16"), 0x1234);
    // 9999 → 9999H = 39321 unsigned (−26215 signed).
    assert_eq!(p.int("D1:u16"), 0x9999);
    assert_eq!(p.int("D1"), -26215);
    // 0 → 0000H (the 77 written before is overwritten).
    assert_eq!(p.int("D2"), 0);
    // 705 → 0705H = 1797.
    assert_eq!(p.int("D3"), 0x0705);
}

#[test]
fn bcd_digit_destination_keeps_low_digits() {
    let mut p = Plc::new("LD SM400\nBCD K567 K2Y0\nEND\n");
    p.set("Y8", "1").scan();
    assert_running(&p);
    // 567 → 0567H; K2Y0 = Y0-Y7 takes the low 2 digits 67H = 103.
    assert_eq!(p.int("K2Y0"), 0x67);
    // Y8 is outside K2Y0 and keeps its ON state.
    assert!(p.bit("Y8"));
}

#[test]
fn bcd_above_9999_is_4100() {
    let mut p = Plc::new("LD SM400\nBCD K10000 D0\nEND\n");
    p.set("D0", "5").scan();
    // 10000 needs 5 digits: OPERATION ERROR, D0 keeps 5.
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0"), 5);
}

#[test]
fn bcd_of_negative_value_is_4100() {
    let mut p = Plc::new("LD SM400\nBCD D10 D0\nEND\n");
    p.set("D10", "-1").scan();
    // −1 is outside 0-9999.
    assert_stopped(&p, 4100);
}

#[test]
fn dbcd_converts_to_eight_digits() {
    let mut p = Plc::new(
        "LD SM400\n\
         DBCD K12345678 D0\n\
         DBCD K99999999 D2\n\
         DBCD K10000 K8M0\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    // 12345678 → 12345678H: lower 4 digits in D0, upper 4 in D1.
    assert_eq!(p.int("D0:u16"), 0x5678);
    assert_eq!(p.int("D1:u16"), 0x1234);
    assert_eq!(p.int("D0:u32"), 0x1234_5678);
    // 99999999 → 99999999H.
    assert_eq!(p.int("D2:u32"), 0x9999_9999);
    // 10000 → 00010000H into M0-M31: only M16 ON.
    assert_eq!(p.int("K8M0:u32"), 0x0001_0000);
    assert!(p.bit("M16"));
    assert!(!p.bit("M0"));
}

#[test]
fn dbcd_above_99999999_is_4100() {
    let mut p = Plc::new("LD SM400\nDBCD K100000000 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD SM400\nDBCD D10 D0\nEND\n");
    p.set("D10:i32", "-5").scan();
    assert_stopped(&p, 4100);
}

// ---------------------------------------------------------------- BIN / DBIN

#[test]
fn bin_converts_bcd_to_bin() {
    let mut p = Plc::new(
        "LD SM400\n\
         BIN H1234 D0\n\
         BIN H9999 D1\n\
         BIN D10 D2\n\
         BIN K2M0 D3\n\
         END\n",
    );
    // D10 = 0705H; K2M0 = M0-M7 = 45H (M16 ON, outside K2M0, is ignored).
    p.set("D10", "0x0705")
        .set("K2M0", "0x45")
        .set("M16", "1")
        .scan();
    assert_running(&p);
    // 1234H → 1234.
    assert_eq!(p.int("D0"), 1234);
    // 9999H → 9999.
    assert_eq!(p.int("D1"), 9999);
    // 0705H → 705.
    assert_eq!(p.int("D2"), 705);
    // 45H → 45.
    assert_eq!(p.int("D3"), 45);
}

#[test]
fn bin_invalid_digit_is_4100() {
    // 12A4H: the tens digit A is not a decimal digit.
    let mut p = Plc::new("LD SM400\nBIN H12A4 D0\nEND\n");
    p.set("D0", "3").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0"), 3);
    // F000H: the thousands digit F (what a negative BIN value looks like).
    let mut p = Plc::new("LD SM400\nBIN D10 D0\nEND\n");
    p.set("D10", "0xF000").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn dbin_converts_eight_digits() {
    let mut p = Plc::new(
        "LD SM400\n\
         DBIN D10 D0\n\
         DBIN H99999999 D2\n\
         DBIN K4M0 D4\n\
         END\n",
    );
    // D10,D11 = 12345678H; K4M0 = 9876H.
    p.set("D10:u32", "0x12345678").set("K4M0", "0x9876").scan();
    assert_running(&p);
    assert_eq!(p.int("D0:i32"), 12_345_678);
    assert_eq!(p.int("D2:i32"), 99_999_999);
    // A 4-digit source is read as 00009876H → 9876.
    assert_eq!(p.int("D4:i32"), 9876);
}

#[test]
fn dbin_invalid_digit_is_4100() {
    // Upper word A000H: the ten-millions digit is A.
    let mut p = Plc::new("LD SM400\nDBIN D10 D0\nEND\n");
    p.set("D10:u32", "0xA0000000").scan();
    assert_stopped(&p, 4100);
    // Lowest digit B.
    let mut p = Plc::new("LD SM400\nDBIN D10 D0\nEND\n");
    p.set("D10:u32", "0x1234567B").scan();
    assert_stopped(&p, 4100);
}

// ---------------------------------------------------------------- Gray code

#[test]
fn gry_and_gbin_16_bits() {
    let mut p = Plc::new(
        "LD SM400\n\
         GRY K1234 D0\n\
         GBIN D0 D1\n\
         GRY K32767 D2\n\
         GRY K0 D3\n\
         GBIN H4000 D4\n\
         END\n",
    );
    p.set("D3", "9").scan();
    assert_running(&p);
    // 1234 = 0000 0100 1101 0010, 1234 >> 1 = 0000 0010 0110 1001;
    // XOR = 0000 0110 1011 1011 = 06BBH = 1723 (the manual's example).
    assert_eq!(p.int("D0"), 0x06BB);
    // And back.
    assert_eq!(p.int("D1"), 1234);
    // 7FFFH ^ 3FFFH = 4000H.
    assert_eq!(p.int("D2"), 0x4000);
    assert_eq!(p.int("D3"), 0);
    // Gray 4000H: b14 = 1, every lower bit = b14 XOR 0 … = 1 → 7FFFH = 32767.
    assert_eq!(p.int("D4"), 32767);
}

#[test]
fn gry_of_negative_is_4100() {
    let mut p = Plc::new("LD SM400\nGRY K-1 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
}

#[test]
fn gbin_of_negative_is_4100() {
    let mut p = Plc::new("LD SM400\nGBIN H8000 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
}

#[test]
fn dgry_and_dgbin_32_bits() {
    let mut p = Plc::new(
        "LD SM400\n\
         DGRY K305419896 D0\n\
         DGBIN D0 D2\n\
         DGRY K65536 D4\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    // 305419896 = 12345678H; >> 1 = 091A2B3CH; XOR nibble by nibble:
    // 1^0=1 2^9=B 3^1=2 4^A=E 5^2=7 6^B=D 7^3=4 8^C=4 → 1B2E7D44H (manual example).
    assert_eq!(p.int("D0:u32"), 0x1B2E_7D44);
    assert_eq!(p.int("D2:i32"), 305_419_896);
    // 65536 = 10000H ^ 8000H = 18000H: the Gray code crosses into the upper word.
    assert_eq!(p.int("D4:u32"), 0x0001_8000);
}

#[test]
fn dgry_and_dgbin_of_negative_are_4100() {
    let mut p = Plc::new("LD SM400\nDGRY K-2147483648 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD SM400\nDGBIN H80000000 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
}

// ---------------------------------------------------------------- NEG / DNEG / ENEG

#[test]
fn neg_inverts_sign_every_scan() {
    let mut p = Plc::new("LD SM400\nNEG D0\nNEG D1\nNEG D2\nEND\n");
    p.set("D0", "5").set("D1", "-32768").set("D2", "0").scan();
    assert_running(&p);
    // 5 → −5 (FFFBH).
    assert_eq!(p.int("D0"), -5);
    // −32768 has no positive counterpart: 8000H stays 8000H, no error.
    assert_eq!(p.int("D1"), -32768);
    assert_eq!(p.int("D2"), 0);
    // NEG is executed every scan: −5 → 5.
    p.scan();
    assert_eq!(p.int("D0"), 5);
}

#[test]
fn negp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nNEGP D0\nEND\n");
    p.set("D0", "7").set("X0", "1").scan();
    assert_eq!(p.int("D0"), -7);
    // X0 still ON: no second inversion.
    p.scan();
    assert_eq!(p.int("D0"), -7);
    // OFF, then ON again: inverted once more.
    p.set("X0", "0").scan();
    assert_eq!(p.int("D0"), -7);
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 7);
}

#[test]
fn neg_of_digit_specified_device() {
    let mut p = Plc::new("LD SM400\nNEGP K1M0\nEND\n");
    // K1M0 = 3 (M0, M1 ON); read as 0003H, −3 = FFFDH, low digit DH = 13 written back.
    p.set("K1M0", "3").set("M4", "1").scan();
    assert_eq!(p.int("K1M0"), 13);
    // M4 is outside K1M0 and keeps its state.
    assert!(p.bit("M4"));
}

#[test]
fn dneg_inverts_32_bits() {
    let mut p = Plc::new("LD SM400\nDNEGP D0\nDNEGP D2\nEND\n");
    p.set("D0:i32", "218460")
        .set("D2:i32", "-2147483648")
        .scan();
    assert_running(&p);
    // The manual's example: 218460 → −218460.
    assert_eq!(p.int("D0:i32"), -218_460);
    // 80000000H stays, no error.
    assert_eq!(p.int("D2:i32"), -2_147_483_648);
}

#[test]
fn eneg_inverts_real_sign() {
    let mut p = Plc::new("LD SM400\nENEGP D0\nENEGP D2\nENEGP D4\nEND\n");
    p.set("D0:f32", "1.5")
        .set("D2:f32", "-0.25")
        .set("D4:u32", "0")
        .scan();
    assert_running(&p);
    assert_eq!(p.real("D0"), -1.5);
    assert_eq!(p.real("D2"), 0.25);
    // 0 stays +0: all bits 0 (no −0 = 80000000H).
    assert_eq!(p.int("D4:u32"), 0);
}

#[test]
fn eneg_of_nan_is_4100() {
    let mut p = Plc::new("LD SM400\nENEG D0\nEND\n");
    // 7FC00000H is a NaN: not a real number for the CPU.
    p.set("D0:u32", "0x7FC00000").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0:u32"), 0x7FC0_0000);
}

// ---------------------------------------------------------------- DBL / WORD

#[test]
fn dbl_sign_extends() {
    let mut p = Plc::new(
        "LD SM400\n\
         DBL K-2 D0\n\
         DBL K32767 D2\n\
         DBL K4M0 D4\n\
         DBL K2M0 D6\n\
         END\n",
    );
    p.set("D3", "99").set("K4M0", "0x8080").scan();
    assert_running(&p);
    // −2 = FFFEH → FFFFFFFEH: D1 = FFFFH.
    assert_eq!(p.int("D0:i32"), -2);
    assert_eq!(p.int("D1:u16"), 0xFFFF);
    // 32767 → 00007FFFH: D3 overwritten with 0.
    assert_eq!(p.int("D2:i32"), 32767);
    assert_eq!(p.int("D3"), 0);
    // K4M0 = 8080H is −32640 → FFFF8080H.
    assert_eq!(p.int("D4:i32"), -32640);
    // K2M0 = 80H (2 digits, positive) → 128.
    assert_eq!(p.int("D6:i32"), 128);
}

#[test]
fn word_narrows_in_range() {
    let mut p = Plc::new(
        "LD SM400\n\
         WORD K-32768 D0\n\
         WORD K32767 D1\n\
         WORD D10 D2\n\
         END\n",
    );
    p.set("D10:i32", "-100").scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), -32768);
    assert_eq!(p.int("D1"), 32767);
    assert_eq!(p.int("D2"), -100);
}

#[test]
fn word_out_of_range_is_4100() {
    let mut p = Plc::new("LD SM400\nWORD K32768 D0\nEND\n");
    p.scan();
    // 32768 does not fit 16 bits signed.
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD SM400\nWORD D10 D0\nEND\n");
    // 65536 = 10000H: its low word 0 would fit, the value does not.
    p.set("D10:i32", "65536").scan();
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD SM400\nWORD K-32769 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
}

// ---------------------------------------------------------------- RAD / DEG

#[test]
fn rad_and_deg() {
    let mut p = Plc::new(
        "LD SM400\n\
         RAD E180 D0\n\
         RAD E-90 D2\n\
         DEG E1.0 D4\n\
         DEG D0 D6\n\
         RAD E0 D8\n\
         END\n",
    );
    p.set("D8:f32", "5").scan();
    assert_running(&p);
    // 180 × π/180 = π = 3.14159265…; single precision is within 1e-6.
    assert!((p.real("D0") - std::f64::consts::PI).abs() < 1e-6);
    // −90° = −π/2 = −1.57079633….
    assert!((p.real("D2") + std::f64::consts::FRAC_PI_2).abs() < 1e-6);
    // 1 rad = 180/π = 57.2957795…°.
    assert!((p.real("D4") - 57.295_779_5).abs() < 1e-5);
    // π (as stored) back to degrees: 180 within single precision.
    assert!((p.real("D6") - 180.0).abs() < 1e-4);
    assert_eq!(p.real("D8"), 0.0);
}

#[test]
fn deg_overflow_is_4100() {
    // 3.0E38 rad × 57.3 = 1.7E40, beyond the single-precision maximum 3.4E38.
    let mut p = Plc::new("LD SM400\nDEG E3.0+38 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
}

#[test]
fn rad_of_infinity_is_4100() {
    let mut p = Plc::new("LD SM400\nRAD D10 D0\nEND\n");
    // 7F800000H = +∞.
    p.set("D10:u32", "0x7F800000").scan();
    assert_stopped(&p, 4100);
}

// ---------------------------------------------------------------- BKBCD / BKBIN

#[test]
fn bkbcd_converts_a_block() {
    let mut p = Plc::new("LD SM400\nBKBCD D0 D10 K3\nEND\n");
    p.set("D0", "1")
        .set("D1", "99")
        .set("D2", "9999")
        .set("D13", "55")
        .scan();
    assert_running(&p);
    // 1 → 0001H, 99 → 0099H, 9999 → 9999H.
    assert_eq!(p.int("D10"), 0x0001);
    assert_eq!(p.int("D11"), 0x0099);
    assert_eq!(p.int("D12:u16"), 0x9999);
    // Only 3 words: D13 untouched.
    assert_eq!(p.int("D13"), 55);
}

#[test]
fn bkbcd_count_from_device_and_zero() {
    let mut p = Plc::new("LD SM400\nBKBCD D0 D10 D100\nEND\n");
    p.set("D0", "12")
        .set("D1", "34")
        .set("D10", "77")
        .set("D11", "88");
    // n = 0: nothing is converted.
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 77);
    assert_eq!(p.int("D11"), 88);
    // n = 1: only D10 (12 → 0012H = 18).
    p.set("D100", "1").scan();
    assert_eq!(p.int("D10"), 0x12);
    assert_eq!(p.int("D11"), 88);
}

#[test]
fn bkbcd_invalid_word_writes_nothing() {
    let mut p = continue_mode("LD SM400\nBKBCD D0 D10 K3\nLD SM400\nMOV K1 D20\nEND\n");
    // D1 = 10000 is beyond 4 digits.
    p.set("D0", "5")
        .set("D1", "10000")
        .set("D2", "6")
        .set("D10", "-1")
        .scan();
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("SD0"), 4100);
    // Every word is checked first: even D10 (from the valid D0) is unchanged.
    assert_eq!(p.int("D10"), -1);
    // The next instruction ran.
    assert_eq!(p.int("D20"), 1);
}

#[test]
fn bkbcd_negative_word_is_4100() {
    let mut p = Plc::new("LD SM400\nBKBCD D0 D10 K2\nEND\n");
    p.set("D1", "-1").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn bkbcd_past_device_end_is_4101() {
    // D12280 + 10 words = D12280-D12289, beyond D12287 (12288 points).
    let mut p = Plc::new("LD SM400\nBKBCD D12280 D0 K10\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    // Destination past the end: D12285-D12287 fit, D12288 does not (n = 4).
    let mut p = Plc::new("LD SM400\nBKBCD D0 D12285 K4\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    // Exactly up to the last point is fine: D12285-D12287 (n = 3).
    let mut p = Plc::new("LD SM400\nBKBCD D0 D12285 K3\nEND\n");
    p.set("D2", "10").scan();
    assert_running(&p);
    assert_eq!(p.int("D12287"), 0x10);
}

#[test]
fn bkbcd_negative_count_is_4101() {
    // K-1 is taken as 65535 words: D0-D65534 is past D12287.
    let mut p = Plc::new("LD SM400\nBKBCD D0 D100 K-1\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bkbcd_overlapping_blocks() {
    // D1-D3 ← BCD of D0-D2, as if D0-D2 were all read first.
    let mut p = Plc::new("LD SM400\nBKBCDP D0 D1 K3\nEND\n");
    p.set("D0", "12").set("D1", "34").set("D2", "56").scan();
    assert_running(&p);
    // 12 → 0012H = 18, 34 → 0034H = 52, 56 → 0056H = 86. (Word by word from
    // D0 would convert D1 after it became 18, giving 0018H = 24.)
    assert_eq!(p.int("D0"), 12);
    assert_eq!(p.int("D1"), 0x12);
    assert_eq!(p.int("D2"), 0x34);
    assert_eq!(p.int("D3"), 0x56);
}

#[test]
fn bkbcd_with_index_modification() {
    let mut p = Plc::new("LD SM400\nBKBCD D0Z0 D10Z1 K2\nEND\n");
    // Z0 = 4 → source D4, D5; Z1 = −2 → destination D8, D9.
    p.set("Z0", "4")
        .set("Z1", "-2")
        .set("D4", "1000")
        .set("D5", "2048")
        .scan();
    assert_running(&p);
    assert_eq!(p.int("D8"), 0x1000);
    assert_eq!(p.int("D9"), 0x2048);
    // D10 (the unmodified destination) untouched.
    assert_eq!(p.int("D10"), 0);
}

#[test]
fn bkbcd_index_past_end_is_4101() {
    // Z0 = 12287 → D12287 + 2 words is past the end.
    let mut p = Plc::new("LD SM400\nBKBCD D0Z0 D100 K2\nEND\n");
    p.set("Z0", "12287").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bkbin_converts_a_block() {
    let mut p = Plc::new("LD SM400\nBKBIN W0 D10 K3\nEND\n");
    p.set("W0", "0x1234")
        .set("W1", "0x9999")
        .set("W2", "0")
        .set("D12", "4");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 1234);
    assert_eq!(p.int("D11"), 9999);
    assert_eq!(p.int("D12"), 0);
}

#[test]
fn bkbin_invalid_digit_is_4100() {
    let mut p = Plc::new("LD SM400\nBKBIN D0 D10 K3\nEND\n");
    // D2 = 12A4H has the digit A.
    p.set("D0", "0x11")
        .set("D2", "0x12A4")
        .set("D10", "3")
        .scan();
    assert_stopped(&p, 4100);
    // Nothing written: D10 keeps 3 although D0 was valid.
    assert_eq!(p.int("D10"), 3);
}

#[test]
fn bkbin_past_device_end_is_4101() {
    // W has 8192 points (W0-W1FFF): W1FFF + 2 words is past the end.
    let mut p = Plc::new("LD SM400\nBKBIN W1FFF D0 K2\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bkbinp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nBKBINP D0 D10 K1\nEND\n");
    p.set("D0", "0x42").set("X0", "1").scan();
    assert_eq!(p.int("D10"), 42);
    // Still ON: D0 changes, D10 does not follow.
    p.set("D0", "0x43").scan();
    assert_eq!(p.int("D10"), 42);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D10"), 43);
}

// ---------------------------------------------------------------- pulse forms

#[test]
fn bcdp_runs_once_per_rising_edge_bcd_every_scan() {
    let mut p = Plc::new("LD X0\nBCDP D0 D1\nLD X0\nBCD D0 D2\nEND\n");
    p.set("D0", "12").set("X0", "1").scan();
    assert_eq!(p.int("D1"), 0x12);
    assert_eq!(p.int("D2"), 0x12);
    // Still ON: BCDP does not run again, BCD does.
    p.set("D0", "34").scan();
    assert_eq!(p.int("D1"), 0x12);
    assert_eq!(p.int("D2"), 0x34);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D1"), 0x34);
}

#[test]
fn condition_off_does_nothing() {
    let mut p = Plc::new("LD X0\nBIN H12A4 D0\nLD X0\nWORD K99999 D1\nEND\n");
    // Both would fail, but X0 is OFF: no error, nothing written.
    p.set("D0", "8").scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), 8);
}

#[test]
fn dbinp_and_dbcdp_pulse_forms_exist() {
    let mut p = Plc::new(
        "LD X0\nDBINP D0 D10\nDBCDP D10 D20\nGRYP K3 D30\nGBINP K2 D31\nDGRYP K3 D32\nDGBINP K2 D34\nDBLP K-1 D36\nWORDP K-1 D38\nRADP E0 D40\nDEGP E0 D42\nEND\n",
    );
    p.set("D0:u32", "0x87654321").set("X0", "1").scan();
    assert_running(&p);
    assert_eq!(p.int("D10:i32"), 87_654_321);
    // And back to BCD.
    assert_eq!(p.int("D20:u32"), 0x8765_4321);
    // 3 = 11b → 11b ^ 01b = 10b = 2; Gray 2 = 10b → 11b = 3.
    assert_eq!(p.int("D30"), 2);
    assert_eq!(p.int("D31"), 3);
    assert_eq!(p.int("D32:i32"), 2);
    assert_eq!(p.int("D34:i32"), 3);
    assert_eq!(p.int("D36:i32"), -1);
    assert_eq!(p.int("D38"), -1);
}

// ---------------------------------------------------------------- load errors

#[test]
fn load_errors() {
    // Operand counts.
    let d = diagnostics("LD X0\nBCD K1 D0 D1\nEND\n");
    assert!(d[0].contains("`BCD` takes 2 operands"), "{d:?}");
    let d = diagnostics("LD X0\nNEG D0 D1\nEND\n");
    assert!(d[0].contains("`NEG` takes 1 operand"), "{d:?}");
    let d = diagnostics("LD X0\nBKBCDP D0 D1\nEND\n");
    assert!(d[0].contains("`BKBCDP` takes 3 operands"), "{d:?}");
    // A constant destination.
    let d = diagnostics("LD X0\nBIN K1 K2\nEND\n");
    assert!(
        d[0].starts_with("2:8:") && d[0].contains("destination"),
        "{d:?}"
    );
    // A block must be a word device: no digit specification.
    let d = diagnostics("LD X0\nBKBIN K4M0 D0 K1\nEND\n");
    assert!(
        d[0].starts_with("2:7:") && d[0].contains("word device"),
        "{d:?}"
    );
    // K5 on a 16-bit destination.
    let d = diagnostics("LD X0\nBCD K1 K5Y0\nEND\n");
    assert!(d[0].contains("K1-K4"), "{d:?}");
    // A real operand needs an E constant.
    let d = diagnostics("LD X0\nRAD K1 D0\nEND\n");
    assert!(d[0].contains("E constant"), "{d:?}");
    // D+1 of a 32-bit destination past the end.
    let d = diagnostics("LD X0\nDBL K1 D12287\nEND\n");
    assert!(d[0].contains("beyond the last device"), "{d:?}");
    // NEG needs a device.
    let d = diagnostics("LD X0\nNEG K1\nEND\n");
    assert!(d[0].contains("destination"), "{d:?}");
}
