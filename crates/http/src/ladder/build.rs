//! Instruction list → rung trees.
//!
//! A rung is a [`Fan`]: a condition ([`Net`] of contacts in series and
//! parallel) followed by its branches, each an output or a further fan. An
//! output followed by more contacts (`OUT Y0`, `AND X1`, `OUT Y1`) and the
//! MPS/MRD/MPP stack both make branches; LD inside a rung opens a block that
//! ANB/ORB close. A rung ends at the LD that follows its outputs (with no
//! block or MPS open), at a label and at a standalone instruction.

use softplc_core::program::isa::{Class, Found};
use softplc_core::program::{Dialect, Source, SourceInstr, SourceItem};

use super::{Elem, Kind, Names};

/// Contacts in series and parallel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Net {
    Elem(Elem),
    Series(Vec<Net>),
    Parallel(Vec<Net>),
}

impl Net {
    fn join(a: Option<Net>, b: Net, parallel: bool) -> Net {
        let Some(a) = a else { return b };
        let mut parts = Vec::new();
        for n in [a, b] {
            match n {
                Net::Series(v) if !parallel => parts.extend(v),
                Net::Parallel(v) if parallel => parts.extend(v),
                n => parts.push(n),
            }
        }
        if parallel {
            Net::Parallel(parts)
        } else {
            Net::Series(parts)
        }
    }

    pub fn for_each<'a>(&'a self, f: &mut impl FnMut(&'a Elem)) {
        match self {
            Net::Elem(e) => f(e),
            Net::Series(v) | Net::Parallel(v) => v.iter().for_each(|n| n.for_each(f)),
        }
    }
}

/// A condition and the branches it drives.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Fan {
    pub prefix: Option<Net>,
    pub items: Vec<Item>,
}

/// A branch of a fan.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Item {
    Out(Elem),
    Fan(Fan),
}

