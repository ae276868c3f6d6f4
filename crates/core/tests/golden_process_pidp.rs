//! S.PIDP with its output stage (000 §9.3, spec §4.11), S.R (§9.7, §4.15)
//! and S.ONF2/S.ONF3 (§9.20-§9.21, §4.24) on a process CPU; expected values
//! from the spec's formulas in f32.

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

const BB1: u16 = 1;
const BB2: u16 = 2;
const BB3: u16 = 4;
const BB4: u16 = 8;
const BB5: u16 = 16;

/// BW = (NMAX − NMIN)/100 × MV + NMIN with NMAX 200 (S2 +7), NMIN −100 (+9).
fn out(mv: f32) -> f32 {
    (200.0f32 - -100.0) / 100.0 * mv + -100.0
}

fn pidp(s: ProcessSettings) -> common::Plc {
    let mut p = start_with("S.PIDP", s);
    setf(&mut p, "D207", 200.0);
    setf(&mut p, "D209", -100.0);
    tf(&mut p, 14, 50.0);
    setf(&mut p, "D0", 40.0);
    p
}

/// S.PIDP position form: In = In-1 + (CT/TI)·DVn, T = KP × (DVn + In + Bn);
/// DV 10, P 1, I 10, CT 1 → T = 11, 12 …; the rate limiter (DML 0.5) and the
/// high limiter (MH 12.6) with MHA2, which then freezes the integral.
#[test]
fn s_pidp_position_form_and_its_output_stage() {
    let mut p = pidp(ProcessSettings::default());
    p.scan();
    assert_eq!(bw(&p), out(0.0), "start execution: T = MV, output of MV 0");
    p.scan();
    assert_eq!((tag(&p, 12), tag(&p, 100), bw(&p)), (11.0, 1.0, out(11.0)));
    p.scan();
    assert_eq!((tag(&p, 12), bw(&p)), (12.0, out(12.0)));
    tf(&mut p, 48, 0.5);
    p.scan();
    assert_eq!(tag(&p, 12), 12.5, "T 13 − MV 12 > DML: MV + DML");
    assert_eq!((tagw(&p, 3) & DMLA, bb(&p)), (DMLA, BB1 | BB5));
    tf(&mut p, 18, 12.6);
    p.scan();
    assert_eq!(tag(&p, 12), 12.6f32, "T1 = 13.0 > MH");
    assert_eq!(tagw(&p, 3), DMLA | MHA);
    assert_eq!(tagw(&p, 116), 2, "MHA2 = b1 (DEC-7)");
    assert_eq!(bb(&p), BB1 | BB3 | BB5);
    assert_eq!(bw(&p), out(12.6));
    p.scan();
    assert_eq!(tag(&p, 100), 4.0, "MHA2 freezes the positive increment");
    // MHI: MHA and BB3 read 0, MHA2 stays.
    tw(&mut p, 4, MHA);
    p.scan();
    assert_eq!((tagw(&p, 3) & MHA, bb(&p) & BB3, tagw(&p, 116)), (0, 0, 2));
}

#[test]
fn s_pidp_low_limit_and_mla2() {
    let mut p = pidp(ProcessSettings::default());
    tf(&mut p, 20, 20.0);
    p.scan().scan();
    assert_eq!((tag(&p, 12), tagw(&p, 3), tagw(&p, 116)), (20.0, MLA, 1));
    assert_eq!(bb(&p), BB1 | BB4);
    assert_eq!(bw(&p), out(20.0));
}

/// DEC-10: on the executions between control cycles T = MV, so the limiter is
/// skipped and its alarms keep their values; the alternative runs it (MV at
/// MH is within the limits, so MHA clears).
#[test]
fn s_pidp_between_cycles_keeps_the_limiter_alarms_dec_10() {
    for skip in [true, false] {
        let mut p = pidp(settings(|s| s.output_tracking_skips_limits = skip));
        tf(&mut p, 46, 2.0);
        tf(&mut p, 18, 5.0);
        p.scans(3);
        assert_eq!((tag(&p, 12), tagw(&p, 3) & MHA), (5.0, MHA));
        p.scan();
        assert_eq!(tagw(&p, 3) & MHA, if skip { MHA } else { 0 });
        assert_eq!(tagw(&p, 116), if skip { 2 } else { 0 });
    }
}

