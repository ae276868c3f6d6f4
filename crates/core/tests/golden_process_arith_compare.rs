//! Process-control arithmetic and comparisons (000 ch. 11-12) on a process
//! CPU; values worked out from the manual's formulas in f32.

mod common;
use common::Plc;
use softplc_core::program::ProcessSettings;

fn fails(p: &Plc, detail: i64) {
    assert_eq!(p.error().map(|e| e.0), Some(4100));
    assert_eq!((p.int("SD1502"), p.int("SD1503")), (detail, 1));
}

const ADD: &str = "LD SM400\nS.ADD D0 D100 D20 SD1506\nEND\n";
const SUB: &str = "LD SM400\nS.SUB D0 D100 D20 SD1506\nEND\n";
const MUL: &str = "LD SM400\nS.MUL D0 D100 D20 SD1506\nEND\n";

/// Inputs n, E at D0; coefficients n, K and B at D20.
fn terms(src: &str, s: ProcessSettings, e: &[f32], k: &[f32], b: f32) -> Plc {
    let mut p = Plc::process_with(src, s);
    p.set("D0", &e.len().to_string())
        .set("D20", &k.len().to_string());
    for (i, v) in e.iter().enumerate() {
        p.set(&format!("D{}:f32", 1 + 2 * i), &v.to_string());
    }
    for (i, v) in k.iter().enumerate() {
        p.set(&format!("D{}:f32", 21 + 2 * i), &v.to_string());
    }
    p.set(&format!("D{}:f32", 21 + 2 * k.len()), &b.to_string());
    p.scan();
    p
}

fn bw(src: &str, e: &[f32], k: &[f32], b: f32) -> f64 {
    let p = terms(src, ProcessSettings::default(), e, k, b);
    assert_eq!(p.error(), None);
    p.real("D100")
}

/// Spec §7: 50 and 100 with K = 1, 1 and B = 0: S.ADD 150, S.SUB −50, S.MUL
/// 5000; coefficients and the bias (added, DEC-30); n = 0 gives B.
#[test]
fn s_add_s_sub_s_mul_weighted_terms_plus_bias() {
    let one = [1.0, 1.0];
    assert_eq!(bw(ADD, &[50.0, 100.0], &one, 0.0), 150.0);
    assert_eq!(bw(SUB, &[50.0, 100.0], &one, 0.0), -50.0);
    assert_eq!(bw(MUL, &[50.0, 100.0], &one, 0.0), 5000.0);
    assert_eq!(bw(ADD, &[50.0, 100.0], &[2.0, 0.5], 3.0), 153.0);
    assert_eq!(bw(SUB, &[50.0, 100.0], &one, 3.0), -47.0);
    assert_eq!(bw(SUB, &[10.0, 2.0, 3.0], &[1.0; 3], 0.0), 5.0);
    assert_eq!(bw(MUL, &[2.0, 3.0, 4.0], &[1.0, 1.0, 0.5], 1.0), 13.0);
    let five = [1.0, 2.0, 3.0, 4.0, 5.0];
    assert_eq!(bw(ADD, &five, &[0.5; 5], 0.0), 7.5);
    for src in [ADD, SUB, MUL] {
        assert_eq!(bw(src, &[], &[], 7.0), 7.0, "n = 0: BW = B");
    }
}

/// DEC-29: the input n sets the terms; K2 is read from S2+3, which with a
/// coefficient n of 1 is B (2·5 + 10·4 + 10). DEC-30 alternative: B is
/// subtracted. DEC-29's alternative is not described: rejected at load.
#[test]
fn s_add_dec_29_and_dec_30() {
    assert_eq!(bw(ADD, &[5.0, 4.0], &[2.0], 10.0), 60.0);
    let alt = ProcessSettings {
        arith_bias_added: false,
        ..ProcessSettings::default()
    };
    assert_eq!(
        terms(ADD, alt, &[50.0, 100.0], &[1.0, 1.0], 3.0).real("D100"),
        147.0
    );
    assert_eq!(terms(SUB, alt, &[], &[], 7.0).real("D100"), -7.0);
    let alt = ProcessSettings {
        arith_input_n: false,
        ..ProcessSettings::default()
    };
    assert!(
        common::process_diagnostics_with(MUL, alt)[0].contains("arith_input_n = false (DEC-29)")
    );
}

