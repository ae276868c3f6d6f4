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

/// An `.apl` program drawn as text: POU headings, comments and step buses.
fn apl(src: &str) -> String {
    let p = super::aplc::from_bytes("t.apl", src.as_bytes()).unwrap();
    draw_apl(&p)
}

fn draw_apl(p: &LadderProgram) -> String {
    render::program_text(p)
}

#[test]
fn apl_manual_example_1_stacks_and_blocks() {
    // 002 L2185-2208 (spec aplc.md §3.2 example 1): MPS/MRD/MPP branches and
    // an ORB inside an ANB; X10 is octal (input 8), drawn as written.
    snap(
        "apl_example1",
        apl("LD X0\nOR X1\nAND X14\nMPS\nOUT Y0\nAND X1\nOUT Y1\nMPP\nAND X2\nMPS\nOUT Y2\nAND X3\nAND X4\nOUT Y3\nMRD\nLD X5\nAND X6\nLD X7\nAND X10\nORB\nANB\nOUT Y4\nMPP\nOUT Y5\n"),
    );
}

#[test]
fn apl_series_parallel_edges_and_compares() {
    // Example 2 (L2798-2803), EU/ED in series, compare contacts of the three
    // widths (L9320-9337, L9464-9475) with the operator written apart.
    // Word-bit contacts (L8833-9076): BLD opens a rung, BORI is parallel.
    let s = apl("LD M1\nAND M2\nLD M3\nAND M4\nORB\nOUT Y0\nLD X0\nEU\nLDI X1\nED\nORB\nSET M0\nLD= D0 D1\nANDD< D0 100\nORR < > D4 1.5\nOUT Y1\nBLD D0 5\nBORI D1 15\nOUT Y2\n");
    snap("apl_series_parallel", s);
    let p = super::aplc::from_bytes("t.apl", b"LDD>= D20 500\nOUT M10\nLDR< D4 1.5\nOUT M11\n")
        .unwrap();
    let e = |r: usize| match &p.rungs[r].body {
        super::RungBody::Fan(f) => match &f.prefix {
            Some(super::Net::Elem(e)) => e.clone(),
            _ => panic!("a contact"),
        },
        _ => panic!("a fan"),
    };
    // The script compares 32-bit and REAL operands read with their type.
    assert_eq!(e(0).values(), ["D20:i32"]);
    assert_eq!(e(1).values(), ["D4:f32"]);
    let p = super::aplc::from_bytes("t.apl", b"BLDI D0 5\nOUT Y0\n").unwrap();
    let svg = render::svg(&p.rungs[0], 0, 0);
    assert!(
        svg.contains(
            r#"class="el k-nc" id="e0-0" data-dev="D0" data-ops="D0 5" data-m="BLDI" data-bit="5""#
        ),
        "{svg}"
    );
}

