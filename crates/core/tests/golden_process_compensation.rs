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
