//! Process-control selectors, limiters and manual/auto elements (000
//! §9.13-§9.19, §9.22, §9.25-§9.26) on a process CPU; values worked out from
//! the manual's tables in f32, ΔT in SD1500.

mod common;
use common::Plc;
use softplc_core::program::ProcessSettings;

fn fails(p: &Plc, detail: i64) {
    assert_eq!(p.error().map(|e| e.0), Some(4100));
    assert_eq!((p.int("SD1502"), p.int("SD1503")), (detail, 1));
}

/// Writes n and E1..En at D0.
fn inputs(p: &mut Plc, e: &[f32]) {
    p.set("D0", &e.len().to_string());
    for (i, v) in e.iter().enumerate() {
        p.set(&format!("D{}:f32", 1 + 2 * i), &v.to_string());
    }
}

fn select(op: &str, e: &[f32]) -> (f64, i64) {
    let mut p = Plc::process(&format!("LD SM400\n{op} D0 D100 SD1506 SD1506\nEND\n"));
    p.set("D102", "-1");
    inputs(&mut p, e);
    p.scan();
    assert_eq!(p.error(), None);
    (p.real("D100"), p.int("D102") & 0xFFFF)
}

const FIVE: [f32; 5] = [50.0, 100.0, 150.0, 200.0, 250.0];

/// Spec §7: S.HS(50 … 250) → 250 with BB5, S.LS → 50 with BB1, S.MID → 150
/// with BB3; ties mark every equal input; n = 1 gives BB1 only (L14601-14614).
#[test]
fn s_hs_and_s_ls_select_and_mark_every_equal_input() {
    assert_eq!(select("S.HS", &FIVE), (250.0, 0x10));
    assert_eq!(select("S.LS", &FIVE), (50.0, 0x01));
    assert_eq!(select("S.HS", &[3.0, 7.0, -1.0, 7.0]), (7.0, 0b1010));
    assert_eq!(select("S.LS", &[-2.0, 7.0, -2.0]), (-2.0, 0b101));
    assert_eq!(select("S.HS", &[-4.5]), (-4.5, 1));
    let sixteen: Vec<f32> = (0..16).map(|i| (i * 3 % 16) as f32).collect();
    assert_eq!(select("S.HS", &sixteen), (15.0, 1 << 5), "3·5 = 15");
    assert_eq!(select("S.LS", &sixteen), (0.0, 1));
}

/// 000 §9.15 (L15164-15176): 2, 5, 1, 4, 3 → 3 with BB5; even n takes the
/// smaller middle value; ties mark every equal input.
#[test]
fn s_mid_takes_the_middle_of_the_stable_sort() {
    assert_eq!(select("S.MID", &[2.0, 5.0, 1.0, 4.0, 3.0]), (3.0, 0x10));
    assert_eq!(select("S.MID", &FIVE), (150.0, 0x04));
    assert_eq!(select("S.MID", &[4.0, 1.0, 3.0, 2.0]), (2.0, 0x08));
    assert_eq!(select("S.MID", &[5.0, 5.0, 1.0]), (5.0, 0b011));
    assert_eq!(select("S.MID", &[9.0, -9.0]), (-9.0, 0b10));
    assert_eq!(select("S.MID", &[8.0]), (8.0, 1));
}

/// 000 §9.16: spec §7 S.AVE(50, 100) → 75; (1 + 2 + 4)/3 in f32.
#[test]
fn s_ave_averages_n_inputs() {
    let mut p = Plc::process("LD SM400\nS.AVE D0 D100 SD1506 SD1506\nEND\n");
    p.set("D102", "77");
    inputs(&mut p, &[50.0, 100.0]);
    p.scan();
    assert_eq!(p.real("D100"), 75.0);
    assert_eq!(p.int("D102"), 77, "S.AVE's block memory is BW only");
    inputs(&mut p, &[1.0, 2.0, 4.0]);
    p.scan();
    assert_eq!(p.real("D100"), (7.0f32 / 3.0) as f64);
}

