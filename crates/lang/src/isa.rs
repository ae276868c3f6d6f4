//! The instruction set as data: one [`Def`] per mnemonic, declared in the
//! instruction's chapter file next to its behaviour and registered in
//! a dialect's registry ([`Isa`]).
//!
//! A definition carries everything the rest of softplc asks about an
//! instruction: its name and pulse form, its rung class (what it does to the
//! ladder structure) and ladder role (what a tool draws: [`Role`]), the
//! control-loop memory it owns, its drive (runs while the condition is ON, or
//! on every execution with the condition as input), its step rule, its manual
//! citation and how it compiles — or why it is rejected. The compiler, the
//! step counter, the error recovery, the program's listing (read by the
//! doors) and COMPATIBILITY.md (see [`compat_markdown`]) all read these
//! definitions; nothing else lists mnemonics.

use std::collections::HashMap;

use super::compile::{Args, Compiler};
use super::source::{SourceInstr, Token};
use softplc_ir::instr::Instr;
use softplc_ir::ops::Join;

pub use softplc_ir::listing::{CoilRole, Link, LoopMemory, Role, Test};

/// How an instruction's pulse (rising-edge) form is spelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pulse {
    /// No pulse form.
    None,
    /// A trailing `P`: `MOVP`, `BMOVP`.
    Suffix,
    /// `SP.` for `S.` instructions: `SP.PIDCONT` (001 §8.1).
    SPrefix,
}

/// What an instruction does to the ladder structure (PM §3: contacts, connection
/// instructions, outputs and instructions written on the bus bar alone).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// Reads a condition: LD starts a rung or block, AND/OR join it.
    Contact,
    /// Works on the operation result or the stacks (ANB, MPS, INV, MEP …).
    Connection,
    /// Driven by the rung's condition (coils, application instructions).
    Output,
    /// Takes no condition (END, FEND, MCR, FOR, NEXT, RET, IRET, JMP).
    Standalone,
}

/// The rung class a ladder role implies.
pub const fn class_of(role: Role) -> Class {
    match role {
        Role::Contact { .. } => Class::Contact,
        Role::Link(_) => Class::Connection,
        Role::Coil(_) | Role::Box => Class::Output,
        Role::Standalone | Role::Step | Role::StepsEnd => Class::Standalone,
    }
}

/// When an instruction's code runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drive {
    /// Only while the condition is ON (for a pulse form, on its rising edge).
    WhenOn,
    /// At every execution: [`Instr::exec`] while the condition is ON,
    /// [`Instr::off`] while it is OFF (STMR, ROTC, tracking instructions).
    Always,
    /// Only on the rising edge of the condition, whatever the spelling: an
    /// instruction the manual defines as edge-triggered (APLC EROMWR), on the
    /// same pulse gate as the pulse forms.
    OnRise,
}

/// How many steps an instruction occupies, for error reports of `.il` files
/// (a GX Works2 CSV export carries the CPU's own step numbers).
///
/// Decision: a list file carries no step numbers, so they are counted with the
/// QnH rule of thumb (COMPATIBILITY.md "Step numbers").
#[derive(Clone, Copy, Debug)]
pub enum Steps {
    /// 1 + the number of operands (application instructions).
    Operands,
    /// 1, plus 1 for each index-modified, digit-specified or word-bit operand
    /// (contacts, coils, connection instructions).
    Basic,
    /// A fixed count.
    Fixed(u32),
    /// A rule of its own (OUT T/C, RST of words and timers).
    Rule(fn(&[Token]) -> u32),
}

impl Steps {
    pub fn count(self, operands: &[Token]) -> u32 {
        match self {
            Steps::Operands => 1 + operands.len() as u32,
            Steps::Basic => basic_steps(operands),
            Steps::Fixed(n) => n,
            Steps::Rule(f) => f(operands),
        }
    }
}

/// The [`Steps::Basic`] rule.
pub fn basic_steps(operands: &[Token]) -> u32 {
    let extended = |t: &Token| {
        let u = t.text.to_ascii_uppercase();
        u.contains('.') && !u.starts_with('E')
            || u.starts_with('K') && u.len() > 2 && u.as_bytes()[2].is_ascii_alphabetic()
            || u.chars().skip(1).any(|c| c == 'Z') && !u.starts_with("ZR")
    };
    1 + operands.iter().filter(|t| extended(t)).count() as u32
}

