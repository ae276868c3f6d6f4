//! Writing during RUN (004 §4.8): one program file replaced between two
//! scans, device memory and the hidden state of its unchanged instructions
//! kept.
//!
//! The old and new listings are matched (`softplc_ir::online::carry`): a
//! kept instruction takes its edge memories and state words along, an added
//! one starts cleared. As on the CPU, a falling-edge instruction of the
//! written file (LDF, ANDF, ORF, MEF, PLF: the falling-edge ops) acts once
//! when its condition is OFF at the first scan after the write (004
//! L4388-4392): its edge memory starts ON. The file is linked again with
//! the others (their CALLs into it follow its pointers, its interrupt
//! pointers replace its old ones) and compiled again by the tier in use.
//! Timers' sub-count remainders and counters' coils are device state of the
//! CPU, not of the program, and so are kept anyway.

use super::*;
use softplc_ir::ops::{Callee, CoilKind, Edge, Op};

/// The limits of a write during RUN (004 §4.8 (b), (e)): the CPU's
/// parameters, with the manual's defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OnlineLimits {
    /// Most steps one write may write (the added instructions' steps): 512.
    pub max_steps: u32,
    /// Steps reserved in each program file for growth by writes during RUN:
    /// 500. A file may grow to the steps it was loaded with plus these.
    pub reserve_steps: u32,
}

impl Default for OnlineLimits {
    fn default() -> Self {
        OnlineLimits {
            max_steps: 512,
            reserve_steps: 500,
        }
    }
}

/// What a write during RUN did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Written {
    /// The program file's slot (parameter order).
    pub slot: usize,
    /// Instructions kept (with their state), added and removed.
    pub kept: usize,
    pub added: usize,
    pub removed: usize,
    /// Steps written (the added instructions') and the file's steps now.
    pub steps_written: u32,
    pub steps: u32,
    /// Falling-edge instructions whose edge memory starts ON.
    pub falling_edges: usize,
    /// The END after which the new program runs (the scans so far).
    pub scan: u64,
}

impl Cpu {
    /// Replaces program file `slot` by `program` (compiled for this CPU's
    /// device points), now — between two scans. Refused, with the old
    /// program still running, when the write breaks a limit of
    /// [`CpuConfig::online`], when another file CALLs a pointer the new
    /// program no longer has, when it does not link, or when the tier in
    /// use cannot compile it.
    pub fn replace_program(&mut self, slot: usize, program: Program) -> Result<Written, String> {
        let Some(old) = self.programs.get(slot) else {
            return Err(format!("there is no program file {slot}"));
        };
        if program.bit_len != self.rt.mem.map.bit_len()
            || program.word_len != self.rt.mem.map.word_len()
        {
            return Err(format!(
                "{} was compiled for other device points than this CPU's parameters",
                program.file
            ));
        }
        let limits = self.cfg.online;
        let carry = softplc_ir::online::carry(&old.listing, &program.listing);
        if carry.written_steps > limits.max_steps {
            return Err(format!(
                "{}: the change writes {} steps; a write during RUN writes at most {} (write it in parts, or in STOP)",
                program.file, carry.written_steps, limits.max_steps
            ));
        }
        let capacity = self.slots[slot].capacity_steps;
        if program.steps > capacity {
            return Err(format!(
                "{}: {} steps do not fit the file's {} ({} steps loaded and a reserve of {} for writes during RUN)",
                program.file,
                program.steps,
                capacity,
                capacity - limits.reserve_steps.min(capacity),
                limits.reserve_steps
            ));
        }
        let remap = self.calls_into(slot, &program)?;
        let old = std::mem::replace(&mut self.programs[slot], program);
        let linked = crate::link::link(&mut self.programs, &*self.cfg.system);
        let native = match (&linked, &self.tier) {
            (Ok(_), Some(tier)) => Some(
                tier.compile(&self.programs[slot])
                    .map_err(|e| format!("{}: {e}", self.programs[slot].file)),
            ),
            _ => None,
        };
        let interrupts = match (linked, native) {
            (Err(e), _) | (_, Some(Err(e))) => {
                self.programs[slot] = old;
                return Err(e);
            }
            (Ok(interrupts), native) => {
                if let Some(Ok(n)) = native {
                    self.natives[slot] = n;
                }
                interrupts
            }
        };
        self.interrupts = interrupts;
        for (i, p) in self.programs.iter_mut().enumerate() {
            if i != slot {
                relink(p, slot, &remap);
            }
        }
        let new = &self.programs[slot];
        let mut state = ProgState::new(new);
        let before = &self.locals[slot];
        for (from, to) in &carry.edges {
            carry_over(&mut state.edges, &before.edges, from, *to);
        }
        for (from, to) in &carry.words {
            carry_over(&mut state.state, &before.state, from, *to);
        }
        let falling = falling_edges(new);
        for &s in &falling {
            state.edges[s as usize] = true;
        }
        self.locals[slot] = state;
        let shared = new.shared_words as usize;
        if shared > self.rt.shared.len() {
            let mut grown = vec![0; shared];
            grown[..self.rt.shared.len()].copy_from_slice(&self.rt.shared);
            self.rt.shared = grown.into_boxed_slice();
        }
        if let Some(stats) = &mut self.tier_stats {
            stats.ops = self.programs.iter().map(|p| p.ops.len()).sum();
            stats.native_ops = self.natives.iter().map(|n| n.native_ops()).sum();
            stats.short_run_ops = self.natives.iter().map(|n| n.short_run_ops()).sum();
        }
        self.program_writes += 1;
        self.rt.programs_write_x = self.programs.iter().any(|p| p.may_write_x);
        self.rt.x_touched();
        let written = Written {
            slot,
            kept: carry.kept,
            added: carry.added,
            removed: carry.removed,
            steps_written: carry.written_steps,
            steps: new.steps,
            falling_edges: falling.len(),
            scan: self.scans,
        };
        self.note(super::DoorEvent::Unrecordable {
            why: "a program file was written during RUN",
        });
        Ok(written)
    }

