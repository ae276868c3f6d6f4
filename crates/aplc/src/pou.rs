//! Program structure of an `.apl` file (contract §1.1 items 7-9): POU
//! headers (`POU MAIN`, `POU SBR_<n>`, `POU INT_<n> EVENT <e>`), local
//! variable tables (`VAR … END_VAR`), the global table (`VAR_GLOBAL …
//! END_VAR`), and the substitution of `#NAME` and global names by their
//! devices, so that the compiler sees device operands only.

use std::collections::HashMap;

use softplc_lang::{Diagnostic, SourceInstr, Token};

use crate::constant::looks_like_constant;
use crate::devices::{looks_like_device, parse_device, Dev};

/// What a POU is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PouKind {
    Main,
    Sbr(u8),
    Int { n: u32, event: u8 },
}

/// A local variable (L2365-2404).
#[derive(Clone, Debug)]
pub struct Var {
    pub name: String,
    pub kind: String,
    pub ty: String,
    /// Its address, `LM3` or `V4`.
    pub addr: String,
}

/// A program organisation unit: its header, variables and instructions.
#[derive(Clone, Debug)]
pub struct Pou {
    pub kind: PouKind,
    pub header: Token,
    pub vars: Vec<Var>,
    pub body: Vec<SourceInstr>,
}

/// A parsed `.apl` file.
#[derive(Clone, Debug, Default)]
pub struct Unit {
    pub pous: Vec<Pou>,
    /// Global names (upper case) → device text.
    pub globals: HashMap<String, String>,
}

const KEYWORDS: &[&str] = &[
    "POU",
    "MAIN",
    "VAR",
    "VAR_GLOBAL",
    "END_VAR",
    "EVENT",
    "IN",
    "OUT",
    "IN_OUT",
    "TEMP",
    "BOOL",
    "INT",
    "WORD",
    "DINT",
    "DWORD",
    "REAL",
];

/// Events an INT routine may be bound to on APLC-TCP (L10087-10105, L671-674).
fn event_ok(e: u32) -> Result<(), &'static str> {
    match e {
        0..=7 | 10..=17 | 26..=28 | 30..=37 => Ok(()),
        8 | 9 => Err("events 8 and 9 are reserved"),
        18 | 19 => Err("PTO-complete interrupts (events 18, 19) are not on APLC-TCP (APLC programming manual §1.1.1)"),
        20..=25 => {
            Err("high-speed counter interrupts (events 20-25) are not on APLC-TCP (APLC programming manual §1.1.1)")
        }
        29 => Err("the power-fail interrupt (event 29) is not on APLC-TCP (APLC programming manual §1.1.1)"),
        _ => Err("events are 0-7, 10-17, 26-28 and 30-37 (APLC programming manual §9.1)"),
    }
}

struct Parser<'a> {
    file: &'a str,
    diags: Vec<Diagnostic>,
    is_mnemonic: &'a dyn Fn(&str) -> bool,
}

