//! SFC in IL: STL, SET/OUT S as transitions, RST S, RET (002 §5.2
//! L3019-3101, chapter 7 L9585-10058; spec aplc.md §3.4, decision D16).
//!
//! A single `STL Sn` opens Sn's step body, which runs up to the next STL, RET
//! or the end of the POU. While Sn is active the body runs; on the scan after
//! it was deactivated the body runs once with every condition OFF (OUT coils
//! OFF, TON/TOF reset, SET/RST and counters hold: the destinations the
//! manual lists are cleared, one scan late, L9819-9823); after that it is
//! skipped. A run of 2-16 consecutive STLs is a merge: the logic after it runs
//! while all its steps are active. In a step (or merge), `SET Sm`/`OUT Sm`
//! reset the current step(s) and set Sm. Compiled on the master-control
//! level 15 of the engine (MC/MCR may not be used in steps, L2518).

use std::collections::HashMap;

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr, LocalSlot, LocalState};
use softplc_ir::local_state;
use softplc_ir::ops::{BitArg, MasterControl, Op};
use softplc_lang::compile::Compiler;
use softplc_lang::isa::{Class, Def, Doc, Role, Steps, Use};
use softplc_lang::SourceInstr;

use crate::devices::{parse_device, Dev, STEP_MC_BIT, STEP_SKIP_BIT};

static DOC: Doc = Doc {
    family: "SFC steps",
    cite: "002 §5.2 L3019-3101, ch. 7 L9585-10058",
    notes: "STL opens a step body (each S at most one, L9889), 2-16 consecutive STLs a merge (D16); SET/OUT S in a step move to the target; a deactivated step's body runs once with conditions OFF, then is skipped; RET ends the SFC section (MAIN only)",
};

pub static DEFS: &[Def] = &[
    // 002 §5.2 L3021 STL (compiled by the driver, which sees the runs of STL)
    Def::lower("STL", Class::Standalone, &DOC, by_driver)
        .role(Role::Step)
        .steps(Steps::Fixed(3)),
    // 002 §5.2 L3089 RET
    Def::lower("RET", Class::Standalone, &DOC, by_driver)
        .role(Role::StepsEnd)
        .steps(Steps::Fixed(1)),
];

fn by_driver(c: &mut Compiler<'_>, u: &Use<'_>) {
    c.err(
        &u.instr.mnemonic,
        format!("`{}` is compiled by the POU driver", u.m),
    );
}

/// The engine's master-control level the steps use (MC uses 0-6).
const LEVEL: u8 = 15;
/// Consecutive STLs of a merge (L3039).
const MAX_MERGE: usize = 16;

local_state! {
    struct Gate {
        was: bool,
    }
}

/// Decides each scan whether a step body runs, runs its clearing pass, or is
/// skipped (the skip bit).
#[derive(Debug)]
struct StepGate {
    step: u32,
    skip: u32,
    st: LocalSlot<Gate>,
}

impl Instr for StepGate {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let active = cx.mem.bits[self.step as usize];
        let mut g = cx.local(&self.st);
        cx.mem.bits[self.skip as usize] = !active && !g.was;
        g.was = active;
        cx.set_local(&self.st, g);
        Ok(())
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.exec(cx)
    }
}

/// The open step or merge.
struct Open {
    steps: Vec<u32>,
    /// The `Cj` skipping a step body.
    skip: Option<usize>,
}

/// SFC state of the POU being compiled.
#[derive(Default)]
pub struct Sfc {
    open: Option<Open>,
    /// Step bodies opened: S number → line.
    bodies: HashMap<u32, u32>,
}

impl Sfc {
    pub fn in_step(&self) -> bool {
        self.open.is_some()
    }