/// Either n outside 0..5 is 4100 with SD1502 = 3; an overflowing product is
/// SD1502 = 6; a bad float 1.
#[test]
fn s_add_s_sub_s_mul_errors() {
    let mut p = Plc::process(ADD);
    p.set("D0", "6").scan();
    fails(&p, 3);
    let mut p = Plc::process(SUB);
    p.set("D20", "-1").scan();
    fails(&p, 3);
    let p = terms(
        MUL,
        ProcessSettings::default(),
        &[1e30, 1e30],
        &[1.0, 1.0],
        0.0,
    );
    fails(&p, 6);
    let mut p = Plc::process(ADD);
    p.set("D0", "1")
        .set("D20", "1")
        .set("D1", "-1")
        .set("D2", "-1")
        .scan();
    fails(&p, 1);
}

const DIV: &str = "LD SM400\nS.DIV D0 D100 D10 SD1506\nEND\n";

/// 000 §11.4: spec §7 50/100 → 0.5; A × (K1·E1 + B1)/(K2·E2 + B2) + B3; a
/// zero denominator gives B3 and is not an error (spec §5).
#[test]
fn s_div_divides_and_gives_b3_for_a_zero_denominator() {
    let mut p = Plc::process(DIV);
    p.set("D0:f32", "50").set("D2:f32", "100");
    for (i, v) in ["1", "1", "1", "0", "0", "0"].iter().enumerate() {
        p.set(&format!("D{}:f32", 10 + 2 * i), v);
    }
    p.scan();
    assert_eq!(p.real("D100"), 0.5);
    for (i, v) in ["2", "1", "2", "10", "-40", "1"].iter().enumerate() {
        p.set(&format!("D{}:f32", 10 + 2 * i), v);
    }
    p.scan();
    assert_eq!(p.real("D100"), 1.75, "2 × 60/160 + 1");
    p.set("D2:f32", "20").scan();
    assert_eq!(p.real("D100"), 1.0, "2·20 − 40 = 0: B3");
    assert_eq!(p.error(), None);
}

const SQR: &str = "LD SM400\nS.SQR D0 D100 D10 SD1506\nEND\n";

/// 000 §11.5: spec §7 S.SQR 50 with K = 10 → 70.71068; at or below the low
/// cut and for E1 < 0 the output is 0.
#[test]
fn s_sqr_square_root_with_low_cut() {
    let mut p = Plc::process(SQR);
    p.set("D0:f32", "50")
        .set("D10:f32", "0")
        .set("D12:f32", "10")
        .scan();
    let v = 10.0f32 * 50f32.sqrt();
    assert_eq!(p.real("D100"), v as f64);
    assert!((p.real("D100") - 70.71068).abs() < 1e-5);
    p.set("D10:f32", &v.to_string()).scan();
    assert_eq!(p.real("D100"), 0.0, "K·√E1 = OLC");
    p.set("D10:f32", "70").scan();
    assert_eq!(p.real("D100"), v as f64);
    p.set("D0:f32", "-4").scan();
    assert_eq!(p.real("D100"), 0.0);
    assert_eq!(p.error(), None);
}

/// 000 §11.6: spec §7 S.ABS(50) → 50, BB1 = 1; the sign bits; other BB
/// bits are left as found.
#[test]
fn s_abs_absolute_value_and_sign_bits() {
    let mut p = Plc::process("LD SM400\nS.ABS D0 D100 SD1506 SD1506\nEND\n");
    p.set("D102", "16");
    for (e1, bw, bb) in [(50.0, 50.0, 17), (-2.5, 2.5, 18), (0.0, 0.0, 16)] {
        p.set("D0:f32", &format!("{e1}")).scan();
        assert_eq!((p.real("D100"), p.int("D102")), (bw, bb), "{e1}");
    }
}

/// Runs one comparison with E2 = 100, K = 0, HS = `hs` over `e1`, BB1 after
/// each (BW = E1 checked).
fn compare(src: &str, s: ProcessSettings, hs: &str, e1: &[f32]) -> Vec<i64> {
    let mut p = Plc::process_with(src, s);
    p.set("D2:f32", "100")
        .set("D10:f32", "0")
        .set("D12:f32", hs);
    e1.iter()
        .map(|v| {
            p.set("D0:f32", &v.to_string()).scan();
            assert_eq!(p.error(), None);
            assert_eq!(p.real("D100"), *v as f64, "BW = E1");
            p.int("D102")
        })
        .collect()
}

