//! Ops → a straight-line plan per chunk: which ops run as native code,
//! which the native code hands to the interpreter one at a time, and which
//! the interpreter runs between native regions.
//!
//! Native can be only ops that touch nothing but the rung registers, plain
//! device indices, the timers' remainders and the program's edge memories:
//! contacts (and LDP/LDF/ANDP…) and coils (and PLS/PLF) on plain bits (or a
//! word's bit), MEP/MEF, the ANB/ORB block stack and MPS stack, 16/32-bit
//! comparison contacts, MOV/DMOV, the word instructions an instruction
//! describes as a [`WordOp`] (+, -, INC, DEC, WAND, WOR, WXOR, BSET, BRST,
//! RST of a timer or counter), timers and counters, and MC/MCR, all on plain
//! words and constants. Those that can fault (a negative set value read from
//! a word) or change the conditions (an MC turning them OFF) have the
//! interpreter run the op on that path. Every other op (FF, pulse forms,
//! other application instructions, index modification, jumps, calls,
//! FOR/NEXT, END) runs in the interpreter with its one implementation.
//!
//! Between native ops, a stretch of interpreted ops is one call of the
//! interpreter (`Host::exec`), which runs the stretch and returns to the
//! call site. A call costs about as much as interpreting a few contacts, so
//! native ops fewer than [`MIN_RUN`] in a row between interpreted ones are
//! interpreted with them, and a chunk without such a run has no native code.

use softplc_ir::ops::{
    BitArg, Callee, CmpOp, CoilKind, Compare, Counter, Edge, Join, Num, Op, Program, Timer, WordArg,
};
use softplc_ir::word_op::{Binary, WordOp};

/// The most work compiled into one function, in ops weighed by the code
/// they become ([`weight_of`]), so that compile time stays linear in the
/// program's length (Cranelift's register allocation grows faster than a
/// function's size, and with its blocks more than its instructions).
pub const CHUNK_WEIGHT: usize = 4096;

/// Fewest native ops in a row, between interpreted ones, worth running
/// natively: a call of the interpreter from native code costs about what the
/// interpreter spends on this many contacts once the program's code no longer
/// fits the instruction cache (docs/performance.md, "Tiers").
pub const MIN_RUN: usize = 8;

/// A bit a contact reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BitSrc {
    /// Flat bit index.
    Bit(u32),
    /// Bit `1` of the word at flat word index `0` (`D0.5`).
    WordBit(u32, u8),
}

/// A word operand read by MOV or a comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WordSrc {
    /// Flat word index (the low word of a 32-bit value).
    Word(u32),
    /// Constant: raw bits, 16-bit operations use the low half.
    Const(u32),
}

/// What a coil does with the condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Store {
    Out,
    Set,
    Rst,
}

/// An op that runs while the condition is ON and leaves it unchanged, on
/// plain words (and a timer's or counter's contact).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// MOV (1 word) or DMOV (2 words).
    Move { words: u8, s: WordSrc, d: u32 },
    /// `d = a op b` on 16 (`wide` false) or 32 bits.
    Binary {
        op: Binary,
        wide: bool,
        a: WordSrc,
        b: WordSrc,
        d: u32,
    },
    /// BSET/BRST: bit `n & 15` of word `d`.
    Bit { set: bool, d: u32, n: WordSrc },
    /// RST of a timer (with its remainder slot) or counter.
    ResetTc {
        value: u32,
        contact: u32,
        slot: Option<u32>,
    },
}

/// `OUT T`/`OUT ST` (`sequence::timer`) on plain devices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimerStep {
    /// The op, for the interpreter to run when the set value is negative.
    pub pc: u32,
    pub coil: u32,
    pub contact: u32,
    pub value: u32,
    pub slot: u32,
    /// A constant set value is not negative.
    pub set: WordSrc,
    pub high_speed: bool,
    pub retentive: bool,
}

/// `OUT C` (`sequence::counter`) on plain devices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CounterStep {
    /// The op, for the interpreter to run when the set value is negative.
    pub pc: u32,
    pub coil: u32,
    pub contact: u32,
    pub value: u32,
    /// A constant set value is not negative.
    pub set: WordSrc,
}

