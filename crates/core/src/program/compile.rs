//! Compiles a [`Source`] into a [`Program`]: looks up each mnemonic, checks and
//! resolves its operands against the device configuration, checks the ladder
//! structure (blocks, MPS, MC/MCR, FOR/NEXT, pointers, END) and reports every
//! error of the file with its line and column.

use std::collections::HashMap;

use super::ops::*;
use super::source::{Diagnostic, Diagnostics, Source, SourceInstr, SourceItem, Token};
use crate::device::{
    parse_operand, Constant, DeviceConfig, DeviceKind, DeviceMap, DeviceName, Operand,
};
use crate::instructions::catalog;

/// MPS nesting limit and block (LD … ANB/ORB) nesting limit.
const MAX_MPS: u32 = 16;
const MAX_BLOCKS: u32 = 16;
/// FOR/NEXT and CALL nesting (programming manual: 16 levels).
pub const MAX_NESTING: usize = 16;

/// Compiles a parsed file for a CPU with the given device points.
pub fn compile(src: &Source, devices: &DeviceConfig) -> Result<Program, Diagnostics> {
    compile_with(src, devices, None)
}

/// Compiles with the "common pointer" parameter: pointers from `common_from` up
/// to P4095 are common (004 §10.9.2); a CALL of one this file does not define is
/// linked to the program that does when the CPU is built.
pub fn compile_with(
    src: &Source,
    devices: &DeviceConfig,
    common_from: Option<u32>,
) -> Result<Program, Diagnostics> {
    let map = DeviceMap::new(devices);
    let mut c = Compiler::new(&src.file, &map);
    c.common_from = common_from.unwrap_or(u32::MAX);
    for item in &src.items {
        match item {
            SourceItem::Label(tok) => c.label(tok),
            SourceItem::Instr(i) => c.instr(i),
        }
    }
    c.finish(src)
}

struct Compiler<'a> {
    file: &'a str,
    map: &'a DeviceMap,
    ops: Vec<Op>,
    op_step: Vec<u32>,
    op_line: Vec<u32>,
    diags: Vec<Diagnostic>,
    labels: HashMap<u32, (u32, u32)>,
    fixups: Vec<(usize, u32, Token)>,
    edge_slots: u32,
    state_words: u32,
    ext: Vec<Box<dyn crate::instructions::Instr>>,
    step: u32,
    cur_step: u32,
    cur_line: u32,
    /// A rung has been started (an LD seen since the last label or standalone instruction).
    has_rung: bool,
    /// The last instruction was an output: the next LD starts a new rung.
    after_output: bool,
    /// Open blocks awaiting ANB/ORB.
    depth: u32,
    /// Open MPS levels.
    /// Open MPS instructions, for MPP pairing and error positions.
    mps: Vec<Token>,
    mc_open: Vec<(u32, Token)>,
    for_open: Vec<Token>,
    end_seen: Option<Token>,
    after_end_reported: bool,
    fend_seen: bool,
    /// Program names used by PSCAN/PSTOP/POFF/PLOW.
    prog_names: Vec<String>,
    /// First common pointer number (`u32::MAX`: none).
    common_from: u32,
    /// Interrupt pointers: number → (op index, line).
    interrupts: HashMap<u32, (u32, u32)>,
}

impl<'a> Compiler<'a> {
    fn new(file: &'a str, map: &'a DeviceMap) -> Self {
        Compiler {
            file,
            map,
            ops: Vec::new(),
            op_step: Vec::new(),
            op_line: Vec::new(),
            diags: Vec::new(),
            labels: HashMap::new(),
            fixups: Vec::new(),
            edge_slots: 0,
            state_words: 0,
            ext: Vec::new(),
            step: 0,
            cur_step: 0,
            cur_line: 0,
            has_rung: false,
            after_output: true,
            depth: 0,
            mps: Vec::new(),
            mc_open: Vec::new(),
            for_open: Vec::new(),
            end_seen: None,
            after_end_reported: false,
            fend_seen: false,
            prog_names: Vec::new(),
            common_from: u32::MAX,
            interrupts: HashMap::new(),
        }
    }

    fn err(&mut self, tok: &Token, msg: impl Into<String>) {
        self.diags.push(Diagnostic::at(self.file, tok, msg));
    }

    fn emit(&mut self, op: Op) -> usize {
        self.ops.push(op);
        self.op_step.push(self.cur_step);
        self.op_line.push(self.cur_line);
        self.ops.len() - 1
    }

    fn slot(&mut self) -> u32 {
        self.edge_slots += 1;
        self.edge_slots - 1
    }

    fn label(&mut self, tok: &Token) {
        let text = tok.text.to_ascii_uppercase();
        if self.end_seen.is_some() {
            self.err(tok, format!("pointer `{text}` after END labels nothing"));
            return;
        }
        let n: u32 = text[1..].parse().unwrap_or(u32::MAX);
        if text.starts_with('I') {
            self.interrupt_label(tok, &text, n);
            return;
        }
        if n > 4095 {
            self.err(tok, format!("pointer `{text}` is out of range (P0-P4095)"));
            return;
        }
        if self.has_rung && !self.after_output || self.depth > 0 || !self.mps.is_empty() {
            self.err(tok, format!("pointer `{text}` inside an unfinished rung"));
        }
        if let Some((_, line)) = self.labels.get(&n) {
            let line = *line;
            self.err(
                tok,
                format!("duplicate pointer `P{n}` (first defined at line {line})"),
            );
            return;
        }
        self.labels.insert(n, (self.ops.len() as u32, tok.line));
        self.has_rung = false;
        self.after_output = true;
    }

    /// An interrupt pointer `In` (004 §4.1.3): it must follow FEND, each number once.
    fn interrupt_label(&mut self, tok: &Token, text: &str, n: u32) {
        if n > 255 {
            return self.err(
                tok,
                format!("interrupt pointer `{text}` is out of range (I0-I255)"),
            );
        }
        if (32..=49).contains(&n) {
            return self.err(
                tok,
                format!("unsupported: `{text}` (error interrupts I32-I39 are not implemented; I33, I37 and I40-I49 are not used)"),
            );
        }
        if !self.fend_seen {
            return self.err(tok, format!("interrupt program `{text}` must follow FEND"));
        }
        if self.has_rung && !self.after_output || self.depth > 0 || !self.mps.is_empty() {
            self.err(tok, format!("pointer `{text}` inside an unfinished rung"));
        }
        if let Some(&(_, line)) = self.interrupts.get(&n) {
            return self.err(
                tok,
                format!("duplicate interrupt pointer `I{n}` (first defined at line {line})"),
            );
        }
        self.interrupts.insert(n, (self.ops.len() as u32, tok.line));
        self.has_rung = false;
        self.after_output = true;
    }

    fn instr(&mut self, i: &SourceInstr) {
        let m = i.mnemonic.text.to_ascii_uppercase();
        if self.end_seen.is_some() {
            if !self.after_end_reported {
                self.after_end_reported = true;
                self.err(&i.mnemonic, format!("`{m}` after END is never executed"));
            }
            return;
        }
        self.cur_step = i.step.unwrap_or(self.step);
        self.cur_line = i.mnemonic.line;
        let steps = catalog::steps(&m, &i.operands);
        let errors = self.diags.len();
        self.dispatch(&m, i);
        if self.diags.len() > errors {
            self.recover(&m);
        }
        self.step = self.cur_step + steps;
    }