#[test]
fn apl_timer_counter_and_locals() {
    // Example 3, TONR (L3161-3164): the timer is a box with its current value.
    let p = super::aplc::from_bytes(
        "t.apl",
        b"LD M0\nTONR T1 5\nLD T1\nOUT Y0\nLD X2\nCTU C0 10\nLD SM0\nMUL C0 100 D10\n",
    )
    .unwrap();
    snap("apl_timer", draw_apl(&p));
    let tonr = match &p.rungs[0].body {
        super::RungBody::Fan(f) => match &f.items[0] {
            super::Item::Out(e) => e.clone(),
            _ => panic!("an output"),
        },
        _ => panic!("a fan"),
    };
    assert_eq!(tonr.kind, super::Kind::Box);
    assert_eq!(tonr.values(), ["TN1"]);
    assert_eq!(tonr.watched(), ["T1", "TN1"]);
    let svg = render::svg(&p.rungs[2], 0, 2);
    assert!(svg.contains(r#"data-dev="C0""#), "{svg}");
    let svg = render::svg(&p.rungs[3], 0, 3);
    assert!(svg.contains(r#"data-v="CN0""#), "{svg}");
    assert!(svg.contains(r#"data-v="D10""#), "{svg}");
}

#[test]
fn apl_sfc_steps_power_their_body() {
    // 002 §5.2 (spec aplc.md §3.4): an initial step, a transition, a merge of
    // two steps (decision D16) and RET.
    let src = "LD SM1\nSET S0\nSTL S0\nLD X0\nSET S20\nSTL S20\nOUT Y0\nLD X1\nSET S21\nSTL S21\nTON T2 10\nLD T2\nSET S22\nSTL S22\nLD X2\nSET S30\nSTL S21\nSTL S22\nLD X3\nSET S0\nRET\nLD X4\nOUT Y7\n";
    let p = super::aplc::from_bytes("t.apl", src.as_bytes()).unwrap();
    snap("apl_sfc", draw_apl(&p));
    let merge = p
        .rungs
        .iter()
        .find(|r| r.bus == ["S21", "S22"])
        .expect("the merge's rung");
    assert_eq!(merge.line, 19);
    // After RET the rail is plain again.
    assert!(p.rungs.last().unwrap().bus.is_empty());
    let step = render::svg(&p.rungs[1], 0, 1);
    assert!(step.contains(r#"class="el k-step""#), "{step}");
    assert!(step.contains(r#"data-ops="S0""#), "{step}");
    let body = render::svg(&p.rungs[2], 0, 2);
    assert!(body.contains(r#"data-bus="S0""#), "{body}");
    assert_eq!(p.devices()[..4], ["SM1", "S0", "X0", "S20"]);
}

#[test]
fn apl_pous_call_and_labels() {
    // Example 5 (L2420-2473): CALL with the callee's parameter names; an
    // interrupt routine; CJ/LBL (L3655-3662) per POU.
    let src = "POU SBR_1\nVAR\n  IN1 IN INT\n  IN2 IN INT\n  OUT1 OUT INT\n  T TEMP BOOL\nEND_VAR\nLD SM0\nADD #IN1 #IN2 #OUT1\nLD #T\nOUT Y1\n\nPOU MAIN\n// M0 calls SBR_1\nLD M0\nCALL SBR_1 3 2 D0\nLD M1\nCJ 0\nLD SM0\nMOV 100 D0\nLBL 0\n\nPOU INT_1 EVENT 26\nLD SM0\nMOV 1 D5\n";
    let p = super::aplc::from_bytes("t.apl", src.as_bytes()).unwrap();
    snap("apl_pous", draw_apl(&p));
    let titles: Vec<&str> = p.sections.iter().map(|s| s.title.as_str()).collect();
    assert_eq!(titles, ["SBR_1", "MAIN", "INT_1 EVENT 26"]);
    assert_eq!(
        p.sections[0].vars,
        [
            "IN1 IN INT = V0",
            "IN2 IN INT = V1",
            "OUT1 OUT INT = V2",
            "T TEMP BOOL = LM0"
        ]
    );
    let svg: String = p
        .rungs
        .iter()
        .enumerate()
        .map(|(k, r)| render::svg(r, 0, k))
        .collect();
    assert!(svg.contains("CALL SBR_1 IN1:=3 IN2:=2 OUT1:=D0"), "{svg}");
    assert!(svg.contains("ADD #IN1=V0 #IN2=V1 #OUT1=V2"), "{svg}");
    // A subroutine's locals are not in device memory at END: not watched.
    assert!(!p
        .devices()
        .iter()
        .any(|d| d.starts_with('V') || d.starts_with("LM")));
    assert_eq!(p.rungs[1].comment, Vec::<String>::new());
    let main = p.sections[1].first;
    assert_eq!(p.rungs[main].comment, ["M0 calls SBR_1"]);
}

#[test]
fn apl_conveyor_example() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/aplc/conveyor.apl"
    );
    let p = super::aplc::from_file(std::path::Path::new(path)).unwrap();
    snap("apl_conveyor", draw_apl(&p));
    // Globals are drawn NAME=DEVICE and watched as their APLC devices; MAIN's
    // TEMP #RUNOK is LM0.
    let svg: String = p
        .rungs
        .iter()
        .enumerate()
        .map(|(k, r)| render::svg(r, 0, k))
        .collect();
    assert!(svg.contains(r#"data-dev="X10""#), "{svg}");
    assert!(svg.contains("急停=X10"), "{svg}");
    assert!(svg.contains("#RUNOK=LM0"), "{svg}");
    let d = p.devices();
    assert_eq!(d[..5], ["X0", "X10", "M0", "X1", "C0"]);
    assert!(d.contains(&"LM0".to_string()));
    assert_eq!(p.sections.len(), 1);
    assert_eq!(
        p.comment[0],
        "Conveyor with batch counter (APLC-TCP dialect)."
    );
}

#[test]
fn apl_errors_name_the_place() {
    let e = super::aplc::from_bytes("t.apl", b"POU MAIN\nLD #NOPE\nOUT Y0\n").unwrap();
    // An unknown local is drawn as written (the compiler reports it).
    assert!(draw_apl(&e).contains("#NOPE"));
    let e = super::aplc::from_bytes("t.apl", b"LD X0\n/* open\n").unwrap_err();
    assert_eq!(e, "t.apl:2:1: `/*`: block comment without `*/`");
}

#[test]
fn wires_name_where_their_power_comes_from() {
    // (X0 AND X1) OR X2 → Y0, then a branch: the short branch's filler wire
    // carries X2's output, the right link the OR of X1 and X2; MPS's branch
    // point what its first branch gets, the wire into Y2 what Y2 gets.
    let s = softplc_core::program::il::parse_il(
        "t.il",
        "LD X0\nAND X1\nOR X2\nOUT Y0\nLD X3\nMPS\nAND X4\nOUT Y1\nMPP\nOUT Y2\n",
    )
    .unwrap();
    let p = LadderProgram::from_source(&s);
    let svg = render::svg(&p.rungs[0], 0, 0);
    assert!(
        svg.contains(r#"<line class="w" data-after="2" x1="136""#),
        "{svg}"
    );
    assert!(svg.contains(r#"class="w link" data-after="1 2""#), "{svg}");
    assert!(svg.contains(r#"class="w link" data-into="0""#), "{svg}");
    let svg = render::svg(&p.rungs[1], 0, 1);
    // X3 (4) → MPS: X4 (5) → Y1 (6); Y2 (7).
    assert!(svg.contains(r#"class="w link" data-into="5""#), "{svg}");
    assert!(svg.contains(r#"<line class="w" data-into="7""#), "{svg}");
}

#[test]
fn a_loaded_program_draws_from_its_listing_as_its_source_does() {
    // What `load_programs` draws for a served program is what the file's
    // source gives (the snapshots above).
    let text = "LD X0\nOR Y0\nANI X1\nMPS\nAND X2\nOUT Y0\nMPP\nOUT Y1\nLDP X3\nLD X4\nORF X5\nANB\nSET M0\nP10\nLD= D0 K5\nMEP\nMOV K100 D10\nOUT T0 K10\nFEND\nEND\n";
    let src = softplc_core::program::il::parse_il("t.il", text).unwrap();
    let program = softplc_core::program::compile_il(
        "t.il",
        text,
        &softplc_core::device::DeviceConfig::default(),
    )
    .unwrap();
    let from_program = LadderProgram::from_program(&program);
    let from_source = LadderProgram::from_source(&src);
    assert_eq!(from_program.rungs, from_source.rungs);
    assert_eq!(draw(&from_program), draw(&from_source));
    assert_eq!(from_program.rungs[2].label.as_deref(), Some("P10"));
}

#[test]
fn a_box_shows_32_bit_and_real_operands_whole() {
    // EMOV E1.5 D0 writes D0-D1 as a real (Programming Manual §6.4): its
    // box shows D0:f32 (1.5), not D0's low word;
    // DMOV's 32-bit destination D10:i32. A device the program also uses as
    // a word (D20) stays a word: its width is not one.
    let src = "LD SM400\nEMOV E1.5 D0\nDMOV K100000 D10\nDMOV D20 D30\nMOV D20 D40\nEND\n";
    let program = softplc_core::program::compile_il(
        "t.il",
        src,
        &softplc_core::device::DeviceConfig::default(),
    )
    .unwrap();
    let p = LadderProgram::from_program(&program);
    let mut values = Vec::new();
    for r in &p.rungs {
        r.for_each(&mut |e| {
            if e.kind == super::Kind::Box {
                values.push(e.values());
            }
        });
    }
    assert_eq!(
        values,
        [
            vec!["D0:f32".to_string()],
            vec!["D10:i32".to_string()],
            vec!["D20".to_string(), "D30:i32".to_string()],
            vec!["D20".to_string(), "D40".to_string()],
        ]
    );
}
