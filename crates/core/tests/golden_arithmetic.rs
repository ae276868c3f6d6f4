//! Golden tests of the BCD arithmetic instructions (PM §6.2.5-6.2.8: B+, B-,
//! B*, B/, DB+, DB-, DB*, DB/) and of the BIN block addition/subtraction (PM
//! §6.2.11: BK+, BK-). Every expected value is worked out by hand in the comment
//! next to it; BCD values are written as hex literals (one decimal digit per
//! nibble) so that the digits can be read off directly.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};
use softplc_core::engine::{CpuConfig, CpuState, ErrorMode};

// ---------------------------------------------------------------- B+ / B-

#[test]
fn b_add_two_and_three_operands() {
    let mut p = Plc::new(
        "LD SM400\n\
         B+ H1234 D0\n\
         B+ H1 D1\n\
         B+ H1234 H5678 D2\n\
         B+ D10 D11 D3\n\
         END\n",
    );
    p.set("D0", "0x4321")
        .set("D1", "0x9999")
        .set("D10", "0x9999")
        .set("D11", "0x0002")
        .scan();
    assert_running(&p);
    // Two operands, D + S → D: 4321 + 1234 = 5555.
    assert_eq!(p.int("D0"), 0x5555);
    // 9999 + 1 = 10000: the fifth digit is dropped → 0000.
    assert_eq!(p.int("D1"), 0);
    // Three operands: 1234 + 5678 = 6912.
    assert_eq!(p.int("D2"), 0x6912);
    // 9999 + 2 = 10001 → 0001.
    assert_eq!(p.int("D3"), 0x0001);
}

#[test]
fn b_add_runs_every_scan() {
    let mut p = Plc::new("LD SM400\nB+ H9 D0\nEND\n");
    // 0 + 9 = 9, then 9 + 9 = 18 (0018H, decimal carry), then 27.
    p.scan();
    assert_eq!(p.int("D0"), 0x09);
    p.scan();
    assert_eq!(p.int("D0"), 0x18);
    p.scan();
    assert_eq!(p.int("D0"), 0x27);
}

#[test]
fn b_sub_and_ten_complement_underflow() {
    let mut p = Plc::new(
        "LD SM400\n\
         B- H1234 D0\n\
         B- H5678 H1234 D1\n\
         B- H0 H1 D2\n\
         B- H1234 H5678 D3\n\
         END\n",
    );
    p.set("D0", "0x5678").scan();
    assert_running(&p);
    // Two operands, D − S → D: 5678 − 1234 = 4444.
    assert_eq!(p.int("D0"), 0x4444);
    // 5678 − 1234 = 4444.
    assert_eq!(p.int("D1"), 0x4444);
    // 0 − 1 = −1 → 10000 − 1 = 9999 (no carry flag).
    assert_eq!(p.int("D2:u16"), 0x9999);
    // 1234 − 5678 = −4444 → 10000 − 4444 = 5556.
    assert_eq!(p.int("D3"), 0x5556);
}

#[test]
fn b_add_digit_specified_operands() {
    let mut p = Plc::new("LD SM400\nB+ K2M0 H1 K2Y0\nB+ K1M8 H5 K3Y10\nEND\n");
    // K2M0 = M0-M7 = 99H; K1M8 = M8-M11 = 7.
    p.set("K2M0", "0x99").set("K1M8", "7").set("Y8", "1").scan();
    assert_running(&p);
    // 99 + 1 = 100 = 0100H; K2Y0 keeps the low 2 digits → 00.
    assert_eq!(p.int("K2Y0"), 0);
    // Y8 is outside K2Y0: untouched.
    assert!(p.bit("Y8"));
    // 7 + 5 = 12 → 012H in K3Y10 (Y10-Y1B).
    assert_eq!(p.int("K3Y10"), 0x012);
}

