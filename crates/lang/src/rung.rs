//! Ladder-structure checks shared by every instruction: rungs, blocks opened
//! by LD and closed by ANB/ORB, MPS levels, and what an instruction's rung class
//! requires before it (PM §3). Every check reports and lets compilation go on.

use super::compile::{Compiler, MAX_BLOCKS};
use super::isa::{Class, Use};
use super::source::{SourceInstr, Token};
use softplc_ir::ops::{Join, Op};

/// An operation on the rung's two stacks (PM §3.5-§3.6; 002 L2757-2820, the
/// same rules): ANB/ORB combine the last block an LD opened with the one
/// before, MPS/MRD/MPP push, read and pop the branch stack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RungStack {
    Anb,
    Orb,
    Mps,
    Mrd,
    Mpp,
}

/// How deep a dialect nests MPS, and how it words the excess: "more than
/// {depth} {excess}".
#[derive(Clone, Copy, Debug)]
pub struct MpsLimit {
    pub depth: usize,
    pub excess: &'static str,
}

impl Compiler<'_> {
    /// The rung-stack rules of both dialects, after the dialect checked the
    /// operands (none): ANB/ORB need a block to combine; MPS/MRD/MPP need a
    /// rung, MPS at most `limit.depth` deep, MRD/MPP an open MPS (an MPS
    /// left open is reported where the rung closes). Emits the op.
    pub fn rung_stack(&mut self, i: &SourceInstr, m: &str, op: RungStack, limit: MpsLimit) {
        match op {
            RungStack::Anb | RungStack::Orb => {
                if self.depth == 0 {
                    self.err(
                        &i.mnemonic,
                        format!("`{m}` has no block to combine (no LD opened one)"),
                    );
                } else {
                    self.depth -= 1;
                }
            }
            RungStack::Mps | RungStack::Mrd | RungStack::Mpp => {
                if !self.need_rung(i, m) {
                    return;
                }
                if op == RungStack::Mps {
                    if self.mps.len() >= limit.depth {
                        let excess = format!("more than {} {}", limit.depth, limit.excess);
                        self.err(&i.mnemonic, excess);
                    } else {
                        self.mps.push(i.mnemonic.clone());
                    }
                } else if self.mps.is_empty() {
                    self.err(&i.mnemonic, format!("`{m}` without MPS"));
                } else if op == RungStack::Mpp {
                    self.mps.pop();
                }
            }
        }
        self.after_output = false;
        self.emit(match op {
            RungStack::Anb => Op::Anb,
            RungStack::Orb => Op::Orb,
            RungStack::Mps => Op::Mps,
            RungStack::Mrd => Op::Mrd,
            RungStack::Mpp => Op::Mpp,
        });
    }

    /// After a faulty instruction, puts the rung state where a correct one of the
    /// same class would have left it, so one mistake gives one diagnostic. An
    /// unknown mnemonic counts as an output.
    pub fn recover(&mut self, class: Option<Class>) {
        match class {
            Some(Class::Contact) => {
                self.has_rung = true;
                self.after_output = false;
            }
            Some(Class::Standalone) => {
                self.has_rung = false;
                self.after_output = true;
                self.depth = 0;
                self.mps.clear();
            }
            Some(Class::Output | Class::Connection) | None => {
                self.has_rung = true;
                self.after_output = true;
                self.depth = 0;
            }
        }
    }

    pub fn count(&mut self, i: &SourceInstr, m: &str, allowed: &[usize]) -> bool {
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

    /// Rung bookkeeping for a contact; emits `op` (preceded by `Push` when it opens
    /// a block inside a rung).
    pub fn contact(&mut self, i: &SourceInstr, join: Join, op: Op) {
        if self.contact_state(i, join) {
            self.emit(Op::Push);
        }
        self.emit(op);
    }

    /// Updates the rung state for a contact; true when a block must be pushed.
    pub fn contact_state(&mut self, i: &SourceInstr, join: Join) -> bool {
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
    pub fn close_rung(&mut self, at: &Token) {
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

    pub fn need_rung(&mut self, i: &SourceInstr, m: &str) -> bool {
        if !self.has_rung {
            self.err(&i.mnemonic, format!("`{m}` needs a preceding LD"));
            return false;
        }
        true
    }

    /// Checks an instruction driven by the rung condition.
    pub fn output(&mut self, i: &SourceInstr, m: &str) -> bool {
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
    pub fn standalone(&mut self, i: &SourceInstr, m: &str) -> bool {
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

    /// For a lowering shared by several definitions that tells them apart by
    /// name: `u` is none of the names it knows. Reported as a load error at
    /// the mnemonic (a softplc bug), so that a definition added without its
    /// case never runs as another instruction.
    pub fn unmatched(&mut self, u: &Use<'_>) {
        self.err(
            &u.instr.mnemonic,
            format!(
                "`{}` has no case in its definition's lowering (a softplc bug: please report it)",
                u.m
            ),
        );
    }

    pub fn pulsed(&mut self, pulse: bool, op: Op) {
        if pulse {
            let s = self.slot();
            self.emit(Op::Pulse(s));
        }
        self.emit(op);
    }

    /// Emits instruction `x` of a lowering function: run while the
    /// condition is ON (behind the pulse gate with `pulse`), or with `always`
    /// at every execution (`Instr::off` while the condition is OFF).
    pub fn emit_instr(&mut self, pulse: bool, always: bool, x: Box<dyn softplc_ir::instr::Instr>) {
        let at = self.ext.len() as u32;
        self.ext.push(x);
        self.pulsed(
            pulse,
            if always {
                Op::ExtAlways(at)
            } else {
                Op::Ext(at)
            },
        );
    }
}
