//! Writing during RUN (004 §4.8): which instructions of a program file
//! survive an edit, so that the CPU keeps their hidden state.
//!
//! The old and new listings are compared instruction by instruction, by
//! mnemonic and operands as written (upper case), with labels as anchors;
//! the longest common subsequence (Myers' diff) is what the edit kept. A
//! kept instruction's edge memories and state words move to where the new
//! program has them ([`Held`]); everything else starts cleared.

use std::ops::Range;

use crate::listing::{Entry, Held, Listing};

/// What an edit keeps: the state to copy and what it changed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Carry {
    /// Each kept instruction's edge memories: (old slots, first new slot).
    pub edges: Vec<(Range<u32>, u32)>,
    /// Each kept instruction's state words: (old words, first new word).
    pub words: Vec<(Range<u32>, u32)>,
    /// Instructions kept, added (new or changed) and removed.
    pub kept: usize,
    pub added: usize,
    pub removed: usize,
    /// Steps of the added instructions: what the write writes.
    pub written_steps: u32,
}

/// An entry's text for matching: labels and instructions never match each
/// other.
fn key(e: &Entry) -> String {
    match e {
        Entry::Label { text, .. } => format!(":{}", text.to_ascii_uppercase()),
        Entry::Instr(i) => {
            let mut k = i.mnemonic.to_ascii_uppercase();
            for o in &i.operands {
                k.push(' ');
                k.push_str(&o.to_ascii_uppercase());
            }
            k
        }
    }
}

fn held(e: &Entry) -> Option<&Held> {
    match e {
        Entry::Instr(i) => Some(&i.held),
        Entry::Label { .. } => None,
    }
}

/// What replacing the program of `old` by that of `new` keeps.
pub fn carry(old: &Listing, new: &Listing) -> Carry {
    let a: Vec<String> = old.entries.iter().map(key).collect();
    let b: Vec<String> = new.entries.iter().map(key).collect();
    let mut out = Carry::default();
    let mut kept_new = vec![false; b.len()];
    for op in similar::capture_diff_slices(similar::Algorithm::Myers, &a, &b) {
        let similar::DiffOp::Equal {
            old_index,
            new_index,
            len,
        } = op
        else {
            continue;
        };
        for k in 0..len {
            let (Some(o), Some(n)) = (
                held(&old.entries[old_index + k]),
                held(&new.entries[new_index + k]),
            ) else {
                continue;
            };
            // The same text compiles to the same state; anything else is new.
            if o.edges.len() != n.edges.len() || o.words.len() != n.words.len() {
                continue;
            }
            kept_new[new_index + k] = true;
            out.kept += 1;
            if !o.edges.is_empty() {
                out.edges.push((o.edges.clone(), n.edges.start));
            }
            if !o.words.is_empty() {
                out.words.push((o.words.clone(), n.words.start));
            }
        }
    }
    for (e, kept) in new.entries.iter().zip(&kept_new) {
        if let (Some(h), false) = (held(e), kept) {
            out.added += 1;
            out.written_steps += h.steps.end - h.steps.start;
        }
    }
    let instrs = old.entries.iter().filter(|e| held(e).is_some()).count();
    out.removed = instrs - out.kept;
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::listing::{Listed, Role};

    fn instr(
        m: &str,
        ops: &[&str],
        edges: Range<u32>,
        words: Range<u32>,
        steps: Range<u32>,
    ) -> Entry {
        Entry::Instr(Listed {
            role: Role::Box,
            mnemonic: m.into(),
            operands: ops.iter().map(|s| s.to_string()).collect(),
            line: 1,
            held: Held {
                edges,
                words,
                steps,
            },
        })
    }

    #[test]
    fn kept_instructions_move_their_state_and_new_ones_count_as_written() {
        let old = Listing {
            entries: vec![
                instr("LDP", &["X0"], 0..1, 0..0, 0..2),
                instr("OUT", &["Y0"], 1..1, 0..0, 2..3),
                instr("LD", &["X1"], 1..1, 0..0, 3..4),
                instr("SCL", &["K1", "D0", "D10"], 1..1, 0..3, 4..8),
            ],
            loops: Vec::new(),
        };
        // A rung inserted before the others (LDF, 1 edge, 2 steps; OUT 1
        // step), and `LD X1` written in lower case.
        let new = Listing {
            entries: vec![
                instr("LDF", &["X5"], 0..1, 0..0, 0..2),
                instr("OUT", &["Y5"], 1..1, 0..0, 2..3),
                instr("LDP", &["X0"], 1..2, 0..0, 3..5),
                instr("OUT", &["Y0"], 2..2, 0..0, 5..6),
                instr("ld", &["x1"], 2..2, 0..0, 6..7),
                instr("SCL", &["K1", "D0", "D10"], 2..2, 0..3, 7..11),
            ],
            loops: Vec::new(),
        };
        let c = carry(&old, &new);
        assert_eq!(c.edges, vec![(0..1, 1)]);
        assert_eq!(c.words, vec![(0..3, 0)]);
        assert_eq!((c.kept, c.added, c.removed, c.written_steps), (4, 2, 0, 3));
    }

    #[test]
    fn a_changed_operand_is_a_new_instruction() {
        let old = Listing {
            entries: vec![instr("PLS", &["M0"], 0..1, 0..0, 0..2)],
            loops: Vec::new(),
        };
        let new = Listing {
            entries: vec![instr("PLS", &["M1"], 0..1, 0..0, 0..2)],
            loops: Vec::new(),
        };
        let c = carry(&old, &new);
        assert!(c.edges.is_empty());
        assert_eq!((c.kept, c.added, c.removed, c.written_steps), (0, 1, 1, 2));
    }
}
