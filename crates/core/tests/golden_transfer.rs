//! Golden tests of the data transfer instructions CML, DCML, BMOV, FMOV, XCH,
//! DXCH, BXCH, SWAP (programming manual §6.5). Every expected value is worked
//! out by hand in the comment next to it. Q06HCPU defaults: D0-D12287,
//! M0-M8191.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};

// ------------------------------------------------------------------- CML

#[test]
fn cml_and_dcml_invert_every_bit() {
    let mut p = Plc::new(
        "LD SM400\n\
         CML H00FF D0\n\
         CML K0 D1\n\
         CML D2 D3\n\
         DCML H0000FFFF D10\n\
         DCML K1 D12\n\
         END\n",
    );
    p.set("D2", "H1234").scan();
    assert_running(&p);
    // NOT 00FFH = FF00H.
    assert_eq!(p.int("D0:u16"), 0xFF00);
    // NOT 0 = FFFFH = −1.
    assert_eq!(p.int("D1"), -1);
    // 1234H = 0001 0010 0011 0100 → 1110 1101 1100 1011 = EDCBH.
    assert_eq!(p.int("D3:u16"), 0xEDCB);
    // NOT 0000FFFFH = FFFF0000H: low word D10 = 0, high word D11 = FFFFH.
    assert_eq!(p.int("D10:u16"), 0);
    assert_eq!(p.int("D11:u16"), 0xFFFF);
    // NOT 00000001H = FFFFFFFEH = −2.
    assert_eq!(p.int("D12:i32"), -2);
}

#[test]
fn cml_digit_specified_source_is_zero_extended() {
    let mut p = Plc::new("LD SM400\nCML K1X0 K2Y0\nCML D0 K1M0\nEND\n");
    // K1X0 = X3..X0 = 0101b = 5 (X4 is outside K1X0 and ignored).
    p.set("X0", "1").set("X2", "1").set("X4", "1");
    p.set("Y8", "1").set("M4", "1").scan();
    // 5 zero-extended = 0005H, NOT = FFFAH; K2Y0 takes the low 8 bits FAH =
    // 1111 1010b → Y1, Y3, Y4-Y7 ON; Y0, Y2 OFF (the bits beyond K1X0 are 0
    // before the inversion, hence 1 after).
    assert_eq!(p.int("K2Y0"), 0xFA);
    assert!(!p.bit("Y0") && p.bit("Y1") && !p.bit("Y2") && p.bit("Y7"));
    // Y8 is outside K2Y0: untouched.
    assert!(p.bit("Y8"));
    // D0 = 0 → NOT = FFFFH → K1M0 = 1111b: M0-M3 ON; M4 untouched (ON before).
    assert_eq!(p.int("K1M0"), 0xF);
    assert!(p.bit("M4"));
}

#[test]
fn cmlp_runs_once_per_rising_edge() {
    // CMLP D0 D0 inverts D0 in place: it flips once per rising edge of X0.
    let mut p = Plc::new("LD X0\nCMLP D0 D0\nEND\n");
    p.set("X0", "1").scan();
    // Rising edge: NOT 0 = −1.
    assert_eq!(p.int("D0"), -1);
    p.scan();
    // X0 still ON: no new edge; CML (not pulsed) would have made it 0 again.
    assert_eq!(p.int("D0"), -1);
    p.set("X0", "0").scan();
    assert_eq!(p.int("D0"), -1);
    p.set("X0", "1").scan();
    // New edge: NOT FFFFH = 0.
    assert_eq!(p.int("D0"), 0);
}

#[test]
fn cml_constant_destination_is_a_load_error() {
    let d = diagnostics("LD SM400\nCML D0 K5\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:8:"), "{d:?}");
}

// ------------------------------------------------------------------ BMOV

