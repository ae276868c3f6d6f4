//! Process-control loop instructions of 000 ch. 9 that are not PID
//! controllers: S.PHPL (§9.8), S.SEL (§9.24), S.PGS (§9.23). Values worked
//! out by hand from the manual's formulas in f32 (spec §4.16, §4.26, §4.27).

mod common;
use common::process::assert_pc_error;
use common::Plc;
use softplc_core::program::ProcessSettings;

/// The loop-tag defaults of spec §3 at `D{d2}`, loop running (ALM = 0),
/// nothing inhibited, MODE = AUT; ΔT = 1 s.
fn loop_tag(p: &mut Plc, d2: u32) {
    p.set("SD1500:f32", "1");
    p.set(&format!("D{}", d2 + 1), "H10")
        .set(&format!("D{}", d2 + 3), "0")
        .set(&format!("D{}", d2 + 4), "0");
    for (off, v) in [
        (18, "100"),
        (22, "100"),
        (26, "100"),
        (30, "100"),
        (38, "0.2"),
        (44, "100"),
        (46, "1"),
        (48, "100"),
        (54, "10"),
    ] {
        p.set(&format!("D{}:f32", d2 + off), v);
    }
}

const PHPL: &str = "LD SM400\nS.PHPL D0 D100 SD1506 D1000\nEND\n";

/// RH = 200, RL = 0; PH = 160, PL = 40, HH = 180, LL = 20 (engineering) →
/// PH' = 100/200 × 160 = 80 %, PL' = 20, HH' = 90, LL' = 10; HS = 5.
fn phpl(settings: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(PHPL, settings);
    loop_tag(&mut p, 1000);
    for (off, v) in [
        (22, "200"),
        (26, "160"),
        (28, "40"),
        (30, "180"),
        (32, "20"),
        (40, "5"),
    ] {
        p.set(&format!("D{}:f32", 1000 + off), v);
    }
    p
}

/// 000 §9.8 (2): set at E1 ≥ X', reset at E1 ≤ PH' − HS (≥ PL' + HS),
/// held between; HHA/LLA only in ALM; BB1 = BB2 ∨ BB3 (DEC-19); (4) PV =
/// (RH − RL)/100 × E1 + RL, BW = E1.
#[test]
fn s_phpl_high_low_alarms_with_hysteresis() {
    let mut p = phpl(ProcessSettings::default());
    for (e1, bb, almw, pv) in [
        ("50", 0, 0, 100.0),
        ("80", 0b011, 0x40, 160.0),
        ("76", 0b011, 0x40, 152.0),
        ("75", 0, 0, 150.0),
        ("90", 0b011, 0x140, 180.0),
        ("86", 0b011, 0x140, 172.0),
        ("85", 0b011, 0x40, 170.0),
        ("20", 0b101, 0x20, 40.0),
        ("24", 0b101, 0x20, 48.0),
        ("10", 0b101, 0xA0, 20.0),
        ("14.5", 0b101, 0xA0, 29.0),
        ("15", 0b101, 0x20, 30.0),
        ("25", 0, 0, 50.0),
    ] {
        p.set("D0:f32", e1).scan();
        assert_eq!((p.int("D102"), p.int("D1003")), (bb, almw), "E1 = {e1}");
        assert_eq!(p.real("D1010"), pv, "PV at {e1}");
        assert_eq!(p.real("D100"), e1.parse::<f64>().unwrap());
    }
    assert_eq!(p.error(), None);
}

/// Inhibits: PHI clears PHA/BB2, HHI clears HHA; with PHI alone HHA
/// stays, and BB1 is 0 under DEC-19 but 1 under its alternative; ERRI
/// clears everything.
#[test]
fn s_phpl_inhibits_and_dec_19() {
    let mut p = phpl(ProcessSettings::default());
    p.set("D0:f32", "95").set("D1004", "H100").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0b011, 0x40));
    p.set("D1004", "H40").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0, 0x100));
    p.set("D1004", "H8000").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0, 0));
    let mut p = phpl(ProcessSettings {
        phpl_bb1_or: false,
        ..ProcessSettings::default()
    });
    p.set("D0:f32", "95").set("D1004", "H40").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0b001, 0x100));
}