impl Parser<'_> {
    fn err(&mut self, t: &Token, m: impl Into<String>) {
        self.diags.push(Diagnostic::at(self.file, t, m));
    }

    /// Checks a variable name (L1176, decision D13).
    fn name_ok(&mut self, t: &Token) -> bool {
        let u = t.text.to_uppercase();
        let chars_ok = u
            .chars()
            .all(|c| c == '_' || c.is_ascii_alphanumeric() || (!c.is_ascii() && c.is_alphabetic()));
        let why = if !chars_ok || u.starts_with(|c: char| c.is_ascii_digit()) {
            Some("letters, digits and `_`, not starting with a digit")
        } else if u.chars().count() > 8 {
            Some("at most 8 characters")
        } else if looks_like_device(&u) || looks_like_constant(&u) {
            Some("it looks like a device or a constant")
        } else if KEYWORDS.contains(&u.as_str()) || (self.is_mnemonic)(&u) {
            Some("it is a keyword, type name or mnemonic")
        } else {
            None
        };
        match why {
            Some(w) => {
                self.err(
                    t,
                    format!(
                        "variable name `{}`: {w} (APLC programming manual §2.2.3)",
                        t.text
                    ),
                );
                false
            }
            None => true,
        }
    }

    fn global(&mut self, line: &[Token], unit: &mut Unit) {
        if line.len() != 2 {
            let t = line.get(2).unwrap_or(&line[0]);
            self.err(
                t,
                "a global variable is `NAME DEVICE` (APLC programming manual §2.2.3)",
            );
            return;
        }
        let (name, addr) = (&line[0], &line[1]);
        if !self.name_ok(name) {
            return;
        }
        let a = addr.text.to_ascii_uppercase();
        match parse_device(&a) {
            Ok(Some(d)) if d.group.is_none() && d.index.is_none() => {
                if matches!(d.dev, Dev::LM | Dev::V) {
                    self.err(
                        addr,
                        format!(
                            "`{}`: LM and V are local, not global (APLC programming manual §3.1.2)",
                            addr.text
                        ),
                    );
                    return;
                }
            }
            Ok(_) => {
                self.err(
                    addr,
                    format!(
                        "`{}`: a global's address is one device without K<n> or index",
                        addr.text
                    ),
                );
                return;
            }
            Err(e) => {
                self.err(addr, e);
                return;
            }
        }
        let key = name.text.to_uppercase();
        if unit.globals.insert(key, a).is_some() {
            self.err(
                name,
                format!("global variable `{}` defined twice", name.text),
            );
        }
    }

    fn header(&mut self, line: &[Token]) -> Option<PouKind> {
        let Some(name) = line.get(1) else {
            self.err(&line[0], "`POU` needs a name: MAIN, SBR_<n> or INT_<n>");
            return None;
        };
        let u = name.text.to_ascii_uppercase();
        let extra = |p: &mut Self, at: usize| {
            if let Some(t) = line.get(at) {
                p.err(t, format!("unexpected `{}` after the POU header", t.text));
            }
        };
        if u == "MAIN" {
            extra(self, 2);
            return Some(PouKind::Main);
        }
        if let Some(n) = u.strip_prefix("SBR_") {
            extra(self, 2);
            return match n.parse::<u8>() {
                Ok(n) if n <= 63 && !n.to_string().is_empty() => Some(PouKind::Sbr(n)),
                _ => {
                    self.err(
                        name,
                        format!(
                            "`{}`: subroutines are SBR_0-SBR_63 (APLC programming manual §4.4.2)",
                            name.text
                        ),
                    );
                    None
                }
            };
        }
        if let Some(n) = u.strip_prefix("INT_") {
            let Ok(n) = n.parse::<u32>() else {
                self.err(
                    name,
                    format!("`{}`: an interrupt routine is INT_<n>", name.text),
                );
                return None;
            };
            let (Some(kw), Some(e)) = (line.get(2), line.get(3)) else {
                self.err(
                    name,
                    format!("`{}`: an interrupt routine needs `EVENT <e>`", name.text),
                );
                return None;
            };
            if !kw.text.eq_ignore_ascii_case("EVENT") {
                self.err(kw, format!("`{}`: expected `EVENT`", kw.text));
                return None;
            }
            extra(self, 4);
            let Ok(ev) = e.text.parse::<u32>() else {
                self.err(e, format!("`{}`: an event number is needed", e.text));
                return None;
            };
            if let Err(why) = event_ok(ev) {
                self.err(e, format!("event `{}`: {why}", e.text));
                return None;
            }
            return Some(PouKind::Int { n, event: ev as u8 });
        }
        self.err(
            name,
            format!("`{}`: a POU is MAIN, SBR_<n> or INT_<n>", name.text),
        );
        None
    }

    fn var(&mut self, line: &[Token], pou: &mut Pou, bools: &mut u32, words: &mut u32) {
        let (addr, rest) = match line.len() {
            3 => (None, line),
            4 => (Some(&line[0]), &line[1..]),
            _ => {
                self.err(
                    &line[0],
                    "a local variable is `[ADDRESS] NAME KIND TYPE` (APLC programming manual §4.4.3)",
                );
                return;
            }
        };
        let (name, kind, ty) = (&rest[0], &rest[1], &rest[2]);
        if !self.name_ok(name) {
            return;
        }
        let k = kind.text.to_ascii_uppercase();
        if !["IN", "OUT", "IN_OUT", "TEMP"].contains(&k.as_str()) {
            self.err(
                kind,
                format!("`{}`: the kind is IN, OUT, IN_OUT or TEMP", kind.text),
            );
            return;
        }
        if k != "TEMP" && !matches!(pou.kind, PouKind::Sbr(_)) {
            self.err(
                kind,
                format!(
                    "`{}`: MAIN and interrupt routines declare TEMP only (APLC programming manual §4.4.3)",
                    kind.text
                ),
            );
            return;
        }
        let t = ty.text.to_ascii_uppercase();
        let (dev, n) = match t.as_str() {
            "BOOL" => ("LM", 1),
            "INT" | "WORD" => ("V", 1),
            "DINT" | "DWORD" | "REAL" => ("V", 2),
            _ => {
                self.err(
                    ty,
                    format!(
                        "`{}`: the type is BOOL, INT, WORD, DINT, DWORD or REAL",
                        ty.text
                    ),
                );
                return;
            }
        };
        let (count, limit) = if dev == "LM" {
            (&mut *bools, 16)
        } else {
            (&mut *words, 16)
        };
        let vars_of_kind = pou
            .vars
            .iter()
            .filter(|v| (v.ty == "BOOL") == (dev == "LM"))
            .count();
        if vars_of_kind >= limit || *count + n > 64 {
            self.err(
                name,
                "more than 16 bit or 16 word variables in one POU (APLC programming manual §4.4.2)",
            );
            return;
        }
        let at = format!("{dev}{count}");
        *count += n;
        if let Some(a) = addr {
            if !a.text.eq_ignore_ascii_case(&at) {
                self.err(
                    a,
                    format!(
                        "`{}`: variables are allocated in table order; this one is {at} (APLC programming manual §4.4.3)",
                        a.text
                    ),
                );
                return;
            }
        }
        let key = name.text.to_uppercase();
        if pou.vars.iter().any(|v| v.name == key) {
            self.err(
                name,
                format!("variable `{}` declared twice in this POU", name.text),
            );
            return;
        }
        pou.vars.push(Var {
            name: key,
            kind: k,
            ty: t,
            addr: at,
        });
    }
}

