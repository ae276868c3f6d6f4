//! Golden tests of transfer, arithmetic, compare contacts, bit groups,
//! indexing and run errors (spec aplc.md §8.1-§8.3, manual example values).

mod common;
use common::plc;

/// §8.2 #17-19: MOV → 500, DMOV → 50000 (D10 high, D11 low), RMOV 50000.5.
#[test]
fn mov_dmov_rmov() {
    let mut p = plc(
        "LD SM0\nMOV 500 D10\nDMOV 50000 D20\nRMOV 50000.5 D30\nMOV 16#FFFF D40\nMOV -10 SD66\n",
    );
    p.scan();
    assert_eq!(p.int("D10"), 500);
    assert_eq!(p.int("D20:i32"), 50000);
    assert_eq!(
        (p.int("D20"), p.int("D21:u16")),
        (0, 50000),
        "high word first"
    );
    assert_eq!(p.real("D30:f32"), 50000.5);
    assert_eq!(p.int("D40:u16"), 0xFFFF);
    assert_eq!(p.int("SD66"), -10);
}

/// §8.1 #15: `MOV 16#89 K2M0` → M0, M3, M7 ON, the others OFF (L1984-1989);
/// §8.1 #14: Z10 = 3, `MOV K1X0Z10 D0` reads X3-X6 (L2013-2030).
#[test]
fn bit_groups_and_index() {
    let mut p = plc("LD SM0\nMOV 16#89 K2M0\nLD M100\nMOV 3 Z10\nMOV K1X0Z10 D0\nMOV K3Y0 D1\n");
    p.set("M100", "1")
        .set("X3", "1")
        .set("X6", "1")
        .set("X7", "1")
        .set("Y10", "1")
        .scan();
    for (m, on) in [(0, true), (1, false), (3, true), (7, true), (2, false)] {
        assert_eq!(p.bit(&format!("M{m}")), on, "M{m}");
    }
    assert_eq!(p.int("D0"), 0b1001);
    // K3Y0 = Y0-Y7, Y10-Y13: Y10 is bit 8.
    assert_eq!(p.int("D1"), 256);
}

/// §8.3 #31-37, #40-46: ADD, SUB, MUL, DIV, INC, DAT and the 32-bit forms.
#[test]
fn arithmetic_examples() {
    let src = "LD SM1\nADD 1000 2000 D0\nSUB 1000 2000 D1\nMUL 1000 2000 D10\nDIV 2500 1000 D20\n\
MOV 1000 D30\nMOV 1000 D31\nINC D30\nDAT D31\nDADD 100000 200000 D40\nDSUB 100000 200000 D42\n\
DMUL 83000 2000 D44\nDDIV 83000 2000 D50\nDMOV 100000 D60\nDMOV 100000 D62\nDINC D60\nDDAT D62\nDDEC D62\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!(p.int("D0"), 3000);
    assert_eq!(p.int("D1"), -1000);
    assert!(!p.bit("SM182"), "SUB: -1000 is in range, no borrow");
    assert_eq!(p.int("D10:i32"), 2_000_000);
    assert_eq!((p.int("D10:u16"), p.int("D11:u16")), (0x001E, 0x8480));
    assert_eq!((p.int("D20"), p.int("D21")), (2, 500));
    assert_eq!((p.int("D30"), p.int("D31")), (1001, 999));
    assert_eq!(p.int("D40:i32"), 300_000);
    assert_eq!(p.int("D42:i32"), -100_000);
    assert_eq!(p.int("D44:i32"), 166_000_000);
    assert_eq!((p.int("D50:i32"), p.int("D52:i32")), (41, 1000));
    assert_eq!((p.int("D60:i32"), p.int("D62:i32")), (100_001, 99_998));
}

/// Flags (D8, D17): carry on overflow with wrap, borrow below the minimum,
/// zero; each execution writes all three.
#[test]
fn add_sub_flags() {
    let mut p = plc("LD M0\nADD 32767 1 D0\nLD M1\nSUB -32768 1 D1\nLD M2\nSUB 5 5 D2\nLD M3\nDADD 2147483647 1 D4\n");
    p.set("M0", "1").scan();
    assert_eq!(p.int("D0"), -32768);
    assert!(p.bit("SM181") && !p.bit("SM180") && !p.bit("SM182"));
    p.set("M0", "0").set("M1", "1").scan();
    assert_eq!(p.int("D1"), 32767);
    assert!(p.bit("SM182") && !p.bit("SM181"));
    p.set("M1", "0").set("M2", "1").scan();
    assert!(p.bit("SM180") && !p.bit("SM182"));
    p.set("M2", "0").set("M3", "1").scan();
    assert_eq!(p.int("D4:i32"), i32::MIN as i64);
    assert!(p.bit("SM181") && !p.bit("SM180"));
}

/// Division by zero is run error 69: SM20, SD20, the CPU keeps running and
/// the destination is unchanged; the history SD20-SD24 pushes only a new code.
#[test]
fn divide_by_zero_is_error_69() {
    let mut p = plc("LD SM0\nMOV 7 D1\nDIV 10 D0 D1\nINC D5\nLD M0\nMOV K1X0Z1 D6\n");
    p.scan();
    assert!(p.running());
    assert_eq!(p.error_code(), Some(69));
    assert!(p.bit("SM20"));
    assert_eq!((p.int("SD20"), p.int("D1"), p.int("D5")), (69, 7, 1));
    p.scan();
    assert_eq!(p.int("SD21"), 0, "the same code is not pushed twice");
    // Index out of range: 65, SM21.
    p.set("Z1", "200").set("M0", "1").scan();
    assert!(p.running());
    assert_eq!((p.int("SD20"), p.int("SD21")), (65, 69));
    assert!(p.bit("SM21"));
}

