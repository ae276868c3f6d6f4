//! Golden tests of bit functions, word-bit contacts and coils, stacks, sums,
//! checksums, string shifts and ramps (spec aplc.md §4.5-§4.18, §8.1-§8.5).

mod common;
use common::plc;

/// §8.4 #67-70, §8.1 #16.
#[test]
fn bit_functions() {
    let mut p = plc("LD SM0\nDECO 2 D9\nDATO 15 D8\nENCO 2#0010 D10\nBITS 16#F0F0 D11\nDBITS 16#FF0FF D12\nDBITS 16#FFFFFFF0 K1M0\nMOV 1 D20\nDECO 16 D20\n");
    p.scan();
    assert_eq!(
        [
            p.int("D9"),
            p.int("D8:u16"),
            p.int("D10"),
            p.int("D11"),
            p.int("D12")
        ],
        [4, 0x8000, 1, 8, 16]
    );
    assert_eq!(p.int("K1M0"), 12, "28 stored as 12 into K1M0 (L1991-1998)");
    assert_eq!((p.int("D20"), p.int("SD20")), (1, 64));
}

/// §8.4 #71-72: D0 = 1000, bit 5 = 1 (L8858-9076).
#[test]
fn word_bits() {
    let src = "LD SM0\nMOV 1000 D0\nMOV 1000 D1\nMOV 1000 D2\nMOV 1000 D3\nBLD D0 5\nOUT Y0\nBLDI D0 5\nOUT Y1\nLD SM0\nBANI D0 5\nOUT Y2\n\
LDI SM0\nBOR D0 3\nOUT Y3\nLD M0\nBOUT D1 4\nLD SM0\nBSET D2 15\nBRST D3 8\n";
    let mut p = plc(src);
    p.scan();
    assert!(p.bit("Y0") && !p.bit("Y1") && !p.bit("Y2") && p.bit("Y3"));
    assert_eq!(
        [p.int("D1"), p.int("D2:u16"), p.int("D3")],
        [1000, 33768, 744]
    );
    p.set("M0", "1").scan();
    assert_eq!(p.int("D1"), 1016);
    p.set("M0", "0").scan();
    assert_eq!(p.int("D1"), 1000, "BOUT follows the power flow");
    let mut p = plc("BLD D0 16\nOUT Y0\n");
    p.scan();
    assert_eq!(p.error_code(), Some(64));
}

/// §8.2 #26-28 (L4113-4191).
#[test]
fn push_fifo_lifo() {
    let mut p = plc("LD M0\nPUSH D0 D100 10\n");
    p.set("D0", "1000").set("D100", "8").set("M0", "1").scan();
    assert_eq!((p.int("D100"), p.int("D109")), (9, 1000));
    p.set("D100", "10").scan();
    assert!(p.bit("SM181"), "full");
    assert_eq!(p.int("D100"), 10);
    let fill = |p: &mut common::Plc| {
        p.set("D100", "10");
        for k in 1..=10 {
            p.set(&format!("D{}", 100 + k), &(1000 * k).to_string());
        }
    };
    let mut p = plc("LD M0\nFIFO D100 D0 10\n");
    fill(&mut p);
    p.set("M0", "1").scan();
    assert_eq!(
        (
            p.int("D0"),
            p.int("D100"),
            p.int("D101"),
            p.int("D109"),
            p.int("D110")
        ),
        (1000, 9, 2000, 10000, 0)
    );
    assert!(!p.bit("SM180"));
    let mut p = plc("LD M0\nLIFO D100 D0 10\n");
    fill(&mut p);
    p.set("M0", "1").scan();
    assert_eq!(
        (p.int("D0"), p.int("D100"), p.int("D110")),
        (10000, 9, 10000)
    );
    p.set("D100", "1").scan();
    assert!(p.bit("SM180"), "the last element taken: empty (D15)");
    p.set("D100", "11").scan();
    assert_eq!(p.error_code(), Some(70));
}

/// §8.3 #49-50 (L4795-4861).
#[test]
fn sums() {
    let src = "LD SM1\nMOV 1000 D0\nMOV 2000 D1\nMOV 3000 D2\nMOV 4000 D3\nMOV 5000 D4\nSUM D0 5 D100\n\
DMOV 100000 D10\nDMOV 200000 D12\nDMOV 300000 D14\nDMOV 400000 D16\nDMOV 500000 D18\nDSUM D10 5 D102\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!((p.int("D100:i32"), p.int("D102:i32")), (15000, 1_500_000));
}