#[test]
fn b_add_invalid_bcd_is_4100() {
    // S = 000AH.
    let mut p = Plc::new("LD SM400\nB+ HA D0\nEND\n");
    p.set("D0", "0x12").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0"), 0x12);
}

#[test]
fn b_add_invalid_destination_value_is_4100() {
    // Two-operand form: D is also a source; F0H is not BCD.
    let mut p = Plc::new("LD SM400\nB+ H1 D0\nEND\n");
    p.set("D0", "0xF0").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0"), 0xF0);
}

#[test]
fn b_sub_invalid_bcd_is_4100() {
    let mut p = Plc::new("LD SM400\nB- D10 D11 D0\nEND\n");
    // D11 = 1B00H: the hundreds digit B.
    p.set("D10", "0x5000").set("D11", "0x1B00").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn b_addp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nB+P H1 D0\nEND\n");
    p.set("D0", "0x09").set("X0", "1").scan();
    // 9 + 1 = 10 → 0010H.
    assert_eq!(p.int("D0"), 0x10);
    // Still ON: no second addition.
    p.scan();
    assert_eq!(p.int("D0"), 0x10);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 0x11);
}

// ---------------------------------------------------------------- DB+ / DB-

#[test]
fn db_add_and_sub() {
    let mut p = Plc::new(
        "LD SM400\n\
         DB+ H12345678 H87654321 D0\n\
         DB+ H1 D2\n\
         DB+ H10234567 H65789123 D4\n\
         DB- H21345679 H21345678 D6\n\
         DB- H21345678 H21345679 D8\n\
         DB- H1 D10\n\
         DB+ K4M0 H1 D12\n\
         END\n",
    );
    p.set("D2:u32", "0x99999999")
        .set("D10:u32", "0x00010000")
        .set("K4M0", "0x9999")
        .scan();
    assert_running(&p);
    // 12345678 + 87654321 = 99999999.
    assert_eq!(p.int("D0:u32"), 0x9999_9999);
    // 99999999 + 1 = 100000000: the ninth digit is dropped → 0.
    assert_eq!(p.int("D2:u32"), 0);
    // 10234567 + 65789123 = 76023690 (lower digits in D4, upper in D5).
    assert_eq!(p.int("D4:u16"), 0x3690);
    assert_eq!(p.int("D5:u16"), 0x7602);
    // 21345679 − 21345678 = 1.
    assert_eq!(p.int("D6:u32"), 1);
    // 21345678 − 21345679 = −1 → 99999999 (the manual's example).
    assert_eq!(p.int("D8:u32"), 0x9999_9999);
    // Two operands: 10000 − 1 = 9999; the borrow crosses into D11.
    assert_eq!(p.int("D10:u32"), 0x0000_9999);
    // K4M0 is read as 4 digits 9999; + 1 = 10000 → 00010000H.
    assert_eq!(p.int("D12:u32"), 0x0001_0000);
}

#[test]
fn db_add_invalid_upper_digit_is_4100() {
    let mut p = Plc::new("LD SM400\nDB+ D10 H1 D0\nEND\n");
    // D11 = A000H: the ten-millions digit is A.
    p.set("D10:u32", "0xA0000000").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0:u32"), 0);
}

#[test]
fn db_sub_digit_destination() {
    let mut p = Plc::new("LD SM400\nDB- H1000000 H1 K5M0\nEND\n");
    p.set("M20", "1").scan();
    assert_running(&p);
    // 1000000 − 1 = 999999 = 00999999H; K5M0 (M0-M19) keeps 5 digits: 99999H.
    assert_eq!(p.int("K5M0:u32"), 0x99999);
    // M20 is outside K5M0: untouched.
    assert!(p.bit("M20"));
}

// ---------------------------------------------------------------- B* / DB*