/// Compiles a family instruction to an [`Instr`]; `None` when a diagnostic was
/// reported through [`Args`].
pub type CompileFn = fn(&mut Args<'_, '_>) -> Option<Box<dyn Instr>>;

/// Lowers an instruction the compiler expands itself (contacts, coils, jumps,
/// master control …) into ladder ops; it checks its own operands and rung class.
pub type LowerFn = fn(&mut Compiler<'_>, &Use<'_>);

/// One use of an instruction in a program, as the compiler hands it to a
/// [`LowerFn`].
pub struct Use<'a> {
    pub def: &'static Def,
    pub instr: &'a SourceInstr,
    /// The mnemonic as written, upper case.
    pub m: &'a str,
    /// The pulse form was written.
    pub pulse: bool,
}

/// How an instruction compiles.
#[derive(Clone, Copy)]
pub enum Kind {
    /// A family instruction: compiled by its function into an [`Instr`], run
    /// through `Op::Ext` as its [`Drive`] says ([`Compiler::family`]).
    Instr(CompileFn),
    /// Expanded into ladder ops by the compiler.
    Lower(LowerFn),
    /// Known but not implemented: rejected at load with this reason.
    Rejected(&'static str),
}

/// A row of COMPATIBILITY.md: the family, the manual reference and notes shared
/// by the definitions that point to it.
#[derive(Debug)]
pub struct Doc {
    pub family: &'static str,
    pub cite: &'static str,
    pub notes: &'static str,
}

/// The definition of one instruction.
#[derive(Clone, Copy)]
pub struct Def {
    pub name: &'static str,
    pub pulse: Pulse,
    pub class: Class,
    /// What it is on the ladder, for the tools that show a program; always
    /// of its `class` (see [`class_of`]).
    pub role: Role,
    /// The control-loop memory it owns: (operand index, declaration).
    pub loop_memory: Option<(usize, &'static LoopMemory)>,
    pub drive: Drive,
    pub steps: Steps,
    pub kind: Kind,
    /// Family, manual section and notes (`None` for rejected instructions).
    pub doc: Option<&'static Doc>,
}

impl std::fmt::Debug for Def {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Def")
            .field("name", &self.name)
            .field("pulse", &self.pulse)
            .field("class", &self.class)
            .field("role", &self.role)
            .field("drive", &self.drive)
            .finish_non_exhaustive()
    }
}

impl Def {
    /// An application instruction of a family: an output with a `P` form,
    /// 1 + operands steps, drawn as a box.
    pub const fn app(name: &'static str, doc: &'static Doc, compile: CompileFn) -> Def {
        Def {
            name,
            pulse: Pulse::Suffix,
            class: Class::Output,
            role: Role::Box,
            loop_memory: None,
            drive: Drive::WhenOn,
            steps: Steps::Operands,
            kind: Kind::Instr(compile),
            doc: Some(doc),
        }
    }

    /// An output (a box) or a standalone instruction the compiler lowers
    /// itself. Contacts, connections and coils say what they are on the
    /// ladder: [`Def::contact`], [`Def::link`], [`Def::coil`].
    pub const fn lower(name: &'static str, class: Class, doc: &'static Doc, f: LowerFn) -> Def {
        let role = match class {
            Class::Output => Role::Box,
            Class::Standalone => Role::Standalone,
            Class::Contact | Class::Connection => {
                panic!("a contact or connection is declared with Def::contact or Def::link")
            }
        };
        Def::lowered(name, role, doc, f)
    }

    /// A contact the compiler lowers: how it joins the rung and what it tests.
    pub const fn contact(
        name: &'static str,
        join: Join,
        test: Test,
        doc: &'static Doc,
        f: LowerFn,
    ) -> Def {
        Def::lowered(name, Role::Contact { join, test }, doc, f)
    }

    /// A connection instruction the compiler lowers.
    pub const fn link(name: &'static str, link: Link, doc: &'static Doc, f: LowerFn) -> Def {
        Def::lowered(name, Role::Link(link), doc, f)
    }