/// DEC-18 with CTIM = 4, ΔT = 1 (m = 4), DPL = 10: the window's end
/// evaluates E1 − E1n-m: ≥ 10 → DPPA/BB4, ≤ −10 → DPNA/BB5, held inside
/// the window; m = 0 does nothing.
#[test]
fn s_phpl_change_rate() {
    let run = |p: &mut Plc, xs: &[&str]| -> Vec<(i64, i64)> {
        xs.iter()
            .map(|x| {
                p.set("D0:f32", x).scan();
                (p.int("D102") & 0b11001, p.int("D1003") & 0x18)
            })
            .collect()
    };
    let mut p = phpl(ProcessSettings::default());
    p.set("D1042:f32", "4").set("D1044:f32", "10");
    let up = (0b01001, 0x10);
    let down = (0b10001, 0x08);
    let none = (0, 0);
    let xs = ["50", "52", "55", "58", "60", "59", "40", "45", "49", "50"];
    assert_eq!(
        run(&mut p, &xs),
        [none, none, none, none, up, up, up, up, down, down]
    );
    assert_eq!(p.real("D1126"), 49.0, "reference re-taken at execution 8");
    // The alternative evaluates against the reference on every execution.
    let mut p = phpl(ProcessSettings {
        change_rate_window: false,
        ..ProcessSettings::default()
    });
    p.set("D1042:f32", "4").set("D1044:f32", "10");
    assert_eq!(
        run(&mut p, &xs),
        [none, none, none, none, up, none, down, down, down, none]
    );
    // CTIM = 0.9 → m = int(0.9) = 0: no change-rate processing at all.
    let mut p = phpl(ProcessSettings::default());
    p.set("D1042:f32", "0.9")
        .set("D1044:f32", "10")
        .set("D102", "H9")
        .set("D1003", "H10");
    assert_eq!(
        run(&mut p, &["50", "90"]),
        [(0b01001, 0x10), (0b01001, 0x10)]
    );
    assert_eq!((p.int("D1124"), p.int("D1125")), (0, 0));
}

/// Loop stop: BW = 100/(RH − RL) × (PV − RL) from the PV in the loop tag,
/// BB1..BB5 and the six alarms := 0 (MODE is not touched, L13496-13508);
/// the change-rate window does not move (DEC-4).
#[test]
fn s_phpl_loop_stop() {
    let mut p = phpl(ProcessSettings::default());
    p.set("D1042:f32", "4");
    p.set("D0:f32", "95").scan();
    p.set("D1003", "H41F8")
        .set("D102", "H1F")
        .set("D1010:f32", "50")
        .scan();
    assert_eq!(p.real("D100"), 25.0);
    assert_eq!(
        (p.int("D102"), p.int("D1003"), p.int("D1001")),
        (0, 0x4000, 0x10)
    );
    assert_eq!((p.int("D1124"), p.int("D1125")), (1, 4));
    let mut p = phpl(ProcessSettings {
        early_end_skips_counters: false,
        ..ProcessSettings::default()
    });
    p.set("D1042:f32", "4")
        .set("D1003", "H4000")
        .set("D0:f32", "30");
    p.scans(2);
    assert_eq!(
        (p.int("D1124"), p.int("D1125"), p.real("D1126")),
        (1, 3, 30.0)
    );
}

