//! Control instructions with the common PID front end (000 §9.1-§9.6; spec
//! §4.8-§4.14) on a process CPU: S.PID, S.2PID, S.IPD, S.BPI, S.SPI. Expected
//! values are worked out from the spec's formulas in f32 (the expressions in
//! the tests are those formulas, evaluated in f32).

mod common;
#[path = "common/process_loop.rs"]
mod lp;

use lp::*;
use softplc_core::program::ProcessSettings;

fn settings(f: impl FnOnce(&mut ProcessSettings)) -> ProcessSettings {
    let mut s = ProcessSettings::default();
    f(&mut s);
    s
}

/// Spec §7 quick check: P = 1, I = 10, D = 0, CT = ΔT = 1, PN = 0, SV 50 %,
/// PV 40 %: the first execution after clearing starts the counter (ΔMV 0,
/// DEC-1), the second computes ΔMV = 1 × (10 − 0 + 0.1·10) = 11.0, the third
/// 1 × (10 − 10 + 1) = 1.0.
#[test]
fn s_pid_one_control_cycle_is_the_quick_check() {
    let mut p = start("S.PID");
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    setf(&mut p, "D100", 7.0);
    p.scan();
    assert_eq!(bw(&p), 0.0, "the start execution outputs ΔMV = 0");
    assert_eq!((tagw(&p, 96), tagw(&p, 97)), (1, 1));
    p.scan();
    assert_eq!(bw(&p), 11.0);
    assert_eq!(tag(&p, 16), 10.0, "DV at +16");
    assert_eq!(tag(&p, 104), 40.0, "PVn at +104");
    assert_eq!(tag(&p, 110), 10.0, "DVn-1 at +110");
    p.scan();
    assert_eq!(bw(&p), 1.0);
    assert_eq!(p.error(), None);
    // DEC-1's alternative: the start execution is also a reach.
    let mut p = start_with("S.PID", settings(|s| s.counter_start_is_time_zero = false));
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    p.scan();
    assert_eq!(bw(&p), 11.0);
}

/// ΔT = 1 s, CT = 5 s: ΔMV is computed at t = 5, 10, 15 and is 0 between
/// (spec §1.3.1). At t = 5: (10 − 0) + 5/10·10 = 15; then 0 + 5 = 5.
#[test]
fn s_pid_computes_on_every_fifth_execution_with_ct_5() {
    let mut p = start("S.PID");
    tf(&mut p, 46, 5.0);
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    let mut out = vec![];
    for t in 0..16 {
        p.scan();
        if bw(&p) != 0.0 {
            out.push((t, bw(&p)));
        }
    }
    assert_eq!(out, [(5, 15.0), (10, 5.0), (15, 5.0)]);
}

/// The incomplete derivative on PV with MTD (spec §4.9): MD = 8, TD = 2,
/// CT = 1 → c = 16/10, CT/TD = 0.5; I = 0. The history is preset (PVn =
/// PVn-1 = 40, DVn-1 = 10). PV steps to 42 (PN = 0).
#[test]
fn s_pid_derivative_uses_mtd_and_the_pv_history() {
    let mut p = start("S.PID");
    tf(&mut p, 14, 50.0);
    tf(&mut p, 54, 0.0);
    tf(&mut p, 56, 2.0);
    tf(&mut p, 104, 40.0);
    tf(&mut p, 106, 40.0);
    tf(&mut p, 110, 10.0);
    setf(&mut p, "D0", 40.0);
    p.scan().scan();
    assert_eq!(bw(&p), 0.0, "x = −(40 − 80 + 40) = 0");
    let c: f32 = 8.0 * 2.0 / (8.0 * 1.0 + 2.0);
    setf(&mut p, "D0", 42.0);
    p.scan();
    let b1 = 0.0 + c * (-(42.0f32 - 2.0 * 40.0 + 40.0) - 1.0 / 2.0 * 0.0);
    assert_eq!(bw(&p), 1.0 * ((8.0 - 10.0) + 0.0 + b1), "≈ −5.2");
    assert_eq!(tag(&p, 102), b1, "Bn-1 at +102");
    p.scan();
    let b2 = b1 + c * (-(42.0f32 - 2.0 * 42.0 + 40.0) - 1.0 / 2.0 * b1);
    assert_eq!(bw(&p), 1.0 * ((8.0 - 8.0) + 0.0 + b2), "≈ 2.56");
    assert_eq!(tag(&p, 108), 40.0, "PVn-2 at +108");
    // MAN (and LCM, CMV) forces Bn = 0; the history still moves.
    tw(&mut p, 1, MAN);
    setf(&mut p, "D0", 45.0);
    p.scan();
    assert_eq!(bw(&p), 1.0 * ((5.0 - 8.0) + 0.0 + 0.0));
    assert_eq!(
        (tag(&p, 102), tag(&p, 104), tag(&p, 106)),
        (0.0, 45.0, 42.0)
    );
    // CMB keeps the derivative.
    tw(&mut p, 1, CMB);
    setf(&mut p, "D0", 46.0);
    p.scan();
    let b = 0.0 + c * (-(46.0f32 - 2.0 * 45.0 + 42.0) - 0.5 * 0.0);
    assert_eq!(bw(&p), (4.0 - 5.0) + b);
}