/// n ∉ 1..16 is 4100 with SD1502 = 3, SD1503 = 1; an n whose inputs run
/// past the end of the device is 4101.
#[test]
fn selectors_check_n() {
    for (op, n) in [
        ("S.HS", "0"),
        ("S.LS", "17"),
        ("S.MID", "-1"),
        ("S.AVE", "0"),
    ] {
        let mut p = Plc::process(&format!("LD SM400\n{op} D0 D100 SD1506 SD1506\nEND\n"));
        p.set("D0", n).scan();
        fails(&p, 3);
    }
    let mut p = Plc::process("LD SM400\nS.HS D12280 D100 SD1506 SD1506\nEND\n");
    p.set("D12280", "16").scan();
    assert_eq!(p.error().map(|e| e.0), Some(4101));
    let mut p = Plc::process("LD SM400\nS.HS D0 D100 SD1506 SD1506\nEND\n");
    p.set("D0", "2").set("D3", "-1").set("D4", "-1").scan();
    fails(&p, 1);
}

const LIMT: &str = "LD SM400\nS.LIMT D0 D100 D10 SD1506\nEND\n";

fn run(p: &mut Plc, e1: f32) -> (f64, i64) {
    p.set("D0:f32", &e1.to_string()).scan();
    assert_eq!(p.error(), None);
    (p.real("D100"), p.int("D102"))
}

/// 000 §9.17: spec §7 S.LIMT(50; 100/0) → 50, BB1 = BB2 = 0; with HS1 =
/// HS2 = 10 the alarms hold inside the bands and reset on their inclusive
/// edges HILMT − HS1 and LOLMT + HS2.
#[test]
fn s_limt_limits_with_hysteresis() {
    let mut p = Plc::process(LIMT);
    p.set("D10:f32", "100").set("D12:f32", "0");
    assert_eq!(run(&mut p, 50.0), (50.0, 0));
    assert_eq!(
        run(&mut p, 100.0),
        (100.0, 1),
        "E1 = HILMT is the limit row"
    );
    assert_eq!(run(&mut p, 120.0), (100.0, 1));
    assert_eq!(run(&mut p, 99.0), (99.0, 0), "HS = 0: no band");
    assert_eq!(run(&mut p, -5.0), (0.0, 2));
    assert_eq!(run(&mut p, 0.0), (0.0, 2));
    p.set("D14:f32", "10").set("D16:f32", "10");
    assert_eq!(run(&mut p, 5.0), (5.0, 2), "low band holds BB2");
    assert_eq!(run(&mut p, 10.0), (10.0, 0), "LOLMT + HS2 resets");
    assert_eq!(run(&mut p, 5.0), (5.0, 0), "and the band keeps 0");
    assert_eq!(run(&mut p, 101.0), (100.0, 1));
    assert_eq!(run(&mut p, 95.0), (95.0, 1), "high band holds BB1");
    assert_eq!(run(&mut p, 90.0), (90.0, 0), "HILMT − HS1 resets");
    assert_eq!(run(&mut p, 95.0), (95.0, 0));
    // The other BB bits are left as found.
    p.set("D102", "256");
    assert_eq!(run(&mut p, 200.0), (100.0, 257));
}

/// HS1 or HS2 < 0 is 4100 with SD1502 = 2 (spec §5), for S.LIMT, S.VLMT1
/// and S.VLMT2.
#[test]
fn limiters_reject_negative_hysteresis() {
    for (op, hs) in [
        ("S.LIMT", "D14:f32"),
        ("S.LIMT", "D16:f32"),
        ("S.VLMT1", "D14:f32"),
        ("S.VLMT2", "D16:f32"),
    ] {
        let mut p = Plc::process(&format!("LD SM400\n{op} D0 D100 D10 SD1506\nEND\n"));
        p.set("SD1500:f32", "1")
            .set("D0:f32", "5")
            .set(hs, "-0.5")
            .scan();
        fails(&p, 2);
        assert_eq!(p.real("D100"), 0.0, "stopped before writing BW");
    }
}

const VLMT1: &str = "LD SM400\nS.VLMT1 D0 D100 D10 SD1506\nEND\n";
const VLMT2: &str = "LD SM400\nS.VLMT2 D0 D100 D10 SD1506\nEND\n";