/// Compare contacts, INT/DINT/REAL, with the operator written apart
/// (L9320-9337, L9442-9447).
#[test]
fn compare_contacts() {
    let src = "LD X0\nOR= D0 D1\nOUT Y0\nLDD> D10 100000\nOUT Y1\nLDR < > D20 D22\nOUT Y2\n\
LD SM0\nAND<= D0 -1\nOUT Y3\nLD SM0\nANDR>= D20 1.5\nOUT Y4\n";
    let mut p = plc(src);
    p.scan();
    assert!(p.bit("Y0") && !p.bit("Y1") && !p.bit("Y2") && !p.bit("Y3"));
    p.set("D0", "-5")
        .set("D10:i32", "100001")
        .set("D20:f32", "1.5")
        .scan();
    assert!(!p.bit("Y0") && p.bit("Y1") && p.bit("Y2") && p.bit("Y3") && p.bit("Y4"));
}

/// FROM/TO load (the manual's listings use them) and raise 73 (D7).
#[test]
fn from_to_raise_73() {
    let mut p = plc("LD SM1\nMOV 1000 D500\nLD M0\nFROM 0 5 D501 1\n");
    p.scan();
    assert_eq!(p.error_code(), None);
    p.set("M0", "1").scan();
    assert_eq!(p.error_code(), Some(73));
    assert!(p.running());
    assert_eq!(p.int("D500"), 1000);
}

/// Globals by bare name, MAIN's TEMP locals by `#NAME`, GB18030 text.
#[test]
fn variables_and_gb18030() {
    let src = "VAR_GLOBAL\n    水压    X0    // 水压标记\n    阀门    Y1    // 控制阀门\nEND_VAR\n\
POU MAIN\nVAR\n    LM0 FLAG TEMP BOOL\n    W  TEMP INT\nEND_VAR\nLD 水压\nOUT #FLAG\nLD #flag\nOUT 阀门\nMOV 5 #W\nMOV #W D0\n";
    let (gb, _, _) = encoding_rs::GB18030.encode(src);
    let program = softplc_aplc::load_bytes("t.apl", &gb).unwrap();
    assert!(program.ops.len() > 5);
    let mut p = plc(src);
    p.set("X0", "1").scan();
    assert!(p.bit("Y1"));
    assert_eq!(p.int("D0"), 5);
    assert_eq!(p.int("V0"), 5, "MAIN's locals after the last scan");
}

/// §8.2 #20-25: BMOV, FMOV 500, DFMOV 100000 (D10-D29), SWAP 16#1027,
/// XCH 5000 ↔ 1000, DXCH 5000000 ↔ 1000000.
#[test]
fn block_transfer_examples() {
    let src = "LD SM1\nFMOV 500 D100 10\nBMOV D100 D200 10\nDFMOV 100000 D10 10\nMOV 16#1027 D0\nSWAP D0\n\
MOV 5000 D1\nMOV 1000 D2\nXCH D1 D2\nDMOV 5000000 D4\nDMOV 1000000 D6\nDXCH D4 D6\nMOV 7 D300\nBMOV D300 D301 -1\n";
    let mut p = plc(src);
    p.scan();
    for k in 0..10 {
        assert_eq!(p.int(&format!("D{}", 100 + k)), 500);
        assert_eq!(p.int(&format!("D{}", 200 + k)), 500);
        assert_eq!(p.int(&format!("D{}:i32", 10 + 2 * k)), 100_000);
    }
    assert_eq!(p.int("D30"), 0);
    assert_eq!(p.int("D0:u16"), 0x2710);
    assert_eq!((p.int("D1"), p.int("D2")), (1000, 5000));
    assert_eq!((p.int("D4:i32"), p.int("D6:i32")), (1_000_000, 5_000_000));
    assert_eq!(
        p.error_code(),
        Some(64),
        "a negative count is an illegal value"
    );
    assert_eq!(p.int("D301"), 0);
}

/// BMOV past the last D is error 65 and copies nothing.
#[test]
fn bmov_out_of_range() {
    let mut p = plc("LD SM0\nMOV 1 D7990\nBMOV D7990 D0 20\n");
    p.scan();
    assert_eq!(p.error_code(), Some(65));
    assert_eq!(p.int("D0"), 0);
    assert!(p.running());
}

/// §8.4 #66: ZRST / ZSET M10 10 (L8699, L8724); ZRST on C clears values.
#[test]
fn zrst_zset() {
    let mut p = plc("LD M0\nZSET M10 10\nLD M1\nZRST M10 10\nZRST C199 2\n");
    p.set("M0", "1").scan();
    assert!((10..20).all(|m| p.bit(&format!("M{m}"))));
    assert!(!p.bit("M20") && !p.bit("M9"));
    p.set("CN199", "5")
        .set("CN200", "70000")
        .set("M0", "0")
        .set("M1", "1")
        .scan();
    assert!((10..20).all(|m| !p.bit(&format!("M{m}"))));
    assert_eq!((p.int("CN199"), p.int("CN200")), (0, 0));
}