    /// A coil the compiler lowers.
    pub const fn coil(name: &'static str, coil: CoilRole, doc: &'static Doc, f: LowerFn) -> Def {
        Def::lowered(name, Role::Coil(coil), doc, f)
    }

    const fn lowered(name: &'static str, role: Role, doc: &'static Doc, f: LowerFn) -> Def {
        Def {
            name,
            pulse: Pulse::None,
            class: class_of(role),
            role,
            loop_memory: None,
            drive: Drive::WhenOn,
            steps: Steps::Operands,
            kind: Kind::Lower(f),
            doc: Some(doc),
        }
    }

    /// A known instruction softplc rejects, with the reason (its `P` form too).
    pub const fn rejected(name: &'static str, reason: &'static str) -> Def {
        Def {
            name,
            pulse: Pulse::Suffix,
            class: Class::Output,
            role: Role::Box,
            loop_memory: None,
            drive: Drive::WhenOn,
            steps: Steps::Operands,
            kind: Kind::Rejected(reason),
            doc: None,
        }
    }

    /// Its ladder role is `role` (an SFC step, the end of the SFC section),
    /// which must be of its class.
    pub const fn role(mut self, role: Role) -> Def {
        assert!(
            class_of(role) as u8 == self.class as u8,
            "a definition's role is of its rung class"
        );
        self.role = role;
        self
    }

    /// It owns control-loop memory: the block at operand `operand` (0-based)
    /// is `memory` (faceplates and OPC UA read the loops from it).
    pub const fn loop_memory(mut self, operand: usize, memory: &'static LoopMemory) -> Def {
        self.loop_memory = Some((operand, memory));
        self
    }

    pub const fn pulse(mut self, p: Pulse) -> Def {
        self.pulse = p;
        self
    }

    pub const fn no_pulse(self) -> Def {
        self.pulse(Pulse::None)
    }

    pub const fn steps(mut self, s: Steps) -> Def {
        self.steps = s;
        self
    }

    /// Runs at every execution (see [`Drive::Always`]); no pulse form.
    pub const fn always(mut self) -> Def {
        self.drive = Drive::Always;
        self.pulse = Pulse::None;
        self
    }

    /// Runs on the rising edge of its condition (see [`Drive::OnRise`]); no
    /// pulse form.
    pub const fn on_rise(mut self) -> Def {
        self.drive = Drive::OnRise;
        self.pulse = Pulse::None;
        self
    }

