//! Compiles a [`Source`] into a [`Program`]: looks up each mnemonic, checks and
//! resolves its operands against the device configuration, checks the ladder
//! structure (blocks, MPS, MC/MCR, FOR/NEXT, pointers, END) and reports every
//! error of the file with its line and column.

use std::collections::HashMap;

use super::dialect::Dialect;
use super::isa::{self, Found, Isa, Kind, Use};
use super::source::{Diagnostic, Diagnostics, Source, SourceInstr, SourceItem, Token};
use softplc_ir::device::{DeviceConfig, DeviceMap};
use softplc_ir::listing::{Entry, Held, Listed, Listing, LoopUse, Role};
use softplc_ir::ops::*;
use softplc_ir::rack::Rack;

pub use super::args::Args;
pub use softplc_ir::ops::{BitBlock, Block, MAX_NESTING};

/// MPS nesting limit and block (LD … ANB/ORB) nesting limit.
pub const MAX_MPS: u32 = 16;
pub const MAX_BLOCKS: u32 = 16;

/// Compiles a parsed file for a CPU with the given device points, in
/// `dialect`, with the "common pointer" parameter: pointers from
/// `common_from` up to P4095 are common (004 §10.9.2); a CALL of one this file
/// does not define is linked to the program that does when the CPU is built.
pub fn compile(
    src: &Source,
    devices: &DeviceConfig,
    dialect: &Dialect,
    common_from: Option<u32>,
) -> Result<Program, Diagnostics> {
    let map = DeviceMap::new(devices);
    let mut c = Compiler::new(&src.file, &map, dialect);
    c.common_from = common_from.unwrap_or(u32::MAX);
    for item in &src.items {
        match item {
            SourceItem::Label(tok) => c.label(tok),
            SourceItem::Instr(i) => c.instr(i),
        }
    }
    c.finish(src)
}

/// The listing of a source as [`compile`] records it (see
/// [`Program::listing`]), without compiling: the ladder of a file that does
/// not load draws from it.
pub fn listing(src: &Source, dialect: &Dialect) -> Listing {
    let mut out = Listing::default();
    for item in &src.items {
        match item {
            SourceItem::Label(tok) => out.entries.push(label_entry(tok)),
            SourceItem::Instr(i) => record(&mut out, dialect.isa, i),
        }
    }
    out
}

fn label_entry(tok: &Token) -> Entry {
    Entry::Label {
        text: tok.text.clone(),
        line: tok.line,
    }
}

/// Adds an instruction to a listing (see [`listed`]).
fn record(out: &mut Listing, isa: &Isa, i: &SourceInstr) {
    let (entry, owned) = listed(isa, i);
    out.entries.push(Entry::Instr(entry));
    out.loops.extend(owned);
}

/// An instruction as a listing records it: its definition's ladder role
/// (an unknown mnemonic is a box, as the compiler's recovery counts it an
/// output), its text as written and the loop memory it owns.
pub fn listed(isa: &Isa, i: &SourceInstr) -> (Listed, Option<LoopUse>) {
    let def = match isa.lookup(&i.mnemonic.text.to_ascii_uppercase()) {
        Found::Def(d, _) | Found::WrongPulse(d) | Found::NoPulse(d) => Some(d),
        Found::Unknown => None,
    };
    let owned = def.and_then(|d| d.loop_memory).and_then(|(k, memory)| {
        Some(LoopUse {
            mnemonic: i.mnemonic.text.clone(),
            block: i.operands.get(k)?.text.clone(),
            line: i.mnemonic.line,
            memory,
        })
    });
    let entry = Listed {
        role: def.map_or(Role::Box, |d| d.role),
        mnemonic: i.mnemonic.text.clone(),
        operands: i.operands.iter().map(|t| t.text.clone()).collect(),
        line: i.mnemonic.line,
        held: Default::default(),
    };
    (entry, owned)
}

/// The compiler's state while it compiles one file. Instruction lowerings
/// ([`isa::LowerFn`]) work on it directly.
pub struct Compiler<'a> {
    pub file: &'a str,
    pub map: &'a DeviceMap,
    /// The dialect being compiled (instruction set, devices, flags).
    pub dialect: &'a Dialect,
    /// CPU-wide state words the instructions need (see `Program::shared_words`).
    pub shared_words: u32,
    pub ops: Vec<Op>,
    pub op_step: Vec<u32>,
    pub op_line: Vec<u32>,
    pub diags: Vec<Diagnostic>,
    pub labels: HashMap<u32, (u32, u32)>,
    pub fixups: Vec<(usize, u32, Token)>,
    pub edge_slots: u32,
    pub state_words: u32,
    pub ext: Vec<Box<dyn softplc_ir::instr::Instr>>,
    pub step: u32,
    pub cur_step: u32,
    pub cur_line: u32,
    /// A rung has been started (an LD seen since the last label or standalone instruction).
    pub has_rung: bool,
    /// The last instruction was an output: the next LD starts a new rung.
    pub after_output: bool,
    /// Open blocks awaiting ANB/ORB.
    pub depth: u32,
    /// Open MPS levels.
    /// Open MPS instructions, for MPP pairing and error positions.
    pub mps: Vec<Token>,
    pub mc_open: Vec<(u32, Token)>,
    pub for_open: Vec<Token>,
    pub end_seen: Option<Token>,
    pub after_end_reported: bool,
    pub fend_seen: bool,
    /// First common pointer number (`u32::MAX`: none).
    pub common_from: u32,
    /// Interrupt pointers: number → (op index, line).
    pub interrupts: HashMap<u32, (u32, u32)>,
    /// Device operands resolved so far (`Program::used_devices`).
    pub used_devices: Vec<(String, softplc_ir::ops::DeviceUse)>,
    /// The instructions and labels seen so far (`Program::listing`).
    pub listing: Listing,
    /// An instruction so far may write X (`Program::may_write_x`).
    pub may_write_x: bool,
}

