//! Snapshot tests of the ladder layout: series/parallel blocks, MPS
//! branches, outputs followed by contacts, MC, application instructions and
//! a CSV export.

use super::grid::Grid;
use super::render;
use super::LadderProgram;

fn ladder(src: &str) -> String {
    let s = softplc_core::program::il::parse_il("t.il", src).unwrap();
    draw(&LadderProgram::from_source(&s))
}

fn draw(p: &LadderProgram) -> String {
    p.rungs
        .iter()
        .map(|r| render::text(&Grid::of(r)))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Compares with `src/ladder/snapshots/NAME.txt` (`SNAPSHOT_UPDATE=1`
/// rewrites it; review the diff).
#[track_caller]
fn snap(name: &str, got: String) {
    let path = format!(
        "{}/src/ladder/snapshots/{name}.txt",
        env!("CARGO_MANIFEST_DIR")
    );
    if std::env::var_os("SNAPSHOT_UPDATE").is_some() {
        std::fs::write(&path, &got).unwrap();
    }
    let want = std::fs::read_to_string(&path).unwrap_or_default();
    assert_eq!(
        got, want,
        "\n--- got ---\n{got}--- want ({path}) ---\n{want}"
    );
}

#[test]
fn series_and_parallel_contacts() {
    snap(
        "series_parallel",
        ladder("LD X0\nOR Y0\nANI X1\nAND X2\nOUT Y0\nEND\n"),
    );
}

#[test]
fn anb_and_orb_blocks() {
    // (X0 | X1) & (X2 | X3), then ORB of two series branches.
    snap(
        "anb_orb",
        ladder(
            "LD X0\nOR X1\nLD X2\nOR X3\nANB\nOUT Y0\nLD X4\nAND X5\nLD X6\nAND X7\nORB\nOUT Y1\n",
        ),
    );
}

#[test]
fn mps_branches() {
    snap(
        "mps",
        ladder("LD X0\nMPS\nAND X1\nOUT Y0\nMRD\nANI X2\nOUT Y1\nMPP\nOUT Y2\n"),
    );
}

#[test]
fn outputs_followed_by_contacts_and_several_coils() {
    snap(
        "outputs_then_contacts",
        ladder("LD X0\nOUT Y0\nOUT Y1\nAND X1\nOUT Y2\nLDP X3\nSET M0\nLDF X4\nRST M0\n"),
    );
}

#[test]
fn master_control_and_application_instructions() {
    snap("mc_and_boxes", ladder(
            "LD X0\nMC N0 M10\nLD= D0 K5\nMOV K100 D10\nLD SM400\nINV\n+ D0 D1 D2\nOUT T0 K10\nMCR N0\n",
        ));
}

#[test]
fn labels_and_unknown_mnemonics_never_panic() {
    // Unbalanced connections and unknown instructions are drawn as they come.
    let s = ladder("ANB\nORB\nMPP\nMRD\nP10\nLD X0\nFOO D0\nOR X1\n");
    assert!(s.contains("[FOO D0]"), "{s}");
    let p = LadderProgram::from_source(
        &softplc_core::program::il::parse_il("t.il", "P10\nLD X0\nOUT Y0\n").unwrap(),
    );
    assert_eq!(p.rungs[0].label.as_deref(), Some("P10"));
    assert_eq!(p.devices(), ["X0", "Y0"]);
}

#[test]
fn a_csv_export() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/csv/blink.csv");
    let p = LadderProgram::from_file(std::path::Path::new(path)).unwrap();
    let got = draw(&p);
    assert!(!p.rungs.is_empty());
    snap("blink_csv", got);
}

#[test]
fn svg_has_an_element_per_contact_and_coil() {
    let s = softplc_core::program::il::parse_il("t.il", "LD X0\nANI X1\nOUT T0 K10\nMOV K1 D0\n")
        .unwrap();
    let p = LadderProgram::from_source(&s);
    let svg = render::svg(&p.rungs[0], 0, 0);
    assert!(svg.contains(r#"id="e0-0" data-dev="X0""#), "{svg}");
    assert!(svg.contains(r#"class="el k-nc" id="e0-1" data-dev="X1""#));
    assert!(svg.contains(r#"class="el k-coil" id="e0-2" data-dev="T0""#));
    assert!(svg.contains(r#"data-v="TN0""#));
    assert!(svg.contains(r#"data-v="D0""#));
    // The structure for the power-flow script: X0 and /X1 in series, then
    // the timer coil and the MOV box.
    assert_eq!(
        render::structure(&p.rungs[0]),
        serde_json::json!({"f": {"s": [0, 1]}, "i": [2, 3]})
    );
    assert!(svg.contains("data-net=\"{&quot;f&quot;"), "{svg}");
    let s =
        softplc_core::program::il::parse_il("t.il", "LD X0\nMPS\nAND X1\nOUT Y0\nMPP\nOUT Y1\n")
            .unwrap();
    let p = LadderProgram::from_source(&s);
    assert_eq!(
        render::structure(&p.rungs[0]),
        serde_json::json!({"f": 0, "i": [{"f": 1, "i": [2]}, 3]})
    );
}