impl Fan {
    pub fn for_each<'a>(&'a self, f: &mut impl FnMut(&'a Elem)) {
        if let Some(p) = &self.prefix {
            p.for_each(f);
        }
        for i in &self.items {
            match i {
                Item::Out(e) => f(e),
                Item::Fan(x) => x.for_each(f),
            }
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RungBody {
    Fan(Fan),
    Standalone(Elem),
}

/// One rung with the pointer label in front of it, if any.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rung {
    pub label: Option<String>,
    /// Source line of its first instruction.
    pub line: u32,
    pub body: RungBody,
    /// The comment lines written just above it.
    pub comment: Vec<String>,
    /// The SFC steps whose body it is in (APLC): its rail has power only
    /// while all of them are ON. Empty: the rail always has power.
    pub bus: Vec<String>,
}

impl Rung {
    pub fn for_each<'a>(&'a self, f: &mut impl FnMut(&'a Elem)) {
        match &self.body {
            RungBody::Fan(x) => x.for_each(f),
            RungBody::Standalone(e) => f(e),
        }
    }
}

/// Fans under construction (indices into an arena).
#[derive(Default)]
struct FanB {
    prefix: Option<Net>,
    items: Vec<ItemB>,
}

enum ItemB {
    Out(Elem),
    Fan(usize),
}

/// What a source instruction adds to its element beyond its tokens.
#[derive(Default)]
pub(crate) struct Notes {
    /// See [`Elem::aliases`].
    pub aliases: Vec<String>,
    /// See [`Elem::params`].
    pub params: Vec<String>,
}

#[derive(Default)]
pub(crate) struct Builder {
    names: Names,
    bus: Vec<String>,
    rungs: Vec<Rung>,
    fans: Vec<FanB>,
    cur: usize,
    net: Option<Net>,
    blocks: Vec<Net>,
    mps: Vec<usize>,
    outputs: usize,
    label: Option<String>,
    line: Option<u32>,
    next_id: u32,
}

impl Builder {
    pub(crate) fn new(names: Names) -> Builder {
        let mut b = Builder {
            names,
            ..Builder::default()
        };
        b.start();
        b
    }

    /// Rungs built so far (the one being built ends first).
    pub(crate) fn count(&mut self) -> usize {
        self.flush();
        self.rungs.len()
    }

    pub(crate) fn finish(mut self) -> Vec<Rung> {
        self.flush();
        self.rungs
    }

    /// Names of the operands from here on.
    pub(crate) fn set_names(&mut self, names: Names) {
        self.flush();
        self.names = names;
    }

    /// A pointer label before the next rung.
    pub(crate) fn label(&mut self, text: &str) {
        self.flush();
        self.label = Some(text.to_string());
    }

    /// An SFC step: a run of STLs (one: a step body, several: a merge) draws
    /// as one step box on a rung of its own; the rungs after it are the
    /// step's until [`Self::end_step`].
    pub(crate) fn step(&mut self, run: &[&SourceInstr]) {
        let Some(first) = run.first() else { return };
        self.flush();
        self.bus.clear();
        let mut e = self.elem(Kind::Step, first, "STL", Notes::default());
        e.operands = run
            .iter()
            .filter_map(|i| i.operands.first().map(|t| t.text.clone()))
            .collect();
        self.bus = e.operands.clone();
        self.rungs.push(Rung {
            label: self.label.take(),
            line: e.line,
            body: RungBody::Standalone(e),
            comment: Vec::new(),
            bus: Vec::new(),
        });
        self.line = None;
    }

    /// The end of an SFC section or POU: rungs go back to the plain rail.
    pub(crate) fn end_step(&mut self) {
        self.flush();
        self.bus.clear();
    }

    fn start(&mut self) {
        self.fans = vec![FanB::default()];
        self.cur = 0;
    }

    fn busy(&self) -> bool {
        self.net.is_some()
            || self
                .fans
                .first()
                .is_some_and(|f| f.prefix.is_some() || !f.items.is_empty())
    }

    /// Ends the rung being built.
    fn flush(&mut self) {
        if self.busy() {
            // A condition without an output still shows.
            self.fork();
            let fan = take(&mut self.fans, 0);
            self.rungs.push(Rung {
                label: self.label.take(),
                line: self.line.unwrap_or(0),
                body: RungBody::Fan(fan),
                comment: Vec::new(),
                bus: self.bus.clone(),
            });
        }
        self.start();
        self.net = None;
        self.blocks.clear();
        self.mps.clear();
        self.outputs = 0;
        self.line = None;
    }

    /// The pending condition becomes a branch point at the current fan.
    fn fork(&mut self) {
        let Some(n) = self.net.take() else { return };
        let f = &mut self.fans[self.cur];
        if f.prefix.is_none() && f.items.is_empty() {
            f.prefix = Some(n);
        } else {
            self.fans.push(FanB {
                prefix: Some(n),
                items: Vec::new(),
            });
            let child = self.fans.len() - 1;
            self.fans[self.cur].items.push(ItemB::Fan(child));
            self.cur = child;
        }
    }

    fn elem(&mut self, kind: Kind, i: &SourceInstr, m: &str, notes: Notes) -> Elem {
        let id = self.next_id;
        self.next_id += 1;
        self.line.get_or_insert(i.mnemonic.line);
        Elem {
            id,
            kind,
            mnemonic: m.to_string(),
            operands: i.operands.iter().map(|t| t.text.clone()).collect(),
            line: i.mnemonic.line,
            names: self.names,
            aliases: notes.aliases,
            params: notes.params,
        }
    }

    /// An instruction of `dialect` (an unknown mnemonic draws as an output box).
    pub(crate) fn item(&mut self, i: &SourceInstr, dialect: &Dialect, notes: Notes) {
        let m = i.mnemonic.text.to_ascii_uppercase();
        let class = match dialect.isa.lookup(&m) {
            Found::Def(d, _) | Found::WrongPulse(d) | Found::NoPulse(d) => d.class,
            Found::Unknown => Class::Output,
        };
        self.instr(i, class, notes);
    }

    fn instr(&mut self, i: &SourceInstr, class: Class, notes: Notes) {
        let m = i.mnemonic.text.to_ascii_uppercase();
        match class {
            Class::Contact => {
                // APLC word-bit contacts BLD/BLDI/BAND/BANI/BOR/BORI (002
                // L8833-9076): LD/AND/OR of bit S2 of word S1.
                let word_bit = m
                    .strip_prefix('B')
                    .filter(|r| ["LD", "AND", "OR"].iter().any(|p| r.starts_with(p)));
                let base = word_bit.unwrap_or(&m);
                let load = base.starts_with("LD");
                if load
                    && self.outputs > 0
                    && self.mps.is_empty()
                    && self.blocks.is_empty()
                    && self.net.is_none()
                {
                    self.flush();
                }
                let kind = if i.operands.len() >= 2 && word_bit.is_none() {
                    Kind::Compare
                } else {
                    match base {
                        "LDI" | "ANI" | "ORI" => Kind::Nc,
                        "LDP" | "ANDP" | "ORP" => Kind::Rise,
                        "LDF" | "ANDF" | "ORF" => Kind::Fall,
                        _ => Kind::No,
                    }
                };
                let e = Net::Elem(self.elem(kind, i, &m, notes));
                if load {
                    if let Some(n) = self.net.take() {
                        self.blocks.push(n);
                    }
                    self.net = Some(e);
                } else {
                    let net = self.net.take();
                    self.net = Some(Net::join(net, e, base.starts_with("OR")));
                }
            }
            Class::Connection => match m.as_str() {
                "ANB" | "ORB" => {
                    let n = self.net.take();
                    self.net = match (self.blocks.pop(), n) {
                        (Some(b), Some(n)) => Some(Net::join(Some(b), n, m == "ORB")),
                        // A block opened at a branch point (LD after MPS/MRD,
                        // 002 L2185-2208): ANB puts it in series there. An
                        // ORB there is drawn the same way.
                        (None, n) => n,
                        (Some(b), None) => Some(b),
                    };
                }
                "MPS" => {
                    self.fork();
                    self.mps.push(self.cur);
                }
                "MRD" | "MPP" => {
                    self.fork();
                    let top = if m == "MRD" {
                        self.mps.last().copied()
                    } else {
                        self.mps.pop()
                    };
                    if let Some(t) = top {
                        self.cur = t;
                    }
                }
                _ => {
                    let e = Net::Elem(self.elem(Kind::Modifier, i, &m, notes));
                    let net = self.net.take();
                    self.net = Some(Net::join(net, e, false));
                }
            },
            Class::Output => {
                let bit = i.operands.first().is_some_and(|o| {
                    self.names.device_type(&o.text) == Some(softplc_core::access::ValueType::Bit)
                });
                let kind = match m.as_str() {
                    "OUT" if bit => Kind::Coil,
                    "SET" if bit => Kind::Set,
                    "RST" if bit => Kind::Reset,
                    _ => Kind::Box,
                };
                let e = self.elem(kind, i, &m, notes);
                self.fork();
                self.fans[self.cur].items.push(ItemB::Out(e));
                self.outputs += 1;
            }
            Class::Standalone => {
                self.flush();
                let e = self.elem(Kind::Standalone, i, &m, notes);
                self.rungs.push(Rung {
                    label: self.label.take(),
                    line: e.line,
                    body: RungBody::Standalone(e),
                    comment: Vec::new(),
                    bus: self.bus.clone(),
                });
                self.line = None;
            }
        }
    }
}

/// Moves fan `i` out of the arena as a tree.
fn take(fans: &mut Vec<FanB>, i: usize) -> Fan {
    let f = std::mem::take(&mut fans[i]);
    let items = f
        .items
        .into_iter()
        .map(|it| match it {
            ItemB::Out(e) => Item::Out(e),
            ItemB::Fan(c) => Item::Fan(take(fans, c)),
        })
        .collect();
    Fan {
        prefix: f.prefix,
        items,
    }
}

/// The rungs of `src`; instruction classes come from `dialect` (an unknown
/// mnemonic draws as an output box).
pub fn build(src: &Source, dialect: &Dialect) -> Vec<Rung> {
    let mut b = Builder::new(Names::default());
    for item in super::items(src) {
        match item {
            SourceItem::Label(t) => b.label(&t.text),
            SourceItem::Instr(i) => b.item(i, dialect, Notes::default()),
        }
    }
    b.finish()
}