/// Joins a compare operator written apart (`LDR < > D0 D2`, L9442-9447) and
/// `EV RD` (L8403) into the mnemonic.
fn instruction(line: &[Token]) -> SourceInstr {
    let mut m = line[0].clone();
    let mut k = 1;
    let base = m
        .text
        .trim_end_matches(['<', '>', '='])
        .to_ascii_uppercase();
    if matches!(
        base.as_str(),
        "LD" | "AND" | "OR" | "LDD" | "ANDD" | "ORD" | "LDR" | "ANDR" | "ORR"
    ) {
        while let Some(t) = line.get(k) {
            if !t.text.is_empty() && t.text.chars().all(|c| matches!(c, '<' | '>' | '=')) {
                m.text.push_str(&t.text);
                k += 1;
            } else {
                break;
            }
        }
    }
    if m.text.eq_ignore_ascii_case("EV")
        && line
            .get(1)
            .is_some_and(|t| t.text.eq_ignore_ascii_case("RD"))
    {
        m.text = "EVRD".into();
        k = 2;
    }
    SourceInstr {
        mnemonic: m,
        operands: line[k..].to_vec(),
        step: None,
    }
}

/// Structures the lines of a file into POUs and variable tables, with `#NAME`
/// and global names replaced by their devices.
pub fn parse(
    file: &str,
    lines: &[Vec<Token>],
    is_mnemonic: &dyn Fn(&str) -> bool,
) -> Result<Unit, Vec<Diagnostic>> {
    let mut unit = parse_as_written(file, lines, is_mnemonic)?;
    let mut diags = Vec::new();
    let globals = std::mem::take(&mut unit.globals);
    for pou in &mut unit.pous {
        substitute(file, pou, &globals, &mut diags);
    }
    unit.globals = globals;
    if diags.is_empty() {
        Ok(unit)
    } else {
        Err(diags)
    }
}

