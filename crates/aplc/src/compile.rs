//! The `.apl` compiler driver: each POU's instructions through the APLC
//! [`Isa`](softplc_lang::isa::Isa) on the shared [`Compiler`] (rung
//! structure, ops), with the APLC's rules: no END (MAIN ends with its last
//! instruction, an implicit END is appended; a subroutine with an implicit
//! return), labels per POU, MAIN's locals zeroed at each entry, CALL linked to
//! the subroutines, and the call graph checked (no recursion, at most 6
//! levels; L2341-2363).

use std::collections::HashMap;

use softplc_ir::device::{DeviceKind, DeviceMap};
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{Op, Program};
use softplc_lang::compile::Compiler;
use softplc_lang::isa::{Found, Kind, Use};
use softplc_lang::{Diagnostic, Diagnostics, Source, SourceInstr, Token};

use crate::call::{self, RET_LABEL};
use crate::pou::{Pou, PouKind, Unit};
use crate::sfc::Sfc;

/// Subroutine nesting below MAIN (L2345).
const MAX_DEPTH: u32 = 6;

/// Clears LM and V when a POU is entered (L1910, L1938, contract §1.1 item 8).
#[derive(Debug)]
struct EnterPou {
    lm: (u32, u32),
    v: (u32, u32),
}

impl Instr for EnterPou {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.off(cx)
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.mem.bits[self.lm.0 as usize..self.lm.1 as usize].fill(false);
        cx.mem.words[self.v.0 as usize..self.v.1 as usize].fill(0);
        Ok(())
    }
}

/// What the driver collects across POUs.
struct Links {
    /// CALL sites: (caller, callee, op index of the `Call`, token).
    calls: Vec<(PouKind, u8, usize, Token)>,
    /// SFC state (step bodies are unique in the program).
    sfc: Sfc,
}

/// Compiles a parsed file.
pub fn compile(file: &str, unit: &Unit) -> Result<Program, Diagnostics> {
    let cfg = crate::devices::device_config();
    let map = DeviceMap::new(&cfg);
    let mut c = Compiler::new(file, &map, crate::dialect());
    let Some(main) = unit.pous.iter().find(|p| p.kind == PouKind::Main) else {
        let t = Token {
            text: String::new(),
            line: 1,
            col: 1,
        };
        c.err(&t, "the program has no instruction (an empty MAIN)");
        return finish(c);
    };
    let mut links = Links {
        calls: Vec::new(),
        sfc: Sfc::default(),
    };
    let ints: Vec<&Pou> = unit
        .pous
        .iter()
        .filter(|p| matches!(p.kind, PouKind::Int { .. }))
        .collect();
    let events: Vec<u8> = ints
        .iter()
        .filter_map(|p| match p.kind {
            PouKind::Int { event, .. } => Some(event),
            _ => None,
        })
        .collect();
    let int_calls = if ints.is_empty() {
        Vec::new()
    } else {
        crate::interrupt::dispatch(&mut c, &events)
    };
    let range = |k: DeviceKind| (map.base(k), map.base(k) + map.points(k));
    let enter = |c: &mut Compiler<'_>| {
        let x = c.ext.len() as u32;
        c.ext.push(Box::new(EnterPou {
            lm: range(DeviceKind::B),
            v: range(DeviceKind::W),
        }));
        c.emit(Op::ExtAlways(x));
    };
    enter(&mut c);
    pou(&mut c, unit, main, &mut links);
    c.emit(Op::End);
    let mut starts = HashMap::new();
    for p in &unit.pous {
        if let PouKind::Sbr(n) = p.kind {
            starts.insert(n, c.ops.len() as u32);
            pou(&mut c, unit, p, &mut links);
            c.emit(Op::Ret);
        }
    }
    for (p, at) in ints.iter().zip(&int_calls) {
        let start = c.ops.len() as u32;
        if let Op::Call(t) = &mut c.ops[*at] {
            *t = start;
        }
        enter(&mut c);
        pou(&mut c, unit, p, &mut links);
        c.emit(Op::Ret);
    }
    for (_, n, at, _) in &links.calls {
        if let (Some(&t), Op::Call(target)) = (starts.get(n), &mut c.ops[*at]) {
            *target = t;
        }
    }
    call_graph(&mut c, &links);
    finish(c)
}

