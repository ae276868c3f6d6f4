//! Process-control dynamic elements (000 §9.9-§9.12: S.LLAG, S.I, S.D,
//! S.DED) on a process CPU; values worked out from the manual's formulas in
//! f32, ΔT in SD1500.

mod common;
use common::Plc;
use softplc_core::program::ProcessSettings;

fn fails(p: &Plc, detail: i64) {
    assert_eq!(p.error().map(|e| e.0), Some(4100));
    assert_eq!((p.int("SD1502"), p.int("SD1503")), (detail, 1));
}

const LLAG: &str = "LD SM400\nS.LLAG D0 D100 D10 D200\nEND\n";

/// 000 §9.9: BW = 1/(ΔT + T1) × {T2·(E1 − E1n-1) + T1·BW + ΔT·E1}. Spec §7:
/// T1 = T2 = 1, ΔT = 1, a step 0 → 50 passes through (50). A pure lag (T2 =
/// 0) goes 25, 37.5, 43.75.
#[test]
fn s_llag_lead_lag_step_and_pure_lag() {
    let mut p = Plc::process(LLAG);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "1")
        .set("D12:f32", "1");
    p.set("D0:f32", "50").scan();
    assert_eq!(p.real("D100"), 50.0);
    assert_eq!(p.real("D200"), 50.0, "E1n-1");
    p.scan();
    assert_eq!(p.real("D100"), 50.0);
    let mut p = Plc::process(LLAG);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "1")
        .set("D12:f32", "0");
    p.set("D0:f32", "50");
    for bw in [25.0, 37.5, 43.75] {
        p.scan();
        assert_eq!(p.real("D100"), bw);
    }
    // Lead 2, lag 1, ΔT = 0.5: 1/1.5 × (2·(50 − 50) + 43.75 + 0.5·50).
    p.set("SD1500:f32", "0.5").set("D12:f32", "2").scan();
    assert_eq!(p.real("D100"), (1.0f32 / 1.5 * (43.75 + 25.0)) as f64);
    assert_eq!(p.error(), None);
}

/// e1 = 1 passes E1 through; DEC-20: E1n-1 follows E1 then too, so the
/// first e1 = 0 output is continuous (80); the alternative keeps the stale
/// E1n-1 = 0 and kicks: 1/2 × (1·(80 − 0) + 80 + 80) = 120.
#[test]
fn s_llag_start_signal_and_dec_20() {
    let run = |s: ProcessSettings| {
        let mut p = Plc::process_with(LLAG, s);
        p.set("SD1500:f32", "1")
            .set("D10:f32", "1")
            .set("D12:f32", "1");
        p.set("D0:f32", "80").set("D2", "1").scan();
        assert_eq!(p.real("D100"), 80.0);
        p.set("D2", "0").scan();
        p.real("D100")
    };
    assert_eq!(run(ProcessSettings::default()), 80.0);
    let alt = ProcessSettings {
        lag_tracks_input_always: false,
        ..ProcessSettings::default()
    };
    assert_eq!(run(alt), 120.0);
}

/// T1 + ΔT = 0 gives BW = 0 and is not an error (spec §5).
#[test]
fn s_llag_with_t1_plus_dt_zero_gives_zero() {
    let mut p = Plc::process(LLAG);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "-1")
        .set("D12:f32", "1");
    p.set("D0:f32", "50").set("D100:f32", "9").scan();
    assert_eq!(p.real("D100"), 0.0);
    assert_eq!(p.error(), None);
    let mut p = Plc::process(LLAG);
    p.set("SD1500", "-1").set("SD1501", "-1").scan();
    fails(&p, 1);
}

const I: &str = "LD SM400\nS.I D0 D100 D10 SD1506\nEND\n";

/// 000 §9.10: Yn = ΔT/T × E1 + Yn-1 (spec §7: 50, 100, 150); T = 0 holds,
/// e1 = 1 presets Ys, BW as found is Yn-1 (DEC-8).
#[test]
fn s_i_integrates_holds_and_presets() {
    let mut p = Plc::process(I);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "1")
        .set("D0:f32", "50");
    for bw in [50.0, 100.0, 150.0] {
        p.scan();
        assert_eq!(p.real("D100"), bw);
    }
    p.set("D10:f32", "0").scan();
    assert_eq!(p.real("D100"), 150.0, "T = 0: Yn-1, no error");
    p.set("D10:f32", "2").set("SD1500:f32", "0.5").scan();
    assert_eq!(p.real("D100"), 162.5, "0.5/2 × 50 + 150");
    p.set("D12:f32", "-7").set("D2", "1").scan();
    assert_eq!(p.real("D100"), -7.0);
    p.set("D2", "0").set("D100:f32", "1000").scan();
    assert_eq!(p.real("D100"), 1012.5);
    assert_eq!(p.error(), None);
}

const D: &str = "LD SM400\nS.D D0 D100 D10 D200\nEND\n";