impl<'a> Compiler<'a> {
    pub fn new(file: &'a str, map: &'a DeviceMap, dialect: &'a Dialect) -> Self {
        Compiler {
            file,
            map,
            dialect,
            shared_words: 0,
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
            common_from: u32::MAX,
            interrupts: HashMap::new(),
            used_devices: Vec::new(),
            listing: Listing::default(),
            may_write_x: false,
        }
    }

    /// Records an instruction in the listing ([`Program::listing`]); every
    /// driver calls it once per source instruction, in source order.
    pub fn record(&mut self, i: &SourceInstr) {
        record(&mut self.listing, self.dialect.isa, i);
        if !self.may_write_x {
            self.may_write_x = self.may_write_x_by(i);
        }
        // Its state begins here; `finish` ends it where the next one's begins.
        if let Some(Entry::Instr(l)) = self.listing.entries.last_mut() {
            let step = i.step.unwrap_or(self.step);
            l.held = Held {
                edges: self.edge_slots..self.edge_slots,
                words: self.state_words..self.state_words,
                steps: step..step,
            };
        }
    }

    /// Whether instruction `i` (just recorded) may write X: it names an X
    /// device (plain, digit-specified, index-modified or direct) in any
    /// operand and is no contact. Contacts only read their operands; every
    /// other role — coils, boxes, CALL arguments, standalone instructions —
    /// counts as a writer, whatever it does with the operand.
    fn may_write_x_by(&self, i: &SourceInstr) -> bool {
        use softplc_ir::device::{parse_operand_in, DeviceKind, Operand};
        let contact = matches!(
            self.listing.entries.last(),
            Some(Entry::Instr(Listed {
                role: Role::Contact { .. },
                ..
            }))
        );
        !contact
            && i.operands.iter().any(|t| {
                matches!(
                    parse_operand_in(self.dialect.devices, &t.text),
                    Ok(Operand::Device { dev, .. }) if dev.kind == DeviceKind::X
                )
            })
    }

    /// Records a pointer label in the listing.
    pub fn record_label(&mut self, tok: &Token) {
        self.listing.entries.push(label_entry(tok));
    }

    pub fn err(&mut self, tok: &Token, msg: impl Into<String>) {
        self.diags.push(Diagnostic::at(self.file, tok, msg));
    }

    pub fn emit(&mut self, op: Op) -> usize {
        self.ops.push(op);
        self.op_step.push(self.cur_step);
        self.op_line.push(self.cur_line);
        self.ops.len() - 1
    }

    pub fn slot(&mut self) -> u32 {
        self.edge_slots += 1;
        self.edge_slots - 1
    }

