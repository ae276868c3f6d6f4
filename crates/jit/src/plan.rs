//! Ops → a straight-line plan per chunk: which ops run as native code, where
//! a native region may be entered, and where it hands back to the interpreter.
//!
//! Native are only ops that cannot fault and touch nothing but the rung
//! registers and plain device indices: contacts and coils on plain bits (or a
//! word's bit), the ANB/ORB block stack and MPS stack, MOV/DMOV on plain
//! words and constants, and 16/32-bit comparison contacts on plain words and
//! constants. Everything else (edges, pulse forms, timers, counters,
//! application instructions, index modification, jumps, calls, FOR/NEXT,
//! master control) is an exit: the region returns that op's index and the
//! interpreter runs it with the shared implementation.

use softplc_ir::ops::{
    Apply, BitArg, CmpOp, CoilKind, Compare, Edge, Join, Num, Op, Program, WordArg,
};

/// Most ops compiled into one function, so compile time stays linear in the
/// program's length (Cranelift's register allocation is superlinear in a
/// function's size).
pub const CHUNK_OPS: usize = 4096;

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

/// What a coil does with the condition (`acc & mc_on`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Store {
    Out,
    Set,
    Rst,
}

/// A MOV (1 word) or DMOV (2 words) into a plain word device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Move {
    pub words: u8,
    pub s: WordSrc,
    pub d: u32,
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
    /// Consecutive MOVs under one condition (a MOV leaves the operation
    /// result unchanged, so one test guards the run).
    Movs(Vec<Move>),
}

/// An element of a chunk's plan, in op order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Piece {
    /// A region may be entered at op `pc` (the interpreter calls in here).
    Entry(u32),
    Step(Step),
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
    /// For every op, whether a region starts there.
    pub entry: Vec<bool>,
}

/// Plans `prog`, checking every device index against the memory size it was
/// compiled for (an op with an index outside is left to the interpreter).
pub fn plan(prog: &Program) -> Plan {
    let lim = Limits {
        bits: prog.bit_len,
        words: prog.word_len,
    };
    let steps: Vec<Option<Step>> = prog.ops.iter().map(|op| step(op, lim)).collect();
    let native: Vec<bool> = steps.iter().map(Option::is_some).collect();
    let targets = targets(prog);
    let n = prog.ops.len();
    let entry: Vec<bool> = (0..n)
        .map(|pc| native[pc] && (pc % CHUNK_OPS == 0 || !native[pc - 1] || targets[pc]))
        .collect();
    let mut chunks = Vec::with_capacity(n.div_ceil(CHUNK_OPS));
    for start in (0..n).step_by(CHUNK_OPS) {
        let end = (start + CHUNK_OPS).min(n);
        chunks.push(chunk(start, end, &steps, &entry));
    }
    Plan {
        chunks,
        native,
        entry,
    }
}

fn chunk(start: usize, end: usize, steps: &[Option<Step>], entry: &[bool]) -> Chunk {
    let mut pieces = Vec::new();
    // Inside a region (native code is being emitted)?
    let mut inside = false;
    for pc in start..end {
        match &steps[pc] {
            Some(s) => {
                if entry[pc] {
                    pieces.push(Piece::Entry(pc as u32));
                    inside = true;
                }
                if !inside {
                    // Reached only through the interpreter (mid-region target
                    // that is not an entry cannot occur: entries cover them).
                    continue;
                }
                match (s, pieces.last_mut()) {
                    (Step::Movs(m), Some(Piece::Step(Step::Movs(run)))) if !entry[pc] => {
                        run.extend_from_slice(m)
                    }
                    _ => pieces.push(Piece::Step(s.clone())),
                }
            }
            None => {
                if inside {
                    pieces.push(Piece::Exit(pc as u32));
                    inside = false;
                }
            }
        }
    }
    if inside {
        pieces.push(Piece::Exit(end as u32));
    }
    Chunk {
        start: start as u32,
        end: end as u32,
        pieces,
    }
}

