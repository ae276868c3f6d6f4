//! Process-control I/O instructions (000 ch. 8) on a process CPU: S.IN,
//! S.OUT1, S.OUT2, S.MOUT (S.DUTY, S.BC, S.PSUM: golden_process_io_counters.rs). Values worked out by hand
//! from the manual's formulas in f32 (spec/process-control.md §4.1-§4.7, §7).

mod common;
use common::process::{assert_pc_error, f, loop_tag};
use common::{process_diagnostics, Plc};
use softplc_core::program::ProcessSettings;

const IN: &str = "LD SM400\nS.IN D0 D100 D10 D1000\nEND\n";

fn s_in(settings: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(IN, settings);
    loop_tag(&mut p, 1000);
    for (off, v) in [
        (0, "100"),
        (2, "0"),
        (4, "100"),
        (6, "0"),
        (8, "110"),
        (10, "100"),
        (12, "0"),
        (14, "-10"),
    ] {
        p.set(&format!("D{}:f32", 10 + off), v);
    }
    p
}

/// Spec §7.10: E1 = 50, α = 0.2, BW_prev = 0 → BW = 50 + 0.2·(0 − 50) = 40,
/// then 50 + 0.2·(40 − 50) = 48; E1 = 120 ≥ HH = 110 → BB2 = BB1 = SEA = 1,
/// the limiter gives T1 = NMAX = 100 and the filter goes on toward 100.
#[test]
fn s_in_filters_and_flags_a_range_over() {
    let mut p = s_in(ProcessSettings::default());
    p.set("D0:f32", "50").scan();
    assert_eq!(p.real("D100"), 40.0);
    p.scan();
    assert_eq!(p.real("D100"), 48.0);
    assert_eq!((p.int("D102"), p.int("D1003")), (0, 0));
    p.set("D0:f32", "120").scan();
    assert_eq!(p.real("D100"), f(100.0 + 0.2 * (48.0 - 100.0)));
    assert_eq!(p.int("D102"), 0b011, "BB1, BB2");
    assert_eq!(p.int("D1003"), 0x200, "SEA");
    // Engineering inverse conversion: EMAX 200, EMIN −100, NMAX 100, NMIN 0,
    // α = 0: E1 = 25 → 300/100 × 25 − 100 = −25.
    p.set("D10:f32", "200")
        .set("D12:f32", "-100")
        .set("D1038:f32", "0");
    p.set("D0:f32", "25").scan();
    assert_eq!(p.real("D100"), -25.0);
    assert_eq!(p.int("D102"), 0);
    assert_eq!(p.error(), None);
}

/// 000 L3777-3806: set at E1 ≥ HH (E1 ≤ LL), reset at E1 ≤ H (E1 ≥ L),
/// held in between.
#[test]
fn s_in_range_check_has_hysteresis() {
    let mut p = s_in(ProcessSettings::default());
    for (e1, bb) in [
        ("110", 0b011),
        ("105", 0b011),
        ("100.5", 0b011),
        ("100", 0),
        ("105", 0),
        ("-10", 0b101),
        ("-5", 0b101),
        ("0", 0),
        ("-5", 0),
    ] {
        p.set("D0:f32", e1).scan();
        assert_eq!(p.int("D102"), bb, "E1 = {e1}");
        assert_eq!(
            p.int("D1003"),
            if bb != 0 { 0x200 } else { 0 },
            "SEA at {e1}"
        );
    }
}

/// DEC-9: BB1 = SEA = BB2 ∨ BB3 after both checks; the row-by-row
/// alternative loses a held low alarm whenever the high check resets.
#[test]
fn s_in_sea_follows_dec_9() {
    let mut p = s_in(ProcessSettings::default());
    p.set("D0:f32", "-20").scan();
    p.set("D0:f32", "-5").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0b101, 0x200));
    let mut p = s_in(ProcessSettings {
        in_sea_after_both_checks: false,
        ..ProcessSettings::default()
    });
    p.set("D0:f32", "-20").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0b101, 0x200));
    p.set("D0:f32", "-5").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0b100, 0), "BB3 only");
}

