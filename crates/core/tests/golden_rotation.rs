//! Golden tests of the rotation and shift instructions ROR, ROL, RCR, RCL,
//! DROR, DROL, DRCR, DRCL (programming manual §7.2), SFR, SFL, BSFR, BSFL,
//! DSFR, DSFL (§7.3) and SFT (§5.4.1). Every expected value is worked out by
//! hand in the comment next to it. The carry flag SM700 is copied to M100,
//! M101 … after each instruction so that each value can be checked.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};

/// `LD SM400` + each instruction followed by `LD SM700 / OUT M10k`.
fn with_carries(instrs: &[&str]) -> String {
    let mut s = String::new();
    for (k, i) in instrs.iter().enumerate() {
        s += &format!("LD SM400\n{i}\nLD SM700\nOUT M{}\n", 100 + k);
    }
    s + "END\n"
}

// ------------------------------------------------------------ ROR / ROL

#[test]
fn ror_rotates_right_and_sets_the_carry() {
    let mut p = Plc::new(&with_carries(&["ROR D0 K1", "ROR D1 K3"]));
    p.set("SM700", "1").set("D0", "6").set("D1", "5").scan();
    assert_running(&p);
    // 0110b → 0011b = 3; the bit rotated out is b0 = 0 → SM700 OFF.
    assert_eq!(p.int("D0"), 3);
    assert!(!p.bit("M100"));
    // 0000…0101b rotated right 3: b2..b0 = 101 go to b15..b13 → A000H; the
    // last bit out is b2 = 1 → SM700 ON.
    assert_eq!(p.int("D1:u16"), 0xA000);
    assert!(p.bit("M101"));
}

#[test]
fn ror_count_is_taken_modulo_16() {
    let mut p = Plc::new(&with_carries(&["ROR D2 K19", "ROR D3 K16", "ROR D4 K-1"]));
    p.set("D2", "5")
        .set("D3", "H1234")
        .set("D4", "H8001")
        .scan();
    // 19 mod 16 = 3: 5 → A000H as above, carry b2 = 1.
    assert_eq!(p.int("D2:u16"), 0xA000);
    assert!(p.bit("M100"));
    // 16 mod 16 = 0: nothing moves and SM700 keeps the 1 from the ROR before.
    assert_eq!(p.int("D3:u16"), 0x1234);
    assert!(p.bit("M101"));
    // K-1 = FFFFH = 65535, mod 16 = 15: right 15 = left 1 → 8001H → 0003H; the
    // last bit out is b14 = 0.
    assert_eq!(p.int("D4:u16"), 0x0003);
    assert!(!p.bit("M102"));
}

#[test]
fn rol_rotates_left_and_sets_the_carry() {
    let mut p = Plc::new(&with_carries(&["ROL D0 K1", "ROL D1 K4", "ROL D2 K4"]));
    p.set("D0", "H8001")
        .set("D1", "H1234")
        .set("D2", "H0234")
        .scan();
    // 8001H ← 1 = 0003H; b15 = 1 went out → SM700 ON.
    assert_eq!(p.int("D0:u16"), 0x0003);
    assert!(p.bit("M100"));
    // 1234H ← 4 = 2341H; last out b12 = 1.
    assert_eq!(p.int("D1:u16"), 0x2341);
    assert!(p.bit("M101"));
    // 0234H ← 4 = 2340H; last out b12 = 0.
    assert_eq!(p.int("D2:u16"), 0x2340);
    assert!(!p.bit("M102"));
}

#[test]
fn rolp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nROLP D0 K1\nEND\n");
    p.set("D0", "1").set("X0", "1").scan();
    assert_eq!(p.int("D0"), 2);
    p.scan();
    // Held: ROL would have given 4.
    assert_eq!(p.int("D0"), 2);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 4);
}

#[test]
fn ror_index_modified() {
    let mut p = Plc::new("LD SM400\nROR D0Z0 K4\nEND\n");
    // Z0 = 3 → D3: 1234H → 4123H (the low digit moves to the top).
    p.set("Z0", "3")
        .set("D3", "H1234")
        .set("D0", "H1234")
        .scan();
    assert_eq!(p.int("D3:u16"), 0x4123);
    assert_eq!(p.int("D0:u16"), 0x1234);
}

