//! Process-control compensation instructions (000 ch. 10) on a process CPU;
//! values worked out from the manual's formulas in f32.

mod common;
use common::{diagnostics, process_diagnostics, Plc};
use softplc_core::program::ProcessSettings;

/// 000 §10.6 S.ENG: BW = (RH − RL)/100 × E1 + RL; §10.7 S.IENG: BW =
/// 100/(RH − RL) × (E1 − RL). RH = 20, RL = 0 (the S.IENG figure,
/// L20316-20352: 16 m³/h → 80 %, 5 → 25 %).
#[test]
fn s_eng_and_s_ieng_convert_between_percent_and_engineering_units() {
    let src = "LD SM400\nS.ENG D0 D100 D10 SD1506\nS.IENG D2 D102 D10 SD1506\nEND\n";
    let mut p = Plc::process(src);
    p.set("D10:f32", "20").set("D12:f32", "0");
    for (pct, eng) in [(50.0, 10.0), (80.0, 16.0), (25.0, 5.0), (100.0, 20.0)] {
        p.set("D0:f32", &pct.to_string())
            .set("D2:f32", &eng.to_string());
        p.scan();
        assert_eq!(p.real("D100"), eng, "S.ENG {pct} %");
        assert_eq!(p.real("D102"), pct, "S.IENG {eng}");
    }
    // RL ≠ 0: (150 − (−50))/100 × 25 + (−50) = 0; inverse of 0 → 25 %.
    p.set("D10:f32", "150").set("D12:f32", "-50");
    p.set("D0:f32", "25").set("D2:f32", "0").scan();
    assert_eq!(p.real("D100"), 0.0);
    assert_eq!(p.real("D102"), 25.0);
    // RH = RL: S.IENG gives 0, not an error (L20408-20416).
    p.set("D10:f32", "7").set("D12:f32", "7").scan();
    assert_eq!(p.real("D102"), 0.0);
    assert_eq!(p.real("D100"), 7.0);
    assert_eq!(p.error(), None);
}

/// DEC-28: with RH < RL the formula is applied (a decreasing mapping); the
/// alternative setting leaves BW unchanged.
#[test]
fn s_ieng_with_rh_below_rl_follows_dec_28() {
    let src = "LD SM400\nS.IENG D0 D100 D10 SD1506\nEND\n";
    let init = |p: &mut Plc| {
        p.set("D10:f32", "0")
            .set("D12:f32", "20")
            .set("D0:f32", "5")
            .set("D100:f32", "-1");
        p.scan();
    };
    let mut p = Plc::process(src);
    init(&mut p);
    assert_eq!(p.real("D100"), 75.0, "100/(0 − 20) × (5 − 20)");
    let mut p = Plc::process_with(
        src,
        ProcessSettings {
            ieng_decreasing: false,
            ..ProcessSettings::default()
        },
    );
    init(&mut p);
    assert_eq!(p.real("D100"), -1.0);
}

/// A NaN input is 4100 with SD1502 = 1 (not a number), SD1503 = 1 (000 §14, DEC-36).
#[test]
fn a_bad_float_is_4100_with_the_detail_codes() {
    let mut p = Plc::process("LD SM400\nS.ENG D0 D100 D10 SD1506\nEND\n");
    p.set("D0", "-1").set("D1", "-1").scan();
    assert_eq!(p.error().map(|e| e.0), Some(4100));
    assert_eq!(p.int("SD1502"), 1);
    assert_eq!(p.int("SD1503"), 1);
}

#[test]
fn process_instructions_need_a_process_cpu_and_word_devices() {
    let d = diagnostics("LD SM400\nS.ENG D0 D100 D10 SD1506\nEND\n");
    assert!(
        d[0].starts_with("2:1: unsupported instruction `S.ENG`: "),
        "{d:?}"
    );
    assert!(d[0].contains("Q06PHCPU"), "{d:?}");
    let d = process_diagnostics("LD SM400\nS.ENG K1 D100 M0 SD1506\nSP.ENG D0 D1 D2 D3\nEND\n");
    assert_eq!(
        d[..2],
        [
            "2:7: `K1`: a word device is needed here",
            "2:15: `M0`: a word device is needed here"
        ]
    );
    assert!(
        d[2].starts_with("3:1: ") && d[2].contains("no pulse form"),
        "{d:?}"
    );
    assert_eq!(d.len(), 3, "{d:?}");
    let d = process_diagnostics("LD SM400\nS.ENG D0 D12287 D10 SD1506\nEND\n");
    assert!(
        d[0].contains("`D12287`: the block memory takes 2 words"),
        "{d:?}"
    );
}