/// The M-group (000 §9.3 (6)): MHA, MLA, DMLA, MHA2, MLA2 and BB3..BB5
/// cleared, BB1 := BB2, BW from the operator's MV. The integral: new
/// firmware freezes it in MAN/LCM/CMV, old firmware integrates (DEC-15).
#[test]
fn s_pidp_manual_mode_and_the_firmware_integral_rules() {
    for (new, grows) in [(true, false), (false, true)] {
        let mut p = pidp(settings(|s| s.firmware_serial_ge_07032 = new));
        tf(&mut p, 50, 10.0);
        tf(&mut p, 48, 1.0);
        p.scans(2);
        assert_eq!(bb(&p), BB1 | BB2 | BB5);
        tw(&mut p, 1, MAN);
        tf(&mut p, 12, 30.0);
        p.scan();
        assert_eq!((tagw(&p, 3), tagw(&p, 116)), (DVLA, 0));
        assert_eq!(bb(&p), BB1 | BB2, "BB1 := BB2");
        assert_eq!((tag(&p, 12), bw(&p)), (30.0, out(30.0)));
        assert_eq!(tag(&p, 100) > 1.0, grows, "firmware ≥ 07032: {new}");
    }
}

/// SD1508 b0 (firmware ≥ 07032): the integral holds while INH.TRKF = 1 in an
/// auto mode (000 §9.3 L9592-9604).
#[test]
fn s_pidp_sd1508_holds_the_integral_while_tracking() {
    for (sd1508, trkf, new, held) in [
        (1, TRKF, true, true),
        (0, TRKF, true, false),
        (1, 0, true, false),
        (1, TRKF, false, false),
    ] {
        let mut p = pidp(settings(|s| s.firmware_serial_ge_07032 = new));
        p.set("SD1508", &sd1508.to_string());
        tw(&mut p, 4, trkf);
        p.scan().scan();
        assert_eq!(
            tag(&p, 100) == 0.0,
            held,
            "SD1508 {sd1508}, INH {trkf:#x}, new {new}"
        );
    }
}

/// Loop stop (000 §9.3 (9)): BW holds; DVLA, MHA, MLA, DMLA, ALM2, BB1..BB5
/// cleared; MODE MAN.
#[test]
fn s_pidp_loop_stop() {
    let mut p = pidp(ProcessSettings::default());
    tf(&mut p, 18, 5.0);
    tf(&mut p, 50, 10.0);
    p.scans(2);
    assert_eq!(bb(&p), BB1 | BB2 | BB3);
    let before = bw(&p);
    let alm = tagw(&p, 3) | SPA;
    tw(&mut p, 3, alm);
    p.scan();
    assert_eq!(
        (bw(&p), bb(&p), tagw(&p, 3), tagw(&p, 116)),
        (before, 0, SPA, 0)
    );
    assert_eq!(tagw(&p, 1), MAN);
}

/// S.PIDP Table 14.2: 1 CT, 2 SV, 3 tracking, 4 gain, 5 PIDP op, 6
/// deviation, 7 rate/limiter, 8 output conversion.
#[test]
fn s_pidp_error_codes() {
    let cases: Vec<Case> = vec![
        ("ΔT 0", Box::new(|p| setf(p, "SD1500", 0.0)), (5, 1)),
        (
            "SVPTN 4",
            Box::new(|p| {
                p.set("D206", "4");
            }),
            (3, 2),
        ),
        ("RH = RL", Box::new(|p| tf(p, 22, 0.0)), (5, 3)),
        ("P < 0", Box::new(|p| tf(p, 52, -1.0)), (2, 4)),
        ("TD < 0", Box::new(|p| tf(p, 56, -1.0)), (2, 5)),
        ("NaN In-1", Box::new(|p| tw(p, 101, 0x7fc0)), (1, 5)),
        ("DVL < 0", Box::new(|p| tf(p, 50, -1.0)), (2, 6)),
        ("DML < 0", Box::new(|p| tf(p, 48, -1.0)), (2, 7)),
        ("NaN MV", Box::new(|p| tw(p, 13, 0x7fc0)), (1, 7)),
        (
            "NaN NMAX",
            Box::new(|p| {
                p.set("D208", "32704");
            }),
            (1, 8),
        ),
    ];
    for (what, setup, want) in cases {
        let mut p = pidp(ProcessSettings::default());
        setup(&mut p);
        assert_eq!(error_after(&mut p, 3), want, "S.PIDP: {what}");
    }
}