// ------------------------------------------------------------ RCR / RCL

#[test]
fn rcr_rotates_through_the_carry() {
    let mut p = Plc::new(&with_carries(&["RCR D0 K1", "RCR D1 K2", "RCR D2 K17"]));
    p.set("SM700", "1")
        .set("D0", "2")
        .set("D1", "3")
        .set("D2", "4")
        .scan();
    // Carry 1, D0 = 0002H: b0 = 0 goes to the carry, the old carry to b15
    // → 8001H, SM700 OFF.
    assert_eq!(p.int("D0:u16"), 0x8001);
    assert!(!p.bit("M100"));
    // Carry 0, D1 = 0003H. Step 1: b0 = 1 → carry, 0 → b15: 0001H, C = 1.
    // Step 2: b0 = 1 → carry, 1 → b15: 8000H, C = 1. (ROR would give C000H.)
    assert_eq!(p.int("D1:u16"), 0x8000);
    assert!(p.bit("M101"));
    // 17 mod 16 = 1; carry 1, D2 = 0004H → 8002H, carry = old b0 = 0.
    assert_eq!(p.int("D2:u16"), 0x8002);
    assert!(!p.bit("M102"));
}

#[test]
fn rcl_rotates_through_the_carry() {
    let mut p = Plc::new(&with_carries(&["RCL D0 K1", "RCL D1 K1", "RCL D2 K3"]));
    p.set("D0", "H8000")
        .set("D1", "0")
        .set("D2", "HA000")
        .scan();
    // Carry 0, 8000H: b15 = 1 → carry, 0 → b0: D0 = 0, SM700 ON.
    assert_eq!(p.int("D0"), 0);
    assert!(p.bit("M100"));
    // Carry 1, D1 = 0: b15 = 0 → carry, 1 → b0: D1 = 1, SM700 OFF.
    assert_eq!(p.int("D1"), 1);
    assert!(!p.bit("M101"));
    // Carry 0, A000H = 1010 0000 … Step 1: out 1 → 4000H, C 1. Step 2: out 0,
    // in 1 → 8001H, C 0. Step 3: out 1, in 0 → 0002H, C 1.
    assert_eq!(p.int("D2"), 2);
    assert!(p.bit("M102"));
}

// ------------------------------------------------------------ 32-bit

#[test]
fn dror_drol_32_bit() {
    let mut p = Plc::new(&with_carries(&["DROR D0 K1", "DROR D2 K33", "DROL D4 K4"]));
    p.set("D0:i32", "1")
        .set("D2:i32", "2")
        .set("D4:u32", "0x12345678");
    p.scan();
    // 00000001H → 80000000H; b0 = 1 went out.
    assert_eq!(p.int("D0:u16"), 0);
    assert_eq!(p.int("D1:u16"), 0x8000);
    assert!(p.bit("M100"));
    // 33 mod 32 = 1: 2 → 1; b0 = 0 went out.
    assert_eq!(p.int("D2:i32"), 1);
    assert!(!p.bit("M101"));
    // 12345678H ← 4 = 23456781H; last out b28 = 1 (top digit 1H = 0001b).
    assert_eq!(p.int("D4:u16"), 0x6781);
    assert_eq!(p.int("D5:u16"), 0x2345);
    assert!(p.bit("M102"));
}

#[test]
fn drcr_drcl_32_bit_through_the_carry() {
    let mut p = Plc::new(&with_carries(&[
        "DRCR D10 K1",
        "DRCL D12 K1",
        "DRCL D14 K2",
    ]));
    p.set("SM700", "1")
        .set("D12:u32", "0x80000000")
        .set("D14:u32", "0x40000000");
    p.scan();
    // Carry 1, D10 = 0: carry → b31 = 80000000H, b0 = 0 → SM700 OFF.
    assert_eq!(p.int("D10:u32"), 0x8000_0000);
    assert!(!p.bit("M100"));
    // Carry 0, 80000000H: b31 = 1 → carry, 0 → b0: 0, SM700 ON.
    assert_eq!(p.int("D12:u32"), 0);
    assert!(p.bit("M101"));
    // Carry 1, 40000000H. Step 1: out 0, in 1 → 80000001H, C 0. Step 2: out 1,
    // in 0 → 00000002H, C 1.
    assert_eq!(p.int("D14:u32"), 2);
    assert!(p.bit("M102"));
}

