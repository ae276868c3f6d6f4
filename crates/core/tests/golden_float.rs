//! Golden tests of the real-number function instructions (programming manual
//! §7.12: SIN, COS, TAN, ASIN, ACOS, ATAN, SQR, EXP, LOG). Every expected value is
//! worked out by hand next to it. Single-precision bit patterns used below:
//!
//! - π/2 = 1.5707963267…; the nearest f32 is 3FC90FDBH = 1.5707963705 (error
//!   4.4·10⁻⁸, half an ulp is 6·10⁻⁸).
//! - π = 3.1415926535…; f32 40490FDBH = 3.1415927410, i.e. π + 8.742278·10⁻⁸.
//! - π/4: f32 3F490FDBH = 0.7853981853 (the π pattern with the exponent − 2).
//! - e = 2.7182818284…; f32 402DF854H = 2.7182817459 (error 8.3·10⁻⁸; the next
//!   pattern 402DF855H = 2.7182819843 is 1.6·10⁻⁷ away).
//! - √2 = 1.4142135623…; f32 3FB504F3H = 1.4142135382 (error 2.4·10⁻⁸; 3FB504F4H
//!   = 1.4142136574 is 9.5·10⁻⁸ away).

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};

const HALF_PI: i64 = 0x3FC9_0FDB;
const PI: i64 = 0x4049_0FDB;
const QUARTER_PI: i64 = 0x3F49_0FDB;
const E: i64 = 0x402D_F854;
const SQRT2: i64 = 0x3FB5_04F3;

/// One unit in the last place of an f32 near `v` (v a normal number).
fn ulp(v: f64) -> f64 {
    let f = v.abs() as f32;
    (f32::from_bits(f.to_bits() + 1) - f) as f64
}

/// Runs `<INSTR> E<x> D0` once and returns the CPU.
fn run1(instr: &str, x: &str) -> Plc {
    let mut p = Plc::new(&format!("LD SM400\n{instr} E{x} D0\nEND\n"));
    p.set("D0:f32", "7").scan();
    p
}

// ------------------------------------------------------------ trigonometric

#[test]
fn sin_cos_exact_values() {
    let mut p = Plc::new(
        "LD SM400\n\
         SIN E0 D0\n\
         COS E0 D2\n\
         SIN D100 D4\n\
         COS D102 D6\n\
         SIN D102 D8\n\
         END\n",
    );
    // D100 = f32 π/2, D102 = f32 π (patterns in the file header).
    p.set("D100:u32", &HALF_PI.to_string())
        .set("D102:u32", &PI.to_string())
        .scan();
    assert_running(&p);
    // sin 0 = 0, cos 0 = 1.
    assert_eq!(p.int("D0:u32"), 0);
    assert_eq!(p.real("D2"), 1.0);
    // sin(π/2 + 4.4·10⁻⁸) = 1 − (4.4·10⁻⁸)²/2 = 1 − 10⁻¹⁵ → rounds to 1.0.
    assert_eq!(p.real("D4"), 1.0);
    // cos(π + δ) = −1 + δ²/2 → −1.0 (BF800000H).
    assert_eq!(p.int("D6:u32"), 0xBF80_0000);
    // sin(π + δ) = −sin δ = −δ with δ = 3.1415927410 − 3.1415926536 = 8.742278·10⁻⁸:
    // the single-precision π is not a zero of SIN.
    let v = p.real("D8");
    assert!((v + 8.742278e-8).abs() < 1e-14, "{v}");
}

#[test]
fn sin_of_thirty_degrees_within_one_ulp() {
    // π/6 = 0.5235987756; as f32 it is off by at most half an ulp (2^-25 ≈ 3·10⁻⁸),
    // so sin = 0.5 ± cos(π/6)·3·10⁻⁸ = 0.5 ± 2.6·10⁻⁸: within one ulp of 0.5.
    let p = run1("SIN", "0.5235988");
    assert_running(&p);
    let v = p.real("D0");
    assert!((v - 0.5).abs() <= ulp(0.5), "{v}");
    // Negative angle: sin(−π/6) = −0.5.
    let p = run1("SIN", "-0.5235988");
    let v = p.real("D0");
    assert!((v + 0.5).abs() <= ulp(0.5), "{v}");
    // cos(π/3) = 0.5 (π/3 = 1.0471975512).
    let p = run1("COS", "1.0471976");
    let v = p.real("D0");
    assert!((v - 0.5).abs() <= ulp(0.5), "{v}");
}

