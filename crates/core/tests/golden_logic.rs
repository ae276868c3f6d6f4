//! Golden tests of the logical operation instructions WAND, WOR, WXOR, WXNR,
//! DAND, DOR, DXOR, DXNR (two and three operands) and BKAND, BKOR, BKXOR,
//! BKXNR (programming manual §7.1). Every expected value is worked out by hand
//! in the comment next to it.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};

fn words(p: &Plc, from: u32, n: u32) -> Vec<i64> {
    (from..from + n)
        .map(|i| p.int(&format!("D{i}:u16")))
        .collect()
}

// ---------------------------------------------------------------- 16-bit

#[test]
fn wand_two_and_three_operands() {
    let mut p = Plc::new("LD SM400\nWAND H0FF0 D0\nWAND D1 D2 D3\nEND\n");
    p.set("D0", "HFF0F")
        .set("D1", "H1234")
        .set("D2", "H00FF")
        .scan();
    assert_running(&p);
    // D0 = FF0FH AND 0FF0H = 0F00H.
    assert_eq!(p.int("D0:u16"), 0x0F00);
    // D3 = 1234H AND 00FFH = 0034H; the sources are unchanged.
    assert_eq!(p.int("D3:u16"), 0x0034);
    assert_eq!(p.int("D1:u16"), 0x1234);
}

#[test]
fn wor_two_and_three_operands() {
    let mut p = Plc::new("LD SM400\nWOR H0034 D0\nWOR H0F00 H00F0 D1\nEND\n");
    p.set("D0", "H1200").scan();
    // 1200H OR 0034H = 1234H.
    assert_eq!(p.int("D0:u16"), 0x1234);
    // Both sources constant: 0F00H OR 00F0H = 0FF0H.
    assert_eq!(p.int("D1:u16"), 0x0FF0);
}

#[test]
fn wxor_two_and_three_operands() {
    let mut p = Plc::new("LD SM400\nWXOR HFFFF D0\nWXOR H1234 H1234 D1\nEND\n");
    p.set("D0", "H5555").set("D1", "7").scan();
    // 0101… XOR 1111… = 1010… = AAAAH.
    assert_eq!(p.int("D0:u16"), 0xAAAA);
    // x XOR x = 0.
    assert_eq!(p.int("D1"), 0);
}

#[test]
fn wxnr_two_and_three_operands() {
    let mut p = Plc::new(
        "LD SM400\n\
         WXNR H1234 H1234 D2\n\
         WXNR H00FF H0F0F D3\n\
         WXNR H0F0F D4\n\
         END\n",
    );
    p.set("D4", "H00FF").scan();
    // NOT (x XOR x) = FFFFH = −1.
    assert_eq!(p.int("D2"), -1);
    // 00FFH XOR 0F0FH = 0FF0H; NOT = F00FH.
    assert_eq!(p.int("D3:u16"), 0xF00F);
    // Two operands: D4 = NOT (00FFH XOR 0F0FH) = F00FH.
    assert_eq!(p.int("D4:u16"), 0xF00F);
}

#[test]
fn logic_digit_specified_operands() {
    let mut p = Plc::new("LD SM400\nWAND H0F0F K2M0\nWOR K1X0 D5\nEND\n");
    // K2M0 = M0-M7 all ON = 00FFH; M8 ON is outside K2M0.
    for i in 0..9 {
        p.set(&format!("M{i}"), "1");
    }
    // K1X0 = X0-X3 ON = FH; X4 ON outside.
    for x in ["X0", "X1", "X2", "X3", "X4"] {
        p.set(x, "1");
    }
    p.scan();
    // 00FFH AND 0F0FH = 000FH → M0-M3 ON, M4-M7 OFF; M8 untouched (ON).
    assert_eq!(p.int("K2M0"), 0x0F);
    assert!(p.bit("M3") && !p.bit("M4") && !p.bit("M7") && p.bit("M8"));
    // K1X0 is zero-extended: 0 OR 000FH = 000FH (X4 not included).
    assert_eq!(p.int("D5"), 0x000F);
}

#[test]
fn logic_index_modified_destination() {
    let mut p = Plc::new("LD SM400\nWAND H00FF D0Z0\nEND\n");
    // Z0 = 5 → D5: 1234H AND 00FFH = 0034H; D0 untouched.
    p.set("Z0", "5")
        .set("D5", "H1234")
        .set("D0", "H1234")
        .scan();
    assert_eq!(p.int("D5:u16"), 0x0034);
    assert_eq!(p.int("D0:u16"), 0x1234);
}

#[test]
fn wxorp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nWXORP HFFFF D0\nEND\n");
    p.set("X0", "1").scan();
    // 0 XOR FFFFH = FFFFH.
    assert_eq!(p.int("D0"), -1);
    p.scan();
    // Held ON: not executed; WXOR would have restored 0.
    assert_eq!(p.int("D0"), -1);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 0);
}

// ---------------------------------------------------------------- 32-bit

#[test]
fn d_forms_work_on_32_bits() {
    let mut p = Plc::new(
        "LD SM400\n\
         DAND H12345678 HFFFF0000 D10\n\
         DOR K1 D20\n\
         DXOR K-1 D30\n\
         DXNR HFFFF0000 H0000FFFF D40\n\
         DXNR K0 K0 D42\n\
         END\n",
    );
    p.set("D20:i32", "65536").scan();
    assert_running(&p);
    // 12345678H AND FFFF0000H = 12340000H: D10 = 0, D11 = 1234H.
    assert_eq!(p.int("D10:u16"), 0);
    assert_eq!(p.int("D11:u16"), 0x1234);
    // 00010000H OR 1 = 00010001H = 65537.
    assert_eq!(p.int("D20:i32"), 65537);
    // 0 XOR FFFFFFFFH = −1.
    assert_eq!(p.int("D30:i32"), -1);
    // FFFF0000H XOR 0000FFFFH = FFFFFFFFH; NOT = 0.
    assert_eq!(p.int("D40:i32"), 0);
    // NOT (0 XOR 0) = FFFFFFFFH: both words FFFFH.
    assert_eq!(p.int("D42:u16"), 0xFFFF);
    assert_eq!(p.int("D43:u16"), 0xFFFF);
}