/// Table 14.2 for S.PHPL: RH = RL is 5 at 1 (5 on loop stop); ΔT = 0 with
/// a change-rate time is 5 at 3, CTIM/ΔT > 32767 is 4 at 3; a NaN E1 is 1
/// at 2, an overflowing PV 6 at 4.
#[test]
fn s_phpl_errors() {
    let mut p = phpl(ProcessSettings::default());
    p.set("D1022:f32", "0").set("D0:f32", "50").scan();
    assert_pc_error(&p, 5, 1);
    let mut p = phpl(ProcessSettings::default());
    p.set("D1022:f32", "0").set("D1003", "H4000").scan();
    assert_pc_error(&p, 5, 5);
    let mut p = phpl(ProcessSettings::default());
    p.set("D1042:f32", "4")
        .set("SD1500:f32", "0")
        .set("D0:f32", "95")
        .scan();
    assert_pc_error(&p, 5, 3);
    assert_eq!(p.int("D1003"), 0x140, "step 2 wrote the alarms");
    let mut p = phpl(ProcessSettings::default());
    p.set("D1042:f32", "40000").scan();
    assert_pc_error(&p, 4, 3);
    let mut p = phpl(ProcessSettings::default());
    p.set("D0", "-1").set("D1", "-1").scan();
    assert_pc_error(&p, 1, 2);
    // (RH − RL)/100 × E1 overflows only in the engineering conversion.
    let mut p = phpl(ProcessSettings::default());
    p.set("D1022:f32", "3e38")
        .set("D1024:f32", "-3e38")
        .set("D0:f32", "50")
        .scan();
    assert_pc_error(&p, 6, 4);
}

const SEL: &str = "LD SM400\nS.SEL D2012 D100 D10 D1000 D3012\nEND\n";

/// S2: NMAX 100, NMIN 0, TRK 0, SVPTN 18H (both used, no cascade); loop
/// tag RH = 200, RL = 0. E1 (D2012) and E2 (D3012) are the MVs of two
/// upper loops whose tags start at D2000 and D3000.
fn sel() -> Plc {
    let mut p = Plc::process(SEL);
    loop_tag(&mut p, 1000);
    p.set("D1022:f32", "200");
    p.set("D10:f32", "100")
        .set("D12:f32", "0")
        .set("D14", "0")
        .set("D15", "H18");
    p.set("D2012:f32", "30").set("D3012:f32", "60");
    p
}

/// 000 §9.24: PV1 = 200/100 × 30 = 60, PV2 = 120; e1 = 0 → PV = PV1, SLNO =
/// b0, T = 100/200 × 60 = 30 → MV = 30, BW = 30; e1 = 1 → PV2, T = 60;
/// DML = 10 and MH = 50 limit as S.OUT1 (BB4/DMLA, BB2/MHA).
#[test]
fn s_sel_selects_and_limits() {
    let mut p = sel();
    p.scan();
    assert_eq!(
        (p.real("D1014"), p.real("D1016"), p.real("D1010")),
        (60.0, 120.0, 60.0)
    );
    assert_eq!(
        (p.int("D1026"), p.real("D1012"), p.real("D100")),
        (1, 30.0, 30.0)
    );
    assert_eq!(p.int("D102"), 0);
    p.set("D15", "H19").scan();
    assert_eq!(
        (p.real("D1010"), p.int("D1026"), p.real("D1012")),
        (120.0, 2, 60.0)
    );
    p.set("D1048:f32", "10").set("D15", "H18").scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (50.0, 0b1001, 0x800)
    );
    p.set("D1048:f32", "100").set("D1018:f32", "20").scan();
    assert_eq!(
        (p.real("D1012"), p.int("D102"), p.int("D1003")),
        (20.0, 0b011, 0x2)
    );
    // MHI inhibits MHA/BB2; output conversion with NMAX 200, NMIN −100.
    p.set("D1004", "H2")
        .set("D10:f32", "200")
        .set("D12:f32", "-100")
        .scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0, 0));
    assert_eq!(p.real("D100"), 300.0 / 100.0 * 20.0 - 100.0);
    // T = MV still runs the limiter (S.SEL has no DEC-10 exception).
    p.set("D1004", "0")
        .set("D1018:f32", "100")
        .set("D1012:f32", "30");
    p.set("D102", "HF").set("D1003", "H803").scan();
    assert_eq!((p.int("D102"), p.int("D1003")), (0, 0));
}