#[test]
fn bmov_copies_n_words() {
    let mut p = Plc::new("LD SM400\nBMOV D0 D10 K3\nBMOV D0 D20 D100\nEND\n");
    p.set("D0", "1").set("D1", "2").set("D2", "3");
    p.set("D13", "99").set("D100", "2").set("D22", "77").scan();
    assert_running(&p);
    // D10..D12 = D0..D2; D13 is the 4th word, outside the block.
    assert_eq!(
        [p.int("D10"), p.int("D11"), p.int("D12"), p.int("D13")],
        [1, 2, 3, 99]
    );
    // n from D100 = 2: D20, D21 copied, D22 untouched.
    assert_eq!([p.int("D20"), p.int("D21"), p.int("D22")], [1, 2, 77]);
}

#[test]
fn bmov_overlapping_blocks_move_as_a_whole() {
    let mut p = Plc::new("LD SM400\nBMOV D0 D2 K3\nBMOV D12 D10 K3\nEND\n");
    for (i, v) in ["1", "2", "3", "4", "5"].iter().enumerate() {
        p.set(&format!("D{i}"), v).set(&format!("D{}", 10 + i), v);
    }
    p.scan();
    // Upward: D2..D4 ← old D0..D2 = 1, 2, 3 → 1 2 1 2 3. (Copying from the
    // bottom would read the already overwritten D2 and give 1 2 1 2 1.)
    let up: Vec<i64> = (0..5).map(|i| p.int(&format!("D{i}"))).collect();
    assert_eq!(up, [1, 2, 1, 2, 3]);
    // Downward: D10..D12 ← old D12..D14 = 3, 4, 5 → 3 4 5 4 5. (Copying from
    // the top would give 5 4 5 4 5.)
    let down: Vec<i64> = (10..15).map(|i| p.int(&format!("D{i}"))).collect();
    assert_eq!(down, [3, 4, 5, 4, 5]);
}

#[test]
fn bmov_n_zero_does_nothing() {
    let mut p = Plc::new("LD SM400\nBMOV D0 D10 K0\nBMOV D0 D12287 D100\nEND\n");
    p.set("D0", "5").set("D10", "9").set("D12287", "8").scan();
    // n = 0 (K0, and D100 = 0): nothing copied, and no range check either.
    assert_running(&p);
    assert_eq!(p.int("D10"), 9);
    assert_eq!(p.int("D12287"), 8);
}

#[test]
fn bmov_up_to_the_last_device_runs() {
    let mut p = Plc::new("LD SM400\nBMOV D0 D12286 K2\nEND\n");
    p.set("D0", "4").set("D1", "6").scan();
    // D12286 + 2 words = D12286, D12287: the last two data registers.
    assert_running(&p);
    assert_eq!([p.int("D12286"), p.int("D12287")], [4, 6]);
}

#[test]
fn bmov_destination_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBMOV D0 D12286 K3\nEND\n");
    p.set("D12286", "1").scan();
    // D12286 + 3 words would need D12288: beyond D12287 → 4101, CPU STOP.
    assert_stopped(&p, 4101);
    // Nothing was written.
    assert_eq!(p.int("D12286"), 1);
}