#[test]
fn dand_k8_digit_destination() {
    let mut p = Plc::new("LD SM400\nDAND H0000FFFF K8M0\nEND\n");
    // M0 and M31 ON = 80000001H; AND 0000FFFFH = 00000001H → M31 OFF.
    p.set("M0", "1").set("M31", "1").scan();
    assert!(p.bit("M0") && !p.bit("M31"));
}

// ---------------------------------------------------------------- blocks

fn block_setup(p: &mut Plc) {
    // S1 = D0..D2, S2 = D10..D12.
    p.set("D0", "HFFFF").set("D1", "H1234").set("D2", "H00F0");
    p.set("D10", "H0F0F")
        .set("D11", "H00FF")
        .set("D12", "HFFFF");
}

#[test]
fn bk_forms_combine_point_by_point() {
    let mut p = Plc::new(
        "LD SM400\n\
         BKAND D0 D10 D20 K3\n\
         BKOR D0 D10 D30 K3\n\
         BKXOR D0 D10 D40 K3\n\
         BKXNR D0 D10 D50 K3\n\
         END\n",
    );
    block_setup(&mut p);
    p.set("D23", "99").scan();
    assert_running(&p);
    // FFFF∧0F0F = 0F0F; 1234∧00FF = 0034; 00F0∧FFFF = 00F0. D23 outside.
    assert_eq!(words(&p, 20, 4), [0x0F0F, 0x0034, 0x00F0, 99]);
    // FFFF∨0F0F = FFFF; 1234∨00FF = 12FF; 00F0∨FFFF = FFFF.
    assert_eq!(words(&p, 30, 3), [0xFFFF, 0x12FF, 0xFFFF]);
    // FFFF⊕0F0F = F0F0; 1234⊕00FF = 12CB (34H⊕FFH = CBH); 00F0⊕FFFF = FF0F.
    assert_eq!(words(&p, 40, 3), [0xF0F0, 0x12CB, 0xFF0F]);
    // NOT of the XOR: 0F0F, ED34, 00F0.
    assert_eq!(words(&p, 50, 3), [0x0F0F, 0xED34, 0x00F0]);
}

#[test]
fn bk_constant_second_source() {
    let mut p = Plc::new("LD SM400\nBKAND D0 H00FF D20 K3\nBKOR D0 K1 D30 D100\nEND\n");
    block_setup(&mut p);
    p.set("D100", "2").scan();
    // Each point AND 00FFH: 00FF, 0034, 00F0.
    assert_eq!(words(&p, 20, 3), [0x00FF, 0x0034, 0x00F0]);
    // n = D100 = 2 points OR 1: FFFF, 1235; D32 untouched.
    assert_eq!(words(&p, 30, 3), [0xFFFF, 0x1235, 0]);
}

#[test]
fn bk_n_zero_does_nothing() {
    let mut p = Plc::new("LD SM400\nBKXOR D0 D10 D12287 K0\nEND\n");
    block_setup(&mut p);
    p.set("D12287", "5").scan();
    assert_running(&p);
    assert_eq!(p.int("D12287"), 5);
}

#[test]
fn bk_destination_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBKAND D0 D10 D12286 K3\nEND\n");
    block_setup(&mut p);
    p.scan();
    // D12286 + 3 points needs D12288 → 4101, CPU STOP, nothing written.
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12286"), 0);
}

#[test]
fn bk_source_past_the_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nBKOR D12287 D10 D20 K2\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bk_negative_count_is_4101() {
    let mut p = Plc::new("LD SM400\nBKXNR D0 D10 D20 D100\nEND\n");
    p.set("D100", "-3").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn bk_index_modified_blocks() {
    let mut p = Plc::new("LD SM400\nBKAND D0Z0 D10 D20Z1 K2\nEND\n");
    block_setup(&mut p);
    // Z0 = 1: S1 = D1, D2; Z1 = 10: D = D30, D31.
    p.set("Z0", "1").set("Z1", "10").scan();
    // 1234∧0F0F = 0204; 00F0∧00FF = 00F0.
    assert_eq!(words(&p, 30, 2), [0x0204, 0x00F0]);
    assert_eq!(p.int("D20"), 0);
}

#[test]
fn bkxorp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nBKXORP D0 H00FF D0 K1\nEND\n");
    p.set("D0", "H1234").set("X0", "1").scan();
    // 1234H XOR 00FFH = 12CBH.
    assert_eq!(p.int("D0:u16"), 0x12CB);
    p.scan();
    // Not again while held (BKXOR would restore 1234H).
    assert_eq!(p.int("D0:u16"), 0x12CB);
}

#[test]
fn logic_operand_errors_are_reported_at_load() {
    // A constant destination, a constant S1 of a block form, a missing n.
    let d = diagnostics(
        "LD SM400\n\
         WAND D0 K1\n\
         BKAND K1 D0 D10 K2\n\
         BKOR D0 D1 D2\n\
         END\n",
    );
    assert_eq!(d.len(), 3, "{d:?}");
    assert!(d[0].starts_with("2:9:"), "{d:?}");
    assert!(d[1].starts_with("3:7:"), "{d:?}");
    assert!(d[2].contains("4 operands"), "{d:?}");
}
