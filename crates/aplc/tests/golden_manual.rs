//! Golden tests of the §8 worked examples the other golden files do not cover
//! (spec aplc.md §8; seed 002 is the authority): the manual's own listings of
//! the contacts, the rotations through the carry, HACKLE and TRIANGLE with the
//! manual's operands, and the examples of instructions APLC-TCP does not
//! have (§11 D6-D7), which must be load errors.

mod common;
use common::{errors, plc, Plc};

/// Runs one scan with the given bits and returns Y0.
fn y0(p: &mut Plc, bits: &[(&str, bool)]) -> bool {
    for (b, v) in bits {
        p.set(b, if *v { "1" } else { "0" });
    }
    p.scan();
    p.bit("Y0")
}

/// §8.1 #1 (L2636-2648): `LD M0`, `AND M1`, `OUT Y0`: Y0 ON when M0 and M1
/// are ON, over the whole truth table.
#[test]
fn ld_and_out() {
    let mut p = plc("LD  M0\nAND M1\nOUT Y0\n");
    for (m0, m1) in [(false, false), (true, false), (false, true), (true, true)] {
        assert_eq!(y0(&mut p, &[("M0", m0), ("M1", m1)]), m0 && m1, "{m0} {m1}");
    }
}

/// §8.1 #2: the ANI (L2664-2670), OR (L2692-2698) and ORI (L2720-2726)
/// listings. The ORI sentence says "M1 ON or M2 OFF" while its listing reads
/// `LD M0` / `ORI M2`: the listing is the program, so M0 is tested.
#[test]
fn ani_or_ori() {
    type Truth = fn(bool, bool) -> bool;
    let cases: [(&str, Truth, &str); 3] = [
        ("LD  M0\nANI M1\nOUT Y0\n", |a, b| a && !b, "M1"),
        ("LD  M0\nOR  M1\nOUT Y0\n", |a, b| a || b, "M1"),
        ("LD  M0\nORI M2\nOUT Y0\n", |a, b| a || !b, "M2"),
    ];
    for (src, want, second) in cases {
        let mut p = plc(src);
        for (a, b) in [(false, false), (true, false), (false, true), (true, true)] {
            assert_eq!(
                y0(&mut p, &[("M0", a), (second, b)]),
                want(a, b),
                "{src} {a} {b}"
            );
        }
    }
}

/// §8.4 #61, the six cases golden_values.rs does not run (L6083, L6115,
/// L6181, L6215, L6248, L6346): RCR 5 and RCL 16 through the carry SM181,
/// DROL 30, DRCR 11, DRCL 25 and DSHR 10, with M0 ON and the manual's D0.
#[test]
fn rotations_through_carry() {
    let run = |src: &str, carry_in: bool| {
        let mut p = plc(&format!("LD M0\n{src}\nLD SM181\nOUT M1\n"));
        p.set("D0", "52629")
            .set("D20:u32", "3013123244")
            .set("D30:u32", "1939381420")
            .set("SM181", if carry_in { "1" } else { "0" })
            .set("M0", "1")
            .scan();
        p
    };
    let p = run("RCR D0 D10 5", false);
    assert_eq!((p.int("D10:u16"), p.bit("M1")), (22124, true));
    let p = run("RCL D0 D10 16", true);
    assert_eq!((p.int("D10:u16"), p.bit("M1")), (59082, true));
    let p = run("DROL D20 D10 30", false);
    assert_eq!((p.int("D10:u32"), p.bit("M1")), (753280811, true));
    let p = run("DRCR D20 D10 11", false);
    assert_eq!((p.int("D10:u32"), p.bit("M1")), (722891539, true));
    let p = run("DRCL D20 D10 25", false);
    assert_eq!((p.int("D10:u32"), p.bit("M1")), (1488165020, true));
    let p = run("DSHR D30 D10 10", false);
    assert_eq!(p.int("D10:u32"), 1893927);
}

/// §8.5 #73 with the manual's operands (L7940-7973, L8015-8048): D0 = 0,
/// D1 = 2000, 1000 steps, X0 drives. HACKLE: D10 = 2000 with M0 ON on scan
/// 1001, D10 = 0 with M0 OFF on scan 1002 (D10). TRIANGLE: 2000 on scan 1001,
/// back at 0 with M0 ON on scan 2001, M0 OFF on the next (D9).
#[test]
fn hackle_and_triangle_manual_operands() {
    let setup = "LD SM1\nMOV 0 D0\nMOV 2000 D1\n";
    let mut p = plc(&format!("{setup}LD X0\nHACKLE D0 D1 D10 1000 M0\n"));
    p.scan().set("X0", "1").scan();
    assert_eq!(p.int("D10"), 0, "the first scan outputs D0");
    p.scans(999);
    assert_eq!((p.int("D10"), p.bit("M0")), (1998, false));
    p.scan();
    assert_eq!((p.int("D10"), p.bit("M0")), (2000, true));
    p.scan();
    assert_eq!((p.int("D10"), p.bit("M0")), (0, false));
    p.set("X0", "0").scan();
    assert_eq!((p.int("D10"), p.bit("M0")), (0, false));

    let mut p = plc(&format!("{setup}LD X0\nTRIANGLE D0 D1 D10 1000 M0\n"));
    p.scan().set("X0", "1").scan();
    p.scans(1000);
    assert_eq!((p.int("D10"), p.bit("M0")), (2000, false));
    p.scans(999);
    assert_eq!((p.int("D10"), p.bit("M0")), (2, false));
    p.scan();
    assert_eq!((p.int("D10"), p.bit("M0")), (0, true));
    p.scan();
    assert_eq!((p.int("D10"), p.bit("M0")), (2, false));
    // A falling edge holds D10 with M0 OFF (L8048).
    p.set("X0", "0").scans(2);
    assert_eq!((p.int("D10"), p.bit("M0")), (2, false));
}

/// §8.4 #63 (TADD/TSUB, L6749-6811) and #64 (DCMP, L6892-6907): the
/// arithmetic of the examples is right, but the clock and date-compare
/// instructions are not on APLC-TCP (table 1-1 L682-683, §11 D6), so the
/// manual's listings are load errors naming the mnemonic.
#[test]
fn clock_examples_are_load_errors() {
    for (src, name) in [
        ("LD M0\nTADD D10 D20 D30\n", "TADD"),
        ("LD M0\nTSUB D10 D20 D30\n", "TSUB"),
        ("LD M0\nDCMP= D0 D10 M0\n", "DCMP="),
        ("LD M0\nDCMP<> D0 D10 M3\n", "DCMP<>"),
    ] {
        let e = errors(src);
        assert!(
            e.contains(&format!(
                "t.apl:2:1: unsupported instruction `{name}`: not available on APLC-TCP: no real-time clock"
            )),
            "{e}"
        );
    }
}

/// §8.4 #65 (DHSZ on C249, L7125-7158): APLC-TCP has no high-speed I/O
/// (table 1-1 L686, §11 D7): the listing `HCNT C249 …` / `DHSZ 1000 2000
/// C249 Y10` is a load error at both lines.
#[test]
fn high_speed_example_is_a_load_error() {
    let e = errors("LD X6\nHCNT C249 2000\nLD M1\nDHSZ 1000 2000 C249 Y10\n");
    for (line, name) in [(2, "HCNT"), (4, "DHSZ")] {
        assert!(
            e.contains(&format!(
                "t.apl:{line}:1: unsupported instruction `{name}`: not available on APLC-TCP: no high-speed I/O"
            )),
            "{e}"
        );
    }
}