fn vlmt(src: &str, s: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(src, s);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "10")
        .set("D12:f32", "20");
    p.set("D14:f32", "2").set("D16:f32", "0");
    p
}

/// 000 §9.18: V1 = 10, V2 = 20 %/s, ΔT = 1, HS1 = 2: a step 0 → 50 ramps 10,
/// 20, 30, 40; at E1 − BW = V1·ΔT (not above) BW = E1 with BB1 held; back
/// within V1·ΔT − HS1 BB1 resets. Falling: 30, 10, then 0 (within V2·ΔT).
#[test]
fn s_vlmt1_limits_the_rate_with_hysteresis() {
    let mut p = vlmt(VLMT1, ProcessSettings::default());
    let up: Vec<_> = (0..6).map(|_| run(&mut p, 50.0)).collect();
    assert_eq!(
        up,
        [
            (10.0, 1),
            (20.0, 1),
            (30.0, 1),
            (40.0, 1),
            (50.0, 1),
            (50.0, 0)
        ]
    );
    let down: Vec<_> = (0..3).map(|_| run(&mut p, 0.0)).collect();
    assert_eq!(down, [(30.0, 2), (10.0, 2), (0.0, 0)]);
    // A rise of 9: within V1·ΔT but not within V1·ΔT − HS1 = 8: BB held.
    p.set("D102", "1");
    assert_eq!(run(&mut p, 9.0), (9.0, 1));
    assert_eq!(run(&mut p, 17.0), (17.0, 0), "8 = V1·ΔT − HS1 resets");
}

/// 000 §9.19 (DEC-25): S.VLMT2 holds BW while the rate is exceeded and in
/// the band; the alternative gives S.VLMT1's rows.
#[test]
fn s_vlmt2_holds_while_the_rate_is_exceeded() {
    let mut p = vlmt(VLMT2, ProcessSettings::default());
    assert_eq!(run(&mut p, 50.0), (0.0, 1));
    assert_eq!(run(&mut p, 50.0), (0.0, 1));
    assert_eq!(run(&mut p, 5.0), (5.0, 0));
    assert_eq!(run(&mut p, 14.0), (5.0, 0), "band: BW = BW, BB held");
    assert_eq!(run(&mut p, 15.0), (5.0, 0), "E1 − BW = V1·ΔT: band");
    assert_eq!(run(&mut p, -20.0), (5.0, 2), "falling 25 > V2·ΔT");
    assert_eq!(run(&mut p, -15.0), (-15.0, 0));
    let alt = ProcessSettings {
        vlmt2_literal: false,
        ..ProcessSettings::default()
    };
    let mut p = vlmt(VLMT2, alt);
    assert_eq!(run(&mut p, 50.0), (10.0, 1));
}

/// 000 §9.22: spec §7 S.DBND(50; 100/0) → 50, BB1 = 1; inclusive edges.
#[test]
fn s_dbnd_dead_band() {
    let mut p = Plc::process("LD SM400\nS.DBND D0 D100 D10 SD1506\nEND\n");
    p.set("D10:f32", "100").set("D12:f32", "0");
    assert_eq!(run(&mut p, 50.0), (50.0, 1));
    p.set("D10:f32", "70").set("D12:f32", "30");
    assert_eq!(run(&mut p, 60.0), (50.0, 1));
    assert_eq!(run(&mut p, 70.0), (50.0, 1));
    assert_eq!(run(&mut p, 30.0), (50.0, 1));
    assert_eq!(run(&mut p, 70.5), (70.5, 0));
    assert_eq!(run(&mut p, 29.5), (29.5, 0));
}

const BUMP: &str = "LD SM400\nS.BUMP D0 D100 D10 D200\nEND\n";