/// One native operation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Step {
    /// A contact: the bit, negated or not, joined into the operation result.
    Contact {
        join: Join,
        negate: bool,
        src: BitSrc,
    },
    /// `LD= S1 S2` … on 16-bit (`wide` false) or 32-bit signed values.
    Compare {
        join: Join,
        op: CmpOp,
        wide: bool,
        a: WordSrc,
        b: WordSrc,
    },
    /// LDP/LDF/ANDP/ORF…: the bit's rising or falling edge against its
    /// edge memory `slot`, negated or not, joined into the result.
    EdgeContact {
        join: Join,
        negate: bool,
        rising: bool,
        src: BitSrc,
        slot: u32,
    },
    /// MEP/MEF: the operation result's rising or falling edge.
    EdgeOfResult {
        rising: bool,
        slot: u32,
    },
    /// PLS/PLF: the bit ON for one scan from the condition's rising or
    /// falling edge.
    PulseCoil {
        rising: bool,
        slot: u32,
        bit: u32,
    },
    Push,
    Anb,
    Orb,
    Mps,
    Mrd,
    Mpp,
    Inv,
    Coil {
        store: Store,
        bit: u32,
    },
    /// Consecutive actions under one condition (they leave the operation
    /// result unchanged, so one test guards the run).
    Actions(Vec<Action>),
    Timer(TimerStep),
    Counter(CounterStep),
    /// MC on a plain bit: the bit ON while the condition is; the
    /// interpreter runs it when the condition is OFF (and goes on with
    /// conditions OFF).
    Mc {
        pc: u32,
        bit: u32,
    },
    /// MCR while no MC forces conditions OFF: nothing to do.
    Mcr,
}

/// An element of a chunk's plan, in op order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Piece {
    /// Native code may be entered at op `pc` (the interpreter calls in here,
    /// or a jump went here).
    Entry(u32),
    Step(Step),
    /// The interpreter runs the ops `from..to` (`Host::exec`); only while
    /// the condition is ON when `guarded` (every op of the stretch is an
    /// instruction that does nothing while its condition is OFF, and none
    /// changes the condition).
    Run {
        from: u32,
        to: u32,
        guarded: bool,
    },
    /// Leave native code: the interpreter goes on at op `pc`.
    Exit(u32),
}

/// The ops `start..end` of a program as native pieces.
#[derive(Debug)]
pub struct Chunk {
    pub start: u32,
    pub end: u32,
    pub pieces: Vec<Piece>,
}

/// The plan of a whole program.
#[derive(Debug)]
pub struct Plan {
    pub chunks: Vec<Chunk>,
    /// For every op, whether it runs as native code.
    pub native: Vec<bool>,
    /// For every op, whether native code may be entered there.
    pub entry: Vec<bool>,
    /// Ops native code could run, left to the interpreter because their run
    /// is shorter than the minimum (`--stats` says so).
    pub short_run_ops: usize,
    /// Timer remainder slots native code uses: all are below this.
    pub timer_slots: u32,
}

/// Plans `prog` with native runs of at least `min_run` ops, checking every
/// device index against the memory size it was compiled for (an op with an
/// index outside is left to the interpreter).
pub fn plan(prog: &Program, min_run: usize) -> Plan {
    let lim = Limits {
        bits: prog.bit_len,
        words: prog.word_len,
        edges: prog.edge_slots,
    };
    let mut steps: Vec<Option<Step>> = prog
        .ops
        .iter()
        .enumerate()
        .map(|(pc, op)| step(pc as u32, op, prog, lim))
        .collect();
    let n = prog.ops.len();
    let can = steps.iter().filter(|s| s.is_some()).count();
    let guarded: Vec<bool> = prog.ops.iter().map(runs_only_when_on).collect();
    let bounds = chunk_bounds(&steps);
    for &(start, end) in &bounds {
        drop_short_runs(&mut steps[start..end], &guarded[start..end], min_run);
    }
    let native: Vec<bool> = steps.iter().map(Option::is_some).collect();
    let timer_slots = steps
        .iter()
        .flatten()
        .filter_map(Step::timer_slot)
        .map(|s| s + 1)
        .max()
        .unwrap_or(0);
    let short_run_ops = can - native.iter().filter(|n| **n).count();
    let targets = targets(prog);
    let mut entry = vec![false; n];
    let chunks = bounds
        .iter()
        .map(|&(start, end)| chunk(start, end, &steps, &guarded, &targets, &mut entry))
        .collect();
    Plan {
        chunks,
        native,
        entry,
        short_run_ops,
        timer_slots,
    }
}