    /// After a faulty instruction, puts the rung state where a correct one of the
    /// same class would have left it, so one mistake gives one diagnostic.
    fn recover(&mut self, m: &str) {
        let contact = parse_compare(m).is_some()
            || ["LD", "AND", "ANI", "OR"].iter().any(|p| m.starts_with(p));
        let standalone = matches!(
            m,
            "END" | "FEND" | "MCR" | "FOR" | "NEXT" | "RET" | "NOP" | "JMP"
        );
        if contact {
            self.has_rung = true;
            self.after_output = false;
        } else if standalone {
            self.has_rung = false;
            self.after_output = true;
            self.depth = 0;
            self.mps.clear();
        } else {
            self.has_rung = true;
            self.after_output = true;
            self.depth = 0;
        }
    }

    fn count(&mut self, i: &SourceInstr, m: &str, allowed: &[usize]) -> bool {
        let n = i.operands.len();
        if allowed.contains(&n) {
            return true;
        }
        let want = match allowed {
            [a] => format!("{a}"),
            [a, b] => format!("{a} or {b}"),
            _ => format!("{allowed:?}"),
        };
        let tok = i
            .operands
            .get(*allowed.iter().max().unwrap_or(&0))
            .unwrap_or(&i.mnemonic);
        self.err(
            tok,
            format!(
                "`{m}` takes {want} operand{}, found {n}",
                if want == "1" { "" } else { "s" }
            ),
        );
        false
    }