/// Gap gain (spec §4.8 (3)): GW = 5, GG = 0.5, P = 2. |DV| = 10 > GW → K =
/// 1 − 0.5 × 5/10 = 0.75, KP = 1.5; |DV| = 4 ≤ GW → K = GG = 0.5, KP = 1.
#[test]
fn s_pid_gap_gain() {
    let mut p = start("S.PID");
    tf(&mut p, 14, 50.0);
    tf(&mut p, 54, 0.0);
    tf(&mut p, 58, 5.0);
    tf(&mut p, 60, 0.5);
    tf(&mut p, 52, 2.0);
    setf(&mut p, "D0", 40.0);
    p.scan().scan();
    assert_eq!(bw(&p), 1.5 * 10.0);
    setf(&mut p, "D0", 46.0);
    p.scan();
    assert_eq!(bw(&p), 1.0 * (4.0 - 10.0));
    // Forward action (PN = 1): DV = E1 − SV′ = −4.
    p.set("D204", "1");
    p.scan();
    assert_eq!(tag(&p, 16), -4.0);
    assert_eq!(bw(&p), 1.0 * (-4.0 - 4.0));
}

/// Cascade SV (spec §4.8 (1), DEC-14): MODE = CAS, SVPTN = 0, RH = 200, RL =
/// 100, E2 = 25 % → SVn = 100/100 × 25 + 100 = 125 engineering units, written
/// to SV; SVn′ = 25 %, E1 = 20 → DV = 5.
#[test]
fn s_pid_cascade_sv_from_e2() {
    let run = |s: ProcessSettings| {
        let mut p = start_with("S.PID", s);
        tw(&mut p, 1, CAS);
        p.set("D206", "0");
        tf(&mut p, 22, 200.0);
        tf(&mut p, 24, 100.0);
        tf(&mut p, 54, 0.0);
        setf(&mut p, "D300", 25.0);
        setf(&mut p, "D0", 20.0);
        p.scan().scan();
        p
    };
    let p = run(ProcessSettings::default());
    assert_eq!(tag(&p, 14), 125.0);
    assert_eq!(tag(&p, 16), 5.0);
    assert_eq!(bw(&p), 5.0);
    let p = run(settings(|s| s.cascade_writes_sv = false));
    assert_eq!(tag(&p, 14), 0.0, "SV untouched");
    assert_eq!(bw(&p), 5.0, "the cascade SV is still used");
    // SVPTN = 1 (E2 unused): SV itself; E2 ignored.
    let mut p = start("S.PID");
    tw(&mut p, 1, CAS);
    p.set("D206", "1");
    tf(&mut p, 14, 30.0);
    tf(&mut p, 54, 0.0);
    setf(&mut p, "D300", 25.0);
    setf(&mut p, "D0", 20.0);
    p.scan().scan();
    assert_eq!(bw(&p), 10.0);
}