/// 000 §9.11: BW = T/(ΔT + T) × (Yn-1 + E1 − E1n-1). Spec §7: T = 1, ΔT =
/// 1, step 0 → 50: 25, then 12.5, 6.25.
#[test]
fn s_d_step_response_decays() {
    let mut p = Plc::process(D);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "1")
        .set("D0:f32", "50");
    for bw in [25.0, 12.5, 6.25] {
        p.scan();
        assert_eq!(p.real("D100"), bw);
    }
    // A falling step 50 → 30: 0.5 × (6.25 + 30 − 50).
    p.set("D0:f32", "30").scan();
    assert_eq!(p.real("D100"), -6.875);
    assert_eq!(p.real("D200"), 30.0);
}

/// e1 = 1 gives Ys and (DEC-20) tracks E1n-1, so the first e1 = 0 output
/// for a constant input is T/(ΔT + T) × Ys = 0.5 × 8 = 4 (no kick). The
/// alternative keeps E1n-1 = 0: 0.5 × (8 + 20 − 0) = 14. ΔT + T = 0 gives 0.
#[test]
fn s_d_preset_dec_20_and_zero_denominator() {
    let run = |s: ProcessSettings| {
        let mut p = Plc::process_with(D, s);
        p.set("SD1500:f32", "1")
            .set("D10:f32", "1")
            .set("D12:f32", "8");
        p.set("D0:f32", "20").set("D2", "1").scan();
        assert_eq!(p.real("D100"), 8.0);
        p.set("D2", "0").scan();
        p.real("D100")
    };
    assert_eq!(run(ProcessSettings::default()), 4.0);
    let alt = ProcessSettings {
        lag_tracks_input_always: false,
        ..ProcessSettings::default()
    };
    assert_eq!(run(alt), 14.0);
    let mut p = Plc::process(D);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "-1")
        .set("D0:f32", "50");
    p.set("D100:f32", "3").scan();
    assert_eq!(p.real("D100"), 0.0);
    assert_eq!(p.error(), None);
}

const DED: &str = "LD SM400\nS.DED D0 D100 D10 D200\nEND\n";

/// Sets ΔT = 1, ST, SN, Ys = −5 and OCHG.
fn ded(s: ProcessSettings, st: &str, sn: &str, ochg: &str) -> Plc {
    let mut p = Plc::process_with(DED, s);
    p.set("SD1500:f32", "1").set("D10:f32", st).set("D12", sn);
    p.set("D13:f32", "-5").set("D15", ochg);
    p
}

fn bb1(p: &Plc) -> i64 {
    p.int("D102") & 1
}

/// DEC-21/DEC-24: after e1 1 → 0 the fill value (E1 at the edge for OCHG =
/// 0) is output with BB1 = 1 for SN sampling periods, then BW(t) = E1(t −
/// ST·SN).
#[test]
fn s_ded_delays_by_st_times_sn_after_the_edge() {
    let mut p = ded(ProcessSettings::default(), "1", "3", "0");
    p.set("D0:f32", "10").set("D2", "1").scan();
    assert_eq!((p.real("D100"), bb1(&p)), (10.0, 0), "e1 = 1: BW = E1");
    p.set("D2", "0");
    let mut seen = Vec::new();
    for t in 0..7 {
        p.set("D0:f32", &(20 + t).to_string()).scan();
        seen.push((p.real("D100"), bb1(&p)));
    }
    assert_eq!(
        seen,
        [
            (20.0, 1),
            (20.0, 1),
            (20.0, 1),
            (20.0, 0),
            (21.0, 0),
            (22.0, 0),
            (23.0, 0)
        ]
    );
    assert_eq!(p.int("D202"), 3, "samples stored");
    // e1 = 1 again: pass-through, BB1 = 0, stored count reset (DEC-23).
    p.set("D2", "1").set("D0:f32", "99").scan();
    assert_eq!((p.real("D100"), bb1(&p), p.int("D202")), (99.0, 0, 0));
}

/// OCHG = 1 fills with Ys (DEC-24); the alternative swaps the polarity.
/// ST = 2 with ΔT = 1 samples every second execution and holds between.
#[test]
fn s_ded_fill_value_polarity_and_sampling_period() {
    let alt = ProcessSettings {
        ded_ochg_fill: false,
        ..ProcessSettings::default()
    };
    for (s, ochg, fill) in [
        (ProcessSettings::default(), "1", -5.0),
        (alt, "0", -5.0),
        (alt, "1", 30.0),
    ] {
        let mut p = ded(s, "2", "2", ochg);
        p.set("D2", "1").scan();
        p.set("D2", "0");
        let mut seen = Vec::new();
        for t in 0..7 {
            p.set("D0:f32", &(30 + t).to_string()).scan();
            seen.push(p.real("D100"));
        }
        // Samples at t = 0, 2, 4, 6 (30, 32, 34, 36); the first comes out
        // at t = 4 (ST·SN = 4 s later).
        assert_eq!(seen, [fill, fill, fill, fill, 30.0, 30.0, 32.0], "{ochg}");
    }
}

