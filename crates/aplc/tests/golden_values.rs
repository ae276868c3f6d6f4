//! Golden tests of word logic, shifts and rotations, REAL arithmetic,
//! conversions and the integer functions, with the manual's example values
//! (spec aplc.md §4.7-§4.10, §8.3-§8.4).

mod common;
use common::plc;

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1.0)
}

/// §8.4 #60 (L5801-5989).
#[test]
fn word_logic() {
    let src = "LD SM0\nWAND 46739 37678 D0\nWOR 46739 37678 D1\nWXOR 46739 37678 D2\nWINV 46739 D3\n\
DWAND 2997282386 976957747 D10\nDWOR 2997282386 976957747 D12\nDWXOR 2997282386 976957747 D14\nDWINV 2997282386 D16\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!(
        [
            p.int("D0:u16"),
            p.int("D1:u16"),
            p.int("D2:u16"),
            p.int("D3:u16")
        ],
        [37378, 47039, 9661, 18796]
    );
    assert_eq!(
        [
            p.int("D10:u32"),
            p.int("D12:u32"),
            p.int("D14:u32"),
            p.int("D16:u32")
        ],
        [841097234, 3133142899, 2292045665, 1297684909]
    );
}

/// §8.4 #61 (L6023-6384), through programs: SM181 is the last bit out.
#[test]
fn shifts_and_rotations() {
    let src = "LD SM0\nMOV 52629 D0\nROR D0 D1 3\nOUT M1\nLD SM181\nOUT M2\nLD SM0\nROL D0 D2 15\nLD SM181\nOUT M3\n\
LD SM0\nSHR 31452 D3 5\nSHL 31452 D4 7\nDMOV 3013123244 D10\nDROR D10 D12 7\nDSHL 1939381420 D14 15\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!(p.int("D1:u16"), 47538);
    assert!(p.bit("M2"), "ROR 3: C = 1");
    assert_eq!(p.int("D2:u16"), 59082);
    assert!(!p.bit("M3"), "ROL 15: C = 0");
    assert_eq!((p.int("D3"), p.int("D4")), (982, 28160));
    assert_eq!(p.int("D12:u32"), 1499935033);
    assert_eq!(p.int("D14:u32"), 1314258944);
    let e = common::errors("LD M0\nROR K2M0 D5 1\n");
    assert!(e.contains("`K2M0`: a bit group here must be K4"), "{e}");
}

/// §8.3 #51: the §4.7 examples (L4892-5204).
#[test]
fn real_arithmetic() {
    let src = "LD SM0\nRADD -10000.2 2000.5 D0\nRSUB -10000.2 2000.5 D2\nRMUL -10000.2 2000.5 D4\nRDIV -10000.2 2000.5 D6\n\
RSQT 10000.2 D8\nSIN 1.57 D10\nCOS 3.14 D12\nTAN 1.57 D14\nPOWER 55.0 3.0 D16\nLN 1000 D18\nEXP 10 D20\nRNEG D0 D22\nRVABS D0 D24\nRSUB 1.5 1.5 D26\n";
    let mut p = plc(src);
    p.scan();
    for (d, want) in [
        ("D0", -7999.7),
        ("D2", -12000.7),
        ("D4", -20005400.0),
        ("D6", -4.998850),
        ("D8", 100.000999),
        ("D10", 1.0),
        ("D12", -0.999999),
        ("D14", 1255.848398),
        ("D16", 166375.0),
        ("D18", 6.907755),
        ("D20", 22026.464844),
        ("D22", 7999.7),
        ("D24", 7999.7),
    ] {
        let got = p.real(&format!("{d}:f32"));
        assert!(close(got, want, 1e-5), "{d} = {got}, want {want}");
    }
    assert!(p.bit("SM180"), "the last one is 0");
    p = plc("LD SM0\nRDIV 1.0 D0 D2\nLD SM0\nRSQT -1.0 D4\n");
    p.scan();
    assert_eq!(p.int("SD20"), 64);
    assert_eq!(p.int("SD21"), 69);
}

/// §8.4 #52-58 and §8.3 #35-39, #44, #47-48, through programs.
#[test]
fn conversions_and_functions() {
    let src = "LD SM0\nDMOV 10000 D0\nDTI D0 D2\nITD -1000 D4\nFLT 10005 D6\nDFLT 100000 D8\nINT 10000.5 D10\n\
LD SM182\nOUT M0\nLD SM0\nDINT 100000.5 D12\nBCD 3333 D14\nBIN 16#5555 D15\nGRY 16#AAAA D16\nGBIN 16#FFFF D17\nSEG 15 D18\n\
SQT 1000 D19\nLD SM182\nOUT M1\nLD SM0\nDSQT 83000 D20\nVABS -1000 D22\nNEG 1000 D23\nDVABS -100000 D24\nDNEG 100000 D26\n\
DBCD 66666666 D28\nDBIN 16#99999999 D30\nDGRY 16#88888888 D32\nDGBIN 16#CCCCCCCC D34\nITD 1000 D36\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!(p.error_code(), None);
    assert_eq!((p.int("D2"), p.int("D4:i32")), (10000, -1000));
    assert_eq!(p.int("D36:i32"), 1000, "the manual's ITD (L5300)");
    assert_eq!((p.real("D6:f32"), p.real("D8:f32")), (10005.0, 100000.0));
    assert_eq!((p.int("D10"), p.int("D12:i32")), (10000, 100000));
    assert!(
        p.bit("M0") && p.bit("M1"),
        "INT and SQT dropped a fraction: B"
    );
    assert_eq!(
        [
            p.int("D14:u16"),
            p.int("D15"),
            p.int("D16:u16"),
            p.int("D17:u16"),
            p.int("D18")
        ],
        [0x3333, 5555, 0xFFFF, 0xAAAA, 0x71]
    );
    assert_eq!((p.int("D19"), p.int("D20:i32")), (31, 288));
    assert_eq!((p.int("D22"), p.int("D23")), (1000, -1000));
    assert_eq!((p.int("D24:i32"), p.int("D26:i32")), (100000, -100000));
    assert_eq!(
        [
            p.int("D28:u32"),
            p.int("D30:u32"),
            p.int("D32:u32"),
            p.int("D34:u32")
        ],
        [0x66666666, 99999999, 0xCCCCCCCC, 0x88888888]
    );
    let mut p = plc("LD SM0\nMOV 7 D1\nDTI 100000 D1\nBCD 10000 D2\n");
    p.scan();
    assert_eq!((p.int("D1"), p.int("SD20")), (7, 64));
}