/// Tracking (spec §4.8 (2), §1.7): TRK = 1, E2 used, a non-cascade mode →
/// E2 := SVn′ and, with E2 the upper loop's MV (SVPTN b1 = 0), the upper
/// loop's INH.TRKF (S3 − 8 = D292) := 1. RH 200, RL 100, SV 150 → 50 %.
#[test]
fn s_pid_tracking_writes_e2_back_and_sets_the_upper_trkf() {
    let mut p = start("S.PID");
    p.set("D205", "1").set("D206", "0");
    tf(&mut p, 22, 200.0);
    tf(&mut p, 24, 100.0);
    tf(&mut p, 14, 150.0);
    setf(&mut p, "D300", 3.0);
    p.set("D292", "1");
    p.scan();
    assert_eq!(getf(&p, "D300"), 3.0, "not on the start execution");
    p.scan();
    assert_eq!(getf(&p, "D300"), 50.0);
    assert_eq!(word(&p, "D292"), 1 | TRKF);
    // SVPTN = 2: E2 used but not the upper MV: no TRKF.
    let mut p = start("S.PID");
    p.set("D205", "1").set("D206", "2");
    tf(&mut p, 14, 40.0);
    p.scan().scan();
    assert_eq!(getf(&p, "D300"), 40.0);
    assert_eq!(word(&p, "D292"), 0);
    // The cascade group does not track; TRK = 0 does not either.
    for (mode, trk) in [(CAS, "1"), (AUT, "0")] {
        let mut p = start("S.PID");
        tw(&mut p, 1, mode);
        p.set("D205", trk).set("D206", "0");
        tf(&mut p, 14, 40.0);
        setf(&mut p, "D300", 3.0);
        p.scan().scan();
        assert_eq!(word(&p, "D292"), 0);
        if mode == AUT {
            assert_eq!(getf(&p, "D300"), 3.0);
        }
    }
    // The upper INH lies before the device: 4101.
    let mut p = common::Plc::process("LD SM400\nS.PID D0 D100 D200 D1000 D5\nEND\n");
    defaults(&mut p);
    constants(&mut p, "S.PID");
    p.set("D205", "1").set("D206", "0");
    p.scan().scan();
    assert_eq!(p.error().map(|e| e.0), Some(4101));
}

/// DVLA with the DVLS hysteresis (spec §4.8 (5)): DVL = 10, DVLS = 2: |DV| ≥
/// 10 → 1, 8 < |DV| < 10 → held, |DV| ≤ 8 → 0; DVLI or ERRI → 0.
#[test]
fn s_pid_deviation_alarm_hysteresis_and_inhibits() {
    let mut p = start("S.PID");
    tf(&mut p, 50, 10.0);
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 50.0);
    p.scan();
    let mut seen = vec![];
    for e1 in [41.0, 40.0, 41.0, 42.0, 41.0, 61.0, 59.5] {
        setf(&mut p, "D0", e1);
        p.scan();
        let dvla = tagw(&p, 3) & DVLA != 0;
        assert_eq!(dvla, bb(&p) & 1 != 0, "BB1 = DVLA");
        seen.push(dvla as u8);
    }
    assert_eq!(seen, [0, 1, 1, 0, 0, 1, 1]);
    for inh in [DVLA, ERRI] {
        tw(&mut p, 4, inh);
        p.scan();
        assert_eq!((tagw(&p, 3) & DVLA, bb(&p) & 1), (0, 0), "INH {inh:#x}");
    }
    // The other ERRI/TRKF placement (DEC-6): b14 inhibits.
    let mut p = start_with("S.PID", settings(|s| s.inh_erri_b15 = false));
    tf(&mut p, 50, 10.0);
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 30.0);
    tw(&mut p, 4, 0x4000);
    p.scan().scan();
    assert_eq!(tagw(&p, 3) & DVLA, 0);
    tw(&mut p, 4, 0x8000);
    p.scan();
    assert_eq!(tagw(&p, 3) & DVLA, DVLA);
}