    /// Ends the open step body (at the next STL, RET or the POU's end).
    pub fn close(&mut self, c: &mut Compiler<'_>) {
        if let Some(open) = self.open.take() {
            c.emit(Op::Mcr(LEVEL));
            if let Some(at) = open.skip {
                let end = c.ops.len() as u32;
                if let Op::Cj { target, .. } = &mut c.ops[at] {
                    *target = end;
                }
            }
            c.has_rung = false;
            c.after_output = true;
        }
    }

    /// A run of consecutive STLs: one step body, or a merge.
    pub fn stl(&mut self, c: &mut Compiler<'_>, run: &[&SourceInstr]) {
        self.close(c);
        if !c.mc_open.is_empty() {
            c.err(
                &run[0].mnemonic,
                "STL inside MC: MC/MCR and SFC steps may not be mixed (APLC programming manual §4.5.3)",
            );
            return;
        }
        if run.len() > MAX_MERGE {
            c.err(
                &run[MAX_MERGE].mnemonic,
                format!("more than {MAX_MERGE} consecutive STL (APLC programming manual §5.3.1)"),
            );
            return;
        }
        let mut steps = Vec::new();
        for i in run {
            if !c.count(i, "STL", &[1]) {
                return;
            }
            let tok = &i.operands[0];
            match parse_device(&tok.text.to_ascii_uppercase()) {
                Ok(Some(d)) if d.dev == Dev::S && d.group.is_none() && d.index.is_none() => {
                    steps.push((d.n, tok));
                }
                Ok(_) => return c.err(tok, format!("`{}`: STL takes a step S0-S1023", tok.text)),
                Err(e) => return c.err(tok, e),
            }
        }
        let s_base = c.map.base(DeviceKind::S);
        let v_base = c.map.base(DeviceKind::V);
        let mut skip = None;
        if let [(n, tok)] = steps[..] {
            if let Some(line) = self.bodies.insert(n, tok.line) {
                c.err(tok, format!("S{n} opens a second step body (first at line {line}): each step once (APLC programming manual §7.4.1)"));
            }
            let slot = c.state_words;
            c.state_words += <Gate as LocalState>::WORDS;
            let x = c.ext.len() as u32;
            c.ext.push(Box::new(StepGate {
                step: s_base + n,
                skip: v_base + STEP_SKIP_BIT,
                st: LocalSlot::new(slot),
            }));
            c.emit(Op::ExtAlways(x));
            c.emit(Op::Ld(v_base + STEP_SKIP_BIT));
            skip = Some(c.emit(Op::Cj {
                target: 0,
                always: false,
            }));
        }
        for (k, (n, _)) in steps.iter().enumerate() {
            c.emit(if k == 0 {
                Op::Ld(s_base + n)
            } else {
                Op::And(s_base + n)
            });
        }
        let dst = BitArg::Bit(v_base + STEP_MC_BIT);
        c.emit(Op::Mc(Box::new(MasterControl { level: LEVEL, dst })));
        // The step's state is the power flow of an OUT written right after STL;
        // an LD starts a rung of its own.
        c.has_rung = true;
        c.after_output = true;
        self.open = Some(Open {
            steps: steps.iter().map(|(n, _)| s_base + n).collect(),
            skip,
        });
    }

    /// `SET Sm`/`OUT Sm` in a step: reset the current step(s), set Sm. Returns
    /// false when `i` is not such a transition.
    pub fn transition(&mut self, c: &mut Compiler<'_>, i: &SourceInstr, m: &str) -> bool {
        let Some(open) = &self.open else {
            return false;
        };
        let target = match i.operands.as_slice() {
            [t] => match parse_device(&t.text.to_ascii_uppercase()) {
                Ok(Some(d)) if d.dev == Dev::S && d.group.is_none() && d.index.is_none() => d.n,
                _ => return false,
            },
            _ => return false,
        };
        if !c.output(i, m) {
            return true;
        }
        for s in &open.steps {
            c.emit(Op::Rst(*s));
        }
        c.emit(Op::Set(c.map.base(DeviceKind::S) + target));
        true
    }
}