// ------------------------------------------------------- digit specified

#[test]
fn rotation_within_the_specified_digits() {
    let mut p = Plc::new(&with_carries(&[
        "ROR K3M0 K15",
        "ROL K1Y0 K1",
        "DROR K6M20 K31",
    ]));
    p.set("SM700", "1").set("M0", "1").set("M12", "1");
    p.set("Y3", "1")
        .set("Y4", "1")
        .set("M20", "1")
        .set("M44", "1");
    p.scan();
    // K3M0 = 12 bits; 15 mod 12 = 3 (the manual's example). 1 rotated right 3
    // within 12 bits → bit 9 → M9 ON, M0 OFF; last out b2 = 0.
    assert!(p.bit("M9") && !p.bit("M0"));
    assert_eq!(p.int("K3M0"), 0x200);
    assert!(!p.bit("M100"));
    // M12 is outside K3M0: untouched.
    assert!(p.bit("M12"));
    // K1Y0 = 4 bits, Y3 ON = 1000b ← 1 → 0001b: Y0 ON, Y3 OFF; last out b3 = 1.
    assert!(p.bit("Y0") && !p.bit("Y3"));
    assert!(p.bit("M101"));
    assert!(p.bit("Y4"));
    // K6M20 = 24 bits (M20-M43); 31 mod 24 = 7. M20 = 1 rotated right 7 within
    // 24 bits → bit 17 → M37 ON; last out b6 = 0. M44 outside stays ON.
    assert!(p.bit("M37") && !p.bit("M20"));
    assert_eq!(p.int("K6M20:u32"), 1 << 17);
    assert!(!p.bit("M102"));
    assert!(p.bit("M44"));
}

// ------------------------------------------------------------ SFR / SFL

#[test]
fn sfr_sfl_shift_n_bits() {
    let mut p = Plc::new(&with_carries(&[
        "SFL D1 K4",
        "SFR D0 K6",
        "SFR D2 K16",
        "SFR D3 K18",
    ]));
    p.set("D0", "H8421")
        .set("D1", "H8421")
        .set("D2", "H1234")
        .set("D3", "H1234");
    p.scan();
    // 8421H ← 4 = 4210H (the top digit 8 falls out); last out b12 = 0.
    assert_eq!(p.int("D1:u16"), 0x4210);
    assert!(!p.bit("M100"));
    // 8421H → 6 = 0210H (33825 / 64 = 528); last out b5 = 1 (21H = 0010 0001b).
    assert_eq!(p.int("D0:u16"), 0x0210);
    assert!(p.bit("M101"));
    // 16 mod 16 = 0: no shift, SM700 keeps 1.
    assert_eq!(p.int("D2:u16"), 0x1234);
    assert!(p.bit("M102"));
    // 18 mod 16 = 2: 1234H → 048DH (4660 / 4 = 1165); last out b1 = 0.
    assert_eq!(p.int("D3:u16"), 0x048D);
    assert!(!p.bit("M103"));
}

#[test]
fn sfr_within_the_specified_digits() {
    let mut p = Plc::new(&with_carries(&["SFR K2Y10 K4", "SFL K1M0 K5"]));
    // K2Y10 = Y10-Y17 = AAH (Y11, Y13, Y15, Y17); Y18 outside.
    for y in ["Y11", "Y13", "Y15", "Y17", "Y18"] {
        p.set(y, "1");
    }
    p.set("M3", "1").set("M4", "1").scan();
    // AAH → 4 = 0AH: Y11, Y13 ON, Y15, Y17 OFF; last out b3 = 1.
    assert_eq!(p.int("K2Y10"), 0x0A);
    assert!(p.bit("M100"));
    assert!(p.bit("Y18"));
    // K1M0 = 4 bits, 5 mod 4 = 1: 1000b ← 1 = 0000b; b3 = 1 went out. M4 is
    // outside K1M0 and is not shifted into.
    assert_eq!(p.int("K1M0"), 0);
    assert!(p.bit("M101"));
    assert!(p.bit("M4") && !p.bit("M5"));
}