/// DEC-21 alternative (push before output): the delay is SN − 1 samples.
#[test]
fn s_ded_push_first_alternative() {
    let alt = ProcessSettings {
        ded_output_before_push: false,
        ..ProcessSettings::default()
    };
    let mut p = ded(alt, "1", "3", "0");
    p.set("D2", "1").scan();
    p.set("D2", "0");
    let mut seen = Vec::new();
    for t in 0..5 {
        p.set("D0:f32", &(20 + t).to_string()).scan();
        seen.push((p.real("D100"), bb1(&p)));
    }
    assert_eq!(
        seen,
        [(20.0, 1), (20.0, 1), (20.0, 0), (21.0, 0), (22.0, 0)]
    );
}

/// DEC-22: from a cleared area with e1 = 0 the first execution starts
/// without a fill value (BW keeps D1's 7); SN = 0 passes E1 with BB1 = 0.
#[test]
fn s_ded_start_without_edge_and_sn_zero() {
    let mut p = ded(ProcessSettings::default(), "1", "2", "0");
    p.set("D100:f32", "7");
    let mut seen = Vec::new();
    for t in 0..4 {
        p.set("D0:f32", &(40 + t).to_string()).scan();
        seen.push((p.real("D100"), bb1(&p)));
    }
    assert_eq!(seen, [(7.0, 1), (7.0, 1), (40.0, 0), (41.0, 0)]);
    p.set("D12", "0").set("D0:f32", "55").scan();
    assert_eq!((p.real("D100"), bb1(&p)), (55.0, 0));
    assert_eq!(p.error(), None);
}

/// SN ∉ 0..48 is 4100 with SD1502 = 3; ST/ΔT over 32767 is 4, ΔT = 0 is 5,
/// ST < 0 is 2 (spec §5, DEC-36), SD1503 = 1.
#[test]
fn s_ded_errors() {
    for (st, sn, dt, detail) in [
        ("1", "49", "1", 3),
        ("1", "-1", "1", 3),
        ("40000", "2", "1", 4),
        ("1", "2", "0", 5),
        ("-1", "2", "1", 2),
    ] {
        let mut p = ded(ProcessSettings::default(), st, sn, "0");
        p.set("SD1500:f32", dt).scan();
        fails(&p, detail);
    }
    // SN = 48 is allowed: the local area takes 3 + 96 words.
    let mut p = ded(ProcessSettings::default(), "1", "48", "0");
    p.scan();
    assert_eq!(p.error(), None);
    assert_eq!(p.int("D202"), 1);
}

/// DEC-22 and DEC-23 have no described alternative: rejected at load.
#[test]
fn s_ded_rejects_undescribed_alternatives() {
    let s = ProcessSettings {
        ded_start_without_edge: false,
        ..ProcessSettings::default()
    };
    let d = common::process_diagnostics_with(DED, s);
    assert!(
        d[0].starts_with("2:1: `S.DED`: [process] ded_start_without_edge = false (DEC-22)"),
        "{d:?}"
    );
    let s = ProcessSettings {
        ded_bypass_resets: false,
        ..ProcessSettings::default()
    };
    assert!(common::process_diagnostics_with(DED, s)[0].contains("DEC-23"));
}

/// DEC-8: previous BW/BB are D1 as found; the hidden-copy alternative is
/// not described, so instructions that read their history reject it at
/// load, and those that do not (S.DBND, S.ADD) accept it.
#[test]
fn dec_8_alternative_is_rejected_where_history_is_read() {
    let alt = ProcessSettings {
        previous_in_block_memory: false,
        ..ProcessSettings::default()
    };
    let d = common::process_diagnostics_with(I, alt);
    assert!(
        d[0].starts_with("2:1: `S.I`: [process] previous_in_block_memory = false (DEC-8)"),
        "{d:?}"
    );
    let src = "LD SM400\nS.LIMT D0 D100 D10 SD1506\nS.> D0 D110 D20 SD1506\n\
               S.SUM D0 D120 D30 SD1506\nS.FLT D0 D130 D40 D200\nS.AMR D0 D140 D50 SD1506\n\
               S.DBND D0 D150 D60 SD1506\nS.ADD D0 D160 D70 SD1506\nEND\n";
    let d = common::process_diagnostics_with(src, alt);
    let lines: Vec<&str> = d.iter().map(|m| &m[..2]).collect();
    assert_eq!(lines, ["2:", "3:", "4:", "5:", "6:"], "{d:?}");
    let mut p = Plc::process_with("LD SM400\nS.DBND D0 D100 D10 SD1506\nEND\n", alt);
    p.set("D10:f32", "100").set("D0:f32", "50").scan();
    assert_eq!(p.real("D100"), 50.0);
}