#[test]
fn tan_values_and_poles() {
    // tan 0 = 0.
    let p = run1("TAN", "0");
    assert_eq!(p.int("D0:u32"), 0);
    // tan(π/4 + δ) = 1 + 2δ with |δ| ≤ 3·10⁻⁸ → within one ulp of 1.0.
    let p = run1("TAN", "0.7853982");
    assert_running(&p);
    let v = p.real("D0");
    assert!((v - 1.0).abs() <= ulp(1.0), "{v}");
    // tan(−π/4) = −1.
    let p = run1("TAN", "-0.7853982");
    let v = p.real("D0");
    assert!((v + 1.0).abs() <= ulp(1.0), "{v}");
    // π/2 (E1.5707964 rounds to 3FC90FDBH = 1.5707963705, 3.0·10⁻⁸ away, half
    // an ulp being 6·10⁻⁸), −π/2 and 3π/2 = 4.7123889804 are the poles of the
    // manual: OPERATION ERROR, D0 keeps its 7.0.
    for x in ["1.5707964", "-1.5707964", "4.712389"] {
        let p = run1("TAN", x);
        assert_stopped(&p, 4100);
        assert_eq!(p.real("D0"), 7.0, "{x}");
    }
    // Next to the pole (one f32 step below π/2, 3FC90FDAH = 1.5707962513) the
    // tangent is 1/(π/2 − x) = 1/7.5·10⁻⁸ ≈ 1.3·10⁷: no error.
    let mut p = Plc::new("LD SM400\nTAN D10 D0\nEND\n");
    p.set("D10:u32", &(HALF_PI - 1).to_string()).scan();
    assert_running(&p);
    let v = p.real("D0");
    assert!((1.3e7..1.4e7).contains(&v), "{v}");
}

#[test]
fn inverse_functions_exact_patterns() {
    let mut p = Plc::new(
        "LD SM400\n\
         ASIN E1 D0\n\
         ASIN E-1 D2\n\
         ACOS E-1 D4\n\
         ACOS E1 D6\n\
         ATAN E1 D8\n\
         ATAN E1+30 D10\n\
         ASIN E0 D12\n\
         ACOS E0 D14\n\
         END\n",
    );
    p.set("D6:f32", "5").scan();
    assert_running(&p);
    // asin 1 = π/2 → 3FC90FDBH; asin −1 = −π/2 → sign bit set: BFC90FDBH.
    assert_eq!(p.int("D0:u32"), HALF_PI);
    assert_eq!(p.int("D2:u32"), HALF_PI | 0x8000_0000);
    // acos −1 = π → 40490FDBH; acos 1 = 0 (the 5.0 written before is replaced).
    assert_eq!(p.int("D4:u32"), PI);
    assert_eq!(p.int("D6:u32"), 0);
    // atan 1 = π/4 → 3F490FDBH; atan 10³⁰ = π/2 − 10⁻³⁰ → π/2.
    assert_eq!(p.int("D8:u32"), QUARTER_PI);
    assert_eq!(p.int("D10:u32"), HALF_PI);
    // asin 0 = 0; acos 0 = π/2.
    assert_eq!(p.int("D12:u32"), 0);
    assert_eq!(p.int("D14:u32"), HALF_PI);
}

#[test]
fn asin_acos_outside_minus_one_to_one() {
    for (i, x) in [
        ("ASIN", "1.0001"),
        ("ASIN", "-2"),
        ("ACOS", "1.5"),
        ("ACOS", "-1.0001"),
    ] {
        let p = run1(i, x);
        assert_stopped(&p, 4100);
        assert_eq!(p.real("D0"), 7.0, "{i} {x}");
    }
    // asin 0.5 = π/6 = 0.5235987756 (within one ulp).
    let p = run1("ASIN", "0.5");
    let v = p.real("D0");
    assert!((v - std::f64::consts::FRAC_PI_6).abs() <= ulp(0.52), "{v}");
}

// ------------------------------------------------------------ SQR, EXP, LOG