    fn dispatch(&mut self, m: &str, i: &SourceInstr) {
        let ops = &i.operands;
        match m {
            "LD" | "LDI" | "AND" | "ANI" | "OR" | "ORI" | "LDP" | "LDF" | "ANDP" | "ANDF"
            | "ORP" | "ORF" => {
                if !self.count(i, m, &[1]) {
                    return;
                }
                let (join, rest) = split_join(m);
                let negate = rest == "I" || m == "ANI";
                let edge = match rest {
                    "P" => Edge::Rising,
                    "F" => Edge::Falling,
                    _ => Edge::None,
                };
                let Some(src) = self.bit_operand(&ops[0]) else {
                    self.contact_state(i, join);
                    return;
                };
                let op = match (&src, edge) {
                    (BitArg::Bit(b), Edge::None) => match (join, negate) {
                        (Join::Load, false) => Op::Ld(*b),
                        (Join::Load, true) => Op::Ldi(*b),
                        (Join::And, false) => Op::And(*b),
                        (Join::And, true) => Op::Ani(*b),
                        (Join::Or, false) => Op::Or(*b),
                        (Join::Or, true) => Op::Ori(*b),
                    },
                    _ => {
                        let slot = if edge == Edge::None { 0 } else { self.slot() };
                        Op::Contact(Box::new(Contact {
                            join,
                            negate,
                            edge,
                            slot,
                            src,
                        }))
                    }
                };
                self.contact(i, join, op);
            }
            "ANB" | "ORB" => {
                if !self.count(i, m, &[0]) {
                    return;
                }
                if self.depth == 0 {
                    self.err(
                        &i.mnemonic,
                        format!("`{m}` has no block to combine (no LD opened one)"),
                    );
                } else {
                    self.depth -= 1;
                }
                self.after_output = false;
                self.emit(if m == "ANB" { Op::Anb } else { Op::Orb });
            }
            "MPS" | "MRD" | "MPP" => {
                if !self.count(i, m, &[0]) || !self.need_rung(i, m) {
                    return;
                }
                match m {
                    "MPS" if self.mps.len() >= MAX_MPS as usize => {
                        self.err(&i.mnemonic, format!("more than {MAX_MPS} nested MPS"))
                    }
                    "MPS" => self.mps.push(i.mnemonic.clone()),
                    _ if self.mps.is_empty() => self.err(&i.mnemonic, format!("`{m}` without MPS")),
                    "MPP" => {
                        self.mps.pop();
                    }
                    _ => {}
                }
                self.after_output = false;
                self.emit(match m {
                    "MPS" => Op::Mps,
                    "MRD" => Op::Mrd,
                    _ => Op::Mpp,
                });
            }
            "EI" | "DI" => {
                if self.count(i, m, &[0]) && self.output(i, m) {
                    self.emit(if m == "EI" { Op::Ei } else { Op::Di });
                }
            }
            "IMASK" => {
                if self.count(i, m, &[1]) && self.output(i, m) {
                    if let Some(s) = self.word_dest(&ops[0], Num::I16, 16) {
                        self.emit(Op::Imask(Box::new(s)));
                    }
                }
            }
            "IRET" => {
                if self.count(i, m, &[0]) && self.standalone(i, m) {
                    self.emit(Op::Iret);
                }
            }
            "LEDR" | "ANR" | "ANRP" => {
                // ANR resets the annunciator shown first (SD62), as LEDR does for
                // annunciators; ANRP on the rising edge.
                if self.count(i, m, &[0]) && self.output(i, m) {
                    self.pulsed(m == "ANRP", Op::Ledr);
                }
            }
            "ANS" => self.ans(i),
            "INV" | "MEP" | "MEF" => {
                if !self.count(i, m, &[0]) || !self.need_rung(i, m) {
                    return;
                }
                self.after_output = false;
                let op = match m {
                    "INV" => Op::Inv,
                    "MEP" => Op::Mep(self.slot()),
                    _ => Op::Mef(self.slot()),
                };
                self.emit(op);
            }
            "EGP" | "EGF" => {
                if !self.count(i, m, &[1]) || !self.need_rung(i, m) {
                    return;
                }
                self.after_output = false;
                if let Some(v) = self.edge_relay(&ops[0]) {
                    self.emit(Op::EdgeRelay {
                        rising: m == "EGP",
                        v,
                    });
                }
            }
            "OUT" | "OUTH" => self.out(i, m),
            "SET" | "RST" => {
                if !self.count(i, m, &[1]) || !self.output(i, m) {
                    return;
                }
                if let Some(n) = self.annunciator(&ops[0]) {
                    let kind = if m == "SET" {
                        AnnKind::Set
                    } else {
                        AnnKind::Rst
                    };
                    self.emit(Op::Ann { kind, n });
                    return;
                }
                if m == "RST" {
                    self.rst(&ops[0]);
                    return;
                }
                if let Some(dst) = self.bit_dest(&ops[0]) {
                    match dst {
                        BitArg::Bit(b) => self.emit(Op::Set(b)),
                        dst => self.emit(Op::Coil(Box::new(Coil {
                            kind: CoilKind::Set,
                            dst,
                        }))),
                    };
                }
            }
            "PLS" | "PLF" | "FF" => {
                if !self.count(i, m, &[1]) || !self.output(i, m) {
                    return;
                }
                if let Some(dst) = self.bit_dest(&ops[0]) {
                    let s = self.slot();
                    let kind = match m {
                        "PLS" => CoilKind::Pls(s),
                        "PLF" => CoilKind::Plf(s),
                        _ => CoilKind::Ff(s),
                    };
                    self.emit(Op::Coil(Box::new(Coil { kind, dst })));
                }
            }
            "MC" => {
                if !self.count(i, m, &[2]) || !self.output(i, m) {
                    return;
                }
                let level = self.nesting(&ops[0]);
                let dst = self.bit_dest(&ops[1]);
                if let Some(level) = level {
                    if let Some((open, _)) = self.mc_open.last() {
                        if level <= *open {
                            let open = *open;
                            self.err(
                                &ops[0],
                                format!(
                                    "MC N{level} inside MC N{open}: nesting numbers must ascend"
                                ),
                            );
                        }
                    }
                    self.mc_open.push((level, ops[0].clone()));
                    if let Some(dst) = dst {
                        self.emit(Op::Mc(Box::new(MasterControl {
                            level: level as u8,
                            dst,
                        })));
                    }
                }
            }
            "MCR" => {
                if !self.count(i, m, &[1]) || !self.standalone(i, m) {
                    return;
                }
                if let Some(level) = self.nesting(&ops[0]) {
                    match self.mc_open.iter().position(|(l, _)| *l == level) {
                        Some(p) => self.mc_open.truncate(p),
                        None => self.err(
                            &ops[0],
                            format!("MCR N{level} without a matching MC N{level}"),
                        ),
                    }
                    self.emit(Op::Mcr(level as u8));
                }
            }
            "NOP" => {
                if self.count(i, m, &[0]) {
                    self.emit(Op::Nop);
                }
            }
            "END" | "FEND" => {
                if !self.count(i, m, &[0]) || !self.standalone(i, m) {
                    return;
                }
                if m == "END" {
                    self.emit(Op::End);
                    self.end_seen = Some(i.mnemonic.clone());
                } else {
                    self.fend_seen = true;
                    self.emit(Op::Fend);
                }
            }
            "PSCAN" | "PSTOP" | "POFF" | "PLOW" | "PSCANP" | "PSTOPP" | "POFFP" | "PLOWP" => {
                if !self.count(i, m, &[1]) || !self.output(i, m) {
                    return;
                }
                let name = match self.parse(&ops[0]) {
                    Some(Operand::Const(Constant::Str(s))) if !s.is_empty() && s.len() <= 8 => s,
                    Some(_) => {
                        return self.err(
                            &ops[0],
                            format!(
                                "`{m}` needs a program name such as \"MAIN\" (up to 8 characters)"
                            ),
                        )
                    }
                    None => return,
                };
                let (base, pulse) = match m {
                    "PSCANP" | "PSTOPP" | "POFFP" | "PLOWP" => (&m[..m.len() - 1], true),
                    _ => (m, false),
                };
                let kind = match base {
                    "PSCAN" => TypeChange::Scan,
                    "PSTOP" => TypeChange::Standby,
                    "POFF" => TypeChange::Off,
                    _ => TypeChange::LowSpeed,
                };
                let id = self.prog_names.len() as u32;
                self.prog_names.push(name.to_ascii_uppercase());
                self.pulsed(pulse, Op::ProgCtl { kind, name: id });
            }
            "WDT" | "WDTP" | "TRACE" | "TRACER" => {
                if self.count(i, m, &[0]) && self.output(i, m) {
                    let op = match m {
                        "TRACE" => Op::Trace { reset: false },
                        "TRACER" => Op::Trace { reset: true },
                        _ => Op::Wdt,
                    };
                    self.pulsed(m == "WDTP", op);
                }
            }
            "DUTY" => {
                if !self.count(i, m, &[3]) || !self.output(i, m) {
                    return;
                }
                let n1 = self.word_src(&ops[0], Num::I16);
                let n2 = self.word_src(&ops[1], Num::I16);
                let clock = match parse_operand(&ops[2].text) {
                    Ok(Operand::Device {
                        dev,
                        digits: None,
                        bit: None,
                        index: None,
                    }) if dev.kind == DeviceKind::SM
                        && matches!(dev.number, 420..=424 | 430..=434) =>
                    {
                        Some(if dev.number < 430 {
                            dev.number - 420
                        } else {
                            dev.number - 425
                        } as u8)
                    }
                    _ => {
                        self.err(
                            &ops[2],
                            format!(
                                "`{}`: DUTY drives a user timing clock SM420-SM424 or SM430-SM434",
                                ops[2].text
                            ),
                        );
                        None
                    }
                };
                if let (Some(n1), Some(n2), Some(c)) = (n1, n2, clock) {
                    self.emit(Op::Duty(Box::new((n1, n2, c))));
                }
            }
            "STOP" | "GOEND" => {
                if self.count(i, m, &[0]) && self.output(i, m) {
                    self.emit(if m == "STOP" { Op::Stop } else { Op::GoEnd });
                }
            }
            "CJ" | "SCJ" => {
                if !self.count(i, m, &[1]) || !self.output(i, m) {
                    return;
                }
                if let Some(p) = self.pointer(&ops[0]) {
                    let op = if m == "CJ" {
                        Op::Cj {
                            target: 0,
                            always: false,
                        }
                    } else {
                        Op::Scj {
                            target: 0,
                            slot: self.slot(),
                        }
                    };
                    let at = self.emit(op);
                    self.fixups.push((at, p, ops[0].clone()));
                }
            }
            "JMP" => {
                if !self.count(i, m, &[1]) {
                    return;
                }
                if self.has_rung && !self.after_output {
                    self.err(
                        &i.mnemonic,
                        "JMP is unconditional; use CJ for a conditional jump",
                    );
                    return;
                }
                self.standalone(i, m);
                if let Some(p) = self.pointer(&ops[0]) {
                    let at = self.emit(Op::Cj {
                        target: 0,
                        always: true,
                    });
                    self.fixups.push((at, p, ops[0].clone()));
                }
            }
            "CALL" | "CALLP" => {
                if ops.len() > 1 {
                    self.err(
                        &ops[1],
                        "unsupported: CALL with arguments (FX/FY/FD) is not implemented yet",
                    );
                    return;
                }
                if !self.count(i, m, &[1]) || !self.output(i, m) {
                    return;
                }
                if let Some(p) = self.pointer(&ops[0]) {
                    if m == "CALLP" {
                        let s = self.slot();
                        self.emit(Op::Pulse(s));
                    }
                    let at = self.emit(Op::Call(0));
                    self.fixups.push((at, p, ops[0].clone()));
                }
            }
            "RET" => {
                if self.count(i, m, &[0]) && self.standalone(i, m) {
                    self.emit(Op::Ret);
                }
            }
            "FOR" => {
                if !self.count(i, m, &[1]) || !self.standalone(i, m) {
                    return;
                }
                if self.for_open.len() >= MAX_NESTING {
                    self.err(
                        &i.mnemonic,
                        format!("FOR nested more than {MAX_NESTING} levels"),
                    );
                }
                self.for_open.push(i.mnemonic.clone());
                if let Some(n) = self.word_src(&ops[0], Num::I16) {
                    self.emit(Op::For(Box::new(n)));
                }
            }
            "NEXT" => {
                if !self.count(i, m, &[0]) || !self.standalone(i, m) {
                    return;
                }
                if self.for_open.pop().is_none() {
                    self.err(&i.mnemonic, "NEXT without FOR");
                }
                self.emit(Op::Next);
            }
            "BREAK" | "BREAKP" => {
                if !self.count(i, m, &[2]) || !self.output(i, m) {
                    return;
                }
                let d = self.word_dest(&ops[0], Num::I16, 1);
                let p = self.pointer(&ops[1]);
                if let (Some(d), Some(p)) = (d, p) {
                    if m == "BREAKP" {
                        let s = self.slot();
                        self.emit(Op::Pulse(s));
                    }
                    let at = self.emit(Op::Break(Box::new((d, 0))));
                    self.fixups.push((at, p, ops[1].clone()));
                }
            }
            _ => {
                if let Some((join, op)) = parse_str_compare(m) {
                    let cmp = {
                        let mut args = Args { c: self, i, m };
                        crate::instructions::strings::StrCompare::compile(&mut args)
                    };
                    match cmp {
                        Some(cmp) => self.contact(
                            i,
                            join,
                            Op::StrCompare(Box::new(StrCompareOp { join, op, cmp })),
                        ),
                        None => {
                            self.contact_state(i, join);
                        }
                    }
                } else if let Some((join, num, op)) = parse_compare(m) {
                    self.compare(i, m, join, num, op);
                } else {
                    self.application(i, m);
                }
            }
        }
    }