fn fails(p: &Plc, detail: i64) {
    assert_eq!(p.error().map(|e| e.0), Some(4100));
    assert_eq!((p.int("SD1502"), p.int("SD1503")), (detail, 1));
}

const FG: &str = "LD SM400\nS.FG D0 D100 D10 D200\nS.IFG D0 D102 D10 D200\nEND\n";

/// Writes SN and the (Xi, Yi) table at D200.
fn table(p: &mut Plc, pts: &[(f32, f32)]) {
    p.set("D10", &pts.len().to_string());
    for (i, (x, y)) in pts.iter().enumerate() {
        p.set(&format!("D{}:f32", 200 + 4 * i), &x.to_string());
        p.set(&format!("D{}:f32", 202 + 4 * i), &y.to_string());
    }
}

fn fg(p: &mut Plc, e1: f32) -> (f64, f64) {
    p.set("D0:f32", &e1.to_string()).scan();
    assert_eq!(p.error(), None);
    (p.real("D100"), p.real("D102"))
}

/// 000 §10.1/§10.2, spec §7: points (30, 40), (60, 70) and E1 = 50 give
/// S.FG 60 and S.IFG 40; outside the table the end values.
#[test]
fn s_fg_and_s_ifg_interpolate_the_breakpoint_table() {
    let mut p = Plc::process(FG);
    table(&mut p, &[(30.0, 40.0), (60.0, 70.0)]);
    assert_eq!(fg(&mut p, 50.0), (60.0, 40.0));
    assert_eq!(fg(&mut p, 10.0), (40.0, 30.0), "E1 ≤ X1 → Y1; E1 ≤ Y1 → X1");
    assert_eq!(fg(&mut p, 30.0), (40.0, 30.0));
    assert_eq!(fg(&mut p, 60.0), (70.0, 30.0 + 20.0));
    assert_eq!(fg(&mut p, 100.0), (70.0, 60.0), "beyond the last point");
    table(&mut p, &[(0.0, 0.0), (3.0, 1.0)]);
    assert_eq!(fg(&mut p, 1.0), ((1.0f32 / 3.0 * 1.0) as f64, 3.0));
}

/// A decreasing X ends the table (n = i − 1); of equal Xi the smallest i
/// is used; SN = 0 is not executed.
#[test]
fn s_fg_truncates_at_a_decreasing_point_and_takes_the_smallest_i() {
    let mut p = Plc::process("LD SM400\nS.FG D0 D100 D10 D200\nEND\n");
    table(
        &mut p,
        &[(0.0, 0.0), (10.0, 100.0), (5.0, 7.0), (20.0, 200.0)],
    );
    p.set("D0:f32", "15").scan();
    assert_eq!(p.real("D100"), 100.0, "n = 2: E1 > X2 → Y2");
    table(
        &mut p,
        &[(0.0, 0.0), (10.0, 100.0), (10.0, 500.0), (20.0, 600.0)],
    );
    p.set("D0:f32", "10").scan();
    assert_eq!(p.real("D100"), 100.0);
    p.set("D0:f32", "15").scan();
    assert_eq!(p.real("D100"), 550.0, "(600 − 500)/(20 − 10) × 5 + 500");
    p.set("D10", "0").set("D100:f32", "9").scan();
    assert_eq!(p.real("D100"), 9.0);
    assert_eq!(p.error(), None);
}

/// SN ∉ 0..48 is 4100 with SD1502 = 3; a table past the device is 4101.
#[test]
fn s_fg_errors() {
    for sn in ["49", "-1"] {
        let mut p = Plc::process("LD SM400\nS.IFG D0 D100 D10 D200\nEND\n");
        p.set("D10", sn).scan();
        fails(&p, 3);
    }
    let mut p = Plc::process("LD SM400\nS.FG D0 D100 D10 D12200\nEND\n");
    p.set("D10", "48").scan();
    assert_eq!(p.error().map(|e| e.0), Some(4101));
}