/// [`parse`] without the substitution: operands as the file writes them
/// (`#RUNOK`, `急停`), for tools that show the program; [`Unit::device_of`]
/// gives each one's device.
pub fn parse_as_written(
    file: &str,
    lines: &[Vec<Token>],
    is_mnemonic: &dyn Fn(&str) -> bool,
) -> Result<Unit, Vec<Diagnostic>> {
    let mut p = Parser {
        file,
        diags: Vec::new(),
        is_mnemonic,
    };
    let mut unit = Unit::default();
    let headers = lines.iter().any(|l| l[0].text.eq_ignore_ascii_case("POU"));
    #[derive(PartialEq)]
    enum In {
        Top,
        Globals,
        Vars,
        Body,
    }
    let mut state = In::Top;
    let mut seen_code = false;
    let (mut bools, mut words) = (0u32, 0u32);
    let mut skip_pou = false;
    for line in lines {
        let first = line[0].text.to_ascii_uppercase();
        if state == In::Globals || state == In::Vars {
            if first == "END_VAR" {
                if line.len() > 1 {
                    p.err(
                        &line[1],
                        format!("unexpected `{}` after END_VAR", line[1].text),
                    );
                }
                state = if state == In::Globals {
                    In::Top
                } else {
                    In::Body
                };
                continue;
            }
            if state == In::Globals {
                p.global(line, &mut unit);
            } else if let Some(pou) = unit.pous.last_mut().filter(|_| !skip_pou) {
                p.var(line, pou, &mut bools, &mut words);
            }
            continue;
        }
        match first.as_str() {
            "VAR_GLOBAL" => {
                if seen_code || !unit.pous.is_empty() {
                    p.err(
                        &line[0],
                        "VAR_GLOBAL must come before the first POU and instruction (APLC programming manual §4.3.2)",
                    );
                }
                state = In::Globals;
            }
            "VAR" => {
                let fresh = unit
                    .pous
                    .last()
                    .is_some_and(|u| u.body.is_empty() && u.vars.is_empty());
                if !fresh || state != In::Body {
                    p.err(
                        &line[0],
                        "VAR must directly follow its POU header (APLC programming manual §4.4.3)",
                    );
                }
                state = In::Vars;
            }
            "END_VAR" => p.err(&line[0], "END_VAR without VAR"),
            "POU" => {
                state = In::Body;
                bools = 0;
                words = 0;
                skip_pou = false;
                match p.header(line) {
                    Some(kind) => {
                        let name = line[1].text.to_ascii_uppercase();
                        if let Some(prev) = unit
                            .pous
                            .iter()
                            .find(|u| u.kind == kind || pou_name(u) == name)
                        {
                            let l = prev.header.line;
                            p.err(
                                &line[1],
                                format!("POU `{name}` defined twice (first at line {l})"),
                            );
                        }
                        if let PouKind::Int { event, .. } = kind {
                            let other = if event < 10 {
                                event + 10
                            } else if event < 18 {
                                event - 10
                            } else {
                                255
                            };
                            if unit.pous.iter().any(|u| matches!(u.kind, PouKind::Int { event: e, .. } if e == event || e == other)) {
                                p.err(&line[3], format!("event {event}: one routine per event, and one edge per input (APLC programming manual §9.4)"));
                            }
                        }
                        unit.pous.push(Pou {
                            kind,
                            header: line[1].clone(),
                            vars: Vec::new(),
                            body: Vec::new(),
                        });
                    }
                    None => skip_pou = true,
                }
            }
            _ => {
                seen_code = true;
                if !headers && unit.pous.is_empty() {
                    unit.pous.push(Pou {
                        kind: PouKind::Main,
                        header: line[0].clone(),
                        vars: Vec::new(),
                        body: Vec::new(),
                    });
                }
                state = In::Body;
                match unit.pous.last_mut() {
                    Some(pou) if !skip_pou => pou.body.push(instruction(line)),
                    Some(_) => {}
                    None => p.err(
                        &line[0],
                        format!(
                            "`{}` before the first POU header (contract §1.1 item 7)",
                            line[0].text
                        ),
                    ),
                }
            }
        }
    }
    if state == In::Globals || state == In::Vars {
        let t = lines.last().map(|l| l[0].clone()).unwrap_or(Token {
            text: String::new(),
            line: 1,
            col: 1,
        });
        p.err(&t, "VAR without END_VAR");
    }
    if headers && !unit.pous.iter().any(|u| u.kind == PouKind::Main) && p.diags.is_empty() {
        let t = lines[0][0].clone();
        p.err(
            &t,
            "the program has no `POU MAIN` (APLC programming manual §4.2.1)",
        );
    }
    if !p.diags.is_empty() {
        return Err(p.diags);
    }
    Ok(unit)
}

