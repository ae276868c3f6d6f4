//! Program flow (002 §6.1 L3546-3743; spec aplc.md §4.4): LBL/CJ within a
//! POU, CFEND, WDT, STOP; and FROM/DFROM/TO/DTO, which load but find no
//! special module on APLC-TCP (decision D7: run error 73).

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::Op;
use softplc_lang::compile::{Args, Compiler};
use softplc_lang::isa::{Class, Def, Doc, Steps, Use};

use crate::num::E_MODULE;
use crate::resolve::{self, at};

static DOC: Doc = Doc {
    family: "program flow",
    cite: "002 §6.1 L3601-3743",
    notes: "LBL/CJ 0-127, unique per POU; CFEND in MAIN ends the scan; no END (the POU ends with its last line)",
};
static MODULE: Doc = Doc {
    family: "peripheral",
    cite: "002 §6.9 L6465-6482, decision D7",
    notes:
        "load; with power flow: nothing transferred, run error 73 (no special module on APLC-TCP)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.1 L3601 LBL
    Def::lower("LBL", Class::Standalone, &DOC, lbl).steps(Steps::Fixed(3)),
    // 002 §6.1 L3627 CJ
    Def::lower("CJ", Class::Output, &DOC, cj).steps(Steps::Fixed(3)),
    // 002 §6.1 L3668 CFEND
    Def::lower("CFEND", Class::Output, &DOC, simple).steps(Steps::Fixed(1)),
    // 002 §6.1 L3689 WDT
    Def::lower("WDT", Class::Output, &DOC, simple).steps(Steps::Fixed(1)),
    // 002 §6.1 L3735 STOP
    Def::lower("STOP", Class::Output, &DOC, simple).steps(Steps::Fixed(1)),
    // 002 §6.9 FROM/DFROM/TO/DTO (D7)
    Def::app("FROM", &MODULE, module)
        .no_pulse()
        .steps(Steps::Fixed(9)),
    Def::app("DFROM", &MODULE, module)
        .no_pulse()
        .steps(Steps::Fixed(10)),
    Def::app("TO", &MODULE, module)
        .no_pulse()
        .steps(Steps::Fixed(9)),
    Def::app("DTO", &MODULE, module)
        .no_pulse()
        .steps(Steps::Fixed(10)),
];

fn lbl(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[1]) {
        return;
    }
    let tok = &i.operands[0];
    let Some(n) = at(c, tok, resolve::number(&tok.text, 0, 127)) else {
        return;
    };
    if c.has_rung && !c.after_output || c.depth > 0 || !c.mps.is_empty() {
        c.err(&i.mnemonic, "`LBL` inside an unfinished rung");
    }
    if let Some(&(_, line)) = c.labels.get(&n) {
        c.err(
            tok,
            format!("LBL {n} defined twice in this POU (first at line {line}, L3621)"),
        );
        return;
    }
    c.labels.insert(n, (c.ops.len() as u32, tok.line));
    c.has_rung = false;
    c.after_output = true;
}

fn cj(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[1]) || !c.output(i, u.m) {
        return;
    }
    let tok = &i.operands[0];
    let Some(n) = at(c, tok, resolve::number(&tok.text, 0, 127)) else {
        return;
    };
    let at = c.emit(Op::Cj {
        target: 0,
        always: false,
    });
    c.fixups.push((at, n, tok.clone()));
}

fn simple(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[0]) || !c.output(i, u.m) {
        return;
    }
    c.emit(match u.m {
        "CFEND" => Op::GoEnd,
        "WDT" => Op::Wdt,
        _ => Op::Stop,
    });
}

#[derive(Debug)]
struct NoModule;

impl Instr for NoModule {
    fn exec(&self, _: &mut ExecCtx<'_>) -> Result<(), Fault> {
        Err(E_MODULE)
    }
}

fn module(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    Some(Box::new(NoModule))
}