impl Step {
    /// The timer remainder slot the step uses.
    fn timer_slot(&self) -> Option<u32> {
        match self {
            Step::Timer(t) => Some(t.slot),
            Step::Actions(a) => a
                .iter()
                .filter_map(|a| match a {
                    Action::ResetTc { slot, .. } => *slot,
                    _ => None,
                })
                .max(),
            _ => None,
        }
    }
}

/// The ops of each chunk: consecutive ranges of at most [`CHUNK_WEIGHT`].
fn chunk_bounds(steps: &[Option<Step>]) -> Vec<(usize, usize)> {
    let mut bounds = Vec::new();
    let (mut start, mut weight) = (0, 0);
    for (pc, s) in steps.iter().enumerate() {
        let w = s.as_ref().map_or(1, weight_of);
        if weight + w > CHUNK_WEIGHT && pc > start {
            bounds.push((start, pc));
            (start, weight) = (pc, 0);
        }
        weight += w;
    }
    if start < steps.len() {
        bounds.push((start, steps.len()));
    }
    bounds
}

/// What a step weighs in a chunk: about the blocks its code has (a
/// contact or coil, a MOV or an interpreted op: none or one).
fn weight_of(s: &Step) -> usize {
    match s {
        Step::Timer(_) => 5,
        Step::Counter(_) | Step::Mc { .. } => 4,
        _ => 1,
    }
}

/// Whether `op` does nothing while its condition is OFF and leaves the
/// condition as it is: native code runs it in the interpreter only while the
/// condition is ON (an application instruction of a family module).
fn runs_only_when_on(op: &Op) -> bool {
    matches!(op, Op::Ext(_))
}

/// Leaves to the interpreter native runs of one chunk that are too short to
/// pay for the calls around them (not a chunk that is one short run). A run
/// goes on across instructions that act only while their condition is ON
/// (`guarded`): native code tests the condition and calls the interpreter
/// only then. Such a call costs what an interpreted stretch's does, but only
/// while the condition is ON: each asks for half [`MIN_RUN`]'s native ops
/// more (`min_run` 1 asks for none).
fn drop_short_runs(steps: &mut [Option<Step>], guarded: &[bool], min_run: usize) {
    let n = steps.len();
    let mut pc = 0;
    while pc < n {
        if steps[pc].is_none() {
            pc += 1;
            continue;
        }
        let len = (pc..n)
            .take_while(|i| steps[*i].is_some() || guarded[*i])
            .count();
        let run = &steps[pc..pc + len];
        let native = run.iter().filter(|s| s.is_some()).count();
        // Guarded stretches: a guarded op after a native one.
        let calls = run
            .windows(2)
            .filter(|w| w[0].is_some() && w[1].is_none())
            .count();
        let need = if min_run > 1 {
            min_run + min_run * calls / 2
        } else {
            1
        };
        if native < need && len < n {
            steps[pc..pc + len].fill(None);
        }
        pc += len;
    }
}

/// The pieces of ops `start..end`: native code from the chunk's first native
/// op to its last, the interpreted stretches between them as calls. Marks in
/// `entry` where it may be entered: at the first native op and wherever
/// control can arrive other than from the op before.
fn chunk(
    start: usize,
    end: usize,
    steps: &[Option<Step>],
    guarded: &[bool],
    targets: &[bool],
    entry: &mut [bool],
) -> Chunk {
    let mut pieces = Vec::new();
    let first = (start..end).find(|pc| steps[*pc].is_some());
    let last = (start..end).rev().find(|pc| steps[*pc].is_some());
    if let (Some(first), Some(last)) = (first, last) {
        // The interpreted stretch open since this op.
        let mut stretch: Option<usize> = None;
        for pc in first..=last {
            if pc == first || targets[pc] {
                if let Some(from) = stretch.take() {
                    pieces.push(run(from, pc, guarded));
                }
                entry[pc] = true;
                pieces.push(Piece::Entry(pc as u32));
            }
            match &steps[pc] {
                Some(s) => {
                    if let Some(from) = stretch.take() {
                        pieces.push(run(from, pc, guarded));
                        // Where the interpreter comes back to native code
                        // when the stretch left it (an MC turned conditions
                        // OFF: native code runs only while they are not).
                        entry[pc] = true;
                        pieces.push(Piece::Entry(pc as u32));
                    }
                    match (s, pieces.last_mut()) {
                        (Step::Actions(a), Some(Piece::Step(Step::Actions(run)))) => {
                            run.extend_from_slice(a)
                        }
                        _ => pieces.push(Piece::Step(s.clone())),
                    }
                }
                None => {
                    stretch.get_or_insert(pc);
                }
            }
        }
        pieces.push(Piece::Exit(last as u32 + 1));
    }
    Chunk {
        start: start as u32,
        end: end as u32,
        pieces,
    }
}