#[test]
fn bmov_source_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBMOV D12287 D0 K2\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bmov_negative_count_is_4101() {
    let mut p = Plc::new("LD SM400\nBMOV D0 D10 D100\nEND\n");
    p.set("D100", "-1").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bmov_index_modified() {
    let mut p = Plc::new("LD SM400\nBMOV D0Z0 D10Z1 K2\nEND\n");
    // Z0 = 3, Z1 = 5: D3, D4 → D15, D16.
    p.set("Z0", "3")
        .set("Z1", "5")
        .set("D3", "30")
        .set("D4", "40");
    p.set("D0", "1").scan();
    assert_running(&p);
    assert_eq!([p.int("D15"), p.int("D16")], [30, 40]);
    // D10 (the unindexed destination) untouched.
    assert_eq!(p.int("D10"), 0);
    // Z1 = 12280: D12290, D12291 are past D12287 → 4101.
    p.set("Z1", "12280").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bmov_digit_specified_blocks() {
    let mut p = Plc::new("LD SM400\nBMOV K1X0 K1Y0 K3\nBMOV K4M0 D0 K2\nEND\n");
    // K1X0 × 3 = X0-XB; XC is outside.
    p.set("X0", "1")
        .set("X5", "1")
        .set("XB", "1")
        .set("XC", "1");
    // K4M0 × 2 = M0-M15 → D0, M16-M31 → D1.
    p.set("M1", "1").set("M17", "1").set("M31", "1").scan();
    assert_running(&p);
    for (y, on) in [("Y0", true), ("Y5", true), ("YB", true), ("YC", false)] {
        assert_eq!(p.bit(y), on, "{y}");
    }
    // D0 = bit 1 = 2; D1 = bits 1 and 15 = 8002H.
    assert_eq!(p.int("D0"), 2);
    assert_eq!(p.int("D1:u16"), 0x8002);
}

#[test]
fn bmov_digit_block_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBMOV D0 K4M8176 K1\nBMOV D0 K4M8176 K2\nEND\n");
    p.set("D0", "H8001").scan();
    // First BMOV: M8176-M8191 is the last group of 16 (8176 + 16 = 8192 points)
    // and was written (M8176 = bit 0, M8191 = bit 15) before the second one,
    // which needs M8192-M8207 → 4101.
    assert!(p.bit("M8176") && p.bit("M8191"));
    assert_stopped(&p, 4101);
}

#[test]
fn bmovp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nBMOVP D0 D10 K1\nEND\n");
    p.set("X0", "1").set("D0", "1").scan();
    assert_eq!(p.int("D10"), 1);
    p.set("D0", "2").scan();
    // Held ON: not executed again.
    assert_eq!(p.int("D10"), 1);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D10"), 2);
}

// ------------------------------------------------------------------ FMOV

#[test]
fn fmov_fills_n_points() {
    let mut p = Plc::new("LD SM400\nFMOV K7 D0 K5\nFMOV K0 K4Y0 K2\nFMOV D20 D20 K3\nEND\n");
    p.set("D5", "99");
    p.set("Y0", "1").set("Y1F", "1").set("Y20", "1");
    p.set("D20", "5").set("D21", "1").set("D22", "1").scan();
    assert_running(&p);
    let d: Vec<i64> = (0..6).map(|i| p.int(&format!("D{i}"))).collect();
    // D0..D4 = 7; D5 is the 6th point, outside.
    assert_eq!(d, [7, 7, 7, 7, 7, 99]);
    // K4Y0 × 2 = Y0-Y1F cleared; Y20 outside stays ON.
    assert!(!p.bit("Y0") && !p.bit("Y1F") && p.bit("Y20"));
    // S = D20 inside its own block: read once (5) before writing.
    assert_eq!([p.int("D20"), p.int("D21"), p.int("D22")], [5, 5, 5]);
}

#[test]
fn fmov_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nFMOV K1 D12280 K8\nFMOV K2 D12280 K9\nEND\n");
    p.scan();
    // First: D12280 + 8 = D12280-D12287 fits and is written; second needs D12288.
    assert_eq!(p.int("D12287"), 1);
    assert_stopped(&p, 4101);
}

#[test]
fn fmov_n_zero_and_index() {
    let mut p = Plc::new("LD SM400\nFMOV K3 D0 K0\nFMOV K4 D0Z0 K2\nEND\n");
    p.set("Z0", "10").scan();
    assert_running(&p);
    // n = 0: D0 untouched; D0Z0 with Z0 = 10 → D10, D11.
    assert_eq!(
        [p.int("D0"), p.int("D10"), p.int("D11"), p.int("D12")],
        [0, 4, 4, 0]
    );
}

// ------------------------------------------------------------------- XCH