/// SM1500 ON: on a range-over BW keeps its last value (L3809-3825); SEI
/// or ERRI inhibit SEA and BB1..BB3, and the limiter then works normally.
#[test]
fn s_in_sm1500_hold_and_inhibits() {
    let mut p = s_in(ProcessSettings::default());
    p.set("D1038:f32", "0")
        .set("D100:f32", "33")
        .set("SM1500", "1");
    p.set("D0:f32", "120").scan();
    assert_eq!(p.real("D100"), 33.0);
    assert_eq!(p.int("D102"), 0b011);
    p.set("SM1500", "0").scan();
    assert_eq!(p.real("D100"), 100.0, "limited to NMAX");
    for inh in ["H200", "H8000"] {
        p.set("D100:f32", "33")
            .set("SM1500", "1")
            .set("D1004", inh)
            .scan();
        assert_eq!(p.real("D100"), 100.0, "INH {inh}: no hold");
        assert_eq!((p.int("D102"), p.int("D1003")), (0, 0), "INH {inh}");
    }
    // DEC-6 alternative: ERRI = b14, so the default INH 4000H inhibits all.
    let mut p = s_in(ProcessSettings {
        inh_erri_b15: false,
        ..ProcessSettings::default()
    });
    p.set("D1004", "H4000").set("D0:f32", "120").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0, 0));
}

/// Loop stop (SPA = 1, L3872-3888): BW holds, SEA := 0, MODE := MAN,
/// BB1..BB3 := 0.
#[test]
fn s_in_loop_stop() {
    let mut p = s_in(ProcessSettings::default());
    p.set("D0:f32", "120").scan();
    let bw = p.real("D100");
    p.set("D1003", "H4200").set("D0:f32", "50").scan();
    assert_eq!(p.real("D100"), bw);
    assert_eq!(p.int("D1003"), 0x4000);
    assert_eq!(p.int("D1001"), 8, "MAN");
    assert_eq!(p.int("D102"), 0);
}

/// NMAX = NMIN divides by 0 (SD1502 5) in the inverse conversion (3); the
/// range check before it has written BB; a NaN input is 1 at 1, a NaN
/// NMAX 1 at 2, a NaN α 1 at 4.
#[test]
fn s_in_errors() {
    let mut p = s_in(ProcessSettings::default());
    p.set("D14:f32", "100")
        .set("D16:f32", "100")
        .set("D0:f32", "120")
        .scan();
    assert_pc_error(&p, 5, 3);
    assert_eq!(p.int("D102"), 0b011, "step 1 wrote BB");
    let mut p = s_in(ProcessSettings::default());
    p.set("D0", "-1").set("D1", "-1").scan();
    assert_pc_error(&p, 1, 1);
    let mut p = s_in(ProcessSettings::default());
    p.set("D0:f32", "50")
        .set("D1038", "-1")
        .set("D1039", "-1")
        .scan();
    assert_pc_error(&p, 1, 4);
    let mut p = s_in(ProcessSettings::default());
    p.set("D0:f32", "50")
        .set("D14", "-1")
        .set("D15", "-1")
        .scan();
    assert_pc_error(&p, 1, 2);
}

const OUT1: &str = "LD SM400\nS.OUT1 D0 D100 D10 D1000\nEND\n";

fn out(src: &str, settings: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(src, settings);
    loop_tag(&mut p, 1000);
    p.set("D10:f32", "100").set("D12:f32", "0");
    p
}

/// Spec §7.10: after the S.PID worked example (ΔMV = 11) with MVP = 0 and
/// TRKF = 0: T = 11 → MV = 11, BW = 11. With TRKF = 1 (the default INH
/// 4000H) the first ΔMV is discarded (MVP := MV, E1 := 0), MV stays 0 and
/// TRKF is cleared; the next ΔMV counts.
#[test]
fn s_out1_adds_the_velocity_input_and_tracks_bumplessly() {
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D0:f32", "11").scan();
    assert_eq!(
        (p.real("D1012"), p.real("D1062"), p.real("D100")),
        (11.0, 11.0, 11.0)
    );
    assert_eq!((p.int("D102"), p.int("D1003"), p.int("D1116")), (0, 0, 0));
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1004", "H4000")
        .set("D1062:f32", "5")
        .set("D0:f32", "11")
        .scan();
    assert_eq!(
        (p.real("D1012"), p.real("D1062"), p.real("D100")),
        (0.0, 0.0, 0.0)
    );
    assert_eq!(p.int("D1004"), 0, "TRKF cleared");
    p.scan();
    assert_eq!((p.real("D1012"), p.real("D100")), (11.0, 11.0));
    // Output conversion: NMAX 200, NMIN −100 → 300/100 × 22 − 100 = −34.
    p.set("D10:f32", "200").set("D12:f32", "-100").scan();
    assert_eq!((p.real("D1012"), p.real("D100")), (22.0, -34.0));
}

