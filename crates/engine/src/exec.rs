//! The interpreter: runs compiled ops from step 0 to END/FEND.
//!
//! The operation result (`acc`), the block stack of ANB/ORB and the MPS stack are
//! fields of the pass that the compiler keeps in registers; the two stacks are
//! bit stacks in a `u32` (depth is checked at load time), so contacts and coils
//! never touch the heap.
//!
//! With a native tier, native code runs from every op where a region starts;
//! it executes the ops it has no native code for by calling back into
//! [`Pass::op`] (through [`Host`]), so every op has the one implementation
//! here.

use super::call_args;
use super::local_devices::Entry;
use super::tier::{Host, NativeProgram, NativeState, Regs, LEAVE, NO_REGION};
use super::{ProgState, Runtime};
use softplc_ir::fault::Fault;
use softplc_ir::kernels::{basic, sequence};
use softplc_ir::ops::MAX_NESTING;
use softplc_ir::ops::{CallArgs, Callee, Edge, Join, Op, Program};

/// How a pass through the program ended.
pub(crate) enum Outcome {
    /// END or FEND reached (or GOEND).
    End,
    /// An instruction of program `slot` faulted at op index `pc`; the CPU stops.
    Fault(Fault, usize, usize),
    /// RET of a subroutine called from another file (a nested pass ends).
    Return,
    /// The host asked the CPU to stop (`Cpu::abort_handle`), mid-scan.
    Abort,
}

/// Back jumps between two wall-clock watchdog checks.
const WDT_CHECK_EVERY: u32 = 1024;

#[inline(always)]
fn join(acc: &mut bool, j: Join, v: bool) {
    match j {
        Join::Load => *acc = v,
        Join::And => *acc &= v,
        Join::Or => *acc |= v,
    }
}

/// Native code of the CPU's programs (one per program), or none (interpreter).
pub(crate) type Natives = [Box<dyn NativeProgram>];

/// Where a pass goes after an op.
enum Flow {
    /// On at this op index.
    Next(usize),
    /// The pass is over.
    Done(Outcome),
}

/// Runs the program once from op `start` (0, or an interrupt pointer) to END/FEND
/// (or IRET). Faults of the "continue" class are recorded through
/// `rt.record_fault` and execution goes on after the failing op.
///
/// With `natives` (a native tier, `tier.rs`), a native region runs wherever
/// one starts.
pub(crate) fn run(
    progs: &[Program],
    natives: &Natives,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    cur: usize,
    start: usize,
) -> Outcome {
    let off = rt.force_off;
    rt.mc_off = 0;
    let fixed = Fixed {
        progs,
        natives,
        prog: &progs[cur],
        cur,
        off,
        watchdog: rt.watchdog,
    };
    let rung = Rung {
        acc: false,
        blocks: 0,
        mps: 0,
        // POFF: the program runs once with every condition forced OFF.
        mc_on: !off,
    };
    // Two instances, so the interpreter alone pays nothing for the tier (nor
    // a program the tier has no native code for).
    if !matches!(natives.get(cur), Some(n) if n.native_ops() > 0) {
        interpret::<false>(fixed, locals, rt, rung, start)
    } else {
        interpret::<true>(fixed, locals, rt, rung, start)
    }
}

/// What does not change during a pass.
#[derive(Clone, Copy)]
struct Fixed<'a> {
    progs: &'a [Program],
    natives: &'a Natives,
    /// The program running, `progs[cur]`.
    prog: &'a Program,
    cur: usize,
    /// POFF: every condition forced OFF.
    off: bool,
    watchdog: std::time::Duration,
}

/// The rung registers: the operation result, the ANB/ORB block stack and the
/// MPS stack, and whether no master control (and no POFF) forces conditions
/// OFF. A local of the interpreter's loop, never behind a pointer, so that
/// they stay in machine registers.
#[derive(Clone, Copy)]
struct Rung {
    acc: bool,
    blocks: u32,
    mps: u32,
    mc_on: bool,
}