/// Anti-windup (spec §4.9, DEC-15, DEC-7): with MVP > MH and a positive
/// increment, firmware ≥ 07032 freezes on MHA2/MLA2 of +116 (b1/b0), ≤ 07031
/// on ALM.MHA/MLA. DV = 10 constant, DVn-1 preset 10: ΔMV = the increment.
#[test]
fn s_pid_anti_windup_under_both_firmware_settings() {
    let case = |new: bool, alm: u16, alm2: u16, mvp: f32, e1: f32| {
        let mut p = start_with("S.PID", settings(|s| s.firmware_serial_ge_07032 = new));
        tf(&mut p, 14, 50.0);
        tf(&mut p, 62, mvp);
        tf(&mut p, 110, 50.0 - e1);
        tw(&mut p, 3, alm);
        tw(&mut p, 116, alm2);
        setf(&mut p, "D0", e1);
        p.scan().scan();
        bw(&p)
    };
    // DV = +10 → increment +1; MVP 120 > MH 100.
    assert_eq!(case(true, 0, 2, 120.0, 40.0), 0.0, "MHA2 freezes");
    assert_eq!(case(true, 0, 1, 120.0, 40.0), 0.0, "MLA2 too (either bit)");
    assert_eq!(
        case(true, MHA, 0, 120.0, 40.0),
        1.0,
        "new firmware ignores ALM"
    );
    assert_eq!(case(true, 0, 2, 90.0, 40.0), 1.0, "MVP within the limits");
    assert_eq!(
        case(false, 0, 2, 120.0, 40.0),
        1.0,
        "old firmware ignores ALM2"
    );
    assert_eq!(case(false, MHA, 0, 120.0, 40.0), 0.0, "old firmware: MHA");
    // DV = −10 → increment −1; MVP −5 < ML 0.
    assert_eq!(case(true, 0, 1, -5.0, 60.0), 0.0);
    assert_eq!(
        case(true, 0, 1, 120.0, 60.0),
        -1.0,
        "a negative increment above MH runs"
    );
    assert_eq!(case(false, MLA, 0, -5.0, 60.0), 0.0);
    // DEC-7's other placement: MHA2 = b0.
    let mut p = start_with("S.PID", settings(|s| s.alm2_mha2_b1 = false));
    tf(&mut p, 14, 50.0);
    tf(&mut p, 62, 120.0);
    tf(&mut p, 110, 10.0);
    tw(&mut p, 116, 1);
    setf(&mut p, "D0", 40.0);
    p.scan().scan();
    assert_eq!(bw(&p), 0.0);
}

/// Loop stop (SPA, spec §4.8 (6)): ΔMV 0, DVLA 0, MODE MAN, BB1 0; the
/// counter does not move (DEC-4), or does under the alternative.
#[test]
fn s_pid_loop_stop() {
    for skip in [true, false] {
        let mut p = start_with("S.PID", settings(|s| s.early_end_skips_counters = skip));
        tf(&mut p, 46, 3.0);
        tf(&mut p, 50, 5.0);
        tf(&mut p, 14, 50.0);
        setf(&mut p, "D0", 40.0);
        p.scans(4);
        assert_eq!(bw(&p), 10.0 + 3.0 / 10.0 * 10.0);
        assert_eq!((tagw(&p, 3) & DVLA, bb(&p) & 1), (DVLA, 1));
        tw(&mut p, 3, SPA | DVLA);
        p.scan();
        assert_eq!(bw(&p), 0.0);
        assert_eq!((tagw(&p, 1), tagw(&p, 3), bb(&p)), (MAN, SPA, 0));
        assert_eq!(tagw(&p, 97), if skip { 3 } else { 2 });
    }
}