fn ratio() -> common::Plc {
    let mut p = start("S.R");
    tf(&mut p, 14, 50.0);
    tf(&mut p, 16, 5.0);
    tf(&mut p, 50, 20.0);
    tf(&mut p, 52, 100.0);
    tf(&mut p, 54, 0.0);
    setf(&mut p, "D0", 50.0);
    setf(&mut p, "D100", 7.0);
    p
}

/// S.R (spec §4.15, DEC-17): Rn moves toward SPR by at most DR per control
/// cycle, BW = E1 × (Rn − RMIN)/(RMAX − RMIN) + BIAS.
#[test]
fn s_r_ratio_with_its_rate_limit() {
    let mut p = ratio();
    p.scan();
    assert_eq!(bw(&p), 7.0, "the start execution holds BW");
    let mut seen = vec![];
    for _ in 0..3 {
        p.scan();
        seen.push((tag(&p, 56), bw(&p)));
    }
    let bw = |rn: f32| 50.0f32 * ((rn - 0.0) / (100.0 - 0.0)) + 5.0;
    assert_eq!(seen, [(20.0, bw(20.0)), (40.0, bw(40.0)), (50.0, bw(50.0))]);
    assert_eq!(tag(&p, 98), 50.0, "Rn-1 at +98");
    // RMIN ≠ 0: (50 − 20)/(120 − 20) = 0.3.
    tf(&mut p, 52, 120.0);
    tf(&mut p, 54, 20.0);
    p.scan();
    assert_eq!(lp::bw(&p), 50.0f32 * ((50.0 - 20.0) / (120.0 - 20.0)) + 5.0);
    // A falling SPR: −DR per cycle.
    tf(&mut p, 14, 0.0);
    p.scan();
    assert_eq!(tag(&p, 56), 30.0);
}

/// S.R cascade (E2 → SPR, written to +14) and tracking (E2 := 100/(RMAX −
/// RMIN) × (SPR − RMIN), upper TRKF), CT hold, loop stop.
#[test]
fn s_r_cascade_tracking_and_stop() {
    let mut p = ratio();
    tw(&mut p, 1, CAS);
    p.set("D201", "0");
    tf(&mut p, 52, 200.0);
    setf(&mut p, "D300", 25.0);
    p.scan().scan();
    assert_eq!(tag(&p, 14), 200.0 / 100.0 * 25.0 + 0.0);
    // AUT with TRK: E2 written back, TRKF in the upper loop.
    let mut p = ratio();
    p.set("D200", "1").set("D201", "0");
    p.scan().scan();
    assert_eq!(getf(&p, "D300"), 100.0f32 / (100.0 - 0.0) * (50.0 - 0.0));
    assert_eq!(word(&p, "D292"), TRKF);
    // CT 3: BW holds between control cycles.
    let mut p = ratio();
    tf(&mut p, 46, 3.0);
    p.scans(4);
    let b = bw(&p);
    p.scan();
    assert_eq!(bw(&p), b);
    assert_eq!(tag(&p, 56), 20.0);
    // Loop stop: BW holds, MODE MAN.
    tw(&mut p, 3, SPA);
    setf(&mut p, "D0", 90.0);
    p.scans(4);
    assert_eq!((bw(&p), tagw(&p, 1)), (b, MAN));
}

