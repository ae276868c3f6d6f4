//! Ladder-structure checks shared by every instruction: rungs, blocks opened
//! by LD and closed by ANB/ORB, MPS levels, and what an instruction's rung class
//! requires before it (PM §3). Every check reports and lets compilation go on.

use super::compile::{Compiler, MAX_BLOCKS};
use super::isa::Class;
use super::source::{SourceInstr, Token};
use softplc_ir::ops::{Join, Op};

impl Compiler<'_> {
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