/// Compiles one POU with its own labels.
fn pou(c: &mut Compiler<'_>, unit: &Unit, p: &Pou, links: &mut Links) {
    c.labels.clear();
    c.fixups.clear();
    c.has_rung = false;
    c.after_output = true;
    c.depth = 0;
    c.mps.clear();
    let mut k = 0;
    while k < p.body.len() {
        let i = &p.body[k];
        if i.mnemonic.text.eq_ignore_ascii_case("STL") {
            let run: Vec<&SourceInstr> = p.body[k..]
                .iter()
                .take_while(|i| i.mnemonic.text.eq_ignore_ascii_case("STL"))
                .collect();
            c.cur_step = c.step;
            c.cur_line = i.mnemonic.line;
            for stl in &run {
                c.record(stl);
            }
            links.sfc.stl(c, &run);
            c.step += 3 * run.len() as u32;
            k += run.len();
            continue;
        }
        instr(c, unit, p.kind, i, links);
        k += 1;
    }
    links.sfc.close(c);
    let last = p
        .body
        .last()
        .map_or(p.header.clone(), |i| i.mnemonic.clone());
    if c.has_rung && !c.after_output {
        c.err(&last, "the last contacts of the POU lead to no output");
    }
    c.close_rung(&last);
    for tok in std::mem::take(&mut c.for_open) {
        let at = Token {
            text: "FOR".into(),
            ..tok
        };
        c.err(
            &at,
            "FOR without its NEXT in this POU (APLC programming manual §6.1.2)",
        );
    }
    for (n, tok) in std::mem::take(&mut c.mc_open) {
        c.err(&tok, format!("MC {n} without MCR {n}"));
    }
    c.cur_line = last.line;
    c.cur_step = c.step;
    c.labels.insert(RET_LABEL, (c.ops.len() as u32, last.line));
    for (at, n, tok) in std::mem::take(&mut c.fixups) {
        match c.labels.get(&n) {
            Some(&(target, _)) => {
                if let Op::Cj { target: t, .. } = &mut c.ops[at] {
                    *t = target;
                }
            }
            // The skip of a FOR without NEXT, reported above.
            None if n > 127 => {}
            None => c.err(
                &tok,
                format!("CJ {n}: no LBL {n} in this POU (APLC programming manual §6.1.4)"),
            ),
        }
    }
    c.labels.clear();
}

fn instr(c: &mut Compiler<'_>, unit: &Unit, kind: PouKind, i: &SourceInstr, links: &mut Links) {
    c.record(i);
    let m = i.mnemonic.text.to_ascii_uppercase();
    c.cur_step = c.step;
    c.cur_line = i.mnemonic.line;
    let errors = c.diags.len();
    let (steps, class) = match crate::isa().lookup(&m) {
        Found::Def(def, false) => {
            let u = Use {
                def,
                instr: i,
                m: &m,
                pulse: false,
            };
            match (m.as_str(), def.kind) {
                ("CALL", _) => {
                    if let Some((n, at, tok)) = call::call(c, unit, kind, i) {
                        links.calls.push((kind, n, at, tok));
                    }
                }
                ("CSRET", _) => csret(c, kind, i),
                ("CIRET", _) if matches!(kind, PouKind::Int { .. }) => ciret(c, i),
                ("RET", _) if kind != PouKind::Main => c.err(
                    &i.mnemonic,
                    "RET outside MAIN: it ends the SFC section of the main program (APLC programming manual §5.3.5)",
                ),
                ("RET", _) => {
                    if c.count(i, "RET", &[0]) {
                        links.sfc.close(c);
                    }
                }
                ("MC" | "MCR", _) if links.sfc.in_step() => c.err(
                    &i.mnemonic,
                    format!("`{m}` in an SFC step: MC/MCR may not be used in steps (APLC programming manual §4.5.3)"),
                ),
                ("SET" | "OUT", _) if links.sfc.transition(c, i, &m) => {}
                ("CFEND", _) if kind != PouKind::Main => c.err(
                    &i.mnemonic,
                    "CFEND outside MAIN: it ends the main program only (APLC programming manual §6.1.5)",
                ),
                (_, Kind::Lower(f)) => f(c, &u),
                (_, Kind::Rejected(why)) => {
                    c.err(&i.mnemonic, format!("unsupported instruction `{m}`: {why}"))
                }
                (_, Kind::Instr(compile)) => c.family(i, &m, def.drive, compile, false),
            }
            (def.steps.count(&i.operands), Some(def.class))
        }
        _ if m == "END" => {
            c.err(&i.mnemonic, "unknown instruction `END`: the APLC has no END, a POU ends with its last line (APLC programming manual §6.1.5)");
            (1, None)
        }
        _ => {
            c.err(&i.mnemonic, format!("unknown instruction `{m}`"));
            (1, None)
        }
    };
    if c.diags.len() > errors {
        c.recover(class);
    }
    c.step = c.cur_step + steps;
}