impl From<Rung> for Regs {
    fn from(r: Rung) -> Regs {
        Regs {
            acc: r.acc as u32,
            blocks: r.blocks,
            mps: r.mps,
            mc_on: r.mc_on as u32,
        }
    }
}

impl From<Regs> for Rung {
    fn from(r: Regs) -> Rung {
        Rung {
            acc: r.acc != 0,
            blocks: r.blocks,
            mps: r.mps,
            mc_on: r.mc_on != 0,
        }
    }
}

/// The return address of a nested pass's call (a call with arguments): its
/// RET ends the pass.
const NESTED: u32 = u32::MAX;

/// A nested pass over program `slot` from op `target` until its RET (a
/// CALL into another file, a call with arguments): `ret` is pushed as the
/// caller's return (`(file, op)`, or [`NESTED`]), the callee file's local
/// devices are swapped in when `callee_locals` (and SM776 says so), and the
/// caller's master-control state comes back after it. The caller checks
/// the nesting depth.
fn nested_pass(
    k: Fixed,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    ret: (u32, u32),
    slot: usize,
    target: usize,
    callee_locals: bool,
) -> Outcome {
    rt.calls.push(ret);
    let mc_off = rt.mc_off;
    // On the caller's local devices or the callee file's (004 §10.13.1 (e)).
    let back = if callee_locals {
        rt.enter_locals(slot, Entry::Call)
    } else {
        None
    };
    let out = run(k.progs, k.natives, locals, rt, slot, target);
    rt.leave_locals(back);
    rt.mc_off = mc_off;
    out
}

/// A call with arguments (or FCALL, ECALL): the arguments in, a nested pass
/// over the subroutine at op `target` of program `slot` (with every
/// condition OFF for FCALL's non-execution processing, `off`), the outputs
/// back. `Some` outcome: the pass ended otherwise than by RET.
#[inline(never)]
fn call_args(
    k: Fixed,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    c: &CallArgs,
    slot: usize,
    target: usize,
    off: bool,
) -> Result<Option<Outcome>, Fault> {
    if slot >= k.progs.len() {
        return Err(Fault::NoProgram);
    }
    if rt.calls.len() >= MAX_NESTING {
        return Err(Fault::CallNesting);
    }
    let caller = call_args::enter(&mut rt.mem, &c.args)?;
    let force_off = rt.force_off;
    rt.force_off |= off;
    let out = nested_pass(
        k,
        locals,
        rt,
        (k.cur as u32, NESTED),
        slot,
        target,
        slot != k.cur,
    );
    rt.force_off = force_off;
    call_args::leave(&mut rt.mem, &c.args, &caller)?;
    Ok(match out {
        Outcome::Return => None,
        other => Some(other),
    })
}

#[inline(never)]
fn interpret<const NATIVE: bool>(
    k: Fixed,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    mut r: Rung,
    start: usize,
) -> Outcome {
    let ops = &k.prog.ops[..];
    let native = k.natives.get(k.cur);
    let entries: &[u32] = native.map_or(&[], |n| n.entries());
    let mut back_jumps = 0u32;
    let mut pc = start;
    loop {
        if NATIVE {
            let unit = entries.get(pc).copied().unwrap_or(NO_REGION);
            // Native code only while no MC/POFF forces conditions OFF
            // (`NativeProgram::run`); the interpreter runs those ops.
            if let (true, Some(native)) = (unit != NO_REGION && r.mc_on, native) {
                let mut ended = None;
                let (next, regs) = enter(
                    k,
                    locals,
                    rt,
                    &**native,
                    unit,
                    pc,
                    Regs::from(r),
                    &mut back_jumps,
                    &mut ended,
                );
                r = Rung::from(regs);
                if next == LEAVE {
                    return ended.unwrap_or(Outcome::End);
                }
                if next as usize != pc {
                    pc = next as usize;
                    continue;
                }
            }
        }
        match op::<true>(k, locals, rt, &mut back_jumps, &ops[pc], &mut r, pc) {
            Flow::Next(next) => pc = next,
            Flow::Done(out) => return out,
        }
    }
}