/// Manual modes (MAN, CMB, CMV, LCM): alarms, ALM2 and BB1..BB4 cleared,
/// TRKF := 1, BW from the operator's MV; back in AUT the first ΔMV is
/// dropped and MVP := MV, so MV does not step.
#[test]
fn s_out1_manual_mode_sets_trkf_and_follows_the_operator() {
    for mode in ["H8", "H40", "H200", "H4"] {
        let mut p = out(OUT1, ProcessSettings::default());
        p.set("D1001", mode)
            .set("D1003", "H803")
            .set("D1116", "3")
            .set("D102", "HF")
            .set("D1012:f32", "30")
            .set("D0:f32", "5")
            .scan();
        assert_eq!(p.real("D100"), 30.0, "MODE {mode}");
        assert_eq!((p.int("D1003"), p.int("D1116"), p.int("D102")), (0, 0, 0));
        assert_eq!(p.int("D1004"), 0x4000, "TRKF");
        assert_eq!(p.real("D1062"), 0.0, "MVP untouched");
        p.set("D1001", "H10").scan();
        assert_eq!(
            (p.real("D1012"), p.real("D1062"), p.real("D100")),
            (30.0, 30.0, 30.0)
        );
        p.scan();
        assert_eq!((p.real("D1012"), p.real("D100")), (35.0, 35.0));
    }
    // LCC (b0) is an auto mode under DEC-5, a manual one with the swap.
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1001", "H1").set("D0:f32", "5").scan();
    assert_eq!(p.real("D1012"), 5.0);
    let mut p = out(
        OUT1,
        ProcessSettings {
            mode_lcc_b0: false,
            ..ProcessSettings::default()
        },
    );
    p.set("D1001", "H1").set("D0:f32", "5").scan();
    assert_eq!((p.real("D1012"), p.int("D1004")), (0.0, 0x4000));
}

/// The change-rate limiter (DML = 10): T = 25 against MV = 0 gives MV + DML
/// = 10 with BB4 = DMLA = 1 (BB1 too); MVP keeps T. Then 20, then 25.
#[test]
fn s_out1_change_rate_limit() {
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1048:f32", "10").set("D0:f32", "25").scan();
    assert_eq!((p.real("D1012"), p.real("D1062")), (10.0, 25.0));
    assert_eq!((p.int("D102"), p.int("D1003")), (0b1001, 0x800));
    p.set("D0:f32", "0").scan();
    assert_eq!(p.real("D1012"), 20.0);
    p.scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (25.0, 0, 0)
    );
    // Downward: T = 25 − 40 = −15 → MV − DML = 15.
    p.set("D0:f32", "-40").scan();
    assert_eq!((p.real("D1012"), p.int("D102")), (15.0, 0b1001));
    // DMLI inhibits DMLA/BB4, not the limiting.
    p.set("D1004", "H800").set("D0:f32", "0").scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (5.0, 0, 0)
    );
}

/// MH = 50, TI = 10, ΔT = 1: T = 60 → MV = MH, BB2 = MHA = MHA2 = 1; the
/// reset windup pulls MVP back: 60 − 1/10 × (60 − 50) = 59 (DEC-11). MHI
/// or ERRI clear MHA/BB2 but not MHA2 (L4437-4443). Low side: MLA2 = b0.
#[test]
fn s_out1_limiter_alm2_and_reset_windup() {
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1018:f32", "50").set("D0:f32", "60").scan();
    assert_eq!((p.real("D1012"), p.real("D100")), (50.0, 50.0));
    assert_eq!(p.real("D1062"), f(60.0 - 1.0 / 10.0 * (60.0 - 50.0)));
    assert_eq!(p.real("D1062"), 59.0);
    assert_eq!(
        (p.int("D102"), p.int("D1003"), p.int("D1116")),
        (0b011, 0x2, 0x2)
    );
    for inh in ["H2", "H8000"] {
        p.set("D1004", inh).set("D0:f32", "1").scan();
        assert_eq!(
            (p.int("D102"), p.int("D1003"), p.int("D1116")),
            (0, 0, 0x2),
            "INH {inh}"
        );
    }
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1020:f32", "10").set("D0:f32", "-20").scan();
    assert_eq!(p.real("D1012"), 10.0);
    assert_eq!(p.real("D1062"), f(-20.0 - 1.0 / 10.0 * (-20.0 - 10.0)));
    assert_eq!(
        (p.int("D102"), p.int("D1003"), p.int("D1116")),
        (0b101, 0x1, 0x1)
    );
    // DEC-7 alternative: MHA2 = b0, MLA2 = b1.
    let mut p = out(
        OUT1,
        ProcessSettings {
            alm2_mha2_b1: false,
            ..ProcessSettings::default()
        },
    );
    p.set("D1020:f32", "10").set("D0:f32", "-20").scan();
    assert_eq!(p.int("D1116"), 0x2);
}