/// S.2PID with α = 0, β = 1 is S.PID (spec §4.10): two loops fed the same PV
/// sequence with a derivative give the same ΔMV bit for bit.
#[test]
fn s_2pid_with_alpha_0_beta_1_equals_s_pid() {
    let src = "LD SM400\nS.PID D0 D100 D200 D1000 D300\nS.2PID D0 D110 D200 D1200 D300\nEND\n";
    let mut p = common::Plc::process(src);
    defaults(&mut p);
    constants(&mut p, "S.PID");
    for off in [1, 3, 4, 14, 18, 22, 46, 48, 50, 52, 54, 56, 60, 66] {
        for k in 0..2 {
            let v = p.int(&format!("D{}:u16", 1000 + off + k));
            p.set(&format!("D{}:u16", 1200 + off + k), &v.to_string());
        }
    }
    for base in [1000, 1200] {
        setf(&mut p, &format!("D{}", base + 14), 50.0);
        setf(&mut p, &format!("D{}", base + 56), 3.0);
        setf(&mut p, &format!("D{}", base + 52), 1.7);
    }
    for e1 in [40.0, 41.5, 43.0, 47.25, 44.0, 44.0, 52.0, 49.9] {
        setf(&mut p, "D0", e1);
        p.scan();
        assert_eq!(
            getf(&p, "D100").to_bits(),
            getf(&p, "D110").to_bits(),
            "E1 {e1}"
        );
    }
    assert!(getf(&p, "D100") != 0.0);
}

/// S.2PID α = 0.5 (spec §4.10): an SV step 50 → 60 with PV steady at 40
/// (history preset): S.PID gives (20 − 10) + 0 = 10, S.2PID (1 − 0.5)(20 −
/// 10) + 0.5·Cn = 5 with Cn = −(40 − 40) = 0. β = 0.5 with D = 2 blends the
/// derivative on DV (Bn) and on PV (Dn).
#[test]
fn s_2pid_alpha_and_beta() {
    let mut p = start("S.2PID");
    tf(&mut p, 54, 0.0);
    tf(&mut p, 64, 0.5);
    tf(&mut p, 14, 60.0);
    tf(&mut p, 104, 40.0);
    tf(&mut p, 110, 10.0);
    setf(&mut p, "D0", 40.0);
    p.scan().scan();
    assert_eq!(bw(&p), 5.0);
    // Now PV moves to 42 (Cn = −2) with β = 0.5, D = 2, MTD 8.
    tf(&mut p, 56, 2.0);
    tf(&mut p, 66, 0.5);
    setf(&mut p, "D0", 42.0);
    p.scan();
    let c: f32 = 8.0 * 2.0 / (8.0 * 1.0 + 2.0);
    let (dv, dv1, dv2) = (18.0f32, 20.0f32, 10.0f32);
    let bn = 0.0 + c * ((dv - 2.0 * dv1 + dv2) - 0.5 * 0.0);
    let dn = 0.0 + c * (-(42.0f32 - 2.0 * 40.0 + 40.0) - 0.5 * 0.0);
    let cn = -(42.0f32 - 40.0);
    let want = 1.0 * ((1.0 - 0.5) * (dv - dv1) + 0.5 * cn + 0.0 + (1.0 - 0.5) * bn + 0.5 * dn);
    assert_eq!(bw(&p), want);
    assert_eq!((tag(&p, 102), tag(&p, 114), tag(&p, 112)), (bn, dn, dv1));
    // MAN: Bn = Dn = 0.
    tw(&mut p, 1, MAN);
    p.scan();
    assert_eq!((tag(&p, 102), tag(&p, 114)), (0.0, 0.0));
}

/// S.IPD (spec §4.13): an SV step moves ΔMV only through the integral term.
/// PV 40 steady (history preset), P 1, I 10: SV 50 → ΔMV = 0.1·10 − 0 = 1;
/// SV 60 → 0.1·20 = 2 (no proportional kick); PV 41 → 0.1·19 − (41 − 40).
#[test]
fn s_ipd_sv_step_does_not_kick() {
    let mut p = start("S.IPD");
    tf(&mut p, 14, 50.0);
    tf(&mut p, 104, 40.0);
    setf(&mut p, "D0", 40.0);
    p.scan().scan();
    assert_eq!(bw(&p), 1.0);
    tf(&mut p, 14, 60.0);
    p.scan();
    assert_eq!(bw(&p), 2.0);
    setf(&mut p, "D0", 41.0);
    p.scan();
    assert_eq!(bw(&p), 1.0 * (0.1f32 * 19.0 - (41.0 - 40.0) + 0.0));
    // PN = 1: DV = PV − SV, the P term +(PVn − PVn-1).
    p.set("D204", "1");
    setf(&mut p, "D0", 43.0);
    p.scan();
    assert_eq!(bw(&p), 0.1f32 * (43.0 - 60.0) + (43.0 - 41.0));
}