#[test]
fn b_mul_eight_digit_product() {
    let mut p = Plc::new(
        "LD SM400\n\
         B* H1234 H5678 D0\n\
         B* H9999 H9999 D2\n\
         B* D10 H0 D4\n\
         B* H1234 H5678 K8M0\n\
         END\n",
    );
    p.set("D10", "0x4321").set("D4:u32", "0x55555555").scan();
    assert_running(&p);
    // 1234 × 5678 = 1234 × 5000 + 1234 × 678 = 6170000 + 836652 = 7006652
    // → 07006652H: lower 4 digits in D0, upper 4 in D1.
    assert_eq!(p.int("D0:u16"), 0x6652);
    assert_eq!(p.int("D1:u16"), 0x0700);
    // 9999 × 9999 = 99980001.
    assert_eq!(p.int("D2:u16"), 0x0001);
    assert_eq!(p.int("D3:u16"), 0x9998);
    // × 0 = 0 in both words.
    assert_eq!(p.int("D4:u32"), 0);
    // A digit-specified destination takes the product in K8M0 (M0-M31).
    assert_eq!(p.int("K8M0:u32"), 0x0700_6652);
}

#[test]
fn b_mul_invalid_bcd_is_4100() {
    let mut p = Plc::new("LD SM400\nB* H1C H2 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
}

#[test]
fn db_mul_sixteen_digit_product() {
    let mut p = Plc::new(
        "LD SM400\n\
         DB* H12345678 H100 D0\n\
         DB* H99999999 H99999999 D10\n\
         DB* H12345678 H100 K8M0\n\
         END\n",
    );
    p.set("D3", "7").scan();
    assert_running(&p);
    // 12345678 × 100 = 1234567800 → 0000001234567800H over D0-D3, low first.
    assert_eq!(p.int("D0:u16"), 0x7800);
    assert_eq!(p.int("D1:u16"), 0x3456);
    assert_eq!(p.int("D2:u16"), 0x0012);
    assert_eq!(p.int("D3:u16"), 0x0000);
    // 99999999² = (10⁸ − 1)² = 10¹⁶ − 2·10⁸ + 1 = 9999999800000001.
    assert_eq!(p.int("D10:u32"), 0x0000_0001);
    assert_eq!(p.int("D12:u32"), 0x9999_9998);
    // K8M0 takes the lowest 8 digits: 34567800.
    assert_eq!(p.int("K8M0:u32"), 0x3456_7800);
}

// ---------------------------------------------------------------- B/ / DB/

#[test]
fn b_div_quotient_and_remainder() {
    let mut p = Plc::new(
        "LD SM400\n\
         B/ H5678 H1234 D0\n\
         B/ H9999 H1 D2\n\
         B/ H7 H9 D4\n\
         END\n",
    );
    p.set("D4", "0x55").scan();
    assert_running(&p);
    // 5678 / 1234 = 4, remainder 5678 − 4936 = 742.
    assert_eq!(p.int("D0"), 0x0004);
    assert_eq!(p.int("D1"), 0x0742);
    // 9999 / 1 = 9999, remainder 0.
    assert_eq!(p.int("D2:u16"), 0x9999);
    assert_eq!(p.int("D3"), 0);
    // 7 / 9 = 0, remainder 7.
    assert_eq!(p.int("D4"), 0);
    assert_eq!(p.int("D5"), 0x07);
}

#[test]
fn b_div_by_zero_is_4100() {
    let mut p = Plc::new("LD SM400\nB/ H1234 D10 D0\nEND\n");
    p.set("D0", "0x11").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0"), 0x11);
}

#[test]
fn b_div_digit_destination_gets_quotient_only() {
    let mut p = Plc::new("LD SM400\nB/ H100 H7 K4M0\nEND\n");
    p.set("M16", "1").scan();
    assert_running(&p);
    // 100 / 7 = 14 remainder 2: K4M0 = 0014H; the remainder is not stored, M16
    // (where it would start) keeps its ON state.
    assert_eq!(p.int("K4M0"), 0x14);
    assert!(p.bit("M16"));
    // K8M0 (M0-M31) gets the quotient as 8 digits, 00000014H: no remainder in
    // M16-M31 either.
    let mut p = Plc::new("LD SM400\nB/ H100 H7 K8M0\nEND\n");
    p.set("M16", "1").scan();
    assert_running(&p);
    assert_eq!(p.int("K8M0:u32"), 0x14);
}

#[test]
fn db_div_quotient_and_remainder() {
    let mut p = Plc::new(
        "LD SM400\n\
         DB/ H12345678 H1000 D0\n\
         DB/ H99999999 H99999999 D4\n\
         DB/ H12345678 H1000 K8M0\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    // 12345678 / 1000 = 12345, remainder 678.
    assert_eq!(p.int("D0:u32"), 0x0001_2345);
    assert_eq!(p.int("D2:u32"), 0x0000_0678);
    // x / x = 1, remainder 0.
    assert_eq!(p.int("D4:u32"), 1);
    assert_eq!(p.int("D6:u32"), 0);
    // Quotient only into K8M0.
    assert_eq!(p.int("K8M0:u32"), 0x0001_2345);
}

#[test]
fn db_div_by_zero_and_invalid_are_4100() {
    let mut p = Plc::new("LD SM400\nDB/ H1 H0 D0\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD SM400\nDB/ D10 H1 D0\nEND\n");
    p.set("D10:u32", "0x0000FFFF").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn db_mulp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nDB*P D0 H2 D0\nEND\n");
    // D0,D1 = 3 → × 2 = 6 into D0-D3 (D2, D3 = 0).
    p.set("D0:u32", "3").set("X0", "1").scan();
    assert_eq!(p.int("D0:u32"), 6);
    p.scan();
    assert_eq!(p.int("D0:u32"), 6);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    // 6 × 2 = 12 → 12H.
    assert_eq!(p.int("D0:u32"), 0x12);
}

// ---------------------------------------------------------------- BK+ / BK-

#[test]
fn bk_add_blocks_and_constant() {
    let mut p = Plc::new(
        "LD SM400\n\
         BK+ D0 D10 D20 K3\n\
         BK+ D0 K5 D30 K3\n\
         BK+ D0 H8000 D40 K1\n\
         END\n",
    );
    p.set("D0", "1")
        .set("D1", "2")
        .set("D2", "32767")
        .set("D10", "10")
        .set("D11", "20")
        .set("D12", "2")
        .set("D23", "99")
        .scan();
    assert_running(&p);
    // 1 + 10, 2 + 20, 32767 + 2 = 32769 − 65536 = −32767 (wraps, no flag).
    assert_eq!(p.int("D20"), 11);
    assert_eq!(p.int("D21"), 22);
    assert_eq!(p.int("D22"), -32767);
    // n = 3: D23 untouched.
    assert_eq!(p.int("D23"), 99);
    // Constant added to each word: 6, 7, 32772 − 65536 = −32764.
    assert_eq!(p.int("D30"), 6);
    assert_eq!(p.int("D31"), 7);
    assert_eq!(p.int("D32"), -32764);
    // H8000 = −32768: 1 + 8000H = 8001H = −32767.
    assert_eq!(p.int("D40"), -32767);
}

#[test]
fn bk_sub_blocks_and_constant() {
    let mut p = Plc::new(
        "LD SM400\n\
         BK- D0 D10 D20 K3\n\
         BK- D0 K-1 D30 K3\n\
         END\n",
    );
    p.set("D0", "1")
        .set("D1", "-32768")
        .set("D2", "100")
        .set("D10", "10")
        .set("D11", "1")
        .set("D12", "-100")
        .scan();
    assert_running(&p);
    // 1 − 10 = −9; −32768 − 1 = −32769 + 65536 = 32767 (wraps); 100 − (−100) = 200.
    assert_eq!(p.int("D20"), -9);
    assert_eq!(p.int("D21"), 32767);
    assert_eq!(p.int("D22"), 200);
    // − (−1) = + 1: 2, −32767, 101.
    assert_eq!(p.int("D30"), 2);
    assert_eq!(p.int("D31"), -32767);
    assert_eq!(p.int("D32"), 101);
}

#[test]
fn bk_add_count_from_device_zero_does_nothing() {
    let mut p = Plc::new("LD SM400\nBK+ D0 D10 D20 D100\nEND\n");
    p.set("D0", "4").set("D10", "5").set("D20", "-1");
    p.scan();
    assert_running(&p);
    // n = D100 = 0: D20 keeps −1.
    assert_eq!(p.int("D20"), -1);
    p.set("D100", "1").scan();
    assert_eq!(p.int("D20"), 9);
}

#[test]
fn bk_add_past_device_end_is_4101() {
    // S1 = D12286-D12288: D12288 does not exist (D0-D12287).
    let mut p = Plc::new("LD SM400\nBK+ D12286 D0 D100 K3\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    // S2 past the end.
    let mut p = Plc::new("LD SM400\nBK+ D0 D12286 D100 K3\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    // D past the end; nothing is written (D12286, D12287 stay 0).
    let mut p = Plc::new("LD SM400\nBK- D0 K1 D12286 K3\nEND\n");
    p.set("D0", "5").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12286"), 0);
    // Exactly up to the last point is fine: D12286, D12287.
    let mut p = Plc::new("LD SM400\nBK- D0 K1 D12286 K2\nEND\n");
    p.set("D0", "5").set("D1", "6").scan();
    assert_running(&p);
    assert_eq!(p.int("D12286"), 4);
    assert_eq!(p.int("D12287"), 5);
}

#[test]
fn bk_add_negative_count_is_4101() {
    // K-1 is taken as 65535 words, past D12287.
    let mut p = Plc::new("LD SM400\nBK+ D0 K1 D100 K-1\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bk_add_negative_count_fits_a_large_device() {
    // ZR has 517120 points: ZR0 + 65535 words fit, so K-1 adds to 65535 words.
    let mut p = Plc::new("LD SM400\nBK+ ZR0 K2 ZR100000 K-1\nEND\n");
    p.set("ZR65534", "40").scan();
    assert_running(&p);
    // ZR100000 = ZR0 + 2 = 2; ZR165534 = ZR65534 + 2 = 42; ZR165535 not written.
    assert_eq!(p.int("ZR100000"), 2);
    assert_eq!(p.int("ZR165534"), 42);
    assert_eq!(p.int("ZR165535"), 0);
}

#[test]
fn bk_add_with_index_modification() {
    let mut p = Plc::new("LD SM400\nBK+ D0Z0 D10Z0 D20Z1 K2\nEND\n");
    // Z0 = 2 → S1 = D2, D3 and S2 = D12, D13; Z1 = 10 → D = D30, D31.
    p.set("Z0", "2")
        .set("Z1", "10")
        .set("D2", "100")
        .set("D3", "200")
        .set("D12", "1")
        .set("D13", "2")
        .scan();
    assert_running(&p);
    assert_eq!(p.int("D30"), 101);
    assert_eq!(p.int("D31"), 202);
    assert_eq!(p.int("D20"), 0);
}

#[test]
fn bk_add_index_past_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBK+ D0 K1 D100Z0 K2\nEND\n");
    // Z0 = 12187 → D12287, D12288: past the end.
    p.set("Z0", "12187").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bk_add_overlapping_runs_first_to_last() {
    // D1 ← D0 + 1, then D2 ← D1 + 1 with the new D1, then D3 ← D2 + 1.
    let mut p = Plc::new("LD SM400\nBK+P D0 K1 D1 K3\nEND\n");
    p.set("D0", "5").scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), 5);
    assert_eq!(p.int("D1"), 6);
    assert_eq!(p.int("D2"), 7);
    assert_eq!(p.int("D3"), 8);
}

#[test]
fn bk_subp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nBK-P D0 K1 D0 K2\nEND\n");
    p.set("D0", "10").set("D1", "20").set("X0", "1").scan();
    assert_eq!(p.int("D0"), 9);
    assert_eq!(p.int("D1"), 19);
    p.scan();
    assert_eq!(p.int("D0"), 9);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 8);
    assert_eq!(p.int("D1"), 18);
}

#[test]
fn bk_add_on_w_devices() {
    let mut p = Plc::new("LD SM400\nBK+ W10 W20 D0 K2\nEND\n");
    // W is hexadecimal: W10 = W16 decimal; W11 follows it.
    p.set("W10", "3")
        .set("W11", "4")
        .set("W20", "30")
        .set("W21", "40")
        .scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), 33);
    assert_eq!(p.int("D1"), 44);
}