/// S.R Table 14.2: 1 CT, 2 engineering conversion, 3 tracking, 4 rate
/// limiter, 5 ratio operation; S.R's other form is rejected at load.
#[test]
fn s_r_error_codes() {
    let cases: Vec<Case> = vec![
        ("CT/ΔT > 32767", Box::new(|p| tf(p, 46, 1e5)), (4, 1)),
        (
            "cascade NaN E2",
            Box::new(|p| {
                tw(p, 1, CAS);
                p.set("D201", "0").set("D301", "32704");
            }),
            (1, 2),
        ),
        (
            "tracking RMAX = RMIN",
            Box::new(|p| {
                p.set("D200", "1").set("D201", "0");
                tf(p, 54, 100.0);
            }),
            (5, 3),
        ),
        ("DR < 0", Box::new(|p| tf(p, 50, -1.0)), (2, 4)),
        ("RMAX = RMIN", Box::new(|p| tf(p, 54, 100.0)), (5, 5)),
        (
            "NaN E1",
            Box::new(|p| {
                p.set("D1", "32704");
            }),
            (1, 5),
        ),
    ];
    for (what, setup, want) in cases {
        let mut p = ratio();
        setup(&mut p);
        assert_eq!(error_after(&mut p, 3), want, "S.R: {what}");
    }
    let dialect = softplc_core::program::dialect_for(
        common::process_cpu(),
        settings(|s| s.ratio_reconstructed = false),
    );
    let e = softplc_core::program::compile_il_in(
        "t.il",
        &program("S.R"),
        &softplc_core::profile::default_config().devices,
        &dialect,
    )
    .unwrap_err();
    assert!(e.0[0].message.contains("ratio_reconstructed"));
}

/// S.ONF2 (spec §4.24): HS0 2 %, PN 0, SV 50: DV > 2 → 100 %, DV < −2 → 0 %,
/// else the previous BW; MV := BW in the A-group; BB1 = |BW| ≥ 50 %.
#[test]
fn s_onf2_two_position_control() {
    let mut p = start("S.ONF2");
    tf(&mut p, 14, 50.0);
    tf(&mut p, 18, 2.0);
    setf(&mut p, "D0", 40.0);
    setf(&mut p, "D100", 30.0);
    p.scan();
    assert_eq!(bw(&p), 30.0, "A-group, not reached: BW holds");
    let mut seen = vec![];
    for e1 in [40.0, 49.0, 53.0, 51.0, 47.0] {
        setf(&mut p, "D0", e1);
        p.scan();
        assert_eq!(tag(&p, 12), bw(&p), "MV := BW");
        seen.push((bw(&p), bb(&p)));
    }
    assert_eq!(
        seen,
        [(100.0, 1), (100.0, 1), (0.0, 0), (0.0, 0), (100.0, 1)]
    );
    assert_eq!(tag(&p, 16), 3.0, "DV at +16");
    // M-group: BW = MV (operator), on every execution.
    tw(&mut p, 1, MAN);
    tf(&mut p, 12, 60.0);
    tf(&mut p, 46, 4.0);
    for _ in 0..3 {
        p.scan();
        assert_eq!((bw(&p), bb(&p)), (60.0, 1));
    }
    tf(&mut p, 12, -55.0);
    p.scan();
    assert_eq!((bw(&p), bb(&p)), (-55.0, 1), "|BW| ≥ 50");
    tf(&mut p, 12, 49.0);
    p.scan();
    assert_eq!(bb(&p), 0);
    // Loop stop: BW and BB hold, MODE MAN.
    tw(&mut p, 1, AUT);
    tw(&mut p, 3, SPA);
    tf(&mut p, 12, 90.0);
    p.scan();
    assert_eq!((bw(&p), bb(&p), tagw(&p, 1)), (49.0, 0, MAN));
}