/// S.BPI (spec §4.14, DEC-16): ΔMV = KP × (DVn + (CT/TI)·ΣDV), ΣDV at +56;
/// frozen while ALM.MHA or MLA = 1.
#[test]
fn s_bpi_blend_pi() {
    let mut p = start("S.BPI");
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    p.scan().scan();
    assert_eq!(bw(&p), 10.0 + 0.1 * 10.0);
    assert_eq!((tag(&p, 56), tag(&p, 98)), (10.0, 1.0));
    p.scan();
    assert_eq!(bw(&p), 10.0 + 0.1 * 20.0);
    tw(&mut p, 3, MHA);
    p.scan();
    assert_eq!(bw(&p), 12.0);
    assert_eq!(tag(&p, 56), 20.0, "ΣDV held");
}

#[test]
fn s_bpi_other_forms_are_rejected_at_load() {
    let dialect = softplc_core::program::dialect_for(
        common::process_cpu(),
        settings(|s| s.bpi_reconstructed = false),
    );
    let e = softplc_core::program::compile_il_in(
        "t.il",
        &program("S.BPI"),
        &softplc_core::profile::default_config().devices,
        &dialect,
    )
    .unwrap_err();
    assert!(
        e.0[0].message.contains("bpi_reconstructed"),
        "{}",
        e.0[0].message
    );
}

/// S.SPI (spec §4.12): STHT 4 s, ST 2 s, ΔT 1 s → operate on the first two
/// executions of every period of four (the start execution begins one).
/// Operate: ΔMV = KP × {(DVn − DVn-1) + (ΔT/TI)·DVn}; hold: 0.
#[test]
fn s_spi_operates_then_holds() {
    let mut p = start("S.SPI");
    tf(&mut p, 56, 4.0);
    tf(&mut p, 46, 2.0);
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    let mut out = vec![];
    for _ in 0..9 {
        p.scan();
        out.push(bw(&p));
    }
    assert_eq!(out, [11.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0]);
    // STHT ≤ ST: continuous PI.
    let mut p = start("S.SPI");
    tf(&mut p, 56, 2.0);
    tf(&mut p, 46, 2.0);
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    let out: Vec<f32> = (0..4).map(|_| bw(p.scan())).collect();
    assert_eq!(out, [11.0, 1.0, 1.0, 1.0]);
    // STHT = 0 (the default): nothing is processed, BW 0.
    let mut p = start("S.SPI");
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    setf(&mut p, "D100", 3.0);
    p.scans(3);
    assert_eq!((bw(&p), tag(&p, 16), tagw(&p, 96)), (0.0, 0.0, 0));
}

/// S.SPI hold phase: tracking and the deviation check on the stored DV go on.
#[test]
fn s_spi_hold_tracks_and_checks_the_deviation() {
    let mut p = start("S.SPI");
    tf(&mut p, 56, 3.0);
    tf(&mut p, 46, 1.0);
    tf(&mut p, 50, 5.0);
    tf(&mut p, 14, 50.0);
    p.set("D203", "1").set("D204", "0");
    setf(&mut p, "D0", 40.0);
    p.scan();
    assert_eq!(tagw(&p, 3) & DVLA, DVLA);
    tf(&mut p, 14, 30.0);
    p.scan();
    assert_eq!(bw(&p), 0.0);
    assert_eq!(getf(&p, "D300"), 30.0, "tracking in the hold phase");
    assert_eq!(tagw(&p, 3) & DVLA, DVLA, "DV 10 kept");
    assert_eq!(word(&p, "D292"), TRKF);
}