    /// Rung bookkeeping for a contact; emits `op` (preceded by `Push` when it opens
    /// a block inside a rung).
    fn contact(&mut self, i: &SourceInstr, join: Join, op: Op) {
        if self.contact_state(i, join) {
            self.emit(Op::Push);
        }
        self.emit(op);
    }

    /// Updates the rung state for a contact; true when a block must be pushed.
    fn contact_state(&mut self, i: &SourceInstr, join: Join) -> bool {
        let mut push = false;
        match join {
            Join::Load => {
                if self.after_output || !self.has_rung {
                    self.close_rung(&i.mnemonic);
                } else if self.depth >= MAX_BLOCKS {
                    self.err(
                        &i.mnemonic,
                        format!("more than {MAX_BLOCKS} open blocks (LD without ANB/ORB)"),
                    );
                } else {
                    self.depth += 1;
                    push = true;
                }
                self.has_rung = true;
            }
            Join::And | Join::Or => {
                self.need_rung(i, &i.mnemonic.text.to_ascii_uppercase());
            }
        }
        self.after_output = false;
        push
    }

    /// Checks that the previous rung left no open block or MPS.
    fn close_rung(&mut self, at: &Token) {
        if self.depth > 0 {
            self.err(
                at,
                format!(
                    "{} block(s) opened by LD were not closed with ANB/ORB",
                    self.depth
                ),
            );
            self.depth = 0;
        }
        let _ = at;
        for tok in std::mem::take(&mut self.mps) {
            self.err(&tok, "MPS without MPP");
        }
    }

    fn need_rung(&mut self, i: &SourceInstr, m: &str) -> bool {
        if !self.has_rung {
            self.err(&i.mnemonic, format!("`{m}` needs a preceding LD"));
            return false;
        }
        true
    }

    /// Checks an instruction driven by the rung condition.
    fn output(&mut self, i: &SourceInstr, m: &str) -> bool {
        if !self.need_rung(i, m) {
            return false;
        }
        if self.depth > 0 {
            self.err(
                &i.mnemonic,
                format!(
                    "`{m}`: {} block(s) opened by LD are not closed with ANB/ORB",
                    self.depth
                ),
            );
            self.depth = 0;
        }
        self.after_output = true;
        true
    }

    /// Checks an instruction that stands alone on the bus bar (END, FEND, MCR, FOR, NEXT, RET).
    fn standalone(&mut self, i: &SourceInstr, m: &str) -> bool {
        if self.has_rung && !self.after_output {
            self.err(
                &i.mnemonic,
                format!("`{m}` takes no condition, but contacts before it lead to no output"),
            );
        }
        self.close_rung(&i.mnemonic);
        self.has_rung = false;
        self.after_output = true;
        true
    }