/// TI = 0 skips the reset windup; the DEC-11 alternative sets MVP := MH.
#[test]
fn s_out1_reset_windup_switches() {
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1054:f32", "0")
        .set("D1018:f32", "50")
        .set("D0:f32", "60")
        .scan();
    assert_eq!((p.real("D1012"), p.real("D1062")), (50.0, 60.0));
    let mut p = out(
        OUT1,
        ProcessSettings {
            reset_windup_first_order: false,
            ..ProcessSettings::default()
        },
    );
    p.set("D1018:f32", "50").set("D0:f32", "60").scan();
    assert_eq!((p.real("D1012"), p.real("D1062")), (50.0, 50.0));
}

/// DEC-10: T = MV skips the limiter and the reset windup; MV, BB and the
/// alarms keep their values (BW is still converted). The alternative runs
/// the limiter and so clears them.
#[test]
fn s_out1_t_equal_mv_keeps_the_alarms_per_dec_10() {
    let init = |p: &mut Plc| {
        p.set("D1012:f32", "20")
            .set("D1062:f32", "20")
            .set("D1003", "H2")
            .set("D1116", "2")
            .set("D102", "3")
            .set("D0:f32", "0")
            .scan();
    };
    let mut p = out(OUT1, ProcessSettings::default());
    init(&mut p);
    assert_eq!((p.int("D102"), p.int("D1003"), p.int("D1116")), (3, 2, 2));
    assert_eq!(p.real("D100"), 20.0);
    let mut p = out(
        OUT1,
        ProcessSettings {
            output_tracking_skips_limits: false,
            ..ProcessSettings::default()
        },
    );
    init(&mut p);
    assert_eq!((p.int("D102"), p.int("D1003"), p.int("D1116")), (0, 0, 0));
}

/// SEA = 1 with SM1501 ON: BB1..BB4 := 0, MV, MVP and BW held
/// (L4359-4365, L4492-4501); with SM1501 OFF the output moves.
#[test]
fn s_out1_sm1501_holds_on_a_sensor_alarm() {
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1003", "H200")
        .set("SM1501", "1")
        .set("D102", "HF")
        .set("D100:f32", "77")
        .set("D1012:f32", "7")
        .set("D1062:f32", "7")
        .set("D0:f32", "5")
        .scan();
    assert_eq!(
        (p.real("D100"), p.real("D1012"), p.real("D1062")),
        (77.0, 7.0, 7.0)
    );
    assert_eq!(p.int("D102"), 0);
    p.set("SM1501", "0").scan();
    assert_eq!((p.real("D100"), p.real("D1012")), (12.0, 12.0));
}

/// Loop stop: BW holds, DMLA = MHA = MLA = 0, ALM2 := 0, MODE := MAN,
/// BB1..BB4 := 0; MV and MVP untouched. A MODE of neither group does nothing.
#[test]
fn s_out1_loop_stop_and_an_unknown_mode() {
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1003", "H4A03")
        .set("D1116", "3")
        .set("D102", "HF")
        .set("D100:f32", "9")
        .set("D1012:f32", "3")
        .set("D0:f32", "5")
        .scan();
    assert_eq!(
        (p.int("D1003"), p.int("D1116"), p.int("D102")),
        (0x4200, 0, 0)
    );
    assert_eq!(
        (p.int("D1001"), p.real("D100"), p.real("D1012")),
        (8, 9.0, 3.0)
    );
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D1001", "0").set("D0:f32", "5").scan();
    assert_eq!(
        (p.real("D1012"), p.real("D1062"), p.real("D100")),
        (0.0, 0.0, 0.0)
    );
}

/// Table 14.2 for S.OUT1: 1 input addition, 2 limiter, 3 reset windup, 4
/// output conversion; detail 1 for a bad float, 6 for an overflow.
#[test]
fn s_out1_errors() {
    let nan = |p: &mut Plc, d: u32| {
        p.set(&format!("D{d}"), "-1")
            .set(&format!("D{}", d + 1), "-1");
    };
    let mut p = out(OUT1, ProcessSettings::default());
    nan(&mut p, 0);
    p.scan();
    assert_pc_error(&p, 1, 1);
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("D0:f32", "3e38").set("D1062:f32", "3e38").scan();
    assert_pc_error(&p, 6, 1);
    let mut p = out(OUT1, ProcessSettings::default());
    nan(&mut p, 1048);
    p.set("D0:f32", "5").scan();
    assert_pc_error(&p, 1, 2);
    assert_eq!(p.real("D1062"), 5.0, "step 1 wrote MVP");
    let mut p = out(OUT1, ProcessSettings::default());
    nan(&mut p, 1054);
    p.set("D1018:f32", "50").set("D0:f32", "60").scan();
    assert_pc_error(&p, 1, 3);
    assert_eq!(p.real("D1012"), 50.0, "step 2 wrote MV");
    let mut p = out(OUT1, ProcessSettings::default());
    p.set("SD1500", "-1").set("SD1501", "-1");
    p.set("D1018:f32", "50").set("D0:f32", "60").scan();
    assert_pc_error(&p, 1, 3);
    let mut p = out(OUT1, ProcessSettings::default());
    nan(&mut p, 10);
    p.set("D0:f32", "5").scan();
    assert_pc_error(&p, 1, 4);
}