#[test]
fn sqr_values() {
    let mut p = Plc::new(
        "LD SM400\n\
         SQR E16 D0\n\
         SQR E2 D2\n\
         SQR E0 D4\n\
         SQR E2.25 D6\n\
         SQR E1-4 D8\n\
         END\n",
    );
    p.set("D4:f32", "3").scan();
    assert_running(&p);
    // √16 = 4, √2 = 3FB504F3H, √0 = 0, √2.25 = 1.5.
    assert_eq!(p.real("D0"), 4.0);
    assert_eq!(p.int("D2:u32"), SQRT2);
    assert_eq!(p.int("D4:u32"), 0);
    assert_eq!(p.real("D6"), 1.5);
    // √(10⁻⁴) = 0.01, within one ulp.
    let v = p.real("D8");
    assert!((v - 0.01).abs() <= ulp(0.01), "{v}");
}

#[test]
fn sqr_of_negative_stops() {
    let p = run1("SQR", "-1");
    assert_stopped(&p, 4100);
    assert_eq!(p.real("D0"), 7.0);
    // The smallest negative value is still negative.
    let p = run1("SQR", "-1.2-38");
    assert_stopped(&p, 4100);
}

#[test]
fn exp_values_and_overflow() {
    let mut p = Plc::new(
        "LD SM400\n\
         EXP E0 D0\n\
         EXP E1 D2\n\
         EXP E-100 D4\n\
         EXP E2 D6\n\
         END\n",
    );
    p.set("D4:f32", "3").scan();
    assert_running(&p);
    // e⁰ = 1; e¹ = 402DF854H.
    assert_eq!(p.real("D0"), 1.0);
    assert_eq!(p.int("D2:u32"), E);
    // e⁻¹⁰⁰ = 3.7·10⁻⁴⁴ is below the smallest real (1.18·10⁻³⁸): stored as 0.
    assert_eq!(p.int("D4:u32"), 0);
    // e² = 7.3890560989, within one ulp.
    let v = p.real("D6");
    assert!((v - 7.389_056_098_9).abs() <= ulp(7.39), "{v}");
    // e⁸⁸ = 1.65·10³⁸ fits (max 3.40·10³⁸); e⁸⁹ = 4.49·10³⁸ does not → 4100.
    let p = run1("EXP", "88");
    assert_running(&p);
    let v = p.real("D0");
    assert!((1.6e38..1.7e38).contains(&v), "{v}");
    let p = run1("EXP", "89");
    assert_stopped(&p, 4100);
    assert_eq!(p.real("D0"), 7.0);
}

#[test]
fn log_values_and_domain() {
    let mut p = Plc::new(
        "LD SM400\n\
         LOG E1 D0\n\
         LOG D100 D2\n\
         LOG E10 D4\n\
         LOG E0.5 D6\n\
         END\n",
    );
    p.set("D0:f32", "3").set("D100:u32", &E.to_string()).scan();
    assert_running(&p);
    // ln 1 = 0.
    assert_eq!(p.int("D0:u32"), 0);
    // ln(2.7182817459) = 1 + (2.7182817459 − 2.7182818285)/e = 1 − 3.04·10⁻⁸:
    // within one ulp of 1.
    let v = p.real("D2");
    assert!((v - 1.0).abs() <= ulp(1.0), "{v}");
    // ln 10 = 2.302585093; ln 0.5 = −ln 2 = −0.6931471806.
    let v = p.real("D4");
    assert!((v - std::f64::consts::LN_10).abs() <= ulp(2.3), "{v}");
    let v = p.real("D6");
    assert!((v + std::f64::consts::LN_2).abs() <= ulp(0.69), "{v}");
    for x in ["0", "-1"] {
        let p = run1("LOG", x);
        assert_stopped(&p, 4100);
        assert_eq!(p.real("D0"), 7.0, "{x}");
    }
}

// ------------------------------------------------------------ operands

#[test]
fn invalid_real_input_is_operation_error() {
    // 7F800000H is +∞, 7FC00000H a NaN, FF800000H −∞: not real numbers for the CPU.
    for bits in ["0x7F800000", "0x7FC00000", "0xFF800000"] {
        for instr in ["SIN", "COS", "ATAN", "EXP", "SQR"] {
            let mut p = Plc::new(&format!("LD SM400\n{instr} D10 D0\nEND\n"));
            p.set("D10:u32", bits).scan();
            assert_stopped(&p, 4100);
        }
    }
    // A denormal input (00000001H) reads as 0: COS gives 1.
    let mut p = Plc::new("LD SM400\nCOS D10 D0\nEND\n");
    p.set("D10:u32", "1").scan();
    assert_running(&p);
    assert_eq!(p.real("D0"), 1.0);
}