    /// Writes during RUN so far: the tools that show the programs redraw
    /// them when it changes.
    pub fn program_writes(&self) -> u64 {
        self.program_writes
    }

    /// Where the other files' linked CALLs into program `slot` go in `new`:
    /// (old op, new op) of every pointer they reach; refused when `new`
    /// lacks one.
    fn calls_into(&self, slot: usize, new: &Program) -> Result<Vec<(u32, u32)>, String> {
        let old = &self.programs[slot];
        let mut remap = Vec::new();
        for (i, p) in self.programs.iter().enumerate() {
            if i == slot {
                continue;
            }
            for pc in far_calls(p, slot) {
                if remap.iter().any(|&(o, _)| o == pc) {
                    continue;
                }
                let common = old.common_labels.iter().find(|&&(_, at)| at == pc);
                let local = old.local_labels.iter().find(|&&(_, at)| at == pc);
                let found = match (common, local) {
                    (Some(&(n, _)), _) => new
                        .common_labels
                        .iter()
                        .find(|l| l.0 == n)
                        .map(|l| (n, l.1)),
                    (None, Some(&(n, _))) => {
                        new.local_labels.iter().find(|l| l.0 == n).map(|l| (n, l.1))
                    }
                    (None, None) => None,
                };
                match (found, common.or(local)) {
                    (Some((_, at)), _) => remap.push((pc, at)),
                    (None, Some(&(n, _))) => {
                        return Err(format!(
                            "{} CALLs P{n} of {}, which the new program no longer has",
                            p.file, old.file
                        ))
                    }
                    (None, None) => {
                        return Err(format!(
                            "{} CALLs into {} where the new program has no pointer",
                            p.file, old.file
                        ))
                    }
                }
            }
        }
        Ok(remap)
    }
}

/// Copies an unchanged instruction's state `from` the old program's to `to`
/// in the new one's (ranges outside either are left: the compiler's
/// listing always fits its program).
fn carry_over<T: Copy>(new: &mut [T], old: &[T], from: &std::ops::Range<u32>, to: u32) {
    let Some(src) = old.get(from.start as usize..from.end as usize) else {
        return;
    };
    if let Some(dst) = new.get_mut(to as usize..to as usize + src.len()) {
        dst.copy_from_slice(src);
    }
}

/// The op indices in program `slot` that `p`'s linked CALLs reach.
fn far_calls(p: &Program, slot: usize) -> impl Iterator<Item = u32> + '_ {
    p.ops.iter().filter_map(move |op| match op {
        Op::CallFar { slot: s, pc } if *s as usize == slot => Some(*pc),
        Op::CallArgs(c) => match c.callee {
            Callee::Far { slot: s, pc } if s as usize == slot => Some(pc),
            _ => None,
        },
        _ => None,
    })
}

/// Points `p`'s linked CALLs into program `slot` at the new ops `remap` gives.
fn relink(p: &mut Program, slot: usize, remap: &[(u32, u32)]) {
    let moved = |pc: &mut u32| {
        if let Some(&(_, to)) = remap.iter().find(|(from, _)| *from == *pc) {
            *pc = to;
        }
    };
    for op in &mut p.ops {
        match op {
            Op::CallFar { slot: s, pc } if *s as usize == slot => moved(pc),
            Op::CallArgs(c) => {
                if let Callee::Far { slot: s, pc } = &mut c.callee {
                    if usize::from(*s) == slot {
                        moved(pc);
                    }
                }
            }
            _ => {}
        }
    }
}

/// The edge memories of `p`'s falling-edge instructions: LDF/ANDF/ORF
/// contacts, MEF and PLF (the ops that act on a falling edge; the
/// "except on a falling edge" contacts are not among them).
fn falling_edges(p: &Program) -> Vec<u32> {
    p.ops
        .iter()
        .filter_map(|op| match op {
            Op::Contact(c) if c.edge == Edge::Falling && !c.negate => Some(c.slot),
            Op::Mef(s) => Some(*s),
            Op::Coil(c) => match c.kind {
                CoilKind::Plf(s) => Some(s),
                _ => None,
            },
            _ => None,
        })
        .collect()
}