/// §8.5 #74 and D19: the Modbus request 01 01 00 00 01 00 gives 16#9A3D; chained in two
/// pieces the same; LRC of 00 11 … 77 is 16#24 (L8652-8667).
#[test]
fn checksums() {
    let src = "LD SM1\nMOV 1 D0\nMOV 1 D1\nMOV 0 D2\nMOV 0 D3\nMOV 1 D4\nMOV 0 D5\nMOV 16#FFFF D10\nCRC16 D0 6 D10\n\
MOV 16#FFFF D11\nCRC16 D0 3 D11\nCRC16 D3 3 D11\nMOV 0 D12\nCCITT D0 6 D12\n\
MOV 16#00 D20\nMOV 16#11 D21\nMOV 16#22 D22\nMOV 16#33 D23\nMOV 16#44 D24\nMOV 16#55 D25\nMOV 16#66 D26\nMOV 16#77 D27\nMOV 0 D30\nLRC D20 8 D30\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!((p.int("D10:u16"), p.int("D11:u16")), (0x9A3D, 0x9A3D));
    assert_eq!(p.int("D30"), 0x24);
}

/// §8.4 #62 and §8.2 #29-30 (L6423-6463, L4219-4271).
#[test]
fn string_shifts() {
    let setup = |p: &mut common::Plc| {
        for (k, v) in [1, 0, 1].iter().enumerate() {
            p.set(&format!("X{k}"), &v.to_string());
        }
        for (k, v) in [0, 1, 1, 0, 0, 1, 0, 0, 0, 1].iter().enumerate() {
            p.set(&format!("M{}", 10 + k), &v.to_string());
        }
        for k in 0..3 {
            p.set(&format!("D{k}"), &(100 * (k + 1)).to_string());
        }
        for k in 0..10 {
            p.set(&format!("D{}", 100 + k), &(1000 * (k + 1)).to_string());
        }
    };
    let bits = |p: &common::Plc| {
        (10..20)
            .map(|m| p.bit(&format!("M{m}")) as u8)
            .collect::<Vec<_>>()
    };
    let words = |p: &common::Plc| {
        (100..110)
            .map(|d| p.int(&format!("D{d}")))
            .collect::<Vec<_>>()
    };
    let mut p = plc("LD M0\nSFTR X0 M10 10 3\nWSFR D0 D100 10 3\n");
    setup(&mut p);
    p.set("M0", "1").scan();
    assert_eq!(bits(&p), [0, 0, 1, 0, 0, 0, 1, 1, 0, 1]);
    assert_eq!(
        words(&p),
        [4000, 5000, 6000, 7000, 8000, 9000, 10000, 100, 200, 300]
    );
    let mut p = plc("LD M0\nSFTL X0 M10 10 3\nWSFL D0 D100 10 3\n");
    setup(&mut p);
    p.set("M0", "1").scan();
    assert_eq!(bits(&p), [1, 0, 1, 0, 1, 1, 0, 0, 1, 0]);
    assert_eq!(
        words(&p),
        [100, 200, 300, 1000, 2000, 3000, 4000, 5000, 6000, 7000]
    );
}

/// §8.5 #73 (L7888, L7973, L8048; D9, D10, D20).
#[test]
fn ramps() {
    let mut p = plc("LD M0\nRAMP 0 2000 D10 1000 M1\n");
    p.set("M0", "1").scan();
    assert_eq!(p.int("D10"), 0);
    p.scans(3);
    assert_eq!(p.int("D10"), 6);
    p.scans(997);
    assert_eq!(p.int("D10"), 2000);
    assert!(p.bit("M1"));
    p.scan();
    assert_eq!(p.int("D10"), 2000);
    p.set("M0", "0").scan();
    assert!(!p.bit("M1"));
    // HACKLE 0 → 10 in 5: 0 2 4 6 8 10(D2) 0 2 …
    let mut p = plc("LD M0\nHACKLE 0 10 D10 5 M1\n");
    p.set("M0", "1");
    let mut seen = Vec::new();
    for _ in 0..8 {
        p.scan();
        seen.push((p.int("D10"), p.bit("M1")));
    }
    assert_eq!(
        seen,
        [
            (0, false),
            (2, false),
            (4, false),
            (6, false),
            (8, false),
            (10, true),
            (0, false),
            (2, false)
        ]
    );
    // TRIANGLE 0 → 10 in 5: period 10, D2 on the scan back at 0.
    let mut p = plc("LD M0\nTRIANGLE 0 10 D10 5 M1\n");
    p.set("M0", "1");
    let mut seen = Vec::new();
    for _ in 0..13 {
        p.scan();
        seen.push(p.int("D10"));
        if p.int("D10") == 0 && seen.len() > 1 {
            assert!(p.bit("M1"));
        }
    }
    assert_eq!(seen, [0, 2, 4, 6, 8, 10, 8, 6, 4, 2, 0, 2, 4]);
    let mut p = plc("LD SM0\nRAMP 0 10 D0 0 M1\n");
    p.scan();
    assert_eq!(p.error_code(), Some(64));
}