// ----------------------------------------------------------- BSFR / BSFL

#[test]
fn bsfr_bsfl_shift_n_bits_by_one() {
    let mut p = Plc::new(&with_carries(&["BSFR M0 K5", "BSFL M10 K5"]));
    for m in ["M0", "M2", "M4", "M5", "M10", "M13", "M15"] {
        p.set(m, "1");
    }
    p.scan();
    assert_running(&p);
    // M4..M0 = 10101 → right: M0←M1, …, M3←M4, M4←0 → 01010: M1, M3 ON.
    let r: Vec<bool> = (0..6).map(|i| p.bit(&format!("M{i}"))).collect();
    assert_eq!(r, [false, true, false, true, false, true]);
    // The old M0 = 1 went to the carry; M5 outside untouched.
    assert!(p.bit("M100"));
    // M14..M10 = 01001 → left: M14←M13, …, M10←0 → 10010: M11, M14 ON; the old
    // M14 = 0 went to the carry; M15 untouched.
    let l: Vec<bool> = (10..16).map(|i| p.bit(&format!("M{i}"))).collect();
    assert_eq!(l, [false, true, false, false, true, true]);
    assert!(!p.bit("M101"));
}

#[test]
fn bsfr_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBSFR M8189 K3\nBSFR M8190 K3\nEND\n");
    p.set("M8190", "1").scan();
    // First: M8189-M8191 fits (M8190 moves to M8189); second needs M8192.
    assert!(p.bit("M8189"));
    assert_stopped(&p, 4101);
}

#[test]
fn bsfl_n_zero_index_and_pulse() {
    let mut p = Plc::new(
        "LD SM400\n\
         BSFL M0 K0\n\
         BSFR M0Z0 K2\n\
         LD X0\n\
         BSFLP M40 K4\n\
         END\n",
    );
    // Z0 = 20 → M20, M21: M21 → M20.
    p.set("M0", "1")
        .set("Z0", "20")
        .set("M21", "1")
        .set("M40", "1");
    p.set("X0", "1").scan();
    assert!(p.bit("M0"), "n = 0 moves nothing");
    assert!(p.bit("M20") && !p.bit("M21"));
    // Rising edge: M40 → M41.
    assert!(p.bit("M41") && !p.bit("M40"));
    p.scan();
    // Held: no shift (BSFL would move it to M42).
    assert!(p.bit("M41") && !p.bit("M42"));
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert!(p.bit("M42") && !p.bit("M41"));
}

#[test]
fn bsfr_timer_contacts_are_rejected_at_load() {
    let d = diagnostics("LD SM400\nBSFR T0 K2\nBSFL D0 K2\nEND\n");
    assert_eq!(d.len(), 2, "{d:?}");
    assert!(d[0].starts_with("2:6:"), "{d:?}");
    assert!(d[1].starts_with("3:6:"), "{d:?}");
}

// ----------------------------------------------------------- DSFR / DSFL

#[test]
fn dsfr_dsfl_shift_n_words_by_one() {
    let mut p = Plc::new("LD SM400\nDSFR D0 K4\nDSFL D10 K4\nEND\n");
    for i in 0..4 {
        p.set(&format!("D{i}"), &format!("{}", i + 1));
        p.set(&format!("D{}", 10 + i), &format!("{}", i + 1));
    }
    p.set("D4", "9").set("D14", "9").scan();
    assert_running(&p);
    // 1 2 3 4 → 2 3 4 0 (D3 ← 0); D4 outside.
    let r: Vec<i64> = (0..5).map(|i| p.int(&format!("D{i}"))).collect();
    assert_eq!(r, [2, 3, 4, 0, 9]);
    // 1 2 3 4 → 0 1 2 3 (D10 ← 0); D14 outside.
    let l: Vec<i64> = (10..15).map(|i| p.int(&format!("D{i}"))).collect();
    assert_eq!(l, [0, 1, 2, 3, 9]);
}