#[test]
fn condition_off_does_nothing() {
    let mut p = Plc::new("LD X0\nSQR E16 D0\nEND\n");
    p.set("D0:f32", "9").scan();
    assert_eq!(p.real("D0"), 9.0);
    // Even a domain error is not raised while the condition is OFF.
    let mut p = Plc::new("LD X0\nSQR E-4 D0\nEND\n");
    p.scan();
    assert_running(&p);
}

#[test]
fn pulse_form_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nSQRP D10 D0\nLD X0\nSQR D10 D2\nEND\n");
    // Scan 1: X0 rises, D10 = 16 → both give 4.
    p.set("X0", "1").set("D10:f32", "16").scan();
    assert_eq!(p.real("D0"), 4.0);
    assert_eq!(p.real("D2"), 4.0);
    // Scan 2: X0 stays ON, D10 = 25 → SQRP does not run, SQR gives 5.
    p.set("D10:f32", "25").scan();
    assert_eq!(p.real("D0"), 4.0);
    assert_eq!(p.real("D2"), 5.0);
    // X0 OFF, then ON again: a new rising edge → SQRP gives 5.
    p.set("X0", "0").scan();
    assert_eq!(p.real("D0"), 4.0);
    p.set("X0", "1").scan();
    assert_eq!(p.real("D0"), 5.0);
    // EXPP: EXP ends in P itself; its pulse form is EXPP.
    let mut p = Plc::new("LD X0\nEXPP D10 D0\nEND\n");
    p.set("D10:f32", "0").set("X0", "1").scan();
    assert_eq!(p.real("D0"), 1.0);
    p.set("D10:f32", "1").scan();
    assert_eq!(p.real("D0"), 1.0);
}