/// Manual modes: alarms cleared, BW from the operator's MV; TRK = 1 tracks
/// the selected input En := MV, and, as SVPTN marks E1 as the upper loop's
/// MV (14H: b3 = 0), sets TRKF in that loop's INH (D2004). In auto modes
/// tracking needs BB1 = 1.
#[test]
fn s_sel_tracking() {
    let mut p = sel();
    p.set("D14", "1")
        .set("D15", "H14")
        .set("D1001", "H8")
        .set("D1012:f32", "25");
    p.set("D1003", "H803").scan();
    assert_eq!((p.real("D100"), p.int("D1003")), (25.0, 0));
    assert_eq!((p.real("D2012"), p.int("D2004")), (25.0, 0x4000));
    assert_eq!((p.real("D3012"), p.int("D3004")), (60.0, 0), "E2 untouched");
    // SVPTN 18H: E1 is not an upper-loop MV, so no TRKF.
    let mut p = sel();
    p.set("D14", "1")
        .set("D1001", "H8")
        .set("D1012:f32", "25")
        .scan();
    assert_eq!((p.real("D2012"), p.int("D2004")), (25.0, 0));
    // Auto, TRK = 1, no alarm: no tracking.
    let mut p = sel();
    p.set("D14", "1").set("D15", "H14").scan();
    assert_eq!(
        (p.real("D1012"), p.real("D2012"), p.int("D2004")),
        (30.0, 30.0, 0)
    );
    // Auto with the high limit (BB1 = 1): E1 := MV = 20.
    p.set("D1018:f32", "20").scan();
    assert_eq!(
        (p.real("D1012"), p.real("D2012"), p.int("D2004")),
        (20.0, 20.0, 0x4000)
    );
    // E2 selected (SVPTN 0DH: e1 = 1, E2 is the upper-loop MV).
    let mut p = sel();
    p.set("D14", "1")
        .set("D15", "HD")
        .set("D1001", "H8")
        .set("D1012:f32", "7")
        .scan();
    assert_eq!(
        (p.real("D3012"), p.int("D3004"), p.real("D2012")),
        (7.0, 0x4000, 30.0)
    );
}

/// Loop stop: BW holds, DMLA/MHA/MLA := 0, MAN, BB1..BB4 := 0.
#[test]
fn s_sel_loop_stop() {
    let mut p = sel();
    p.set("D100:f32", "5")
        .set("D1003", "H4803")
        .set("D102", "HF")
        .scan();
    assert_eq!(
        (
            p.real("D100"),
            p.int("D1003"),
            p.int("D1001"),
            p.int("D102")
        ),
        (5.0, 0x4000, 8, 0)
    );
    assert_eq!(p.real("D1014"), 0.0, "nothing converted");
}

/// Table 14.2 for S.SEL: RH = RL in an auto mode is 5 at 3 (the manual
/// modes do not divide); a NaN E2 is 1 at 1, a NaN DML 1 at 4, a NaN NMIN
/// 1 at 5; an upper INH below D0 is 4101.
#[test]
fn s_sel_errors() {
    let mut p = sel();
    p.set("D1022:f32", "0").scan();
    assert_pc_error(&p, 5, 3);
    assert_eq!(p.int("D1026"), 1, "step 2 ran");
    let mut p = sel();
    p.set("D1022:f32", "0").set("D1001", "H8").scan();
    assert_eq!(p.error(), None);
    let mut p = sel();
    p.set("D3012", "-1").set("D3013", "-1").scan();
    assert_pc_error(&p, 1, 1);
    let mut p = sel();
    p.set("D1048", "-1").set("D1049", "-1").scan();
    assert_pc_error(&p, 1, 4);
    let mut p = sel();
    p.set("D12", "-1").set("D13", "-1").scan();
    assert_pc_error(&p, 1, 5);
    assert_eq!(p.real("D1012"), 30.0, "step 4 wrote MV");
    let mut p = Plc::process("LD SM400\nS.SEL D4 D100 D10 D1000 D3012\nEND\n");
    loop_tag(&mut p, 1000);
    p.set("D10:f32", "100")
        .set("D14", "1")
        .set("D15", "H14")
        .set("D1001", "H8");
    p.scan();
    assert_eq!(p.error().map(|e| e.0), Some(4101));
}

