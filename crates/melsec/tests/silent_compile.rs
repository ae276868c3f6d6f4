//! No instruction is dropped in silence: a compile function that gives no
//! instruction must have said why, or the load fails naming the place.

use softplc_ir::device::{DeviceConfig, DeviceMap};
use softplc_lang::audit::renamed;
use softplc_lang::il::parse_il;
use softplc_lang::isa::{Def, Doc, Isa};
use softplc_lang::{compile, Diagnostics};
use softplc_melsec::{dialect, Args, Instr, DEFS};

const DOC: Doc = Doc {
    family: "test",
    cite: "-",
    notes: "",
};

/// A faulty compile function: no instruction and no diagnostic.
fn silent(_: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    None
}

/// One that refuses its operand with a reason.
fn refusing(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    a.error(0, "not this operand");
    None
}

static TEST_DEFS: &[Def] = &[
    Def::app("SILENT", &DOC, silent),
    Def::app("REFUSE", &DOC, refusing),
];

fn load(src: &str) -> Result<(), Diagnostics> {
    let families: Vec<&'static [Def]> = DEFS.iter().copied().chain([TEST_DEFS]).collect();
    let isa: &'static Isa = Box::leak(Box::new(Isa::new(&families)));
    let d = softplc_lang::dialect::Dialect {
        isa,
        ..dialect().clone()
    };
    let src = parse_il("t.il", src).expect("parses");
    compile(&src, &DeviceConfig::default(), &d, None).map(|_| ())
}

#[test]
fn an_instruction_compiled_to_nothing_without_a_reason_fails_the_load() {
    let err = load("LD X0\nSILENT D0\nEND\n").unwrap_err().to_string();
    assert_eq!(
        err,
        "t.il:2:1: `SILENT` compiled to nothing without a reason (a softplc bug: please report it)"
    );
}

#[test]
fn a_refused_operand_gives_its_own_reason_only() {
    let err = load("LD X0\nREFUSE D0\nEND\n").unwrap_err().to_string();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("t.il:2:"), "{err}");
    assert!(err.contains("not this operand"), "{err}");
    assert!(load("LD X0\nMOV K1 D0\nEND\n").is_ok());
}

/// Operand sets to try: devices of each kind and constants in a few
/// patterns, then the forms some instructions need.
fn candidates(_: &Def) -> Vec<Vec<String>> {
    let mut sets = softplc_lang::audit::operand_sets(
        |k| format!("D{}", 1000 * k),
        |k| format!("M{}", 100 * k),
        |k| format!("K{}", k + 1),
    );
    let special: &[&[&str]] = &[
        &["T0", "K10"],
        &["C0", "K10"],
        &["ST0", "K10"],
        &["T0"],
        &["P0"],
        &["N0", "M0"],
        &["N0"],
        &["X0", "Y0"],
        &["K4X0", "D1000"],
        &["D1000", "K4Y0"],
        &["\"AB\"", "D1000"],
        &["\"AB\"", "\"CD\"", "D1000"],
        &["E1.5", "D1000"],
        &["E1.5", "E2.5", "D1000"],
        &["D1000", "\"AB\"", "D2000"],
        &["M0", "K4M100"],
        &["V0"],
        &["T0", "K10", "F0"],
        &["D1000", "P0"],
        &["\"AB\"", "P0", "D1000"],
        &["\"AB\""],
        &["K10", "K20", "SM420"],
        &["D1000", "K1", "M0"],
        &["D1000", "K5", "K1", "M0", "D2000"],
        &["T0", "K10", "M0"],
        &["K1", "K10", "D1000", "K5", "M0"],
    ];
    sets.extend(
        special
            .iter()
            .map(|s| s.iter().map(|t| t.to_string()).collect()),
    );
    sets
}

/// Every MELSEC and process definition compiles, under a name that is not
/// its own, to its own instruction or to a load error that says it is a
/// softplc bug: no match on the mnemonic falls through to another
/// instruction.
#[test]
fn no_definition_compiles_as_another_under_a_foreign_name() {
    let map = DeviceMap::new(&DeviceConfig::default());
    let bug = |d: &str| d.contains("a softplc bug");
    // The redundant CPU's set: every MELSEC-Q definition (PID included) and
    // the process ones.
    let d = softplc_melsec::redundant_dialect(Default::default());
    {
        let r = renamed(&d, &map, "ZZ", &candidates, &bug);
        assert!(
            r.differing.is_empty(),
            "{}",
            r.differing
                .iter()
                .map(|(n, a, b)| format!("{n}:\n  own   {a:?}\n  alias {b:?}"))
                .collect::<Vec<_>>()
                .join("\n")
        );
        assert!(
            r.uncovered.is_empty(),
            "no operand set compiles: {:?}",
            r.uncovered
        );
    }
}