    pub fn is_implemented(&self) -> bool {
        !matches!(self.kind, Kind::Rejected(_))
    }
}

/// An instruction set: a dialect's definitions, indexed by name.
pub struct Isa {
    defs: Vec<&'static [Def]>,
    index: HashMap<&'static str, &'static Def>,
}

impl Isa {
    /// Indexes the definitions (a dialect's families, in registry order). A name
    /// defined twice is a programming error of the dialect.
    pub fn new(defs: &[&'static [Def]]) -> Isa {
        let mut isa = Isa {
            defs: Vec::new(),
            index: HashMap::new(),
        };
        for family in defs {
            isa.add(family);
        }
        isa
    }

    fn add(&mut self, family: &'static [Def]) {
        for d in family {
            let prev = self.index.insert(d.name, d);
            assert!(prev.is_none(), "instruction {} defined twice", d.name);
        }
        self.defs.push(family);
    }

    /// The set plus `foreign` families (instructions of another CPU model of
    /// the dialect, e.g. the process CPU's), each rejected at load with
    /// `reason`, so a program using one learns which model it needs.
    pub fn rejecting(mut self, foreign: &[&'static [Def]], reason: &'static str) -> Isa {
        for family in foreign {
            // Keeps the class, so a rejected contact leaves the rung as a
            // contact would (no second diagnostic at the next ANB or OUT), and
            // is still the same instruction to a tool that shows the program.
            let rejected: Vec<Def> = family
                .iter()
                .map(|d| Def {
                    class: d.class,
                    role: d.role,
                    loop_memory: d.loop_memory,
                    ..Def::rejected(d.name, reason).pulse(d.pulse)
                })
                .collect();
            // Built once per dialect (in a `LazyLock`), so leaking is bounded.
            self.add(Box::leak(rejected.into_boxed_slice()));
        }
        self
    }

    /// All definitions, in registry order.
    pub fn all(&self) -> impl Iterator<Item = &'static Def> + '_ {
        self.defs.iter().flat_map(|f| f.iter())
    }

    fn get(&self, name: &str) -> Option<&'static Def> {
        self.index.get(name).copied()
    }

    /// Looks up a mnemonic as written: the plain name, the `P` suffix form or
    /// the `SP.` prefix form.
    pub fn lookup(&self, m: &str) -> Found {
        if let Some(d) = self.get(m) {
            return Found::Def(d, false);
        }
        if let Some(d) = m.strip_suffix('P').and_then(|b| self.get(b)) {
            return match d.pulse {
                Pulse::Suffix => Found::Def(d, true),
                Pulse::SPrefix => Found::WrongPulse(d),
                Pulse::None => Found::NoPulse(d),
            };
        }
        if let Some(rest) = m.strip_prefix("SP.") {
            if let Some(d) = self.get(&format!("S.{rest}")) {
                return match d.pulse {
                    Pulse::SPrefix => Found::Def(d, true),
                    _ => Found::NoPulse(d),
                };
            }
        }
        Found::Unknown
    }
}

impl std::fmt::Debug for Isa {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Isa({} instructions)", self.all().count())
    }
}

/// What a written mnemonic (upper case) names.
pub enum Found {
    /// The definition, and whether its pulse form was written.
    Def(&'static Def, bool),
    /// `S.xxxP`: the pulse form of `S.xxx` is `SP.xxx`.
    WrongPulse(&'static Def),
    /// A `P` form of an instruction that has none.
    NoPulse(&'static Def),
    Unknown,
}

/// The generated part of COMPATIBILITY.md: the "Implemented" and "Rejected at
/// load" tables, from the definitions (`tests/compat.rs` keeps the file current).
pub fn compat_markdown(isa: &Isa) -> String {
    let mut out = implemented_table(isa);
    out += "\n## Rejected at load\n\nEach of these gives `unsupported instruction`, with the reason shown here, at\nthe mnemonic's line and column.\n\n";
    out += &rejected_table(isa);
    out
}

/// The implemented instructions, one row per [`Doc`].
pub fn implemented_table(isa: &Isa) -> String {
    let mut out =
        String::from("| instructions | family | reference | notes |\n|---|---|---|---|\n");
    let mut rows: Vec<(&'static Doc, Vec<String>)> = Vec::new();
    for d in isa.all() {
        let Some(doc) = d.doc else { continue };
        let name = match d.pulse {
            Pulse::Suffix => format!("{}(P)", d.name),
            Pulse::SPrefix => format!("{}/SP.{}", d.name, &d.name[2..]),
            Pulse::None => d.name.to_string(),
        };
        let name = name.replace('|', "\\|");
        match rows.iter_mut().find(|(r, _)| std::ptr::eq(*r, doc)) {
            Some((_, names)) => names.push(name),
            None => rows.push((doc, vec![name])),
        }
    }
    for (doc, names) in &rows {
        out += &format!(
            "| {} | {} | {} | {} |\n",
            names.join(", "),
            doc.family,
            public_text(doc.cite),
            public_text(doc.notes)
        );
    }
    out
}

/// The rejected instructions, one row per reason.
pub fn rejected_table(isa: &Isa) -> String {
    let mut out = String::from("| instructions | reason |\n|---|---|\n");
    let mut rejected: Vec<(&'static str, Vec<String>)> = Vec::new();
    for d in isa.all() {
        let Kind::Rejected(reason) = d.kind else {
            continue;
        };
        let name = format!("`{}`", d.name);
        match rejected.iter_mut().find(|(r, _)| *r == reason) {
            Some((_, names)) => names.push(name),
            None => rejected.push((reason, vec![name])),
        }
    }
    for (reason, names) in &rejected {
        out += &format!("| {} | {} |\n", names.join(", "), public_text(reason));
    }
    out
}

/// The manuals by the short names the generated tables use (their titles
/// are in COMPATIBILITY.md's heading and docs/manuals.md), for the numbers
/// the code's citations use.
const MANUALS: &[(&str, &str)] = &[
    ("000", "PC"),
    ("001", "PID"),
    ("002", "APLC"),
    ("004", "QCPU"),
];

/// A citation or note as the generated tables show it to users: the
/// manuals by their short names, without the line numbers and decision
/// labels of the project's own reading notes (`004 §10.2 L5420-5755` →
/// `QCPU §10.2`, `… (DEC-16)` → `…`).
pub fn public_text(text: &str) -> String {
    let mut words: Vec<String> = Vec::new();
    let text = without_aplc_decisions(text);
    for word in text.split(' ') {
        // Keep the punctuation around a dropped label: `L12-34,` → `,`.
        let core = word
            .trim_start_matches('(')
            .trim_end_matches([')', ',', ';', '.']);
        let head = &word[..word.len() - word.trim_start_matches('(').len()];
        let tail = &word[head.len() + core.len()..];
        if is_line_label(core) || is_decision_label(core) {
            if !head.is_empty() || !tail.is_empty() {
                words.push(format!("{head}{tail}"));
            }
            continue;
        }
        match MANUALS.iter().find(|(n, _)| *n == core) {
            Some((_, name)) => words.push(format!("{head}{name}{tail}")),
            None => words.push(word.to_string()),
        }
    }
    let mut out = words.join(" ").replace(" per ;", ";").replace(" per,", ",");
    // Tidy what a dropped label leaves: `()`, `( `, ` )`, ` ,`, doubled spaces.
    for (from, to) in [
        ("(), ", ""),
        (" ()", ""),
        ("()", ""),
        ("( ", "("),
        (" )", ")"),
        (" ,", ","),
        (",)", ")"),
        (", ,", ","),
        ("(,", "("),
        ("  ", " "),
    ] {
        while out.contains(from) {
            out = out.replace(from, to);
        }
    }
    out.trim().trim_end_matches(',').trim().to_string()
}

/// The text without `decision D7` (a numbered decision of the APLC reading
/// notes) and the `, ` or `; ` before it.
fn without_aplc_decisions(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("decision D") {
        let after = &rest[at + "decision D".len()..];
        let digits = after.bytes().take_while(u8::is_ascii_digit).count();
        if digits == 0 {
            out += &rest[..at + "decision D".len()];
            rest = after;
            continue;
        }
        let before = rest[..at].trim_end_matches([',', ';', ' ']);
        out += before;
        rest = &after[digits..];
    }
    out + rest
}

/// `L1234`, `L123-456`: a line of the project's copy of a manual (three
/// digits or more; a latch relay such as `L10` in a note stays).
fn is_line_label(w: &str) -> bool {
    let Some(rest) = w.strip_prefix('L') else {
        return false;
    };
    let mut parts = rest.splitn(2, '-');
    let digits =
        |p: Option<&str>| p.is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()));
    let first = parts.next();
    digits(first)
        && first.is_some_and(|f| f.len() >= 3)
        && parts.next().is_none_or(|p| digits(Some(p)))
}

/// `DEC-16`, `DEC-1..4`: a numbered decision of the project's reading notes.
fn is_decision_label(w: &str) -> bool {
    w.strip_prefix("DEC-")
        .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit() || b == b'.'))
}

#[cfg(test)]
mod public_text_tests {
    use super::public_text;

    #[test]
    fn labels_go_manuals_get_names() {
        assert_eq!(public_text("004 §10.2 L5420-5755"), "QCPU §10.2");
        assert_eq!(
            public_text("000 §9.24 L17898-18569, §5.2.3 L2466-2500"),
            "PC §9.24, §5.2.3"
        );
        assert_eq!(
            public_text("blend PI, KP × (DVn + (CT/TI)·ΣDV) (DEC-16)"),
            "blend PI, KP × (DVn + (CT/TI)·ΣDV)"
        );
        assert_eq!(
            public_text("ANB/ORB without operand (erratum L2757); MPS depth 8 (L2808-2820)"),
            "ANB/ORB without operand (erratum); MPS depth 8"
        );
        assert_eq!(
            public_text("PM FROM/DFRO, TO/DTO; 004 ch. 8"),
            "PM FROM/DFRO, TO/DTO; QCPU ch. 8"
        );
        // Devices and numbers that only look alike stay.
        assert_eq!(
            public_text("writes L10 and D16 (K4000)"),
            "writes L10 and D16 (K4000)"
        );
    }
}