const PGS: &str = "LD SM400\nS.PGS SD1506 D100 SD1506 D1000\nEND\n";

/// PTNO = 3: (SV, MV) = (2, 10), (5, 40), (10, 20); MODE AUT, TYPE 0.
fn pgs() -> Plc {
    let mut p = Plc::process(PGS);
    loop_tag(&mut p, 1000);
    p.set("D1010", "3").set("D1016", "0").set("D1014:f32", "0");
    for (i, (sv, mv)) in [("2", "10"), ("5", "40"), ("10", "20")].iter().enumerate() {
        p.set(&format!("D{}:f32", 1022 + 2 * i), sv);
        p.set(&format!("D{}:f32", 1054 + 2 * i), mv);
    }
    p
}

fn pgs_run(p: &mut Plc, n: usize) -> Vec<f64> {
    (0..n).map(|_| p.scan().real("D100")).collect()
}

/// 000 §9.23: SV' = SV + ΔT each execution, MV1 up to SV1, then linear
/// interpolation: SV 3 → 30/3 × 1 + 10 = 20, 4 → 30, 5 → 40, 6 → −20/5 ×
/// 1 + 40 = 36 …; at SV' ≥ SV3 the hold type ends with MV = MV3, MODE :=
/// MAN and SV kept; in MAN the program is stopped (BW = MV).
#[test]
fn s_pgs_hold_type() {
    let mut p = pgs();
    assert_eq!(
        pgs_run(&mut p, 10),
        [10.0, 10.0, 20.0, 30.0, 40.0, 36.0, 32.0, 28.0, 24.0, 20.0]
    );
    assert_eq!(
        (p.int("D1001"), p.real("D1014"), p.real("D1012")),
        (8, 10.0, 20.0)
    );
    assert_eq!(pgs_run(&mut p, 2), [20.0, 20.0]);
    assert_eq!(p.real("D1014"), 10.0, "stopped");
    // Restart: SV set, MAN → AUT.
    p.set("D1014:f32", "3").set("D1001", "H10");
    assert_eq!(pgs_run(&mut p, 1), [30.0]);
}

/// Return type (TYPE 1): the end sets SV := 0 and MAN; cyclic type (CAS):
/// SV := 0 and MV := MV1 with no mode change, restarting at once.
#[test]
fn s_pgs_return_and_cyclic_types() {
    let mut p = pgs();
    p.set("D1016", "1");
    pgs_run(&mut p, 10);
    assert_eq!(
        (p.int("D1001"), p.real("D1014"), p.real("D100")),
        (8, 0.0, 20.0)
    );
    let mut p = pgs();
    p.set("D1001", "H20");
    let v = pgs_run(&mut p, 12);
    assert_eq!(v[9..], [10.0, 10.0, 10.0]);
    assert_eq!((p.int("D1001"), p.real("D1014")), (0x20, 2.0));
}

/// The output is limited to ML … MH with MHA/BB2, MLA/BB3 (MHI inhibits);
/// LCA and LCC stop the program like the manual modes; loop stop or PTNO =
/// 0 hold BW, clear MHA/MLA/BB and set MAN.
#[test]
fn s_pgs_limits_modes_and_stop() {
    let mut p = pgs();
    p.set("D1018:f32", "30").set("D1020:f32", "15");
    assert_eq!(pgs_run(&mut p, 5), [15.0, 15.0, 20.0, 30.0, 30.0]);
    assert_eq!((p.int("D102"), p.int("D1003")), (0b011, 0x2));
    p.set("D1004", "H2").scan();
    assert_eq!(
        (p.real("D100"), p.int("D102"), p.int("D1003")),
        (30.0, 0, 0)
    );
    p.set("D1004", "0")
        .set("D1001", "H2")
        .set("D1012:f32", "12")
        .scan();
    assert_eq!(
        (p.real("D100"), p.real("D1014"), p.int("D102")),
        (12.0, 6.0, 0)
    );
    p.set("D1001", "H10")
        .set("D1003", "H4003")
        .set("D102", "7")
        .scan();
    assert_eq!(
        (
            p.real("D100"),
            p.int("D1003"),
            p.int("D1001"),
            p.int("D102")
        ),
        (12.0, 0x4000, 8, 0)
    );
    let mut p = pgs();
    p.set("D1010", "0").set("D100:f32", "3").scan();
    assert_eq!(
        (p.real("D100"), p.int("D1001"), p.real("D1014")),
        (3.0, 8, 0.0)
    );
}