const OUT2: &str = "LD SM400\nS.OUT2 D0 D100 D10 D1000\nEND\n";

/// 000 §8.3: E1 is the MV target, rate- and MH/ML-limited when E1 ≠ MV; no
/// MVP, no ALM2; manual modes do not set TRKF.
#[test]
fn s_out2_positional_output() {
    let mut p = out(OUT2, ProcessSettings::default());
    p.set("D1048:f32", "10")
        .set("D1018:f32", "25")
        .set("D0:f32", "30")
        .scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (10.0, 0b1001, 0x800)
    );
    p.scan();
    assert_eq!(p.real("D1012"), 20.0);
    p.scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (25.0, 0b011, 0x2)
    );
    assert_eq!(
        (p.real("D100"), p.real("D1062"), p.int("D1116")),
        (25.0, 0.0, 0)
    );
    // E1 = MV: everything kept (DEC-10).
    p.set("D0:f32", "25")
        .set("D102", "HB")
        .set("D1003", "H802")
        .scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (25.0, 0b1011, 0x802)
    );
    p.set("D0:f32", "24").scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (24.0, 0, 0)
    );
    p.set("D1001", "H8")
        .set("D1012:f32", "60")
        .set("D102", "HF")
        .scan();
    assert_eq!(
        (p.real("D100"), p.int("D1004"), p.int("D102")),
        (60.0, 0, 0)
    );
    p.set("D1003", "H4000").set("D1001", "H10").scan();
    assert_eq!((p.int("D1001"), p.real("D100")), (8, 60.0));
    // SM1501 with SEA holds.
    let mut p = out(OUT2, ProcessSettings::default());
    p.set("D1003", "H200")
        .set("SM1501", "1")
        .set("D0:f32", "30")
        .scan();
    assert_eq!(p.real("D1012"), 0.0);
}

#[test]
fn s_out2_errors() {
    let mut p = out(OUT2, ProcessSettings::default());
    p.set("D0", "-1").set("D1", "-1").scan();
    assert_pc_error(&p, 1, 2);
    let mut p = out(OUT2, ProcessSettings::default());
    p.set("D12", "-1")
        .set("D13", "-1")
        .set("D0:f32", "5")
        .scan();
    assert_pc_error(&p, 1, 4);
    assert_eq!(p.real("D1012"), 5.0);
}

/// 000 §8.4: manual modes BW = (NMAX − NMIN)/100 × MV + NMIN; auto modes
/// hold BW; loop stop holds BW and sets MAN.
#[test]
fn s_mout_manual_output() {
    let mut p = Plc::process("LD SM400\nS.MOUT SD1506 D100 D10 D1000\nEND\n");
    loop_tag(&mut p, 1000);
    p.set("D10:f32", "200")
        .set("D12:f32", "0")
        .set("D1012:f32", "40");
    p.set("D1001", "H8").scan();
    assert_eq!(p.real("D100"), 80.0);
    p.set("D1001", "H10").set("D1012:f32", "10").scan();
    assert_eq!(p.real("D100"), 80.0);
    p.set("D1003", "H4000").scan();
    assert_eq!((p.int("D1001"), p.real("D100")), (8, 80.0));
    p.set("D1003", "0").scan();
    assert_eq!(p.real("D100"), 20.0);
    p.set("D1012", "-1").set("D1013", "-1").scan();
    assert_pc_error(&p, 1, 1);
}

/// Steps per 000 §2.2.7 and the operand areas.
#[test]
fn process_io_operands_are_checked() {
    let d = process_diagnostics("LD SM400\nS.OUT1 D0 D100 D10 D12200\nEND\n");
    assert!(
        d[0].contains("`D12200`: the loop tag takes 128 words"),
        "{d:?}"
    );
    let d = process_diagnostics("LD SM400\nS.IN D0 D100 K5 D1000\nS.BC D0 D1 D2\nEND\n");
    assert!(d[0].contains("`K5`: a word device is needed here"), "{d:?}");
    assert_eq!(d.len(), 2, "{d:?}");
}
