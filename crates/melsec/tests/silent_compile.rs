//! No instruction is dropped in silence: a compile function that gives no
//! instruction must have said why, or the load fails naming the place.

use softplc_ir::device::DeviceConfig;
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