    fn out(&mut self, i: &SourceInstr, m: &str) {
        let ops = &i.operands;
        if ops.is_empty() {
            self.count(i, m, &[1, 2]);
            return;
        }
        if !self.output(i, m) {
            return;
        }
        let op0 = match parse_operand(&ops[0].text) {
            Ok(o) => o,
            Err(e) => return self.err(&ops[0], e.message),
        };
        let tc = match &op0 {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                index,
            } if matches!(dev.kind, DeviceKind::TS | DeviceKind::STS | DeviceKind::CS)
                && dev.generic =>
            {
                Some((*dev, *index))
            }
            _ => None,
        };
        let Some((dev, index)) = tc else {
            if m == "OUTH" {
                return self.err(
                    &ops[0],
                    format!("OUTH needs a timer (T or ST), found `{}`", ops[0].text),
                );
            }
            if ops.len() != 1 {
                return self.err(&ops[1], format!("`OUT {}` takes no set value", ops[0].text));
            }
            if let Some(n) = self.annunciator(&ops[0]) {
                self.emit(Op::Ann {
                    kind: AnnKind::Out,
                    n,
                });
                return;
            }
            if let Some(dst) = self.bit_dest(&ops[0]) {
                match dst {
                    BitArg::Bit(b) => self.emit(Op::Out(b)),
                    dst => self.emit(Op::Coil(Box::new(Coil {
                        kind: CoilKind::Out,
                        dst,
                    }))),
                };
            }
            return;
        };
        if index.is_some() {
            return self.err(
                &ops[0],
                "unsupported: index modification of a timer or counter coil",
            );
        }
        let name = dev
            .kind
            .format(dev.number)
            .replace("TS", "T")
            .replace("CS", "C");
        if ops.len() != 2 {
            return self.err(
                &ops[0],
                format!(
                    "`{m} {}` needs a set value, e.g. `{m} {} K10`",
                    ops[0].text, ops[0].text
                ),
            );
        }
        let counter = dev.kind == DeviceKind::CS;
        if counter && m == "OUTH" {
            return self.err(&i.mnemonic, "OUTH is for timers; counters use OUT");
        }
        let (coil_k, value_k) = match dev.kind {
            DeviceKind::TS => (DeviceKind::TC, DeviceKind::TN),
            DeviceKind::STS => (DeviceKind::STC, DeviceKind::STN),
            _ => (DeviceKind::CC, DeviceKind::CN),
        };
        let Some(contact) = self.map.index(dev.kind, dev.number) else {
            return self.range_err(&ops[0], dev.kind, dev.number, &name);
        };
        let set = self.set_value(&ops[1]);
        let coil = self.map.base(coil_k) + dev.number;
        let value = self.map.base(value_k) + dev.number;
        let Some(set) = set else { return };
        if counter {
            self.emit(Op::Counter(Box::new(Counter {
                coil,
                contact,
                value,
                set,
            })));
        } else {
            let retentive = dev.kind == DeviceKind::STS;
            let slot = timer_slot(self.map, retentive, dev.number);
            self.emit(Op::Timer(Box::new(Timer {
                coil,
                contact,
                value,
                slot,
                set,
                high_speed: m == "OUTH",
                retentive,
            })));
        }
    }

    /// `ANS T n F`: annunciator F is set when the condition has been ON for
    /// n × 100 ms, timed by timer T (004 §10.2.4; PM ANS). Compiled as `OUT T n`
    /// followed by `SET F` driven by the timer's contact, leaving the rung's
    /// operation result unchanged (MPS … MPP).
    fn ans(&mut self, i: &SourceInstr) {
        let ops = &i.operands;
        if !self.count(i, "ANS", &[3]) || !self.output(i, "ANS") {
            return;
        }
        let timer = match parse_operand(&ops[0].text) {
            Ok(Operand::Device {
                dev,
                digits: None,
                bit: None,
                index: None,
            }) if dev.generic && dev.kind == DeviceKind::TS => dev,
            _ => return self.err(&ops[0], format!("`{}`: ANS needs a timer T", ops[0].text)),
        };
        let Some(n) = self.annunciator(&ops[2]) else {
            return self.err(
                &ops[2],
                format!("`{}`: ANS needs an annunciator F", ops[2].text),
            );
        };
        let Some(contact) = self.map.index(DeviceKind::TS, timer.number) else {
            return self.range_err(&ops[0], DeviceKind::TS, timer.number, &ops[0].text);
        };
        let Some(set) = self.set_value(&ops[1]) else {
            return;
        };
        self.emit(Op::Timer(Box::new(Timer {
            coil: self.map.base(DeviceKind::TC) + timer.number,
            contact,
            value: self.map.base(DeviceKind::TN) + timer.number,
            slot: timer_slot(self.map, false, timer.number),
            set,
            high_speed: false,
            retentive: false,
        })));
        self.emit(Op::Mps);
        self.emit(Op::Ld(contact));
        self.emit(Op::Ann {
            kind: AnnKind::Set,
            n,
        });
        self.emit(Op::Mpp);
    }

    /// `Fn` written plainly: OUT/SET/RST make it an annunciator (004 §10.2.4).
    fn annunciator(&mut self, tok: &Token) -> Option<u16> {
        match parse_operand(&tok.text) {
            Ok(Operand::Device {
                dev,
                digits: None,
                bit: None,
                index: None,
            }) if dev.kind == DeviceKind::F && dev.number < self.map.points(DeviceKind::F) => {
                Some(dev.number as u16)
            }
            _ => None,
        }
    }

    fn set_value(&mut self, tok: &Token) -> Option<WordArg> {
        if let Ok(Operand::Const(Constant::Int { value, .. })) = parse_operand(&tok.text) {
            if !(0..=32767).contains(&value) {
                self.err(
                    tok,
                    format!("set value `{}` out of range (K0-K32767)", tok.text),
                );
                return None;
            }
        }
        self.word_src(tok, Num::I16)
    }

    fn rst(&mut self, tok: &Token) {
        let op = match parse_operand(&tok.text) {
            Ok(o) => o,
            Err(e) => return self.err(tok, e.message),
        };
        if let Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        } = &op
        {
            let timer = match dev.kind {
                DeviceKind::TS | DeviceKind::TC | DeviceKind::TN => {
                    Some((DeviceKind::TS, DeviceKind::TN, false))
                }
                DeviceKind::STS | DeviceKind::STC | DeviceKind::STN => {
                    Some((DeviceKind::STS, DeviceKind::STN, true))
                }
                DeviceKind::CS | DeviceKind::CC | DeviceKind::CN => {
                    Some((DeviceKind::CS, DeviceKind::CN, false))
                }
                _ => None,
            };
            if let Some((ck, vk, retentive)) = timer {
                if dev.kind == DeviceKind::TN && !dev.generic
                    || dev.kind == DeviceKind::CN
                    || dev.kind == DeviceKind::STN
                {
                    // RST TN0: clear the current value word only.
                } else {
                    let Some(contact) = self.map.index(ck, dev.number) else {
                        return self.range_err(tok, ck, dev.number, &tok.text);
                    };
                    let slot = if ck == DeviceKind::CS {
                        u32::MAX
                    } else {
                        timer_slot(self.map, retentive, dev.number)
                    };
                    self.emit(Op::Apply(Box::new(Apply::ResetTc(ResetTc {
                        contact,
                        value: self.map.base(vk) + dev.number,
                        slot,
                    }))));
                    return;
                }
            }
            if !dev.kind.is_bit() || dev.generic {
                // RST of a word device writes 0.
                if let Some(d) = self.word_dest(tok, Num::I16, 1) {
                    self.emit(Op::Apply(Box::new(Apply::Mov {
                        words: 1,
                        s: WordArg::Const(0),
                        d,
                    })));
                }
                return;
            }
        }
        if let Operand::Device {
            dev,
            bit: None,
            digits: None,
            ..
        } = &op
        {
            if !dev.kind.is_bit() {
                if let Some(d) = self.word_dest(tok, Num::I16, 1) {
                    self.emit(Op::Apply(Box::new(Apply::Mov {
                        words: 1,
                        s: WordArg::Const(0),
                        d,
                    })));
                }
                return;
            }
        }
        if let Some(dst) = self.bit_dest(tok) {
            match dst {
                BitArg::Bit(b) => self.emit(Op::Rst(b)),
                dst => self.emit(Op::Coil(Box::new(Coil {
                    kind: CoilKind::Rst,
                    dst,
                }))),
            };
        }
    }

    fn compare(&mut self, i: &SourceInstr, m: &str, join: Join, num: Num, op: CmpOp) {
        if !self.count(i, m, &[2]) {
            self.contact_state(i, join);
            return;
        }
        let a = self.word_src(&i.operands[0], num);
        let b = self.word_src(&i.operands[1], num);
        let (Some(a), Some(b)) = (a, b) else {
            self.contact_state(i, join);
            return;
        };
        self.contact(
            i,
            join,
            Op::Compare(Box::new(Compare {
                join,
                op,
                num,
                a,
                b,
            })),
        );
    }

    fn application(&mut self, i: &SourceInstr, m: &str) {
        // Family instructions; pulse forms are a `P` suffix (`BCDP`) or `SP.` for
        // `S.` instructions (`SP.PIDCONT`).
        let family = crate::instructions::lookup(m)
            .map(|f| (f, false))
            .or_else(|| {
                m.strip_suffix('P')
                    .and_then(crate::instructions::lookup)
                    .map(|f| (f, true))
            })
            .or_else(|| {
                let base = format!("S.{}", m.strip_prefix("SP.")?);
                crate::instructions::lookup(&base).map(|f| (f, true))
            });
        if let Some((compile, pulse)) = family {
            if !self.output(i, m) {
                return;
            }
            let mut args = Args { c: self, i, m };
            if let Some(x) = compile(&mut args) {
                let at = self.ext.len() as u32;
                self.ext.push(x);
                self.pulsed(pulse, Op::Ext(at));
            }
            return;
        }
        let (name, pulse) = match catalog::application(m) {
            Some(_) => (m, false),
            None => match m
                .strip_suffix('P')
                .filter(|b| catalog::application(b).is_some())
            {
                Some(base) => (base, true),
                None => {
                    let msg = if catalog::is_known(m) {
                        format!(
                            "unsupported instruction `{m}`: {}",
                            catalog::unsupported_reason(m)
                        )
                    } else {
                        format!("unknown instruction `{m}`")
                    };
                    return self.err(&i.mnemonic, msg);
                }
            },
        };
        let Some(app) = catalog::application(name) else {
            return;
        };
        use catalog::App;
        let ops = &i.operands;
        let ok_count = match app {
            App::Mov(_) | App::Flt(_) | App::Int(_) => self.count(i, m, &[2]),
            App::Arith(..) => self.count(i, m, &[2, 3]),
            App::Step(..) => self.count(i, m, &[1]),
        };
        if !ok_count || !self.output(i, m) {
            return;
        }
        let apply = match app {
            App::Mov(num) => {
                let s = self.word_src(&ops[0], num);
                let d = self.word_dest(&ops[1], num, num.words());
                let (Some(s), Some(d)) = (s, d) else { return };
                match (&s, &d, num) {
                    (WordArg::Const(k), WordArg::Word(d), Num::I16) => {
                        return self.pulsed(
                            pulse,
                            Op::MovK {
                                k: *k as u16,
                                d: *d,
                            },
                        )
                    }
                    (WordArg::Word(s), WordArg::Word(d), Num::I16) => {
                        return self.pulsed(pulse, Op::MovW { s: *s, d: *d })
                    }
                    _ => Apply::Mov {
                        words: num.words() as u8,
                        s,
                        d,
                    },
                }
            }
            App::Arith(op, num) => {
                let dest_words = match (op, num) {
                    (ArithOp::Mul | ArithOp::Div, Num::I16) => 2,
                    (ArithOp::Mul | ArithOp::Div, Num::I32) => 4,
                    _ => num.words(),
                };
                // A digit-specified `*`/`/` destination takes K1-K8 (the 32-bit
                // product or the quotient).
                let dest_num = match (op, num) {
                    (ArithOp::Mul | ArithOp::Div, Num::I16) => Num::I32,
                    _ => num,
                };
                let (s1, s2, d) = if ops.len() == 3 {
                    (
                        self.word_src(&ops[0], num),
                        self.word_src(&ops[1], num),
                        self.word_dest(&ops[2], dest_num, dest_words),
                    )
                } else {
                    (
                        self.word_src(&ops[1], num),
                        self.word_src(&ops[0], num),
                        self.word_dest(&ops[1], dest_num, dest_words),
                    )
                };
                let (Some(s1), Some(s2), Some(d)) = (s1, s2, d) else {
                    return;
                };
                Apply::Arith { op, num, s1, s2, d }
            }
            App::Step(num, delta) => {
                let Some(d) = self.word_dest(&ops[0], num, num.words()) else {
                    return;
                };
                Apply::Step { num, delta, d }
            }
            App::Flt(num) => {
                let s = self.word_src(&ops[0], num);
                let d = self.word_dest(&ops[1], Num::F32, 2);
                let (Some(s), Some(d)) = (s, d) else { return };
                Apply::Flt { num, s, d }
            }
            App::Int(num) => {
                let s = self.word_src(&ops[0], Num::F32);
                let d = self.word_dest(&ops[1], num, num.words());
                let (Some(s), Some(d)) = (s, d) else { return };
                Apply::Int { num, s, d }
            }
        };
        self.pulsed(pulse, Op::Apply(Box::new(apply)));
    }

    fn pulsed(&mut self, pulse: bool, op: Op) {
        if pulse {
            let s = self.slot();
            self.emit(Op::Pulse(s));
        }
        self.emit(op);
    }

    // --- operands ---

    fn parse(&mut self, tok: &Token) -> Option<Operand> {
        match parse_operand(&tok.text) {
            Ok(o) => Some(o),
            Err(e) => {
                let t = Token {
                    col: tok.col + e.offset as u32,
                    ..tok.clone()
                };
                self.err(&t, e.message);
                None
            }
        }
    }

    fn range_err(&mut self, tok: &Token, kind: DeviceKind, number: u32, text: &str) {
        let points = self.map.points(kind);
        let _ = number;
        let name = display_kind(kind);
        let msg = if points == 0 {
            format!("`{text}`: device {name} has 0 points in this CPU configuration")
        } else {
            let last = kind.format(points - 1);
            let last = last.trim_start_matches(kind.name());
            format!("`{text}` is out of range ({name}0-{name}{last})")
        };
        self.err(tok, msg);
    }

    fn indexed(&mut self, kind: IndexedKind, dk: DeviceKind, number: u32, z: u8) -> Box<Indexed> {
        self.computed(kind, dk, number, Some(z))
    }

    /// An operand resolved at run time: index-modified, or a file register `R`,
    /// which addresses the block selected by RSET (ZR = block × 32768 + n).
    fn computed(
        &self,
        kind: IndexedKind,
        dk: DeviceKind,
        number: u32,
        z: Option<u8>,
    ) -> Box<Indexed> {
        let z = z.map_or(Indexed::NONE, |z| self.map.base(DeviceKind::Z) + z as u32);
        if dk == DeviceKind::R {
            return Box::new(Indexed {
                kind,
                base: self.map.base(DeviceKind::ZR),
                number,
                points: self.map.points(DeviceKind::ZR),
                z,
                block: self.map.base(DeviceKind::SD) + 648,
            });
        }
        Box::new(Indexed {
            kind,
            base: self.map.base(dk),
            number,
            points: self.map.points(dk),
            z,
            block: Indexed::NONE,
        })
    }

    fn bit_operand(&mut self, tok: &Token) -> Option<BitArg> {
        let op = self.parse(tok)?;
        match op {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                index,
            } if dev.kind.is_bit() => {
                if dev.number >= self.map.points(dev.kind) {
                    self.range_err(tok, dev.kind, dev.number, &tok.text);
                    return None;
                }
                Some(match index {
                    None => BitArg::Bit(self.map.base(dev.kind) + dev.number),
                    Some(z) => {
                        BitArg::Indexed(self.indexed(IndexedKind::Bit, dev.kind, dev.number, z))
                    }
                })
            }
            Operand::Device {
                dev,
                digits: None,
                bit: Some(b),
                index,
            } => {
                if dev.number >= self.map.points(dev.kind) {
                    self.range_err(tok, dev.kind, dev.number, &tok.text);
                    return None;
                }
                Some(match index {
                    None if dev.kind == DeviceKind::R => BitArg::Indexed(self.computed(
                        IndexedKind::WordBit(b),
                        dev.kind,
                        dev.number,
                        None,
                    )),
                    None => BitArg::WordBit {
                        word: self.map.base(dev.kind) + dev.number,
                        bit: b,
                    },
                    Some(z) => BitArg::Indexed(self.indexed(
                        IndexedKind::WordBit(b),
                        dev.kind,
                        dev.number,
                        z,
                    )),
                })
            }
            Operand::Device {
                dev, digits: None, ..
            } => {
                self.err(
                    tok,
                    format!("`{}` is a word device; a bit operand needs a bit device or a word bit such as `{}.0`", tok.text, tok.text),
                );
                let _ = dev;
                None
            }
            Operand::Device { .. } => {
                self.err(
                    tok,
                    format!(
                        "`{}` is a digit-specified word; a bit operand is needed here",
                        tok.text
                    ),
                );
                None
            }
            Operand::Const(_) => {
                self.err(
                    tok,
                    format!(
                        "constant `{}` cannot be a bit operand; a bit device is needed",
                        tok.text
                    ),
                );
                None
            }
            _ => {
                self.err(
                    tok,
                    format!(
                        "`{}` cannot be a bit operand; a bit device is needed",
                        tok.text
                    ),
                );
                None
            }
        }
    }

    fn bit_dest(&mut self, tok: &Token) -> Option<BitArg> {
        if let Ok(Operand::Device { dev, .. }) = parse_operand(&tok.text) {
            if matches!(
                dev.kind,
                DeviceKind::TS
                    | DeviceKind::TC
                    | DeviceKind::STS
                    | DeviceKind::STC
                    | DeviceKind::CS
                    | DeviceKind::CC
            ) {
                self.err(tok, format!("`{}`: timer and counter contacts and coils are driven by `OUT {}` with a set value", tok.text, tok.text));
                return None;
            }
        }
        self.bit_operand(tok)
    }

    fn edge_relay(&mut self, tok: &Token) -> Option<u32> {
        match self.bit_operand(tok)? {
            BitArg::Bit(b)
                if (self.map.base(DeviceKind::V)
                    ..self.map.base(DeviceKind::V) + self.map.points(DeviceKind::V))
                    .contains(&b) =>
            {
                Some(b)
            }
            _ => {
                self.err(
                    tok,
                    format!("`{}`: EGP/EGF need an edge relay V without index", tok.text),
                );
                None
            }
        }
    }

    /// A word operand read as `num`.
    fn word_src(&mut self, tok: &Token, num: Num) -> Option<WordArg> {
        let op = self.parse(tok)?;
        if let Operand::Const(c) = &op {
            return self.constant(tok, c, num);
        }
        self.word_device(tok, op, num, num.words())
    }

    /// A word operand written as `num`, occupying `words` words.
    fn word_dest(&mut self, tok: &Token, num: Num, words: u32) -> Option<WordArg> {
        let op = self.parse(tok)?;
        if let Operand::Const(_) = op {
            self.err(
                tok,
                format!("constant `{}` cannot be a destination", tok.text),
            );
            return None;
        }
        self.word_device(tok, op, num, words)
    }

    fn constant(&mut self, tok: &Token, c: &Constant, num: Num) -> Option<WordArg> {
        match (c, num) {
            (Constant::Int { value, hex }, Num::I16) => {
                let ok = if *hex {
                    (0..=0xFFFF).contains(value)
                } else {
                    (-32768..=32767).contains(value)
                };
                if !ok {
                    let range = if *hex {
                        "H0-HFFFF"
                    } else {
                        "K-32768 to K32767"
                    };
                    self.err(
                        tok,
                        format!(
                            "constant `{}` does not fit a 16-bit operand ({range})",
                            tok.text
                        ),
                    );
                    return None;
                }
                Some(WordArg::Const(*value as i32 as u32 & 0xFFFF))
            }
            (Constant::Int { value, hex }, Num::I32) => {
                let ok = if *hex {
                    (0..=0xFFFF_FFFF).contains(value)
                } else {
                    (i32::MIN as i64..=i32::MAX as i64).contains(value)
                };
                if !ok {
                    self.err(
                        tok,
                        format!("constant `{}` does not fit a 32-bit operand", tok.text),
                    );
                    return None;
                }
                Some(WordArg::Const(*value as u32))
            }
            (Constant::Real(v), Num::F32) => {
                let f = *v as f32;
                if f.is_infinite() || (*v != 0.0 && f.abs() < f32::MIN_POSITIVE) {
                    self.err(
                        tok,
                        format!(
                            "real constant `{}` is outside the single-precision range",
                            tok.text
                        ),
                    );
                    return None;
                }
                Some(WordArg::Const(f.to_bits()))
            }
            (Constant::Int { .. }, Num::F32) => {
                self.err(
                    tok,
                    format!(
                        "`{}`: a real operand needs an E constant, e.g. E1.5",
                        tok.text
                    ),
                );
                None
            }
            (Constant::Real(_), _) => {
                self.err(
                    tok,
                    format!(
                        "real constant `{}` where a BIN value (K or H) is needed",
                        tok.text
                    ),
                );
                None
            }
            (Constant::Str(_), _) => {
                self.err(
                    tok,
                    format!("string `{}` where a numeric operand is needed", tok.text),
                );
                None
            }
        }
    }

    fn word_device(&mut self, tok: &Token, op: Operand, num: Num, words: u32) -> Option<WordArg> {
        let Operand::Device {
            dev,
            digits,
            bit,
            index,
        } = op
        else {
            self.err(tok, format!("`{}` cannot be a word operand", tok.text));
            return None;
        };
        if bit.is_some() {
            self.err(
                tok,
                format!("`{}` is a bit; a word operand is needed here", tok.text),
            );
            return None;
        }
        if let Some(n) = digits {
            if num == Num::F32 {
                self.err(
                    tok,
                    format!(
                        "`{}`: digit specification cannot hold a real number",
                        tok.text
                    ),
                );
                return None;
            }
            let max = if num == Num::I16 { 4 } else { 8 };
            if n > max {
                self.err(
                    tok,
                    format!(
                        "`{}`: K{n} needs a 32-bit instruction (K1-K{max} here)",
                        tok.text
                    ),
                );
                return None;
            }
            let need = dev.number as u64 + 4 * n as u64;
            if dev.number >= self.map.points(dev.kind) || need > self.map.points(dev.kind) as u64 {
                self.range_err(tok, dev.kind, dev.number, &tok.text);
                return None;
            }
            return Some(match index {
                None => WordArg::Digits {
                    bit: self.map.base(dev.kind) + dev.number,
                    n,
                },
                Some(z) => {
                    WordArg::Indexed(self.indexed(IndexedKind::Digits(n), dev.kind, dev.number, z))
                }
            });
        }
        let kind = dev.word_kind();
        if kind.is_bit() {
            self.err(
                tok,
                format!("`{}` is a bit device; a word operand needs a digit specification such as `K4{}`", tok.text, tok.text),
            );
            return None;
        }
        let points = self.map.points(kind);
        if dev.number >= points {
            self.range_err(tok, kind, dev.number, &tok.text);
            return None;
        }
        if index.is_none() && dev.number as u64 + words as u64 > points as u64 {
            let last = name_of(&dev, kind, dev.number + words - 1);
            self.err(
                tok,
                format!(
                    "`{}`: this operand uses {words} words, up to `{last}`, beyond the last device",
                    tok.text
                ),
            );
            return None;
        }
        Some(match index {
            None if kind == DeviceKind::R => {
                WordArg::Indexed(self.computed(IndexedKind::Word, kind, dev.number, None))
            }
            None => WordArg::Word(self.map.base(kind) + dev.number),
            Some(z) => WordArg::Indexed(self.indexed(IndexedKind::Word, kind, dev.number, z)),
        })
    }

    fn pointer(&mut self, tok: &Token) -> Option<u32> {
        match self.parse(tok)? {
            Operand::Pointer(p) if p <= 4095 => Some(p),
            Operand::Pointer(_) => {
                self.err(
                    tok,
                    format!("pointer `{}` is out of range (P0-P4095)", tok.text),
                );
                None
            }
            _ => {
                self.err(
                    tok,
                    format!("`{}`: a pointer P0-P4095 is needed here", tok.text),
                );
                None
            }
        }
    }

    fn nesting(&mut self, tok: &Token) -> Option<u32> {
        match self.parse(tok)? {
            Operand::Nesting(n) if n <= 14 => Some(n),
            _ => {
                self.err(
                    tok,
                    format!("`{}`: a nesting number N0-N14 is needed here", tok.text),
                );
                None
            }
        }
    }

    fn finish(mut self, src: &Source) -> Result<Program, Diagnostics> {
        let last = src
            .items
            .last()
            .map(|it| match it {
                SourceItem::Label(t) => t.clone(),
                SourceItem::Instr(i) => i.mnemonic.clone(),
            })
            .unwrap_or(Token {
                text: String::new(),
                line: 1,
                col: 1,
            });
        if self.end_seen.is_none() {
            self.err(
                &last,
                "missing END instruction (MISSING END INS., error 4010)",
            );
        }
        for (level, tok) in std::mem::take(&mut self.mc_open) {
            self.err(&tok, format!("MC N{level} without a matching MCR N{level}"));
        }
        for tok in std::mem::take(&mut self.for_open) {
            self.err(&tok, "FOR without NEXT");
        }
        for (at, p, tok) in std::mem::take(&mut self.fixups) {
            match self.labels.get(&p) {
                Some(&(target, _)) => match &mut self.ops[at] {
                    Op::Cj { target: t, .. } | Op::Scj { target: t, .. } | Op::Call(t) => {
                        *t = target
                    }
                    Op::Break(b) => b.1 = target,
                    _ => {}
                },
                None if p >= self.common_from && matches!(self.ops[at], Op::Call(_)) => {
                    self.ops[at] = Op::CallCommon(p);
                }
                None if p >= self.common_from => self.err(
                    &tok,
                    format!("`P{p}` is a common pointer of another program: jumps cannot leave their file (only CALL can)"),
                ),
                None => self.err(&tok, format!("undefined pointer `P{p}`")),
            }
        }
        if !self.diags.is_empty() {
            self.diags.sort_by_key(|d| (d.line, d.col));
            return Err(Diagnostics(self.diags));
        }
        Ok(Program {
            file: self.file.to_string(),
            ops: self.ops,
            op_step: self.op_step,
            op_line: self.op_line,
            edge_slots: self.edge_slots,
            bit_len: self.map.bit_len(),
            word_len: self.map.word_len(),
            state_words: self.state_words,
            interrupts: {
                let mut v: Vec<(u8, u32)> = self
                    .interrupts
                    .iter()
                    .map(|(n, (at, _))| (*n as u8, *at))
                    .collect();
                v.sort_unstable();
                v
            },
            ext: self.ext,
            prog_names: self.prog_names,
            common_labels: self
                .labels
                .iter()
                .filter(|(n, _)| **n >= self.common_from)
                .map(|(n, (at, _))| (*n, *at))
                .collect(),
            steps: self.step,
        })
    }
}