#[test]
fn index_modification_and_range() {
    let mut p = Plc::new("LD SM400\nSQR D0Z1 D10Z1\nEND\n");
    // Z1 = 4: SQR D4 D14; D4 = 9 → D14 = 3; D10 stays 0.
    p.set("Z1", "4").set("D4:f32", "9").scan();
    assert_running(&p);
    assert_eq!(p.real("D14"), 3.0);
    assert_eq!(p.int("D10:u32"), 0);
    // Z1 = 12287: the source D12287-D12288 runs past D12287 (12288 points) → 4101.
    let mut p = Plc::new("LD SM400\nSQR D0Z1 D10\nEND\n");
    p.set("Z1", "12287").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn load_time_operand_checks() {
    let d = diagnostics("LD SM400\nSIN K1 D0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:5:"), "{d:?}");
    let d = diagnostics("LD SM400\nLOG D0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    let d = diagnostics("LD SM400\nCOS E1 E2\nEND\n");
    assert!(d[0].contains("destination"), "{d:?}");
}

// ------------------------------------------------------------ BCD type

/// Runs one BCD instruction with `S` preset and returns the CPU.
fn bcd_run(src: &str, setup: &[(&str, &str)]) -> Plc {
    let mut p = Plc::new(&format!("LD SM400\n{src}\nEND\n"));
    for (d, v) in setup {
        p.set(d, v);
    }
    p.scan();
    p
}

/// Words `D<n>`… as unsigned 16-bit values.
fn words<const N: usize>(p: &Plc, n: u32) -> [i64; N] {
    std::array::from_fn(|k| p.int(&format!("D{}:u16", n + k as u32)))
}

#[test]
fn bsqr_and_bdsqr() {
    let p = bcd_run(
        "BSQR H2 D0\nBSQR H9999 D2\nBSQR H16 D4\nBSQR H0 D6\nBDSQR H1000000 D8",
        &[("D7", "5")],
    );
    assert_running(&p);
    // √2 = 1.41421356… → 14142.1356 ten-thousandths → 1 and 4142 (BCD 4142H).
    assert_eq!(words::<2>(&p, 0), [0x1, 0x4142]);
    // √9999 = 99.99499987… → 999949.9987 → 999950 → 99 and 9950.
    assert_eq!(words::<2>(&p, 2), [0x99, 0x9950]);
    // BCD 16H is sixteen: √16 = 4.0000.
    assert_eq!(words::<2>(&p, 4), [0x4, 0]);
    assert_eq!(words::<2>(&p, 6), [0, 0]);
    // BCD 01000000H is one million: √ = 1000 → BCD 1000H.
    assert_eq!(words::<2>(&p, 8), [0x1000, 0]);
    // 12A4H is not BCD.
    assert_stopped(&bcd_run("BSQR H12A4 D0", &[]), 4100);
}

#[test]
fn bsin_bcos_btan() {
    let p = bcd_run(
        "BSIN H30 D0\nBSIN H270 D3\nBSIN H180 D6\nBSIN H45 D9\n\
         BCOS H60 D12\nBCOS H120 D15\nBTAN H45 D18\nBTAN H89 D21\nBTAN H135 D24",
        &[("D6", "9")],
    );
    assert_running(&p);
    // sin 30° = 0.5: sign 0, integer 0, decimals 5000H.
    assert_eq!(words::<3>(&p, 0), [0, 0, 0x5000]);
    // sin 270° = −1: sign 1, integer 1, decimals 0.
    assert_eq!(words::<3>(&p, 3), [1, 1, 0]);
    // sin 180° = 1.2·10⁻¹⁶ in double precision → 0.0000, sign 0 (D6 preset 9).
    assert_eq!(words::<3>(&p, 6), [0, 0, 0]);
    // sin 45° = 0.70710678 → 7071.0678 → 7071.
    assert_eq!(words::<3>(&p, 9), [0, 0, 0x7071]);
    // cos 60° = 0.5; cos 120° = −0.5.
    assert_eq!(words::<3>(&p, 12), [0, 0, 0x5000]);
    assert_eq!(words::<3>(&p, 15), [1, 0, 0x5000]);
    // tan 45° = 1; tan 89° = 57.28996163 → 572899.6163 → 572900 → 57 and 2900.
    assert_eq!(words::<3>(&p, 18), [0, 1, 0]);
    assert_eq!(words::<3>(&p, 21), [0, 0x57, 0x2900]);
    // tan 135° = −1.
    assert_eq!(words::<3>(&p, 24), [1, 1, 0]);
    // Errors: tan 90° and 270°, an angle above 360, a non-BCD angle.
    for src in ["BTAN H90 D0", "BTAN H270 D0", "BSIN H361 D0", "BCOS H1A D0"] {
        assert_stopped(&bcd_run(src, &[]), 4100);
    }
}

#[test]
fn basin_bacos_batan() {
    // S = sign, integer part, 4 decimals (BCD); D = whole degrees (BCD).
    let cases: [(&str, [&str; 3], i64); 9] = [
        // asin 0.5 = 30°; asin −0.5 = −30° → 330°; asin 1 = 90°.
        ("BASIN", ["0", "0", "H5000"], 0x30),
        ("BASIN", ["1", "0", "H5000"], 0x330),
        ("BASIN", ["0", "1", "0"], 0x90),
        // acos 0.5 = 60°; acos −0.5 = 120°; acos −1 = 180°.
        ("BACOS", ["0", "0", "H5000"], 0x60),
        ("BACOS", ["1", "0", "H5000"], 0x120),
        ("BACOS", ["1", "1", "0"], 0x180),
        // atan 1 = 45°; atan −1 = −45° → 315°; atan 9999.9999 = 89.994° → 90°.
        ("BATAN", ["0", "1", "0"], 0x45),
        ("BATAN", ["1", "1", "0"], 0x315),
        ("BATAN", ["0", "H9999", "H9999"], 0x90),
    ];
    for (i, s, want) in cases {
        let p = bcd_run(
            &format!("{i} D0 D10"),
            &[("D0", s[0]), ("D1", s[1]), ("D2", s[2])],
        );
        assert_running(&p);
        assert_eq!(p.int("D10:u16"), want, "{i} {s:?}");
    }
    // 1.0001 is outside −1 … 1; sign 2 is undefined; 1A00H is not BCD.
    for (i, s) in [
        ("BASIN", ["0", "1", "1"]),
        ("BACOS", ["2", "0", "0"]),
        ("BATAN", ["0", "0", "H1A00"]),
    ] {
        let p = bcd_run(
            &format!("{i} D0 D10"),
            &[("D0", s[0]), ("D1", s[1]), ("D2", s[2])],
        );
        assert_stopped(&p, 4100);
    }
}