const GT: &str = "LD SM400\nS.> D0 D100 D10 SD1506\nEND\n";
const LT: &str = "LD SM400\nS.< D0 D100 D10 SD1506\nEND\n";
const EQ: &str = "LD SM400\nS.= D0 D100 D10 SD1506\nEND\n";
const GE: &str = "LD SM400\nS.>= D0 D100 D10 SD1506\nEND\n";
const LE: &str = "LD SM400\nS.<= D0 D100 D10 SD1506\nEND\n";

/// 000 §12, DEC-31 with HS = 5 around E2 + K = 100: set on the named
/// relation, reset on the complementary edge shifted by HS, held between.
#[test]
fn comparisons_with_hysteresis_hold_between_the_edges() {
    let d = ProcessSettings::default();
    // Spec §7: S.>(50, 100, K = 0) → BB1 = 0, BW = 50.
    assert_eq!(
        compare(GT, d, "5", &[50.0, 101.0, 100.0, 95.5, 95.0, 97.0, 100.5]),
        [0, 1, 1, 1, 0, 0, 1]
    );
    assert_eq!(
        compare(LT, d, "5", &[150.0, 99.0, 100.0, 104.5, 105.0, 102.0, 99.5]),
        [0, 1, 1, 1, 0, 0, 1]
    );
    assert_eq!(
        compare(GE, d, "5", &[50.0, 100.0, 96.0, 95.0, 94.5, 99.5, 100.0]),
        [0, 1, 1, 1, 0, 0, 1]
    );
    assert_eq!(
        compare(
            LE,
            d,
            "5",
            &[150.0, 100.0, 104.0, 105.0, 105.5, 100.5, 100.0]
        ),
        [0, 1, 1, 1, 0, 0, 1]
    );
    assert_eq!(
        compare(EQ, d, "5", &[100.0, 100.5, 100.0, 99.0]),
        [1, 0, 1, 0]
    );
}

/// With HS = 0 every input sets or resets (complementary edges, DEC-31);
/// the alternative's exclusive reset edge holds at E1 = X (S.>, S.<) and
/// resets at E1 = X − HS (S.>=).
#[test]
fn comparisons_dec_31_boundaries() {
    let d = ProcessSettings::default();
    assert_eq!(compare(GT, d, "0", &[101.0, 100.0]), [1, 0]);
    assert_eq!(compare(LT, d, "0", &[99.0, 100.0]), [1, 0]);
    assert_eq!(compare(GE, d, "0", &[100.0, 99.9]), [1, 0]);
    assert_eq!(compare(LE, d, "0", &[100.0, 100.1]), [1, 0]);
    let alt = ProcessSettings {
        compare_complementary: false,
        ..d
    };
    assert_eq!(compare(GT, alt, "0", &[101.0, 100.0, 99.0]), [1, 1, 0]);
    assert_eq!(compare(LT, alt, "0", &[99.0, 100.0, 101.0]), [1, 1, 0]);
    assert_eq!(compare(GE, alt, "5", &[100.0, 95.0]), [1, 0]);
    assert_eq!(compare(LE, alt, "5", &[100.0, 105.0]), [1, 0]);
}

/// K shifts the comparison point; other BB bits are kept; HS < 0 is 4100
/// with SD1502 = 2 (not for S.=, which has no HS).
#[test]
fn comparisons_set_value_and_errors() {
    let mut p = Plc::process(GE);
    p.set("D0:f32", "50")
        .set("D2:f32", "100")
        .set("D10:f32", "-60");
    p.set("D102", "256").scan();
    assert_eq!(p.int("D102"), 257, "50 ≥ 100 − 60");
    for src in [GT, LT, GE, LE] {
        let mut p = Plc::process(src);
        p.set("D12:f32", "-1").scan();
        fails(&p, 2);
    }
    let mut p = Plc::process(EQ);
    p.set("D0:f32", "3").set("D2:f32", "1").set("D10:f32", "2");
    p.set("D12", "-1").set("D13", "-1").scan();
    assert_eq!((p.int("D102"), p.error()), (1, None));
}