/// 000 §9.25 with T = 4, ΔT = 1: manual sets Xq = Xp = E2 − E1 = 40; auto
/// ramps Xp by ΔT/T·Xq = 10 (BW 50, 40, 30) until |Xp| ≤ 10 gives E1.
/// Spec §7 (timing conditions): T = ΔT = 1 gives BW = E1 = 0.
#[test]
fn s_bump_ramps_the_deviation_away() {
    let mut p = Plc::process(BUMP);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "4")
        .set("D12:f32", "1");
    p.set("D0:f32", "20").set("D2:f32", "60").scan();
    assert_eq!(p.real("D100"), 60.0);
    assert_eq!((p.real("D200"), p.real("D202")), (40.0, 40.0));
    p.set("D4", "1");
    let bw: Vec<f64> = (0..5).map(|_| p.scan().real("D100")).collect();
    assert_eq!(bw, [50.0, 40.0, 30.0, 20.0, 20.0]);
    assert_eq!(p.real("D202"), 0.0);
    // Delay zone a = 50 ≥ |Xp|: first-order lag Xp′ = T/(T + ΔT)·Xp.
    p.set("D4", "0").set("D12:f32", "50").scan();
    p.set("D4", "1").scan();
    let x1 = 4.0f32 / 5.0 * 40.0;
    assert_eq!(p.real("D100"), (20.0 + x1) as f64);
    p.scan();
    assert_eq!(p.real("D100"), (20.0 + 4.0f32 / 5.0 * x1) as f64);
    // Timing conditions: E1 = 0, E2 = 50, T = a = 1 = ΔT.
    let mut p = Plc::process(BUMP);
    p.set("SD1500:f32", "1")
        .set("D10:f32", "1")
        .set("D12:f32", "1");
    p.set("D2:f32", "50").scan();
    assert_eq!(p.real("D100"), 50.0);
    p.set("D4", "1").scan();
    assert_eq!(p.real("D100"), 0.0);
    // T = 0 ≤ ΔT: BW = E1, not an error (spec §5).
    p.set("D4", "0").scan();
    p.set("D10:f32", "0").set("D4", "1").scan();
    assert_eq!(p.real("D100"), 0.0);
    assert_eq!(p.error(), None);
}

const AMR: &str = "LD SM400\nS.AMR D0 D100 D10 SD1506\nEND\n";

/// 000 §9.26 (spec §7 timing conditions): E1 = E2 = 50, e1 = e2 = 1, d1 =
/// 50, ΔT = 1: 0 → 50, capped at d1; down by |E2|·ΔT to d2; e1 = 0: BW = E3.
#[test]
fn s_amr_ramps_by_push_buttons() {
    let mut p = Plc::process(AMR);
    p.set("SD1500:f32", "1")
        .set("D0:f32", "50")
        .set("D2:f32", "50");
    p.set("D10:f32", "50")
        .set("D12:f32", "0")
        .set("D6", "3")
        .scan();
    assert_eq!(p.real("D100"), 50.0);
    p.scan();
    assert_eq!(p.real("D100"), 50.0, "capped at d1");
    p.set("D6", "7").scan();
    assert_eq!(p.real("D100"), 50.0, "e2 = e3: holds");
    p.set("D2:f32", "-30").set("D6", "5").scan();
    assert_eq!(p.real("D100"), 20.0, "BW − |E2|·ΔT");
    p.scan();
    assert_eq!(p.real("D100"), 0.0, "floored at d2");
    p.set("SD1500:f32", "0.5")
        .set("D0:f32", "-10")
        .set("D6", "3")
        .scan();
    assert_eq!(p.real("D100"), 5.0, "BW + |E1|·ΔT");
    p.set("D4:f32", "33").set("D6", "6").scan();
    assert_eq!(p.real("D100"), 33.0, "e1 = 0: BW = E3");
}

/// Index modification (000 §2.2.8): the variable-length input area follows
/// Z0, and an indexed block memory past the end of D is 4101.
#[test]
fn selectors_with_index_modification() {
    let mut p = Plc::process("LD SM400\nS.AVE D0Z0 D100Z1 SD1506 SD1506\nEND\n");
    p.set("Z0", "10").set("Z1", "0").set("D10", "3");
    p.set("D11:f32", "3")
        .set("D13:f32", "4")
        .set("D15:f32", "8")
        .scan();
    assert_eq!(p.real("D100"), 5.0);
    p.set("Z1", "12187").scan();
    assert_eq!(p.error().map(|e| e.0), Some(4101));
}