/// A word-device block operand whose length is known only at run time (BMOV,
/// FMOV, SUM …): the first word and the flat index one past the device's last
/// point, which a block may not cross (4101).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    pub start: WordArg,
    /// Flat index one past the last point of the device kind; for an index-modified
    /// start the range is in its [`Indexed`].
    pub limit: u32,
}

/// A bit-device block operand whose length is known only at run time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BitBlock {
    pub start: BitArg,
    /// Flat bit index one past the last point of the device kind.
    pub limit: u32,
}

/// Operand access for a family module compiling one instruction. Every method
/// reports its own diagnostic (with the operand's position) and returns `None`
/// on error.
pub struct Args<'c, 'a> {
    c: &'c mut Compiler<'a>,
    i: &'c SourceInstr,
    m: &'c str,
}

impl Args<'_, '_> {
    /// The mnemonic as written, upper case (with its `P` suffix, if any).
    pub fn mnemonic(&self) -> &str {
        self.m
    }

    pub fn len(&self) -> usize {
        self.i.operands.len()
    }

    pub fn is_empty(&self) -> bool {
        self.i.operands.is_empty()
    }

    /// Checks the operand count; reports and returns false otherwise.
    pub fn count(&mut self, allowed: &[usize]) -> bool {
        self.c.count(self.i, self.m, allowed)
    }