const FLT: &str = "LD SM400\nS.FLT D0 D100 D10 D200\nEND\n";

fn flt(s: ProcessSettings, st: &str, sn: &str, dt: &str) -> Plc {
    let mut p = Plc::process_with(FLT, s);
    p.set("SD1500:f32", dt).set("D10:f32", st).set("D12", sn);
    p
}

/// Feeds `e` one per execution; (BW, BB1) after each.
fn feed(p: &mut Plc, e: &[f32]) -> Vec<(f64, i64)> {
    e.iter()
        .map(|v| {
            p.set("D0:f32", &v.to_string()).scan();
            assert_eq!(p.error(), None);
            (p.real("D100"), p.int("D102") & 1)
        })
        .collect()
}

/// 000 §10.3 (DEC-26): the first execution starts and samples; no mean until
/// SN samples are stored (BB1 = 1), then the mean of the last SN.
#[test]
fn s_flt_moving_average() {
    let mut p = flt(ProcessSettings::default(), "1", "3", "1");
    assert_eq!(
        feed(&mut p, &[10.0, 20.0, 30.0, 40.0, 50.0]),
        [(0.0, 1), (0.0, 1), (20.0, 0), (30.0, 0), (40.0, 0)]
    );
    // An SN change restarts: emptied, BW holds until 2 new samples.
    p.set("D12", "2");
    assert_eq!(
        feed(&mut p, &[1.0, 2.0, 4.0]),
        [(40.0, 1), (1.5, 0), (3.0, 0)]
    );
    // Spec §6 timing conditions: E1 = 50, ST = 1, SN = 10.
    let mut p = flt(ProcessSettings::default(), "1", "10", "1");
    let r = feed(&mut p, &[50.0; 10]);
    assert_eq!(r[8], (0.0, 1));
    assert_eq!(r[9], (50.0, 0));
    // SN = 0 clears BW and BB.
    p.set("D12", "0").set("D102", "-1");
    assert_eq!(feed(&mut p, &[7.0]), [(0.0, 0)]);
    assert_eq!(p.int("D102"), 0);
}