/// S.ONF3: HS0 1, HS1 5: DV ≥ 6 → 100 % (BB1), DV ≤ −6 → 0 % (BB2), −4 ≤ DV ≤
/// 4 → 50 % (neither), otherwise the previous BW.
#[test]
fn s_onf3_three_position_control() {
    let mut p = start("S.ONF3");
    tf(&mut p, 14, 50.0);
    tf(&mut p, 18, 1.0);
    tf(&mut p, 20, 5.0);
    p.scan();
    let mut seen = vec![];
    for e1 in [40.0, 45.0, 47.0, 55.0, 57.0, 55.5, 54.0] {
        setf(&mut p, "D0", e1);
        p.scan();
        seen.push((bw(&p), bb(&p)));
    }
    assert_eq!(
        seen,
        [
            (100.0, 1),
            (100.0, 1),
            (50.0, 0),
            (50.0, 0),
            (0.0, 2),
            (0.0, 2),
            (50.0, 0)
        ]
    );
}

/// S.ONF2/3 Table 14.2: 1 CT, 2 SV, 3 tracking, 4 MV compensation, 5 MV
/// output.
#[test]
fn s_onf_error_codes() {
    for m in ["S.ONF2", "S.ONF3"] {
        let cases: Vec<Case> = vec![
            ("ΔT 0", Box::new(|p| setf(p, "SD1500", 0.0)), (5, 1)),
            (
                "SVPTN 4",
                Box::new(|p| {
                    p.set("D202", "4");
                }),
                (3, 2),
            ),
            ("RH = RL", Box::new(|p| tf(p, 22, 0.0)), (5, 3)),
            ("HS0 < 0", Box::new(|p| tf(p, 18, -1.0)), (2, 4)),
            (
                "NaN E1",
                Box::new(|p| {
                    p.set("D1", "32704");
                }),
                (1, 4),
            ),
            (
                "MAN, NaN MV",
                Box::new(|p| {
                    tw(p, 1, MAN);
                    tw(p, 13, 0x7fc0);
                }),
                (1, 5),
            ),
        ];
        for (what, setup, want) in cases {
            let mut p = start(m);
            tf(&mut p, 18, 1.0);
            setup(&mut p);
            assert_eq!(error_after(&mut p, 3), want, "{m}: {what}");
        }
    }
}

/// Each control instruction loads on a process CPU with the steps of 000
/// §2.2.7 (2 + ⌈len/2⌉ + 5 operands: 9, S.R 8) and its operand checks.
#[test]
fn control_instructions_load_with_their_steps_and_operand_checks() {
    let programs = [
        ("LD SM400\nS.PID D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.2PID D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.PIDP D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.SPI D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.IPD D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.BPI D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.R D0 D100 D200 D1000 SD1506\nEND\n", 8),
        ("LD SM400\nS.ONF2 D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.ONF3 D0 D100 D200 D1000 SD1506\nEND\n", 9),
        ("LD SM400\nS.AT1 D0 D100 D200 D1000 D300\nEND\n", 9),
    ];
    let dialect =
        softplc_core::program::dialect_for(common::process_cpu(), ProcessSettings::default());
    let devices = softplc_core::profile::default_config().devices;
    for (src, steps) in programs {
        let prog = softplc_core::program::compile_il_in("t.il", src, &devices, &dialect)
            .unwrap_or_else(|d| panic!("{src}: {d}"));
        assert_eq!(prog.op_step.last().copied(), Some(1 + steps), "{src}");
    }
    let d = common::process_diagnostics(
        "LD SM400\nS.PID D0 D100 D200 D12200 D300\nS.PIDP D0 K1 D200 D1000 D300\nS.AT1 D0 D100 D200 D1000\nEND\n",
    );
    assert!(
        d[0].contains("`D12200`: the loop memory takes 128 words"),
        "{d:?}"
    );
    assert!(d[1].contains("`K1`: a word device is needed here"), "{d:?}");
    assert!(d[2].starts_with("4:1: "), "{d:?}");
    assert_eq!(d.len(), 3, "{d:?}");
    // A plain Q CPU rejects them, naming the process models.
    let d = common::diagnostics("LD SM400\nS.PID D0 D100 D200 D1000 D300\nEND\n");
    assert!(d[0].contains("Q06PHCPU"), "{d:?}");
}