/// Runs `native`'s region `unit` at op `pc` on `regs`: the op to go on at
/// (or [`LEAVE`], with the outcome in `ended`) and the registers after.
/// Apart from the interpreter's loop, and taking and returning the registers
/// by value, so that the loop keeps them in machine registers.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn enter(
    k: Fixed,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    native: &dyn NativeProgram,
    unit: u32,
    pc: usize,
    mut regs: Regs,
    back_jumps: &mut u32,
    ended: &mut Option<Outcome>,
) -> (u32, Regs) {
    let mut host = Callback {
        k,
        locals,
        rt,
        back_jumps: *back_jumps,
        ended: None,
    };
    let next = native.run(unit, pc as u32, &mut regs, &mut host);
    *back_jumps = host.back_jumps;
    *ended = host.ended;
    (next, regs)
}

/// Runs `code`, op `pc` of program `k.cur`. `OUT_OF_LINE`: the rarer ops
/// (program control, master control, edges) run in a call ([`rare`]), so
/// that the interpreter's loop keeps its registers for the others; native
/// code's calls keep them inline, where the call would cost more than it
/// saves.
#[inline(always)]
fn op<const OUT_OF_LINE: bool>(
    k: Fixed,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    back_jumps: &mut u32,
    code: &Op,
    r: &mut Rung,
    pc: usize,
) -> Flow {
    let (prog, cur) = (k.prog, k.cur);
    let acc = &mut r.acc;
    let mc_on = &mut r.mc_on;
    let mut next = pc + 1;
    macro_rules! try_op {
        ($e:expr) => {
            if let Err(code) = $e {
                if rt.record_fault(prog, code, pc) {
                    return Flow::Done(Outcome::Fault(code, cur, pc));
                }
            }
        };
    }
    /// What a family instruction sees while it runs.
    macro_rules! exec_ctx {
        () => {
            softplc_ir::instr::ExecCtx {
                mem: &mut rt.mem,
                state: &mut locals[cur].state,
                now_us: rt.now_us,
                scan_us: rt.scan_us,
                clock: &mut rt.clock,
                shared: &mut rt.shared,
                cpu: &mut rt.cpu,
            }
        };
    }
    macro_rules! back_jump {
        ($target:expr) => {
            if ($target as usize) <= pc {
                *back_jumps += 1;
                if *back_jumps % WDT_CHECK_EVERY == 0 {
                    // A loop that resets the watchdog (WDT) still stops on request.
                    if rt.abort.load(std::sync::atomic::Ordering::Relaxed) {
                        return Flow::Done(Outcome::Abort);
                    }
                    if rt.cpu.watchdog_start.elapsed() > k.watchdog {
                        return Flow::Done(Outcome::Fault(Fault::Watchdog, cur, pc));
                    }
                }
            }
        };
    }
    let cond = *acc & *mc_on;
    match code {
        Op::Mep(_)
        | Op::Mef(_)
        | Op::DirectIn(_)
        | Op::EdgeRelay { .. }
        | Op::Mc(_)
        | Op::Mcr(_)
        | Op::Scj { .. }
        | Op::GoEnd
        | Op::Call(_)
        | Op::CallFar { .. }
        | Op::CallCommon(_)
        | Op::Ret
        | Op::CallArgs(_)
        | Op::For(_)
        | Op::Next
        | Op::Break(_)
        | Op::Stop
        | Op::StopNow
        | Op::Iret
            if OUT_OF_LINE =>
        {
            return rare(k, locals, rt, back_jumps, code, r, pc);
        }
        Op::Ld(i) => *acc = rt.mem.bits[*i as usize],
        Op::Ldi(i) => *acc = !rt.mem.bits[*i as usize],
        Op::And(i) => *acc &= rt.mem.bits[*i as usize],
        Op::Ani(i) => *acc &= !rt.mem.bits[*i as usize],
        Op::Or(i) => *acc |= rt.mem.bits[*i as usize],
        Op::Ori(i) => *acc |= !rt.mem.bits[*i as usize],
        Op::Contact(c) => {
            let v = match rt.mem.read_bit(&c.src) {
                Ok(v) => v,
                Err(code) => {
                    try_op!(Err::<(), _>(code));
                    return Flow::Next(next);
                }
            };
            let v = match c.edge {
                Edge::None => v,
                Edge::Rising => {
                    let prev = std::mem::replace(&mut locals[cur].edges[c.slot as usize], v);
                    v && !prev
                }
                Edge::Falling => {
                    let prev = std::mem::replace(&mut locals[cur].edges[c.slot as usize], v);
                    !v && prev
                }
            };
            join(&mut *acc, c.join, v ^ c.negate);
        }
        Op::Compare(c) => match basic::compare(&rt.mem, c) {
            Ok(v) => join(&mut *acc, c.join, v),
            Err(code) => try_op!(Err::<(), _>(code)),
        },
        Op::Cond(c) => match c.cond.eval(&rt.mem) {
            Ok(v) => join(&mut *acc, c.join, v),
            Err(code) => try_op!(Err::<(), _>(code)),
        },
        Op::Push => r.blocks = r.blocks << 1 | *acc as u32,
        Op::Anb => {
            *acc &= r.blocks & 1 != 0;
            r.blocks >>= 1;
        }
        Op::Orb => {
            *acc |= r.blocks & 1 != 0;
            r.blocks >>= 1;
        }
        Op::Mps => r.mps = r.mps << 1 | *acc as u32,
        Op::Mrd => *acc = r.mps & 1 != 0,
        Op::Mpp => {
            *acc = r.mps & 1 != 0;
            r.mps >>= 1;
        }
        Op::Inv => *acc = !*acc,
        Op::DirectIn(n) => rt.direct_input(*n),
        Op::Mep(s) => {
            let prev = std::mem::replace(&mut locals[cur].edges[*s as usize], *acc);
            *acc = *acc && !prev;
        }
        Op::Mef(s) => {
            let prev = std::mem::replace(&mut locals[cur].edges[*s as usize], *acc);
            *acc = !*acc && prev;
        }
        Op::EdgeRelay { rising, v } => {
            let prev = std::mem::replace(&mut rt.mem.bits[*v as usize], *acc);
            *acc = if *rising {
                *acc && !prev
            } else {
                !*acc && prev
            };
        }
        Op::Out(i) => rt.mem.bits[*i as usize] = cond,
        Op::Set(i) => {
            if cond {
                rt.mem.bits[*i as usize] = true
            }
        }
        Op::Rst(i) => {
            if cond {
                rt.mem.bits[*i as usize] = false
            }
        }
        Op::Coil(c) => try_op!(sequence::coil(&mut rt.mem, &mut locals[cur].edges, c, cond)),
        Op::Timer(t) => {
            let base = rt.timer_base_us[t.high_speed as usize];
            try_op!(sequence::timer(
                &mut rt.mem,
                &mut rt.cpu.timer_rem,
                base,
                rt.scan_us,
                t,
                cond
            ))
        }
        Op::Counter(c) => try_op!(sequence::counter(&mut rt.mem, c, cond)),
        // MC: when the condition is OFF, everything up to MCR runs with its
        // condition forced OFF (coils OFF, timers reset, SET/RST/counters hold).
        Op::Mc(m) => {
            try_op!(rt.mem.write_bit(&m.dst, cond));
            if cond {
                rt.mc_off &= !(1 << m.level);
            } else {
                rt.mc_off |= 1 << m.level;
            }
            *mc_on = rt.mc_off == 0 && !k.off;
        }
        Op::Mcr(l) => {
            rt.mc_off &= (1u16 << l) - 1;
            *mc_on = rt.mc_off == 0 && !k.off;
        }
        Op::Pulse(s) => {
            let prev = std::mem::replace(&mut locals[cur].edges[*s as usize], cond);
            if !cond || prev {
                next += 1;
            }
        }
        Op::MovK { k, d } => {
            if cond {
                rt.mem.words[*d as usize] = *k;
            }
        }
        Op::MovW { s, d } => {
            if cond {
                rt.mem.words[*d as usize] = rt.mem.words[*s as usize];
            }
        }
        Op::MovD { s, d } => {
            if cond {
                let (s, d) = (*s as usize, *d as usize);
                rt.mem.words.copy_within(s..s + 2, d);
            }
        }
        Op::MovDK { k, d } => {
            if cond {
                let d = *d as usize;
                rt.mem.words[d] = *k as u16;
                rt.mem.words[d + 1] = (*k >> 16) as u16;
            }
        }
        Op::Ext(x) => {
            if cond {
                let mut cx = exec_ctx!();
                try_op!(prog.ext[*x as usize].exec(&mut cx));
                if rt.cpu.pending {
                    rt.serve_requests();
                }
            }
        }
        Op::ExtAlways(x) => {
            let mut cx = exec_ctx!();
            let instr = &prog.ext[*x as usize];
            try_op!(if cond {
                instr.exec(&mut cx)
            } else {
                instr.off(&mut cx)
            });
            if rt.cpu.pending {
                rt.serve_requests();
            }
        }
        Op::Cj { target, always } => {
            if *always || cond {
                back_jump!(*target);
                next = *target as usize;
            }
        }
        // SCJ: jumps from the scan after the condition turned ON.
        Op::Scj { target, slot } => {
            let prev = std::mem::replace(&mut locals[cur].edges[*slot as usize], cond);
            if cond && prev {
                back_jump!(*target);
                next = *target as usize;
            }
        }
        Op::GoEnd => {
            if cond {
                return Flow::Done(rt.end_checks(cur, pc));
            }
        }
        Op::Call(target) => {
            if cond {
                if rt.calls.len() >= MAX_NESTING {
                    try_op!(Err::<(), _>(Fault::CallNesting));
                    return Flow::Next(next);
                }
                rt.calls.push((cur as u32, next as u32));
                back_jump!(*target);
                next = *target as usize;
            }
        }
        // CALL of another file's subroutine (a common pointer): it runs as a
        // nested pass over that file's ops until its RET returns here.
        Op::CallFar { slot, pc: target } => {
            if cond {
                if rt.calls.len() >= MAX_NESTING {
                    try_op!(Err::<(), _>(Fault::CallNesting));
                    return Flow::Next(next);
                }
                let ret = (cur as u32, next as u32);
                let (slot, target) = (*slot as usize, *target as usize);
                match nested_pass(k, locals, rt, ret, slot, target, true) {
                    Outcome::Return => {}
                    other => return Flow::Done(other),
                }
            }
        }
        // Linking replaces every CallCommon; one left means a bug, not input.
        Op::CallCommon(_) => try_op!(Err::<(), _>(Fault::NoProgram)),
        Op::CallArgs(c) => {
            let now = match c.pulse {
                Some(s) => {
                    let prev = std::mem::replace(&mut locals[cur].edges[s as usize], cond);
                    cond && !prev
                }
                None => cond,
            };
            // FCALL with its condition OFF: the non-execution processing.
            let off = c.fcall && !cond;
            if now || off {
                let (slot, target) = match c.callee {
                    Callee::Here(t) => (cur, t),
                    Callee::Far { slot, pc } => (slot as usize, pc),
                    // Linking resolves the others: a bug, not input.
                    _ => (usize::MAX, 0),
                };
                match call_args(k, locals, rt, c, slot, target as usize, off) {
                    Ok(None) => {}
                    Ok(Some(out)) => return Flow::Done(out),
                    Err(code) => try_op!(Err::<(), _>(code)),
                }
            }
        }
        Op::Ret => match rt.calls.pop() {
            // RET to another file or out of a nested pass (a call with
            // arguments): back to the pass that called it.
            Some((slot, ret)) if slot as usize != cur || ret == NESTED => {
                return Flow::Done(Outcome::Return)
            }
            Some((_, ret)) => next = ret as usize,
            None => try_op!(Err::<(), _>(Fault::RetInMain)),
        },
        // FOR n: n of 0 or less runs once.
        Op::For(n) => {
            let n = match rt.mem.read16(n) {
                Ok(v) => (v as i16).max(1),
                Err(code) => {
                    try_op!(Err::<(), _>(code));
                    return Flow::Next(next);
                }
            };
            if rt.fors.len() >= MAX_NESTING {
                try_op!(Err::<(), _>(Fault::ForNesting));
                return Flow::Next(next);
            }
            rt.fors.push((next as u32, n));
        }
        Op::Next => match rt.fors.last_mut() {
            Some((start, left)) => {
                *left -= 1;
                if *left > 0 {
                    let target = *start;
                    back_jump!(target);
                    next = target as usize;
                } else {
                    rt.fors.pop();
                }
            }
            None => try_op!(Err::<(), _>(Fault::NextWithoutFor)),
        },
        // BREAK d p: ends the innermost FOR, storing the repetitions left
        // (the interrupted one included) in d, and jumps to p.
        Op::Break(b) => {
            if cond {
                match rt.fors.pop() {
                    Some((_, left)) => {
                        try_op!(rt.mem.write16(&b.0, left as u16));
                        next = b.1 as usize;
                    }
                    None => try_op!(Err::<(), _>(Fault::BreakWithoutFor)),
                }
            }
        }
        Op::Stop => {
            if cond {
                rt.stop_request = true;
            }
        }
        Op::StopNow => {
            if cond {
                rt.stop_now = true;
                return Flow::Done(Outcome::Abort);
            }
        }
        Op::Fend | Op::End => {
            // A scan longer than the watchdog is WDT ERROR even without a loop.
            if rt.cpu.watchdog_start.elapsed() > k.watchdog {
                return Flow::Done(Outcome::Fault(Fault::Watchdog, cur, pc));
            }
            return Flow::Done(rt.end_checks(cur, pc));
        }
        Op::Nop => {}
        Op::Iret => {
            if rt.in_interrupt {
                return Flow::Done(Outcome::End);
            }
            try_op!(Err::<(), _>(Fault::IretInMain));
        }
    }
    Flow::Next(next)
}

