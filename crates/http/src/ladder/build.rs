//! Instruction list → rung trees.
//!
//! A rung is a [`Fan`]: a condition ([`Net`] of contacts in series and
//! parallel) followed by its branches, each an output or a further fan. An
//! output followed by more contacts (`OUT Y0`, `AND X1`, `OUT Y1`) and the
//! MPS/MRD/MPP stack both make branches; LD inside a rung opens a block that
//! ANB/ORB close. A rung ends at the LD that follows its outputs (with no
//! block or MPS open), at a label and at a standalone instruction.

use softplc_ir::listing::{CoilRole, Entry, Link, Listed, Role, Test};
use softplc_ir::ops::Join;

use super::{Elem, Kind, Names, Wide};

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
    /// The step box drawn last, while SFC steps follow each other (a merge).
    step: Option<usize>,
    /// The program's 32-bit and real devices.
    wide: Wide,
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

    /// Shows the operands of `wide` as whole values.
    pub(crate) fn with_wide(mut self, wide: Wide) -> Builder {
        self.wide = wide;
        self
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

    /// An SFC step: a run of steps (one: a step body, several: a merge)
    /// draws as one step box on a rung of its own; the rungs after it are
    /// the step's until the SFC section or the POU ends.
    fn step(&mut self, l: &Listed) {
        let operand = l.operands.first().cloned();
        if let Some(RungBody::Standalone(e)) = self.step.map(|r| &mut self.rungs[r].body) {
            e.operands.extend(operand.clone());
            self.bus.extend(operand);
            return;
        }
        self.flush();
        let mut e = self.elem(Kind::Step, l, Notes::default());
        e.operands = operand.into_iter().collect();
        self.bus = e.operands.clone();
        self.rungs.push(Rung {
            label: self.label.take(),
            line: e.line,
            body: RungBody::Standalone(e),
            comment: Vec::new(),
            bus: Vec::new(),
        });
        self.step = Some(self.rungs.len() - 1);
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
        self.step = None;
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

    fn elem(&mut self, kind: Kind, l: &Listed, notes: Notes) -> Elem {
        let id = self.next_id;
        self.next_id += 1;
        self.line.get_or_insert(l.line);
        Elem {
            id,
            kind,
            role: l.role,
            mnemonic: l.mnemonic.to_ascii_uppercase(),
            operands: l.operands.clone(),
            line: l.line,
            names: self.names,
            aliases: notes.aliases,
            params: notes.params,
            wide: l.operands.iter().map(|o| self.wide.get(o)).collect(),
        }
    }

    /// An entry of a program's listing.
    pub(crate) fn entry(&mut self, e: &Entry) {
        match e {
            Entry::Label { text, .. } => self.label(text),
            Entry::Instr(l) => self.item(l, Notes::default()),
        }
    }

    /// An instruction, drawn as its ladder role says.
    pub(crate) fn item(&mut self, l: &Listed, notes: Notes) {
        if l.role != Role::Step {
            self.step = None;
        }
        match l.role {
            Role::Contact { join, test } => self.contact(l, join, test, notes),
            Role::Link(link) => self.link(l, link, notes),
            Role::Coil(coil) => {
                let bit = l.operands.first().is_some_and(|o| {
                    self.names.device_type(o) == Some(softplc_core::access::ValueType::Bit)
                });
                let kind = match coil {
                    CoilRole::Out if bit => Kind::Coil,
                    CoilRole::Set if bit => Kind::Set,
                    CoilRole::Reset if bit => Kind::Reset,
                    _ => Kind::Box,
                };
                self.output(l, kind, notes);
            }
            Role::Box => self.output(l, Kind::Box, notes),
            Role::Step => self.step(l),
            Role::StepsEnd => {
                self.end_step();
                self.standalone(l, notes);
            }
            Role::Standalone => self.standalone(l, notes),
        }
    }

    fn contact(&mut self, l: &Listed, join: Join, test: Test, notes: Notes) {
        let load = join == Join::Load;
        if load
            && self.outputs > 0
            && self.mps.is_empty()
            && self.blocks.is_empty()
            && self.net.is_none()
        {
            self.flush();
        }
        let kind = match test {
            Test::Open | Test::WordBit { closed: false } => Kind::No,
            Test::Closed | Test::WordBit { closed: true } => Kind::Nc,
            Test::Rising => Kind::Rise,
            Test::Falling => Kind::Fall,
            Test::NotRising => Kind::RiseNot,
            Test::NotFalling => Kind::FallNot,
            Test::Compare(_) | Test::Computed => Kind::Compare,
        };
        let e = Net::Elem(self.elem(kind, l, notes));
        if load {
            if let Some(n) = self.net.take() {
                self.blocks.push(n);
            }
            self.net = Some(e);
        } else {
            let net = self.net.take();
            self.net = Some(Net::join(net, e, join == Join::Or));
        }
    }

    fn link(&mut self, l: &Listed, link: Link, notes: Notes) {
        match link {
            Link::BlockAnd | Link::BlockOr => {
                let n = self.net.take();
                self.net = match (self.blocks.pop(), n) {
                    (Some(b), Some(n)) => Some(Net::join(Some(b), n, link == Link::BlockOr)),
                    // A block opened at a branch point (LD after MPS/MRD,
                    // 002 L2185-2208): ANB puts it in series there. An
                    // ORB there is drawn the same way.
                    (None, n) => n,
                    (Some(b), None) => Some(b),
                };
            }
            Link::Push => {
                self.fork();
                self.mps.push(self.cur);
            }
            Link::Read | Link::Pop => {
                self.fork();
                let top = if link == Link::Read {
                    self.mps.last().copied()
                } else {
                    self.mps.pop()
                };
                if let Some(t) = top {
                    self.cur = t;
                }
            }
            Link::Invert | Link::Rising | Link::Falling | Link::Nothing => {
                let e = Net::Elem(self.elem(Kind::Modifier, l, notes));
                let net = self.net.take();
                self.net = Some(Net::join(net, e, false));
            }
        }
    }

    fn output(&mut self, l: &Listed, kind: Kind, notes: Notes) {
        let e = self.elem(kind, l, notes);
        self.fork();
        self.fans[self.cur].items.push(ItemB::Out(e));
        self.outputs += 1;
    }

    fn standalone(&mut self, l: &Listed, notes: Notes) {
        self.flush();
        let e = self.elem(Kind::Standalone, l, notes);
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

/// The rungs of a program's listing (MELSEC names).
pub fn build(entries: &[Entry]) -> Vec<Rung> {
    build_wide(entries, Wide::default())
}

/// [`build`] showing the operands of `wide` as whole values.
pub fn build_wide(entries: &[Entry], wide: Wide) -> Vec<Rung> {
    let mut b = Builder::new(Names::default()).with_wide(wide);
    for e in entries {
        b.entry(e);
    }
    b.finish()
}
