//! A check a dialect's tests run over its whole instruction set: no
//! definition compiles as another's instruction. Each definition is compiled
//! once under its own name and once under a name no definition has (the
//! situation of a name added to a dialect's list but not to the code that
//! tells its definitions apart). The second must give the same instruction,
//! or fail the load as a softplc bug; a compile function whose catch-all
//! picks an instruction gives another one and is reported.

use softplc_ir::device::DeviceMap;

use crate::compile::Compiler;
use crate::dialect::Dialect;
use crate::isa::{Class, Def, Kind, Use};
use crate::source::{SourceInstr, Token};

/// What compiling one instruction gave: its ops and family instructions
/// (debug text) and its diagnostics.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    pub code: String,
    pub diags: Vec<String>,
}

impl Outcome {
    /// Compiled to code without a diagnostic.
    pub fn clean(&self) -> bool {
        self.diags.is_empty() && !self.code.is_empty()
    }
}

/// What [`renamed`] found.
#[derive(Debug, Default)]
pub struct Report {
    /// Definitions checked (an operand set compiled under their own name).
    pub checked: Vec<&'static str>,
    /// Definitions none of whose operand sets compiled cleanly.
    pub uncovered: Vec<&'static str>,
    /// Definitions that compiled, under another name, to something else
    /// without a load error: (name, own outcome, outcome under the alias).
    pub differing: Vec<(&'static str, Outcome, Outcome)>,
}

fn tok(text: &str, col: u32) -> Token {
    Token {
        text: text.to_string(),
        line: 1,
        col,
    }
}

/// Compiles one use of `def` written `name` with `operands`, on a fresh
/// compiler whose rung state is the one its class expects (a rung for a
/// contact, connection or output, an open block and MPS for a connection,
/// an open MC for a standalone instruction; an open FOR for all).
pub fn compile_one(
    dialect: &Dialect,
    map: &DeviceMap,
    def: &'static Def,
    name: &str,
    operands: &[String],
) -> Outcome {
    let mut c = Compiler::new("audit", map, dialect);
    let i = SourceInstr {
        mnemonic: tok(name, 1),
        operands: operands
            .iter()
            .enumerate()
            .map(|(k, t)| tok(t, 2 + k as u32))
            .collect(),
        step: None,
    };
    c.for_open.push(tok("FOR", 1));
    match def.class {
        Class::Standalone => {
            c.has_rung = false;
            c.after_output = true;
            c.mc_open.push((0, tok("MC", 1)));
        }
        Class::Connection => {
            c.has_rung = true;
            c.after_output = false;
            c.depth = 1;
            c.mps.push(tok("MPS", 1));
        }
        Class::Contact | Class::Output => {
            c.has_rung = true;
            c.after_output = false;
        }
    }
    match def.kind {
        Kind::Instr(f) => c.family(&i, name, def.drive, f, false),
        Kind::Lower(f) => f(
            &mut c,
            &Use {
                def,
                instr: &i,
                m: name,
                pulse: false,
            },
        ),
        Kind::Rejected(_) => {}
    }
    Outcome {
        code: format!("{:?} {:?}", c.ops, c.ext),
        diags: c.diags.iter().map(|d| d.message.clone()).collect(),
    }
}

/// Checks every implemented definition of `dialect`: the first operand set
/// of `candidates` that compiles cleanly under the definition's own name is
/// compiled again under `alias` + name. `bug` recognises the diagnostics
/// that fail such a load as a softplc bug.
pub fn renamed(
    dialect: &Dialect,
    map: &DeviceMap,
    alias: &str,
    candidates: &dyn Fn(&Def) -> Vec<Vec<String>>,
    bug: &dyn Fn(&str) -> bool,
) -> Report {
    let mut r = Report::default();
    for def in dialect.isa.all().filter(|d| d.is_implemented()) {
        let own = candidates(def)
            .into_iter()
            .map(|ops| (compile_one(dialect, map, def, def.name, &ops), ops))
            .find(|(o, _)| o.clean());
        let Some((own, ops)) = own else {
            r.uncovered.push(def.name);
            continue;
        };
        r.checked.push(def.name);
        let other = format!("{alias}{}", def.name);
        let mut got = compile_one(dialect, map, def, &other, &ops);
        if got.diags.iter().any(|d| bug(d)) {
            continue;
        }
        // Texts that name the mnemonic name the one written.
        got.code = got.code.replace(&other, def.name);
        for d in &mut got.diags {
            *d = d.replace(&other, def.name);
        }
        if got != own {
            r.differing.push((def.name, own, got));
        }
    }
    r
}

/// Operand sets of 0 to 7 operands to try each definition with: word
/// devices, bit devices and constants (`word(i)`, `bit(i)`, `constant(i)`
/// for the i-th operand) in a few patterns, each set once. A dialect's test
/// adds the special forms some of its instructions need.
pub fn operand_sets(
    word: fn(usize) -> String,
    bit: fn(usize) -> String,
    constant: fn(usize) -> String,
) -> Vec<Vec<String>> {
    type Pattern = fn(usize) -> char;
    let patterns: [Pattern; 10] = [
        |_| 'w',
        |_| 'b',
        |_| 'k',
        |i| if i == 0 { 'k' } else { 'w' },
        |i| if i == 0 { 'b' } else { 'w' },
        |i| if i == 0 { 'w' } else { 'b' },
        |i| if i == 0 { 'w' } else { 'k' },
        |i| if i == 1 { 'k' } else { 'w' },
        |i| if i == 2 { 'k' } else { 'w' },
        |i| if i >= 1 { 'k' } else { 'w' },
    ];
    let mut sets: Vec<Vec<String>> = Vec::new();
    for n in 0..=7usize {
        for p in patterns {
            let set: Vec<String> = (0..n)
                .map(|i| match p(i) {
                    'w' => word(i),
                    'b' => bit(i),
                    _ => constant(i),
                })
                .collect();
            if !sets.contains(&set) {
                sets.push(set);
            }
        }
    }
    sets
}