/// The rarer ops of [`op`], out of the interpreter's loop.
#[cold]
#[inline(never)]
fn rare(
    k: Fixed,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    back_jumps: &mut u32,
    code: &Op,
    r: &mut Rung,
    pc: usize,
) -> Flow {
    op::<false>(k, locals, rt, back_jumps, code, r, pc)
}

/// A pass as native code sees it while one of its regions runs.
struct Callback<'a> {
    k: Fixed<'a>,
    locals: &'a mut [ProgState],
    rt: &'a mut Runtime,
    back_jumps: u32,
    /// How the pass ended, when an op called from native code ended it.
    ended: Option<Outcome>,
}

/// Native code calls back here for the ops it has no code for.
impl Host for Callback<'_> {
    fn state(&mut self) -> NativeState<'_> {
        let rt = &mut *self.rt;
        NativeState {
            mem: &mut rt.mem,
            timer_rem: &mut rt.cpu.timer_rem,
            edges: &mut self.locals[self.k.cur].edges,
            timer_base_us: rt.timer_base_us,
            scan_us: rt.scan_us,
        }
    }

    fn exec(&mut self, from: u32, to: u32, regs: &mut Regs) -> u32 {
        let mut r = Rung::from(*regs);
        let k = self.k;
        let (from, to) = (from as usize, (to as usize).min(k.prog.ops.len()));
        let mut pc = from;
        let next = loop {
            if !(from..to).contains(&pc) {
                break pc as u32;
            }
            let code = &k.prog.ops[pc];
            match op::<false>(
                k,
                self.locals,
                self.rt,
                &mut self.back_jumps,
                code,
                &mut r,
                pc,
            ) {
                Flow::Next(next) => pc = next,
                Flow::Done(out) => {
                    self.ended = Some(out);
                    break LEAVE;
                }
            }
        };
        *regs = Regs::from(r);
        next
    }
}