#[test]
fn dsfr_digit_specified_and_indexed() {
    let mut p = Plc::new("LD SM400\nDSFR K1M0 K3\nDSFL D20Z0 K2\nEND\n");
    // Groups of 4: M0-M3 = 1 (M0), M4-M7 = 2 (M5), M8-M11 = 4 (M10); M12 outside.
    for m in ["M0", "M5", "M10", "M12"] {
        p.set(m, "1");
    }
    // Z0 = 5 → D25, D26.
    p.set("Z0", "5").set("D25", "7").set("D26", "8").scan();
    // 1 2 4 → 2 4 0: M1 (2 in group 0), M6 (4 in group 1) ON; M12 untouched.
    let on: Vec<u32> = (0..13).filter(|i| p.bit(&format!("M{i}"))).collect();
    assert_eq!(on, [1, 6, 12]);
    // 7 8 → 0 7.
    assert_eq!([p.int("D25"), p.int("D26")], [0, 7]);
}

#[test]
fn dsfl_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nDSFL D12286 K3\nEND\n");
    p.set("D12286", "5").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12286"), 5);
}

#[test]
fn dsfrp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nDSFRP D0 K3\nEND\n");
    p.set("D0", "1")
        .set("D1", "2")
        .set("D2", "3")
        .set("X0", "1")
        .scan();
    assert_eq!([p.int("D0"), p.int("D1"), p.int("D2")], [2, 3, 0]);
    p.scan();
    // DSFR would give 3 0 0.
    assert_eq!([p.int("D0"), p.int("D1"), p.int("D2")], [2, 3, 0]);
}

// ------------------------------------------------------------------- SFT

#[test]
fn sft_moves_the_preceding_bit() {
    let mut p = Plc::new(
        "LD SM400\n\
         SFT M11\n\
         SFT M21\n\
         SFT D0.5\n\
         SFT M0\n\
         SFT D1.0\n\
         END\n",
    );
    p.set("M10", "1").set("M21", "1").set("D0", "H0010");
    p.set("M0", "1").set("D1", "H0003").scan();
    assert_running(&p);
    // M10 ON → M11 ON, M10 OFF.
    assert!(p.bit("M11") && !p.bit("M10"));
    // M20 OFF → M21 OFF.
    assert!(!p.bit("M21"));
    // D0 bit 4 → bit 5, bit 4 cleared: 0010H → 0020H.
    assert_eq!(p.int("D0"), 0x20);
    // No device before M0: it counts as OFF (decision) → M0 OFF.
    assert!(!p.bit("M0"));
    // No bit before b0: D1 = 0003H → b0 = 0 → 0002H.
    assert_eq!(p.int("D1"), 2);
}

#[test]
fn sftp_shift_register_advances_once_per_edge() {
    // The classic shift register: highest bit first.
    let mut p = Plc::new("LD X0\nSFTP M3\nSFTP M2\nSFTP M1\nEND\n");
    p.set("M0", "1");
    let bits = |p: &Plc| -> Vec<bool> { (0..4).map(|i| p.bit(&format!("M{i}"))).collect() };
    p.set("X0", "1").scan();
    // Edge 1: M3 ← M2 (0), M2 ← M1 (0), M1 ← M0 (1), M0 OFF.
    assert_eq!(bits(&p), [false, true, false, false]);
    p.scan();
    // Held ON: no further shift (SFT would have moved it on to M2).
    assert_eq!(bits(&p), [false, true, false, false]);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(bits(&p), [false, false, true, false]);
}

#[test]
fn sft_index_modified() {
    let mut p = Plc::new("LD SM400\nSFT M10Z0\nEND\n");
    // Z0 = 5 → SFT M15: M14 → M15.
    p.set("Z0", "5").set("M14", "1").set("M9", "1").scan();
    assert!(p.bit("M15") && !p.bit("M14"));
    // M10 ← M9 did not happen.
    assert!(!p.bit("M10") && p.bit("M9"));
    // Z0 = 8182 → M8192, beyond M8191 → 4101.
    p.set("Z0", "8182").scan();
    assert_stopped(&p, 4101);
}
