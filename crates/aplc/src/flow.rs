//! Program flow (002 §6.1 L3546-3743; spec aplc.md §4.4): FOR/NEXT, LBL/CJ
//! within a POU, CFEND, WDT, STOP; and FROM/DFROM/TO/DTO, which load but find no
//! special module on APLC-TCP (decision D7: run error 73).

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::kernels::cpu::ResetWatchdog;
use softplc_ir::ops::{Op, WordArg};
use softplc_lang::compile::{Args, Compiler};
use softplc_lang::isa::{Class, Def, Doc, Steps, Use};

use crate::constant::Width;
use crate::devices::FOR_BIT;
use crate::num::E_MODULE;
use crate::resolve::{self, at};

/// First label number of the hidden labels after each NEXT (APLC labels
/// are 0-127).
const FOR_LABELS: u32 = 1 << 16;
/// FOR/NEXT nesting (the engine's FOR stack).
const MAX_FOR: usize = 16;

static DOC: Doc = Doc {
    family: "program flow",
    cite: "002 §6.1 L3601-3743",
    notes: "FOR S runs the body S times with power flow and S > 0, else skips past NEXT (under an OFF MC the body runs once with its conditions OFF); LBL/CJ 0-127, unique per POU; CFEND in MAIN ends the scan; STOP with power flow stops the CPU at once (the rest of the scan and its END processing do not run, no error); no END (the POU ends with its last line)",
};
static MODULE: Doc = Doc {
    family: "peripheral",
    cite: "002 §6.9 L6465-6482, decision D7",
    notes:
        "load; with power flow: nothing transferred, run error 73 (no special module on APLC-TCP)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.1 L3548 FOR
    Def::lower("FOR", Class::Output, &DOC, for_).steps(Steps::Fixed(3)),
    // 002 §6.1 L3548 NEXT
    Def::lower("NEXT", Class::Standalone, &DOC, next).steps(Steps::Fixed(1)),
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
            format!("LBL {n} defined twice in this POU (first at line {line}, APLC programming manual §6.1.3)"),
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
    match u.m {
        "CFEND" => {
            c.emit(Op::GoEnd);
        }
        "WDT" => c.emit_instr(false, false, Box::new(ResetWatchdog)),
        // 002 §6.1.10: "系统将立即停止用户程序的执行", at once, not at END.
        "STOP" => {
            c.emit(Op::StopNow);
        }
        _ => c.unmatched(u),
    }
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

/// The FOR gate: the hidden bit is ON when FOR has power flow and S > 0.
#[derive(Debug)]
struct ForGate {
    n: WordArg,
    bit: u32,
}

impl Instr for ForGate {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.mem.bits[self.bit as usize] = cx.mem.read16(&self.n)? as i16 > 0;
        Ok(())
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.mem.bits[self.bit as usize] = false;
        Ok(())
    }
}

// 002 §6.1 L3548-3599 FOR: gate, skip past NEXT when closed, engine FOR.
fn for_(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[1]) || !c.output(i, u.m) {
        return;
    }
    let tok = &i.operands[0];
    let r = resolve::word(c.map, &tok.text, Width::W16, false, false);
    let Some(n) = at(c, tok, r) else {
        return;
    };
    if c.for_open.len() >= MAX_FOR {
        c.err(
            &i.mnemonic,
            format!("FOR nested more than {MAX_FOR} levels"),
        );
        return;
    }
    let bit = c.map.base(DeviceKind::V) + FOR_BIT;
    let x = c.ext.len() as u32;
    c.ext.push(Box::new(ForGate { n: n.clone(), bit }));
    c.emit(Op::ExtAlways(x));
    c.emit(Op::Ldi(bit));
    let label = FOR_LABELS + c.ops.len() as u32;
    let at = c.emit(Op::Cj {
        target: 0,
        always: false,
    });
    c.fixups.push((at, label, i.mnemonic.clone()));
    c.emit(Op::For(Box::new(n)));
    // The open FOR remembers its hidden label in the token's text.
    let mut open = i.mnemonic.clone();
    open.text = label.to_string();
    c.for_open.push(open);
    c.has_rung = false;
    c.after_output = true;
}

// 002 §6.1 L3548 NEXT
fn next(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[0]) || !c.standalone(i, u.m) {
        return;
    }
    let Some(open) = c.for_open.pop() else {
        c.err(
            &i.mnemonic,
            "NEXT without FOR (APLC programming manual §6.1.2)",
        );
        return;
    };
    c.emit(Op::Next);
    let label = open.text.parse().unwrap_or(u32::MAX);
    c.labels
        .insert(label, (c.ops.len() as u32, i.mnemonic.line));
}