fn pou_name(u: &Pou) -> String {
    u.name()
}

impl Pou {
    /// `MAIN`, `SBR_<n>` or `INT_<n>`.
    pub fn name(&self) -> String {
        match self.kind {
            PouKind::Main => "MAIN".into(),
            PouKind::Sbr(n) => format!("SBR_{n}"),
            PouKind::Int { n, .. } => format!("INT_{n}"),
        }
    }

    /// The device a `#NAME` operand stands for in this POU: `None` when it
    /// is no `#NAME`, an error when the POU has no such variable.
    pub fn local_device(&self, operand: &str) -> Option<Result<&str, String>> {
        local_device(&self.vars, operand)
    }
}

fn local_device<'a>(vars: &'a [Var], operand: &str) -> Option<Result<&'a str, String>> {
    let name = operand.strip_prefix('#')?;
    let key = name.to_uppercase();
    Some(match vars.iter().find(|v| v.name == key) {
        Some(v) => Ok(v.addr.as_str()),
        None => Err(format!(
            "`{operand}`: no local variable `{name}` in this POU"
        )),
    })
}

impl Unit {
    /// The device an operand of `pou` stands for: a `#NAME` its local's
    /// address, a global name its device, anything else itself (contract
    /// §1.1 items 8-9).
    pub fn device_of<'a>(&'a self, pou: &'a Pou, operand: &'a str) -> Result<&'a str, String> {
        match pou.local_device(operand) {
            Some(d) => d,
            None => Ok(self
                .globals
                .get(&operand.to_uppercase())
                .map_or(operand, String::as_str)),
        }
    }
}

/// Replaces `#NAME` and global names in operands by their devices.
fn substitute(
    file: &str,
    pou: &mut Pou,
    globals: &HashMap<String, String>,
    diags: &mut Vec<Diagnostic>,
) {
    for i in &mut pou.body {
        for t in &mut i.operands {
            match local_device(&pou.vars, &t.text) {
                Some(Ok(dev)) => t.text = dev.to_string(),
                Some(Err(e)) => diags.push(Diagnostic::at(file, t, e)),
                None => {
                    if let Some(dev) = globals.get(&t.text.to_uppercase()) {
                        t.text = dev.clone();
                    }
                }
            }
        }
    }
}