/// 002 §6.1 L3792 CSRET: with power flow, return from the subroutine.
fn csret(c: &mut Compiler<'_>, kind: PouKind, i: &SourceInstr) {
    if !matches!(kind, PouKind::Sbr(_)) {
        c.err(
            &i.mnemonic,
            "CSRET outside a subroutine (APLC programming manual §6.1.12)",
        );
        return;
    }
    if !c.count(i, "CSRET", &[0]) || !c.output(i, "CSRET") {
        return;
    }
    let at = c.emit(Op::Cj {
        target: 0,
        always: false,
    });
    c.fixups.push((at, RET_LABEL, i.mnemonic.clone()));
}

/// 002 §6.1 L3725 CIRET: with power flow, return from the interrupt routine.
fn ciret(c: &mut Compiler<'_>, i: &SourceInstr) {
    if !c.count(i, "CIRET", &[0]) || !c.output(i, "CIRET") {
        return;
    }
    let at = c.emit(Op::Cj {
        target: 0,
        always: false,
    });
    c.fixups.push((at, RET_LABEL, i.mnemonic.clone()));
}

/// Recursion, call cycles and nesting deeper than 6 (L2345, L2353-2358).
fn call_graph(c: &mut Compiler<'_>, links: &Links) {
    fn depth(
        n: u8,
        links: &Links,
        memo: &mut HashMap<u8, Option<u32>>,
        path: &mut Vec<u8>,
        bad: &mut Vec<(Token, String)>,
    ) -> u32 {
        if let Some(d) = memo.get(&n) {
            return d.unwrap_or(0);
        }
        path.push(n);
        memo.insert(n, None);
        let mut deepest = 0;
        for (from, to, _, tok) in &links.calls {
            if *from != PouKind::Sbr(n) {
                continue;
            }
            if path.contains(to) {
                let cycle: Vec<String> = path
                    .iter()
                    .chain([to])
                    .map(|k| format!("SBR_{k}"))
                    .collect();
                bad.push((
                    tok.clone(),
                    format!(
                        "recursive call: {} (APLC programming manual §4.4.2)",
                        cycle.join(" → ")
                    ),
                ));
                continue;
            }
            deepest = deepest.max(depth(*to, links, memo, path, bad));
        }
        path.pop();
        memo.insert(n, Some(deepest + 1));
        deepest + 1
    }
    let mut memo = HashMap::new();
    let mut bad = Vec::new();
    for (from, to, _, tok) in &links.calls {
        let d = depth(*to, links, &mut memo, &mut Vec::new(), &mut bad);
        if *from == PouKind::Main && d > MAX_DEPTH {
            bad.push((
                tok.clone(),
                format!("calls nested {d} levels deep from MAIN, more than {MAX_DEPTH} (APLC programming manual §4.4.2)"),
            ));
        }
    }
    bad.sort_by_key(|(t, _)| (t.line, t.col));
    bad.dedup_by(|a, b| a.0 == b.0);
    for (tok, msg) in bad {
        c.err(&tok, msg);
    }
}

fn finish(mut c: Compiler<'_>) -> Result<Program, Diagnostics> {
    c.end_seen = Some(Token {
        text: String::new(),
        line: 1,
        col: 1,
    });
    let src = Source {
        file: c.file.to_string(),
        items: Vec::new(),
        model: None,
    };
    c.finish(&src)
}

/// A diagnostic for the whole file (no position).
pub fn file_error(file: &str, message: String) -> Diagnostics {
    Diagnostics(vec![Diagnostic {
        file: file.to_string(),
        line: 0,
        col: 0,
        message,
    }])
}