#[test]
fn continue_mode_skips_failing_bcd_instruction() {
    let cfg = CpuConfig {
        operation_error: ErrorMode::Continue,
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("LD SM400\nB* HF H1 D0\nLD SM400\nB+ H1 H2 D2\nEND\n", cfg);
    p.set("D0:u32", "0x12345678").scan();
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("SD0"), 4100);
    // B* skipped: D0, D1 unchanged; the next instruction ran (1 + 2 = 3).
    assert_eq!(p.int("D0:u32"), 0x1234_5678);
    assert_eq!(p.int("D2"), 3);
}

// ---------------------------------------------------------------- load errors

#[test]
fn load_errors() {
    // B* and B/ have the three-operand form only.
    let d = diagnostics("LD X0\nB* H1 D0\nEND\n");
    assert!(d[0].contains("`B*` takes 3 operands, found 2"), "{d:?}");
    let d = diagnostics("LD X0\nDB/P H1 D0\nEND\n");
    assert!(d[0].contains("`DB/P` takes 3 operands, found 2"), "{d:?}");
    // B+ takes 2 or 3.
    let d = diagnostics("LD X0\nB+ H1 H2 D0 D1\nEND\n");
    assert!(
        d[0].contains("`B+` takes 2 or 3 operands, found 4"),
        "{d:?}"
    );
    // BK+ takes 4.
    let d = diagnostics("LD X0\nBK+ D0 D1 D2\nEND\n");
    assert!(d[0].contains("`BK+` takes 4 operands, found 3"), "{d:?}");
    // Two-operand form: an out-of-range D is reported once, at its column.
    let d = diagnostics("LD X0\nB+ H1 D12288\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(
        d[0].starts_with("2:7:") && d[0].contains("out of range"),
        "{d:?}"
    );
    // A constant cannot be the destination.
    let d = diagnostics("LD X0\nB- H1 H2\nEND\n");
    assert!(d[0].contains("destination"), "{d:?}");
    // B* writes D, D+1: D12287 has no D+1.
    let d = diagnostics("LD X0\nB* H1 H2 D12287\nEND\n");
    assert!(d[0].contains("beyond the last device"), "{d:?}");
    // DB* writes D-D+3.
    let d = diagnostics("LD X0\nDB* H1 H2 D12285\nEND\n");
    assert!(d[0].contains("beyond the last device"), "{d:?}");
    // BK+ blocks are word devices: no digit specification, no constant S1 or D.
    let d = diagnostics("LD X0\nBK+ K4M0 D0 D10 K1\nEND\n");
    assert!(
        d[0].starts_with("2:5:") && d[0].contains("word device"),
        "{d:?}"
    );
    let d = diagnostics("LD X0\nBK+ D0 D1 K5 K1\nEND\n");
    assert!(
        d[0].starts_with("2:11:") && d[0].contains("word device"),
        "{d:?}"
    );
    // DB+ constant wider than 32 bits (9 hex digits).
    let d = diagnostics("LD X0\nDB+ H100000000 D0\nEND\n");
    assert!(
        d[0].starts_with("2:") && d[0].contains("H100000000"),
        "{d:?}"
    );
}