    pub fn label(&mut self, tok: &Token) {
        self.record_label(tok);
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

    /// An interrupt pointer `In` (004 §4.1.3, App. 3): it must follow FEND,
    /// each number once. I28-I31 and I32-I39 (not I33, I37) are the CPU's
    /// own; any other only when a slot of the rack raises it — the rack is
    /// the `Arc<Rack>` of the dialect's settings (none: no slot), so that no
    /// pointer whose cause cannot occur is accepted in silence.
    pub fn interrupt_label(&mut self, tok: &Token, text: &str, n: u32) {
        if n > 255 {
            return self.err(
                tok,
                format!("interrupt pointer `{text}` is out of range (I0-I255)"),
            );
        }
        if matches!(n, 33 | 37 | 40..=49) {
            return self.err(
                tok,
                format!("interrupt pointer `{text}` is not used by the CPU (I33, I37 and I40-I49 have no interrupt cause)"),
            );
        }
        // I28-I31 are the CPU's timers and I32-I39 its errors; a module's
        // pointer only when a slot of the rack raises it (004 App. 3).
        let rack = self.dialect.settings.get::<std::sync::Arc<Rack>>();
        if !(28..=39).contains(&n) && !rack.is_some_and(|r| r.raises(n)) {
            return self.err(
                tok,
                format!(
                    "interrupt pointer {text}: no slot raises it (an interrupt module (QI60) raises I0-I15; \
                     intelligent modules raise I50-I255 as their slot's interrupts = {{ 0 = \"I50\" }} sets)"
                ),
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
        self.record(i);
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
        let errors = self.diags.len();
        // A misspelt form counts its steps as an application instruction.
        let unknown_steps = isa::Steps::Operands.count(&i.operands);
        let (steps, class) = match self.dialect.isa.lookup(&m) {
            Found::Def(def, pulse) => {
                self.compile_def(&Use {
                    def,
                    instr: i,
                    m: &m,
                    pulse,
                });
                (def.steps.count(&i.operands), Some(def.class))
            }
            Found::NoPulse(def) => {
                let name = def.name;
                self.err(&i.mnemonic, format!("`{m}`: {name} has no pulse form"));
                (unknown_steps, Some(def.class))
            }
            Found::WrongPulse(def) => {
                let base = &def.name[2..];
                self.err(
                    &i.mnemonic,
                    format!(
                        "unknown instruction `{m}`: the pulse form of `S.{base}` is `SP.{base}`"
                    ),
                );
                (unknown_steps, Some(def.class))
            }
            Found::Unknown => {
                self.err(&i.mnemonic, format!("unknown instruction `{m}`"));
                (unknown_steps, None)
            }
        };
        if self.diags.len() > errors {
            self.recover(class);
        }
        self.step = self.cur_step + steps;
    }

    fn compile_def(&mut self, u: &Use<'_>) {
        match u.def.kind {
            Kind::Lower(lower) => lower(self, u),
            Kind::Rejected(reason) => {
                let m = u.m;
                self.err(
                    &u.instr.mnemonic,
                    format!("unsupported instruction `{m}`: {reason}"),
                );
            }
            Kind::Instr(compile) => self.family(u.instr, u.m, u.def.drive, compile, u.pulse),
        }
    }

    /// A family instruction (any dialect): the rung's output check, its
    /// [`Instr`] compiled, and the op its drive and spelling call for (a
    /// pulse form or [`isa::Drive::OnRise`] behind the pulse gate).
    pub fn family(
        &mut self,
        i: &SourceInstr,
        m: &str,
        drive: isa::Drive,
        compile: isa::CompileFn,
        pulse: bool,
    ) {
        if !self.output(i, m) {
            return;
        }
        let errors = self.diags.len();
        let mut args = Args::new(self, i, m);
        match compile(&mut args) {
            Some(x) => {
                let at = self.ext.len() as u32;
                self.ext.push(x);
                match drive {
                    isa::Drive::WhenOn => self.pulsed(pulse, Op::Ext(at)),
                    isa::Drive::Always => self.pulsed(pulse, Op::ExtAlways(at)),
                    isa::Drive::OnRise => self.pulsed(true, Op::Ext(at)),
                }
            }
            // An instruction is never dropped in silence: a compile function
            // that gives no instruction has said why, or the load fails here.
            None if self.diags.len() == errors => self.err(
                &i.mnemonic,
                format!(
                    "`{m}` compiled to nothing without a reason (a softplc bug: please report it)"
                ),
            ),
            None => {}
        }
    }

    pub fn finish(mut self, src: &Source) -> Result<Program, Diagnostics> {
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
                    Op::CallArgs(c) => c.callee = Callee::Here(target),
                    _ => {}
                },
                None if p >= self.common_from && matches!(self.ops[at], Op::Call(_)) => {
                    self.ops[at] = Op::CallCommon(p);
                }
                None if p >= self.common_from && matches!(self.ops[at], Op::CallArgs(_)) => {
                    if let Op::CallArgs(c) = &mut self.ops[at] {
                        c.callee = Callee::Common(p);
                    }
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
        self.listing
            .close_held(self.edge_slots, self.state_words, self.step);
        Ok(Program {
            file: self.file.to_string(),
            sources: Vec::new(),
            globals: Vec::new(),
            used_devices: {
                let mut u = self.used_devices;
                u.sort();
                u.dedup();
                u
            },
            ops: self.ops,
            op_step: self.op_step,
            op_line: self.op_line,
            edge_slots: self.edge_slots,
            bit_len: self.map.bit_len(),
            word_len: self.map.word_len(),
            state_words: self.state_words,
            shared_words: self.shared_words,
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
            local_labels: {
                let mut v: Vec<(u32, u32)> = self
                    .labels
                    .iter()
                    .filter(|(n, _)| **n < self.common_from)
                    .map(|(n, (at, _))| (*n, *at))
                    .collect();
                v.sort_unstable();
                v
            },
            common_labels: self
                .labels
                .iter()
                .filter(|(n, _)| **n >= self.common_from)
                .map(|(n, (at, _))| (*n, *at))
                .collect(),
            steps: self.step,
            listing: self.listing,
            may_write_x: self.may_write_x,
        })
    }
}