/// Table 14.2 for S.PGS: 2 SV count-up, 3 MVPGS (PTNO > 16 or TYPE 2 is
/// SD1502 = 3), a NaN MV1 is 1 at 3, a NaN MH 1 at 4.
#[test]
fn s_pgs_errors() {
    let mut p = pgs();
    p.set("D1010", "17").scan();
    assert_pc_error(&p, 3, 3);
    assert_eq!(p.real("D1014"), 1.0, "step 2 counted SV up");
    let mut p = pgs();
    p.set("D1016", "2").scan();
    assert_pc_error(&p, 3, 3);
    let mut p = pgs();
    p.set("D1014", "-1").set("D1015", "-1").scan();
    assert_pc_error(&p, 1, 2);
    let mut p = pgs();
    p.set("D1054", "-1").set("D1055", "-1").scan();
    assert_pc_error(&p, 1, 3);
    let mut p = pgs();
    p.set("D1018", "-1").set("D1019", "-1").scan();
    assert_pc_error(&p, 1, 4);
}

/// One loop tag shared by S.IN → S.PHPL → S.OUT1 (the SMON loop plus an
/// output, 000 §2.3, App. 1): from the documented initial state (MODE 8H,
/// ALM 4000H = stopped, INH 4000H = TRKF) the loop runs once ALM := 0, the
/// manual mode keeps TRKF, AUT drops the first ΔMV (bumpless), the next one
/// counts, and a sensor alarm from S.IN with SM1501 ON holds MV.
#[test]
fn a_loop_tag_shared_by_s_in_s_phpl_and_s_out1() {
    let src = "LD SM400\nS.IN D0 D100 D10 D1000\nS.PHPL D100 D110 SD1506 D1000\n\
               S.OUT1 D200 D120 D30 D1000\nEND\n";
    let mut p = Plc::process(src);
    loop_tag(&mut p, 1000);
    p.set("D1001", "H8")
        .set("D1003", "H4000")
        .set("D1004", "H4000");
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
    p.set("D30:f32", "100").set("D32:f32", "0");
    p.set("D0:f32", "50").set("D200:f32", "2").scan();
    assert_eq!(
        (p.real("D100"), p.real("D110"), p.real("D120")),
        (0.0, 0.0, 0.0)
    );
    assert_eq!(p.int("D1001"), 8);
    p.set("D1003", "0").scan();
    assert_eq!(
        (p.real("D100"), p.real("D1010"), p.real("D120")),
        (40.0, 40.0, 0.0)
    );
    assert_eq!(p.int("D1004"), 0x4000, "manual keeps TRKF");
    p.set("D1001", "H10").scan();
    assert_eq!(
        (p.real("D100"), p.real("D1012"), p.int("D1004")),
        (48.0, 0.0, 0)
    );
    p.scan();
    let bw = 50f32 + 0.2 * (48.0 - 50.0);
    assert_eq!((p.real("D100"), p.real("D1010")), (bw as f64, bw as f64));
    assert_eq!((p.real("D1012"), p.real("D120")), (2.0, 2.0));
    p.set("D0:f32", "120").set("SM1501", "1").scan();
    assert_eq!(
        (p.int("D1003"), p.real("D1012"), p.real("D120")),
        (0x200, 2.0, 2.0)
    );
    p.set("SM1501", "0").scan();
    assert_eq!(p.real("D1012"), 4.0);
    assert_eq!(p.error(), None);
}