/// Table 14.2 processing numbers and DEC-36 detail codes, S.PID: 1 CT
/// judgment, 2 SV setting, 3 tracking, 4 gain, 5 PID, 6 deviation check.
#[test]
fn s_pid_error_codes() {
    for m in ["S.PID", "S.2PID", "S.IPD", "S.BPI"] {
        let (pn, trk, svptn) = pattern_at(m);
        let check = if m == "S.2PID" { 8 } else { 6 };
        let dvls = if m == "S.BPI" { "D200" } else { "D202" };
        let cases: Vec<Case> = vec![
            ("ΔT = 0", Box::new(|p| setf(p, "SD1500", 0.0)), (5, 1)),
            ("ΔT < 0", Box::new(|p| setf(p, "SD1500", -1.0)), (2, 1)),
            ("CT/ΔT > 32767", Box::new(|p| tf(p, 46, 40000.0)), (4, 1)),
            ("NaN CT", Box::new(|p| tw(p, 47, 0x7fc0)), (1, 1)),
            (
                "SVPTN 4",
                Box::new(move |p| {
                    p.set(&format!("D{svptn}"), "4");
                }),
                (3, 2),
            ),
            (
                "TRK 2",
                Box::new(move |p| {
                    p.set(&format!("D{trk}"), "2");
                }),
                (3, 2),
            ),
            (
                "cascade NaN E2",
                Box::new(move |p| {
                    tw(p, 1, CAS);
                    p.set(&format!("D{svptn}"), "0");
                    p.set("D301", "32704");
                }),
                (1, 2),
            ),
            ("RH = RL", Box::new(|p| tf(p, 22, 0.0)), (5, 3)),
            (
                "PN 2",
                Box::new(move |p| {
                    p.set(&format!("D{}", pn.unwrap()), "2");
                }),
                (3, 4),
            ),
            ("P < 0", Box::new(|p| tf(p, 52, -1.0)), (2, 4)),
            (
                "NaN E1",
                Box::new(|p| {
                    p.set("D1", "32704");
                }),
                (1, 4),
            ),
            ("I < 0", Box::new(|p| tf(p, 54, -1.0)), (2, 5)),
            ("DVL < 0", Box::new(|p| tf(p, 50, -1.0)), (2, check)),
            (
                "DVLS < 0",
                Box::new(move |p| setf(p, dvls, -2.0)),
                (2, check),
            ),
        ];
        for (what, setup, want) in cases {
            let mut p = start(m);
            setup(&mut p);
            assert_eq!(error_after(&mut p, 3), want, "{m}: {what}");
        }
    }
    // The algorithm's own numbers: S.PID/S.IPD MTD < 0 at 5; S.2PID 5 Bn/Cn,
    // 6 Dn (a NaN Dn-1), 7 ΔMV (α > 1).
    for (m, setup, want) in [
        ("S.PID", "D200", (2, 5)),
        ("S.IPD", "D200", (2, 5)),
        ("S.2PID", "D200", (2, 5)),
    ] {
        let mut p = start(m);
        setf(&mut p, setup, -8.0);
        assert_eq!(error_after(&mut p, 3), want, "{m} MTD");
    }
    let mut p = start("S.2PID");
    tw(&mut p, 115, 0x7fc0);
    assert_eq!(error_after(&mut p, 3), (1, 6));
    let mut p = start("S.2PID");
    tf(&mut p, 64, 1.5);
    assert_eq!(error_after(&mut p, 3), (3, 7));
    let mut p = start("S.2PID");
    tf(&mut p, 66, -0.5);
    assert_eq!(error_after(&mut p, 3), (2, 7));
}

/// An error stops the instruction at its step; what earlier steps wrote stays
/// (DEC-36): a bad DVL (step 6) leaves this execution's ΔMV and DV written.
#[test]
fn s_pid_error_keeps_the_earlier_writes() {
    let mut p = start("S.PID");
    tf(&mut p, 14, 50.0);
    tf(&mut p, 50, -1.0);
    setf(&mut p, "D0", 40.0);
    assert_eq!(error_after(&mut p, 3), (2, 6));
    assert_eq!((bw(&p), tag(&p, 16)), (11.0, 10.0));
}

