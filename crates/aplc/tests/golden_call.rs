//! Subroutines: CALL with IN/OUT/IN_OUT arguments, fresh LM/V frames, CSRET,
//! and the load checks of the call graph (contract §1.1 items 7-8, spec
//! aplc.md §3.3).

mod common;
use common::{errors, plc};

/// §8.1 #13, Example 5 (L2420-2473): M0 ON → `CALL SBR_1 3 2 D0` → D0 = 5.
#[test]
fn manual_subroutine_example() {
    let src = "POU SBR_1\nVAR\n    IN1   IN   INT      // V0\n    IN2   IN   INT      // V1\n    OUT1  OUT  INT      // V2\nEND_VAR\n\
LD SM0\nADD #IN1 #IN2 #OUT1\n\nPOU MAIN\nLD M0\nCALL SBR_1 3 2 D0\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!(p.int("D0"), 0);
    p.set("M0", "1").scan();
    assert_eq!(p.int("D0"), 5);
}

/// IN_OUT, BOOL and DINT/REAL parameters; the caller's locals survive the
/// call; CSRET returns early; the rung's power flow continues after CALL.
#[test]
fn frames_and_kinds() {
    let src = "POU MAIN\nVAR\n    KEEP TEMP INT\nEND_VAR\nLD SM0\nMOV 77 #KEEP\nMOV 10 D0\nDMOV 100000 D2\n\
CALL SBR_2 D0 M5 D2 D4 M6\nOUT Y0\nLD SM0\nMOV #KEEP D10\n\n\
POU SBR_2\nVAR\n    V0 ACC IN_OUT INT\n    B1 IN BOOL\n    BIG IN DINT\n    R OUT REAL\n    DONE OUT BOOL\nEND_VAR\n\
LD SM0\nINC #ACC\nMOV 1 V3\nLD #B1\nCSRET\nLD SM0\nDADD #BIG 1 D20\nDFLT #BIG #R\nSET #DONE\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!(p.int("D0"), 11, "IN_OUT copied in and back");
    assert_eq!(p.int("D20:i32"), 100_001);
    assert_eq!(p.real("D4:f32"), 100000.0);
    assert!(p.bit("M6") && p.bit("Y0"));
    assert_eq!(p.int("D10"), 77, "the caller's V0 is restored");
    // With B1 ON the subroutine returns early: OUTs are still copied back.
    p.set("M5", "1").set("M6", "0").set("D20:i32", "0").scan();
    assert_eq!(p.int("D0"), 11, "D0 is reset to 10 each scan, +1");
    assert_eq!(p.int("D20:i32"), 0);
    assert!(!p.bit("M6"), "DONE starts at 0 in the fresh frame");
}

/// Nested calls: MAIN → SBR_1 → SBR_2, each with its own frame.
#[test]
fn nested_calls() {
    let src = "POU MAIN\nLD SM0\nCALL SBR_1 4 D0\n\
POU SBR_1\nVAR\n  X IN INT\n  Y OUT INT\n  T TEMP INT\nEND_VAR\nLD SM0\nMOV 100 #T\nCALL SBR_2 #X #Y\nADD #Y #T #Y\n\
POU SBR_2\nVAR\n  A IN INT\n  B OUT INT\nEND_VAR\nLD SM0\nMUL #A #A D50\nMOV D51 #B\n";
    let mut p = plc(src);
    p.scan();
    assert_eq!(p.int("D0"), 116);
}

#[test]
fn call_diagnostics() {
    let sbr1 =
        "POU SBR_1\nVAR\n    IN1 IN INT\n    OUT1 OUT INT\nEND_VAR\nLD SM0\nMOV #IN1 #OUT1\n";
    let e = errors(&format!("POU MAIN\nLD M0\nCALL SBR_1 3\n{sbr1}"));
    assert!(
        e.contains("t.apl:3:6: CALL SBR_1: takes 2 argument(s) (IN1, OUT1), found 1 (APLC programming manual §6.1.11)"),
        "{e}"
    );
    let e = errors(&format!("POU MAIN\nLD M0\nCALL SBR_1 3 4\n{sbr1}"));
    assert!(
        e.contains("t.apl:3:14: constant `4` cannot be a destination"),
        "{e}"
    );
    let e = errors(&format!("POU MAIN\nLD M0\nCALL SBR_1 3 K2X0\n{sbr1}"));
    assert!(e.contains("`K2X0` cannot be a destination"), "{e}");
    let e = errors(&format!("POU MAIN\nLD M0\nCALL SBR_1 1.5 D0\n{sbr1}"));
    assert!(
        e.contains("REAL constant `1.5` where an integer operand is needed"),
        "{e}"
    );
    let e = errors("POU MAIN\nLD M0\nCALL SBR_3\n");
    assert!(
        e.contains("t.apl:3:6: CALL of `SBR_3`: no POU SBR_3 in the program (APLC programming manual §6.1.11)"),
        "{e}"
    );
    let e = errors("POU MAIN\nLD M0\nCALL SBR_0\nPOU SBR_0\nLD M0\nCALL SBR_0\n");
    assert!(
        e.contains("t.apl:6:6: recursive call: SBR_0 → SBR_0"),
        "{e}"
    );
    let e = errors(
        "POU MAIN\nLD M0\nCALL SBR_0\nPOU SBR_0\nLD M0\nCALL SBR_1\nPOU SBR_1\nLD M0\nCALL SBR_0\n",
    );
    assert!(e.contains("recursive call: SBR_0 → SBR_1 → SBR_0"), "{e}");
    let mut deep = String::from("POU MAIN\nLD M0\nCALL SBR_1\n");
    for n in 1..=7 {
        deep += &format!("POU SBR_{n}\nLD M0\n");
        deep += &if n < 7 {
            format!("CALL SBR_{}\n", n + 1)
        } else {
            "OUT Y0\n".to_string()
        };
    }
    let e = errors(&deep);
    assert!(
        e.contains("t.apl:3:6: calls nested 7 levels deep from MAIN, more than 6 (APLC programming manual §4.4.2)"),
        "{e}"
    );
    deep = deep.replace("CALL SBR_7\n", "OUT Y1\n");
    softplc_aplc::load_bytes("t.apl", deep.as_bytes()).unwrap();
    let e = errors("POU MAIN\nLD M0\nCSRET\n");
    assert!(e.contains("t.apl:3:1: CSRET outside a subroutine"), "{e}");
    let e = errors("POU MAIN\nLD M0\nOUT Y0\nPOU SBR_1\nLD M0\nCFEND\n");
    assert!(e.contains("t.apl:6:1: CFEND outside MAIN"), "{e}");
    let e = errors("POU MAIN\nLD M0\nCALL SBR1\n");
    assert!(e.contains("`SBR1`: a subroutine is SBR_0-SBR_63"), "{e}");
    // Labels are per POU: the same number in two POUs is fine.
    softplc_aplc::load_bytes(
        "t.apl",
        b"POU MAIN\nLBL 1\nLD M0\nCJ 1\nPOU SBR_0\nLBL 1\nLD M0\nCJ 1\n",
    )
    .unwrap();
    let e = errors("POU MAIN\nLD M0\nCJ 1\nPOU SBR_0\nLBL 1\nLD M0\nOUT Y0\n");
    assert!(e.contains("t.apl:3:4: CJ 1: no LBL 1 in this POU"), "{e}");
}