fn run(from: usize, to: usize, guarded: &[bool]) -> Piece {
    Piece::Run {
        from: from as u32,
        to: to as u32,
        guarded: guarded[from..to].iter().all(|g| *g),
    }
}

/// Ops where execution can arrive other than from the op before: jump, CALL
/// and BREAK targets, common and interrupt pointers, the op after the one a
/// pulse gate skips, and the ops RET and NEXT return to (after CALL, FOR).
fn targets(prog: &Program) -> Vec<bool> {
    let n = prog.ops.len();
    let mut t = vec![false; n + 2];
    for (pc, op) in prog.ops.iter().enumerate() {
        match op {
            Op::Cj { target, .. } | Op::Scj { target, .. } => t[(*target as usize).min(n)] = true,
            Op::Call(target) => {
                t[(*target as usize).min(n)] = true;
                t[pc + 1] = true;
            }
            Op::CallArgs(c) => {
                if let Callee::Here(target) = c.callee {
                    t[(target as usize).min(n)] = true;
                }
            }
            Op::For(_) => t[pc + 1] = true,
            // Where the interpreter, having run the ops an MC turned OFF,
            // comes back to native code.
            Op::Mcr(_) => t[pc + 1] = true,
            Op::Break(b) => t[(b.1 as usize).min(n)] = true,
            Op::Pulse(_) => t[pc + 2] = true,
            _ => {}
        }
    }
    for &(_, pc) in &prog.common_labels {
        t[(pc as usize).min(n)] = true;
    }
    for &(_, pc) in &prog.interrupts {
        t[(pc as usize).min(n)] = true;
    }
    t.truncate(n);
    t
}

#[derive(Clone, Copy)]
struct Limits {
    bits: u32,
    words: u32,
    edges: u32,
}

impl Limits {
    fn edge(self, s: u32) -> Option<u32> {
        (s < self.edges).then_some(s)
    }

    fn bit(self, i: u32) -> Option<u32> {
        (i < self.bits).then_some(i)
    }

    /// A word operand of `words` words starting at a plain index.
    fn word(self, i: u32, words: u8) -> Option<u32> {
        (u64::from(i) + u64::from(words) <= u64::from(self.words)).then_some(i)
    }

    /// A plain word destination.
    fn dest(self, a: &WordArg, words: u8) -> Option<u32> {
        match a {
            WordArg::Word(i) => self.word(*i, words),
            _ => None,
        }
    }

    fn src(self, a: &WordArg, words: u8) -> Option<WordSrc> {
        match a {
            WordArg::Word(i) => self.word(*i, words).map(WordSrc::Word),
            WordArg::Const(k) => Some(WordSrc::Const(*k)),
            WordArg::Digits { .. } | WordArg::Indexed(_) => None,
        }
    }

    fn bit_src(self, a: &BitArg) -> Option<BitSrc> {
        match a {
            BitArg::Bit(i) => self.bit(*i).map(BitSrc::Bit),
            BitArg::WordBit { word, bit } if *bit < 16 => {
                self.word(*word, 1).map(|w| BitSrc::WordBit(w, *bit))
            }
            _ => None,
        }
    }
}

fn contact(join: Join, negate: bool, i: u32, lim: Limits) -> Option<Step> {
    lim.bit(i).map(|b| Step::Contact {
        join,
        negate,
        src: BitSrc::Bit(b),
    })
}

fn coil(store: Store, i: u32, lim: Limits) -> Option<Step> {
    lim.bit(i).map(|bit| Step::Coil { store, bit })
}