/// S.SPI numbers: 1 operation-time monitoring, 2 SV, 3 tracking, 4 gain, 5
/// SPI, 6 deviation check.
#[test]
fn s_spi_error_codes() {
    let base = |p: &mut common::Plc| {
        tf(p, 56, 2.0);
        tf(p, 46, 1.0);
    };
    let cases: Vec<Case> = vec![
        ("ΔT 0", Box::new(|p| setf(p, "SD1500", 0.0)), (5, 1)),
        ("STHT/ΔT > 32767", Box::new(|p| tf(p, 56, 1e6)), (4, 1)),
        ("ST < 0", Box::new(|p| tf(p, 46, -1.0)), (2, 1)),
        (
            "SVPTN 5",
            Box::new(|p| {
                p.set("D204", "5");
            }),
            (3, 2),
        ),
        ("RH = RL", Box::new(|p| tf(p, 24, 100.0)), (5, 3)),
        ("GG < 0", Box::new(|p| tf(p, 60, -1.0)), (2, 4)),
        ("I < 0", Box::new(|p| tf(p, 54, -1.0)), (2, 5)),
        ("DVLS < 0", Box::new(|p| setf(p, "D200", -1.0)), (2, 6)),
    ];
    for (what, setup, want) in cases {
        let mut p = start("S.SPI");
        base(&mut p);
        setup(&mut p);
        assert_eq!(error_after(&mut p, 3), want, "S.SPI: {what}");
    }
}

/// The counter decisions on S.PID (spec §1.3.1): DEC-3, a CT change takes
/// effect when the period in progress ends (CT 5 → 2 at t = 2: computes at
/// t = 5, 7, 9); DEC-2, CT 0.9 / ΔT 0.3 = 2.9999998 in f32 rounds to 3
/// (computes at t = 3, 6), the alternative truncates to 2 (t = 2, 4, 6).
#[test]
fn s_pid_counter_decisions() {
    let at = |s: ProcessSettings, ct: f32, dt: f32, change: Option<(usize, f32)>| {
        let mut p = start_with("S.PID", s);
        setf(&mut p, "SD1500", dt);
        tf(&mut p, 46, ct);
        tf(&mut p, 14, 50.0);
        setf(&mut p, "D0", 40.0);
        let mut out = vec![];
        for t in 0..10 {
            if let Some((when, v)) = change {
                if t == when {
                    tf(&mut p, 46, v);
                }
            }
            p.scan();
            if bw(&p) != 0.0 {
                out.push(t);
            }
        }
        out
    };
    let d = ProcessSettings::default();
    assert_eq!(at(d, 5.0, 1.0, Some((2, 2.0))), [5, 7, 9]);
    assert_eq!(at(d, 0.9, 0.3, None), [3, 6, 9]);
    let trunc = settings(|s| s.period_count_rounds = false);
    assert_eq!(at(trunc, 0.9, 0.3, None), [2, 4, 6, 8]);
    // DEC-3's alternative compares an up-count with the current N: the
    // change to 2 at t = 2 computes at once (count 2 ≥ 2), then every 2.
    let up = settings(|s| s.period_change_at_reach = false);
    assert_eq!(at(up, 5.0, 1.0, Some((2, 2.0))), [2, 4, 6, 8]);
}

/// DEC-5: LCM = b2 and LCC = b0 by default; the derivative is forced to 0 in
/// LCM (and CMV), kept in LCC; the switch swaps the two bits.
#[test]
fn s_pid_derivative_modes_follow_dec_5() {
    let run = |s: ProcessSettings, mode: u16| {
        let mut p = start_with("S.PID", s);
        tw(&mut p, 1, mode);
        tf(&mut p, 56, 2.0);
        tf(&mut p, 54, 0.0);
        setf(&mut p, "D0", 40.0);
        p.scan().scan();
        tag(&p, 102)
    };
    let d = ProcessSettings::default();
    let swapped = settings(|s| s.mode_lcc_b0 = false);
    assert_eq!(run(d, 0x4), 0.0, "LCM");
    assert_eq!(run(d, CMV), 0.0, "CMV");
    assert!(run(d, 0x1) != 0.0, "LCC");
    assert!(run(swapped, 0x4) != 0.0, "LCC = b2 when swapped");
    assert_eq!(run(swapped, 0x1), 0.0, "LCM = b0 when swapped");
}