/// §8.4 #59: ITA and ATI with SM186 OFF and ON (L5695-5771).
#[test]
fn ita_ati() {
    let src = "LD SM0\nITA 16#9876 D20 6\nATI D10 D30 4\n";
    let mut p = plc(src);
    for (d, v) in [
        ("D10", 0x3938),
        ("D11", 0x3736),
        ("D12", 0x3534),
        ("D13", 0x3332),
    ] {
        p.set(d, &v.to_string());
    }
    p.scan();
    assert_eq!((p.int("D20:u16"), p.int("D21:u16")), (0x3839, 0x3637));
    assert_eq!(p.int("D30:u16"), 0x8967);
    p.set("SM186", "1").scan();
    assert_eq!(
        [p.int("D20"), p.int("D21"), p.int("D22"), p.int("D23")],
        [0x39, 0x38, 0x37, 0x36]
    );
    assert_eq!(p.int("D30:u16"), 0x8642);
    p.set("D10", &0x3961.to_string()).set("SM186", "0").scan();
    assert_eq!(p.int("SD20"), 64, "lower-case hex is not accepted");
}

/// REF is checked at load; REFF quantises (L6510-6571); RSUM (L5206-5239).
#[test]
fn ref_reff_rsum() {
    let mut p =
        plc("LD SM0\nREF X0 8\nREFF 30\nRMOV 100000.5 D0\nRMOV 50001.0 D2\nRSUM D0 2 D10\n");
    p.scan();
    assert_eq!(p.int("SD35"), 16);
    assert_eq!(p.real("D10:f32"), 150001.5);
    let e = common::errors("LD M0\nREF X4 8\nREF Y0 12\n");
    assert!(
        e.contains("t.apl:2:5: `X4`: REF starts at X or Y, a multiple of 8"),
        "{e}"
    );
    assert!(
        e.contains("t.apl:3:8: `12`: REF's count is a constant 8-256"),
        "{e}"
    );
}

/// PID by hand: P only (Kp 100 %, reverse): MV follows EV = SV − PV; with
/// TI = 25 (2.5 s) and Ts = 500 ms the first step adds Ts/TI·EV = 0.2·EV.
#[test]
fn pid_velocity_form() {
    let setup = "LD SM1\nMOV 1000 D500\nMOV 500 D510\nMOV 1 D511\nMOV 0 D512\nMOV 100 D513\nMOV 0 D514\nMOV 0 D515\nMOV 0 D516\nFMOV 0 D517 8\n\
LD SM0\nPID D500 D501 D510 D502\n";
    let mut p = plc(setup);
    p.scan_us = 500_000;
    p.scan(); // scan 1: no time elapsed yet (scan time 0 before the first END)
    p.scan();
    assert_eq!(p.int("D502"), 1000, "EV 1000");
    p.set("D501", "500").scan();
    assert_eq!(p.int("D502"), 500, "EV 500: ΔMV = −500");
    let mut p = plc(&setup.replace("MOV 0 D514", "MOV 25 D514"));
    p.scan_us = 500_000;
    p.scans(2);
    assert_eq!(p.int("D502"), 1200);
    p.scan();
    assert_eq!(p.int("D502"), 1400, "integral 200 a sample");
    // Output limits (bit 5): clamped to [D528, D527].
    let mut p = plc(&setup.replace("MOV 1 D511", "MOV 33 D511").replace(
        "FMOV 0 D517 8",
        "FMOV 0 D517 8\nMOV 600 D527\nMOV -100 D528",
    ));
    p.scan_us = 500_000;
    p.scans(2);
    assert_eq!(p.int("D502"), 600);
    // A parameter out of range is error 64.
    let mut p = plc(&setup.replace("MOV 100 D513", "MOV 0 D513"));
    p.scans(2);
    assert_eq!(p.error_code(), Some(64));
}

/// §8.4 #59: ASC "12345678" with SM186 OFF and ON (L5690-5693).
#[test]
fn asc() {
    let mut p = plc("LD M0\nASC 16#31 16#32 16#33 16#34 16#35 16#36 16#37 16#38 D0\n");
    p.set("M0", "1").scan();
    assert_eq!(
        [p.int("D0"), p.int("D1"), p.int("D2"), p.int("D3")],
        [0x3231, 0x3433, 0x3635, 0x3837]
    );
    p.set("SM186", "1").scan();
    assert_eq!(
        (0..8).map(|k| p.int(&format!("D{k}"))).collect::<Vec<_>>(),
        (0x31..=0x38).collect::<Vec<_>>()
    );
    let e = common::errors("LD M0\nASC 16#20 D0\n");
    assert!(
        e.contains("`16#20`: ASC takes character codes 16#21-16#7E"),
        "{e}"
    );
}