/// The native step of `op` (op `pc` of `prog`), if it has one.
fn step(pc: u32, op: &Op, prog: &Program, lim: Limits) -> Option<Step> {
    Some(match op {
        Op::Ld(i) => return contact(Join::Load, false, *i, lim),
        Op::Ldi(i) => return contact(Join::Load, true, *i, lim),
        Op::And(i) => return contact(Join::And, false, *i, lim),
        Op::Ani(i) => return contact(Join::And, true, *i, lim),
        Op::Or(i) => return contact(Join::Or, false, *i, lim),
        Op::Ori(i) => return contact(Join::Or, true, *i, lim),
        Op::Contact(c) => match c.edge {
            Edge::None => Step::Contact {
                join: c.join,
                negate: c.negate,
                src: lim.bit_src(&c.src)?,
            },
            Edge::Rising | Edge::Falling => Step::EdgeContact {
                join: c.join,
                negate: c.negate,
                rising: c.edge == Edge::Rising,
                src: lim.bit_src(&c.src)?,
                slot: lim.edge(c.slot)?,
            },
        },
        Op::Mep(s) => Step::EdgeOfResult {
            rising: true,
            slot: lim.edge(*s)?,
        },
        Op::Mef(s) => Step::EdgeOfResult {
            rising: false,
            slot: lim.edge(*s)?,
        },
        Op::Compare(c) => compare(c, lim)?,
        Op::Push => Step::Push,
        Op::Anb => Step::Anb,
        Op::Orb => Step::Orb,
        Op::Mps => Step::Mps,
        Op::Mrd => Step::Mrd,
        Op::Mpp => Step::Mpp,
        Op::Inv => Step::Inv,
        Op::Out(i) => return coil(Store::Out, *i, lim),
        Op::Set(i) => return coil(Store::Set, *i, lim),
        Op::Rst(i) => return coil(Store::Rst, *i, lim),
        Op::Coil(c) => {
            let store = match c.kind {
                CoilKind::Out => Store::Out,
                CoilKind::Set => Store::Set,
                CoilKind::Rst => Store::Rst,
                CoilKind::Pls(s) | CoilKind::Plf(s) => {
                    let BitArg::Bit(i) = c.dst else {
                        return None;
                    };
                    return Some(Step::PulseCoil {
                        rising: matches!(c.kind, CoilKind::Pls(_)),
                        slot: lim.edge(s)?,
                        bit: lim.bit(i)?,
                    });
                }
                CoilKind::Ff(_) => return None,
            };
            match c.dst {
                BitArg::Bit(i) => return coil(store, i, lim),
                _ => return None,
            }
        }
        Op::MovK { k, d } => action(Action::Move {
            words: 1,
            s: WordSrc::Const(u32::from(*k)),
            d: lim.word(*d, 1)?,
        }),
        Op::MovW { s, d } => action(Action::Move {
            words: 1,
            s: WordSrc::Word(lim.word(*s, 1)?),
            d: lim.word(*d, 1)?,
        }),
        Op::MovD { s, d } => action(Action::Move {
            words: 2,
            s: WordSrc::Word(lim.word(*s, 2)?),
            d: lim.word(*d, 2)?,
        }),
        Op::MovDK { k, d } => action(Action::Move {
            words: 2,
            s: WordSrc::Const(*k),
            d: lim.word(*d, 2)?,
        }),
        Op::Ext(x) => action(word_op(prog.ext.get(*x as usize)?.word_op()?, lim)?),
        Op::Timer(t) => Step::Timer(timer(pc, t, lim)?),
        Op::Counter(c) => Step::Counter(counter(pc, c, lim)?),
        Op::Mc(m) => match m.dst {
            BitArg::Bit(i) => Step::Mc {
                pc,
                bit: lim.bit(i)?,
            },
            _ => return None,
        },
        Op::Mcr(_) => Step::Mcr,
        _ => return None,
    })
}

fn action(a: Action) -> Step {
    Step::Actions(vec![a])
}