/// The update period is round(ST/ΔT) (L19656, DEC-2): 0.9/0.3 is 2.9999998
/// in f32 and rounds to 3; ST = 2, ΔT = 1 holds between samples.
#[test]
fn s_flt_sampling_period_rounds() {
    let mut p = flt(ProcessSettings::default(), "0.9", "1", "0.3");
    let e: Vec<f32> = (0..7).map(|t| t as f32).collect();
    let bw: Vec<f64> = feed(&mut p, &e).iter().map(|r| r.0).collect();
    assert_eq!(bw, [0.0, 0.0, 0.0, 3.0, 3.0, 3.0, 6.0]);
    let mut p = flt(ProcessSettings::default(), "2", "2", "1");
    let bw: Vec<f64> = feed(&mut p, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
        .iter()
        .map(|r| r.0)
        .collect();
    assert_eq!(bw, [0.0, 0.0, 2.0, 2.0, 4.0, 4.0], "samples 1, 3, 5");
}

/// DEC-3: a change of ΔT takes effect when the period in progress ends (ST
/// = 2, ΔT 1 → 2 after the start: the next sample at t = 2, then every
/// execution); the alternative compares an up-count with the current N.
#[test]
fn s_flt_period_change_follows_dec_3() {
    let run = |s: ProcessSettings| {
        let mut p = flt(s, "2", "1", "1");
        let mut bw = Vec::new();
        for t in 0..4 {
            p.set("D0:f32", &t.to_string()).scan();
            bw.push(p.real("D100"));
            p.set("SD1500:f32", "2");
        }
        bw
    };
    assert_eq!(run(ProcessSettings::default()), [0.0, 0.0, 2.0, 3.0]);
    let alt = ProcessSettings {
        period_change_at_reach: false,
        ..ProcessSettings::default()
    };
    assert_eq!(run(alt), [0.0, 1.0, 2.0, 3.0]);
}

/// SN ∉ 0..48: SD1502 = 3; ST/ΔT over 32767: 4; ΔT = 0: 5 (spec §5);
/// DEC-26's alternative is not described: rejected at load.
#[test]
fn s_flt_errors_and_dec_26() {
    for (st, sn, dt, detail) in [
        ("1", "49", "1", 3),
        ("40000", "2", "1", 4),
        ("1", "2", "0", 5),
    ] {
        let mut p = flt(ProcessSettings::default(), st, sn, dt);
        p.scan();
        fails(&p, detail);
    }
    let s = ProcessSettings {
        flt_restart_on_change: false,
        ..ProcessSettings::default()
    };
    assert!(common::process_diagnostics_with(FLT, s)[0]
        .contains("flt_restart_on_change = false (DEC-26)"));
}

const SUM: &str = "LD SM400\nS.SUM D0 D100 D10 SD1506\nEND\n";

/// 000 §10.4: e1 = 0 gives A; above the low cut BW += E1·ΔT/T (spec §6
/// timing: E1 = 50, RANGE = 1 → 50, 100); RANGE 2 divides by 60.
#[test]
fn s_sum_totalises_above_the_low_cut() {
    let mut p = Plc::process(SUM);
    p.set("SD1500:f32", "1").set("D0:f32", "50").set("D14", "1");
    p.set("D12:f32", "5").scan();
    assert_eq!(p.real("D100"), 5.0, "e1 = 0: A");
    p.set("D12:f32", "0").set("D100:f32", "0").set("D2", "1");
    p.scan();
    assert_eq!(p.real("D100"), 50.0);
    p.scan();
    assert_eq!(p.real("D100"), 100.0);
    p.set("D10:f32", "50").scan();
    assert_eq!(p.real("D100"), 100.0, "E1 ≤ ILC holds");
    p.set("D10:f32", "0").set("D14", "2").scan();
    assert_eq!(p.real("D100"), (100.0f32 + 50.0 * 1.0 / 60.0) as f64);
    p.set("D14", "3")
        .set("D100:f32", "0")
        .set("D0:f32", "7200")
        .scan();
    assert_eq!(p.real("D100"), 2.0, "7200 per hour for 1 s");
    for range in ["0", "4"] {
        let mut p = Plc::process(SUM);
        p.set("D14", range).scan();
        fails(&p, 3);
    }
}

const TPC: &str = "LD SM400\nS.TPC D0 D100 D10 SD1506\nEND\n";

fn tpc(s: ProcessSettings, flags: &str) -> f64 {
    let mut p = Plc::process_with(TPC, s);
    p.set("D0:f32", "100")
        .set("D2:f32", "300")
        .set("D4:f32", "10000");
    p.set("D6", flags)
        .set("D10:f32", "0")
        .set("D12:f32", "273.15");
    p.set("D14:f32", "0").set("D16:f32", "10332").scan();
    assert_eq!(p.error(), None);
    p.real("D100")
}

/// 000 §10.5, DEC-27, spec §7 (timing conditions): E1 = 100, E2 = 300, E3 =
/// 10000, T′ = P′ = 0: A1 = 273.15/573.15, A2 = 20332/10332, BW ≈ 93.784.
#[test]
fn s_tpc_compensates_temperature_and_pressure() {
    let d = ProcessSettings::default();
    let a1 = (273.15f32 + 0.0) / (273.15 + 300.0);
    let a2 = (10332.0f32 + 10000.0) / (10332.0 + 0.0);
    let bw = tpc(d, "3");
    assert_eq!(bw, (100.0 * a1 * a2) as f64);
    assert!((bw - 93.784).abs() < 1e-3, "{bw}");
    assert_eq!(tpc(d, "1"), (100.0 * a1) as f64, "E3 unused: A2 = 1");
    assert_eq!(tpc(d, "2"), (100.0 * a2) as f64, "E2 unused: A1 = 1");
    assert_eq!(tpc(d, "0"), 100.0);
    let alt = ProcessSettings {
        tpc_reconstructed: false,
        ..d
    };
    let a1 = (273.15f32 + 300.0) / (273.15 + 0.0);
    let a2 = (10332.0f32 + 0.0) / (10332.0 + 10000.0);
    assert_eq!(tpc(alt, "3"), (100.0 * a1 * a2) as f64, "numerator first");
    // B1 + E2 = 0: division by 0, SD1502 = 5.
    let mut p = Plc::process(TPC);
    p.set("D2:f32", "300")
        .set("D12:f32", "-300")
        .set("D6", "1")
        .scan();
    fails(&p, 5);
}