    /// The text of operand `k`.
    pub fn text(&self, k: usize) -> &str {
        &self.i.operands[k].text
    }

    /// Operand `k` as parsed syntax (for constants and special operands).
    pub fn operand(&mut self, k: usize) -> Option<Operand> {
        self.c.parse(&self.i.operands[k])
    }

    pub fn word_src(&mut self, k: usize, num: Num) -> Option<WordArg> {
        self.c.word_src(&self.i.operands[k], num)
    }

    /// A destination of `words` words read or written as `num`.
    pub fn word_dest(&mut self, k: usize, num: Num, words: u32) -> Option<WordArg> {
        self.c.word_dest(&self.i.operands[k], num, words)
    }

    pub fn bit_src(&mut self, k: usize) -> Option<BitArg> {
        self.c.bit_operand(&self.i.operands[k])
    }

    pub fn bit_dest(&mut self, k: usize) -> Option<BitArg> {
        self.c.bit_dest(&self.i.operands[k])
    }

    /// A word device starting a block (no constants, no digit specification).
    pub fn block(&mut self, k: usize) -> Option<Block> {
        let tok = &self.i.operands[k];
        let op = self.c.parse(tok)?;
        let kind = match &op {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                ..
            } if !dev.word_kind().is_bit() => dev.word_kind(),
            _ => {
                self.c
                    .err(tok, format!("`{}`: a word device is needed here", tok.text));
                return None;
            }
        };
        let start = self.c.word_device(tok, op, Num::I16, 1)?;
        Some(Block {
            start,
            limit: self.c.map.base(kind) + self.c.map.points(kind),
        })
    }

    /// A bit device starting a block of bits (BKRST, SFT, BSFR …).
    pub fn bit_block(&mut self, k: usize) -> Option<BitBlock> {
        let tok = &self.i.operands[k];
        let kind = match self.c.parse(tok)? {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                ..
            } if dev.kind.is_bit() => dev.kind,
            _ => {
                self.c
                    .err(tok, format!("`{}`: a bit device is needed here", tok.text));
                return None;
            }
        };
        let start = self.c.bit_operand(tok)?;
        Some(BitBlock {
            start,
            limit: self.c.map.base(kind) + self.c.map.points(kind),
        })
    }

    /// Reports a diagnostic at operand `k` (or at the mnemonic when `k` is out of
    /// range).
    pub fn error(&mut self, k: usize, msg: impl Into<String>) {
        let tok = self.i.operands.get(k).unwrap_or(&self.i.mnemonic).clone();
        self.c.err(&tok, msg);
    }

    /// Allocates `n` hidden state words for this instruction; returns the first index.
    pub fn state_words(&mut self, n: u32) -> u32 {
        self.c.state_words += n;
        self.c.state_words - n
    }

    pub fn map(&self) -> &DeviceMap {
        self.c.map
    }
}