/// Ops where execution can arrive other than from the op before: jump, CALL
/// and BREAK targets, common and interrupt pointers, and the op after the one
/// a pulse gate skips.
fn targets(prog: &Program) -> Vec<bool> {
    let n = prog.ops.len();
    let mut t = vec![false; n + 2];
    for (pc, op) in prog.ops.iter().enumerate() {
        match op {
            Op::Cj { target, .. } | Op::Scj { target, .. } | Op::Call(target) => {
                t[(*target as usize).min(n)] = true
            }
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
}

impl Limits {
    fn bit(self, i: u32) -> Option<u32> {
        (i < self.bits).then_some(i)
    }

    /// A word operand of `words` words starting at a plain index.
    fn word(self, i: u32, words: u8) -> Option<u32> {
        (u64::from(i) + u64::from(words) <= u64::from(self.words)).then_some(i)
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

/// The native step of `op`, if it has one.
fn step(op: &Op, lim: Limits) -> Option<Step> {
    Some(match op {
        Op::Ld(i) => return contact(Join::Load, false, *i, lim),
        Op::Ldi(i) => return contact(Join::Load, true, *i, lim),
        Op::And(i) => return contact(Join::And, false, *i, lim),
        Op::Ani(i) => return contact(Join::And, true, *i, lim),
        Op::Or(i) => return contact(Join::Or, false, *i, lim),
        Op::Ori(i) => return contact(Join::Or, true, *i, lim),
        Op::Contact(c) if c.edge == Edge::None => Step::Contact {
            join: c.join,
            negate: c.negate,
            src: lim.bit_src(&c.src)?,
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
                CoilKind::Pls(_) | CoilKind::Plf(_) | CoilKind::Ff(_) => return None,
            };
            match c.dst {
                BitArg::Bit(i) => return coil(store, i, lim),
                _ => return None,
            }
        }
        Op::MovK { k, d } => Step::Movs(vec![Move {
            words: 1,
            s: WordSrc::Const(u32::from(*k)),
            d: lim.word(*d, 1)?,
        }]),
        Op::MovW { s, d } => Step::Movs(vec![Move {
            words: 1,
            s: WordSrc::Word(lim.word(*s, 1)?),
            d: lim.word(*d, 1)?,
        }]),
        Op::Apply(a) => match &**a {
            Apply::Mov {
                words,
                s,
                d: WordArg::Word(d),
            } if *words == 1 || *words == 2 => Step::Movs(vec![Move {
                words: *words,
                s: lim.src(s, *words)?,
                d: lim.word(*d, *words)?,
            }]),
            _ => return None,
        },
        _ => return None,
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
            prog_names: vec![],
            common_labels: vec![],
            interrupts: vec![],
            ext: vec![],
            steps: n as u32,
            bit_len: 100,
            word_len: 100,
            sources: vec![],
            globals: vec![],
            used_devices: vec![],
        }
    }

    #[test]
    fn regions_exit_at_interpreted_ops_and_reenter_after_them() {
        // LD M0, OUT M1, CJ → 4, MOV, MOV, END
        let p = program(vec![
            Op::Ld(0),
            Op::Out(1),
            Op::Cj {
                target: 5,
                always: false,
            },
            Op::MovK { k: 7, d: 0 },
            Op::MovW { s: 0, d: 1 },
            Op::Ld(200), // outside the 100 bits: interpreted
            Op::End,
        ]);
        let plan = plan(&p);
        assert_eq!(plan.native, [true, true, false, true, true, false, false]);
        assert_eq!(plan.entry, [true, false, false, true, false, false, false]);
        let pieces = &plan.chunks[0].pieces;
        assert_eq!(pieces.len(), 7);
        assert_eq!(pieces[0], Piece::Entry(0));
        assert_eq!(pieces[3], Piece::Exit(2));
        assert_eq!(pieces[4], Piece::Entry(3));
        // The two MOVs under one condition.
        let Piece::Step(Step::Movs(run)) = &pieces[5] else {
            panic!("{pieces:?}")
        };
        assert_eq!(run.len(), 2);
        assert_eq!(pieces[6], Piece::Exit(5));
    }

    #[test]
    fn jump_targets_and_pulse_skips_are_entries() {
        let p = program(vec![
            Op::Ld(0),
            Op::Pulse(0),
            Op::MovK { k: 1, d: 0 },
            Op::MovK { k: 2, d: 1 },
            Op::Out(3),
            Op::Cj {
                target: 4,
                always: true,
            },
            Op::End,
        ]);
        let plan = plan(&p);
        assert_eq!(plan.entry, [true, false, true, true, true, false, false]);
    }
}