#[test]
fn xch_and_dxch_exchange() {
    let mut p = Plc::new(
        "LD SM400\n\
         XCH D0 D1\n\
         DXCH D10 D20\n\
         XCH K4M0 D30\n\
         END\n",
    );
    p.set("D0", "1").set("D1", "2");
    p.set("D10:i32", "100000").set("D20:i32", "-5");
    p.set("M0", "1").set("M1", "1").set("D30", "H8001").scan();
    assert_running(&p);
    assert_eq!([p.int("D0"), p.int("D1")], [2, 1]);
    // Both 32-bit values, all four words.
    assert_eq!(p.int("D10:i32"), -5);
    assert_eq!(p.int("D20:i32"), 100000);
    // K4M0 = 3 ↔ D30 = 8001H: M0 and M15 ON, M1 OFF; D30 = 3.
    assert_eq!(p.int("D30"), 3);
    assert!(p.bit("M0") && !p.bit("M1") && p.bit("M15"));
}

#[test]
fn xchp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nXCHP D0 D1\nEND\n");
    p.set("D0", "1").set("D1", "2").set("X0", "1").scan();
    assert_eq!([p.int("D0"), p.int("D1")], [2, 1]);
    p.scan();
    // XCH (not pulsed) would swap back to 1, 2.
    assert_eq!([p.int("D0"), p.int("D1")], [2, 1]);
}

#[test]
fn xch_constant_is_a_load_error() {
    let d = diagnostics("LD SM400\nXCH K1 D0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:5:"), "{d:?}");
}

// ------------------------------------------------------------------ BXCH

#[test]
fn bxch_exchanges_blocks() {
    let mut p = Plc::new("LD SM400\nBXCH D0 D10 K3\nBXCH D20 D30 K0\nEND\n");
    for i in 0..4 {
        p.set(&format!("D{i}"), &format!("{}", i + 1));
        p.set(&format!("D{}", 10 + i), &format!("{}", i + 7));
    }
    p.set("D20", "1").set("D30", "2").scan();
    assert_running(&p);
    // D0..D2 = 1,2,3 ↔ D10..D12 = 7,8,9; D3 = 4, D13 = 10 outside.
    let a: Vec<i64> = (0..4).map(|i| p.int(&format!("D{i}"))).collect();
    let b: Vec<i64> = (10..14).map(|i| p.int(&format!("D{i}"))).collect();
    assert_eq!(a, [7, 8, 9, 4]);
    assert_eq!(b, [1, 2, 3, 10]);
    // n = 0: nothing exchanged.
    assert_eq!([p.int("D20"), p.int("D30")], [1, 2]);
}

#[test]
fn bxch_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBXCH D0 D12286 K3\nEND\n");
    p.set("D0", "1").scan();
    assert_stopped(&p, 4101);
    // Nothing exchanged.
    assert_eq!(p.int("D0"), 1);
}

// ------------------------------------------------------------------ SWAP

#[test]
fn swap_exchanges_bytes() {
    let mut p = Plc::new("LD SM400\nSWAP D0\nSWAP D1Z0\nEND\n");
    p.set("D0", "H1234")
        .set("Z0", "4")
        .set("D5", "H00FF")
        .scan();
    // 12H|34H → 34H|12H.
    assert_eq!(p.int("D0:u16"), 0x3412);
    // D1Z0 = D5: 00FFH → FF00H.
    assert_eq!(p.int("D5:u16"), 0xFF00);
}

#[test]
fn swapp_is_the_pulse_form_of_swap() {
    // `SWAPP` = SWAP + P: once per rising edge (SWAP itself ends in P).
    let mut p = Plc::new("LD X0\nSWAPP D0\nEND\n");
    p.set("D0", "H1234").set("X0", "1").scan();
    assert_eq!(p.int("D0:u16"), 0x3412);
    p.scan();
    // SWAP every scan would have restored 1234H.
    assert_eq!(p.int("D0:u16"), 0x3412);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0:u16"), 0x1234);
}

#[test]
fn not_qnh_transfer_instructions_are_rejected() {
    // DFMOV is a Universal-model (QnU) instruction.
    let d = diagnostics("LD SM400\nDFMOV K1 D0 K2\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("DFMOV"), "{d:?}");
}

#[test]
fn block_count_must_be_given() {
    let d = diagnostics("LD SM400\nBMOV D0 D10\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("3 operands"), "{d:?}");
}