/// Remainder slot of timer `n`: T first, then ST.
pub(crate) fn timer_slot(map: &DeviceMap, retentive: bool, n: u32) -> u32 {
    if retentive {
        map.points(DeviceKind::TS) + n
    } else {
        n
    }
}

fn display_kind(k: DeviceKind) -> &'static str {
    match k {
        DeviceKind::TS | DeviceKind::TN => "T",
        DeviceKind::STS | DeviceKind::STN => "ST",
        DeviceKind::CS | DeviceKind::CN => "C",
        k => k.name(),
    }
}

fn name_of(dev: &DeviceName, kind: DeviceKind, n: u32) -> String {
    if dev.generic {
        format!("{}{}", display_kind(kind), n)
    } else {
        kind.format(n)
    }
}

fn split_join(m: &str) -> (Join, &str) {
    if let Some(r) = m.strip_prefix("LD") {
        (Join::Load, r)
    } else if let Some(r) = m.strip_prefix("AN") {
        // AND, ANDP, ANDF, ANI
        (Join::And, r.strip_prefix('D').unwrap_or(r))
    } else {
        (Join::Or, m.strip_prefix("OR").unwrap_or(m))
    }
}

/// `LD$=`, `AND$<>`, `OR$>` … → (join, operator).
fn parse_str_compare(m: &str) -> Option<(Join, CmpOp)> {
    let (join, rest) = if let Some(r) = m.strip_prefix("LD$") {
        (Join::Load, r)
    } else if let Some(r) = m.strip_prefix("AND$") {
        (Join::And, r)
    } else {
        (Join::Or, m.strip_prefix("OR$")?)
    };
    let op = match rest {
        "=" => CmpOp::Eq,
        "<>" => CmpOp::Ne,
        ">" => CmpOp::Gt,
        "<=" => CmpOp::Le,
        "<" => CmpOp::Lt,
        ">=" => CmpOp::Ge,
        _ => return None,
    };
    Some((join, op))
}

/// `LD=`, `ANDD<>`, `ORE>=` … → (join, number type, operator).
fn parse_compare(m: &str) -> Option<(Join, Num, CmpOp)> {
    let (join, rest) = if let Some(r) = m.strip_prefix("LD") {
        (Join::Load, r)
    } else if let Some(r) = m.strip_prefix("AND") {
        (Join::And, r)
    } else {
        (Join::Or, m.strip_prefix("OR")?)
    };
    let (num, rest) = match rest.as_bytes().first()? {
        b'D' => (Num::I32, &rest[1..]),
        b'E' => (Num::F32, &rest[1..]),
        _ => (Num::I16, rest),
    };
    let op = match rest {
        "=" => CmpOp::Eq,
        "<>" => CmpOp::Ne,
        ">" => CmpOp::Gt,
        "<=" => CmpOp::Le,
        "<" => CmpOp::Lt,
        ">=" => CmpOp::Ge,
        _ => return None,
    };
    Some((join, num, op))
}