/// A word instruction's action on plain words and constants.
fn word_op(w: WordOp, lim: Limits) -> Option<Action> {
    Some(match w {
        WordOp::Binary {
            op,
            wide,
            s1,
            s2,
            d,
        } => {
            let words = if wide { 2 } else { 1 };
            Action::Binary {
                op,
                wide,
                a: lim.src(s1, words)?,
                b: lim.src(s2, words)?,
                d: lim.dest(d, words)?,
            }
        }
        WordOp::Bit { set, d, n } => Action::Bit {
            set,
            d: lim.dest(d, 1)?,
            n: lim.src(n, 1)?,
        },
        WordOp::ResetTc(r) => Action::ResetTc {
            value: lim.word(r.value, 1)?,
            contact: lim.bit(r.contact)?,
            slot: (r.slot != u32::MAX).then_some(r.slot),
        },
    })
}

/// A set value native code reads: a constant that is not negative (the
/// interpreter faults on one that is), or a plain word.
fn set_value(a: &WordArg, lim: Limits) -> Option<WordSrc> {
    match lim.src(a, 1)? {
        WordSrc::Const(k) if (k as u16 as i16) < 0 => None,
        s => Some(s),
    }
}

fn timer(pc: u32, t: &Timer, lim: Limits) -> Option<TimerStep> {
    Some(TimerStep {
        pc,
        coil: lim.bit(t.coil)?,
        contact: lim.bit(t.contact)?,
        value: lim.word(t.value, 1)?,
        slot: t.slot,
        set: set_value(&t.set, lim)?,
        high_speed: t.high_speed,
        retentive: t.retentive,
    })
}

fn counter(pc: u32, c: &Counter, lim: Limits) -> Option<CounterStep> {
    Some(CounterStep {
        pc,
        coil: lim.bit(c.coil)?,
        contact: lim.bit(c.contact)?,
        value: lim.word(c.value, 1)?,
        set: set_value(&c.set, lim)?,
    })
}

fn compare(c: &Compare, lim: Limits) -> Option<Step> {
    let words = match c.num {
        Num::I16 => 1,
        Num::I32 => 2,
        // Reals: ±∞/NaN are operation errors (4100), left to the kernel.
        Num::F32 => return None,
    };
    Some(Step::Compare {
        join: c.join,
        op: c.op,
        wide: words == 2,
        a: lim.src(&c.a, words)?,
        b: lim.src(&c.b, words)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn program(ops: Vec<Op>) -> Program {
        let n = ops.len();
        Program {
            file: "t".into(),
            ops,
            op_step: (0..n as u32).collect(),
            op_line: vec![1; n],
            edge_slots: 1,
            state_words: 0,
            shared_words: 0,
            common_labels: vec![],
            local_labels: vec![],
            interrupts: vec![],
            ext: vec![],
            steps: n as u32,
            bit_len: 100,
            word_len: 100,
            sources: vec![],
            globals: vec![],
            used_devices: vec![],
            listing: Default::default(),
            may_write_x: true,
        }
    }

    /// `k` contacts and coils on bits 0-9.
    fn contacts(k: u32) -> Vec<Op> {
        (0..k)
            .map(|i| {
                if i % 2 == 0 {
                    Op::Ld(i % 10)
                } else {
                    Op::Out(i % 10)
                }
            })
            .collect()
    }

    fn entries(plan: &Plan) -> Vec<usize> {
        (0..plan.entry.len()).filter(|pc| plan.entry[*pc]).collect()
    }

    #[test]
    fn interpreted_stretches_are_runs_between_native_ops() {
        let k = MIN_RUN as u32;
        let mut ops = contacts(k);
        ops.push(Op::Cj {
            target: 2 * k + 3,
            always: false,
        });
        ops.extend(contacts(k - 2));
        ops.push(Op::MovK { k: 7, d: 0 });
        ops.push(Op::MovW { s: 0, d: 1 });
        ops.push(Op::Ld(200)); // outside the 100 bits: interpreted
        ops.push(Op::End);
        let n = ops.len();
        let plan = plan(&program(ops), MIN_RUN);
        let mut native = vec![true; n];
        for pc in [k, 2 * k + 1, 2 * k + 2] {
            native[pc as usize] = false;
        }
        assert_eq!(plan.native, native);
        // CJ's target is interpreted: no entry there; native code may be
        // entered again after the interpreted CJ.
        assert_eq!(entries(&plan), [0, k as usize + 1]);
        let pieces = &plan.chunks[0].pieces;
        let k = k as usize;
        assert_eq!(pieces.len(), 1 + k + 2 + (k - 2) + 1 + 1, "{pieces:?}");
        assert_eq!(pieces[0], Piece::Entry(0));
        assert_eq!(
            pieces[k + 1],
            Piece::Run {
                from: k as u32,
                to: k as u32 + 1,
                guarded: false,
            }
        );
        assert_eq!(pieces[k + 2], Piece::Entry(k as u32 + 1));
        // The two MOVs under one condition.
        let Piece::Step(Step::Actions(run)) = &pieces[2 * k + 1] else {
            panic!("{pieces:?}")
        };
        assert_eq!(run.len(), 2);
        assert_eq!(pieces[2 * k + 2], Piece::Exit(2 * k as u32 + 1));
    }

    #[test]
    fn short_native_runs_between_interpreted_ops_are_interpreted() {
        let p = program(vec![
            Op::Ld(0),
            Op::Out(1),
            Op::Ld(200),
            Op::Out(2),
            Op::End,
        ]);
        let plan = plan(&p, MIN_RUN);
        assert_eq!(plan.native, [false; 5]);
        assert!(plan.chunks[0].pieces.is_empty());
        // Three could be native (bit 200 is beyond the program's memory):
        // `--stats` says they are in short runs.
        assert_eq!(plan.short_run_ops, 3);
        // A whole program of two native ops is native.
        let plan = super::plan(&program(contacts(2)), MIN_RUN);
        assert_eq!(plan.native, [true, true]);
        assert_eq!(plan.short_run_ops, 0);
        assert_eq!(
            plan.chunks[0].pieces.last(),
            Some(&Piece::Exit(2)),
            "{:?}",
            plan.chunks[0].pieces
        );
    }

    #[test]
    fn jump_targets_pulse_skips_and_returns_are_entries() {
        let k = MIN_RUN as u32;
        let mut ops = contacts(k);
        ops.push(Op::Pulse(0)); // k: skips to k + 2
        ops.extend(contacts(k));
        ops.push(Op::For(Box::new(WordArg::Const(3)))); // 2k + 1: NEXT returns after it
        ops.extend(contacts(k));
        ops.push(Op::Cj {
            target: k + 3,
            always: true,
        }); // 3k + 2
        ops.extend(contacts(k));
        ops.push(Op::End);
        let plan = plan(&program(ops), MIN_RUN);
        let k = k as usize;
        // Also after each interpreted op (k, 2k + 1, 3k + 2).
        assert_eq!(
            entries(&plan),
            [0, k + 1, k + 2, k + 3, 2 * k + 2, 3 * k + 3]
        );
        let runs: Vec<&Piece> = plan.chunks[0]
            .pieces
            .iter()
            .filter(|p| matches!(p, Piece::Run { .. }))
            .collect();
        let run = |from: usize| Piece::Run {
            from: from as u32,
            to: from as u32 + 1,
            guarded: false,
        };
        assert_eq!(runs, [&run(k), &run(2 * k + 1), &run(3 * k + 2)]);
        assert_eq!(
            plan.chunks[0].pieces.last(),
            Some(&Piece::Exit(4 * k as u32 + 3))
        );
    }

    #[test]
    fn instructions_that_run_only_when_on_do_not_break_native_runs() {
        // Three quarters of a run, two application instructions, three
        // quarters of a run (together a run, and half one more for the
        // call), then one that also acts while OFF (a pulse gate): only the
        // first joins.
        let h = MIN_RUN as u32 * 3 / 4;
        let mut ops = contacts(h);
        ops.push(Op::Ext(0));
        ops.push(Op::Ext(1));
        ops.extend(contacts(h));
        ops.push(Op::Pulse(0));
        ops.extend(contacts(h));
        ops.push(Op::End);
        let plan = plan(&program(ops), MIN_RUN);
        let h = h as usize;
        let mut native = vec![false; plan.native.len()];
        native[..h].fill(true);
        native[h + 2..2 * h + 2].fill(true);
        assert_eq!(plan.native, native);
        let runs: Vec<&Piece> = plan.chunks[0]
            .pieces
            .iter()
            .filter(|p| matches!(p, Piece::Run { .. }))
            .collect();
        let (from, to) = (h as u32, h as u32 + 2);
        assert_eq!(
            runs,
            [&Piece::Run {
                from,
                to,
                guarded: true
            }]
        );
    }
}
