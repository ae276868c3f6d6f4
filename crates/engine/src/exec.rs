//! The interpreter: runs compiled ops from step 0 to END/FEND.
//!
//! The operation result (`acc`), the block stack of ANB/ORB and the MPS stack are
//! locals held in registers; the two stacks are bit stacks in a `u32` (depth is
//! checked at load time), so contacts and coils never touch the heap.

use std::time::Instant;

use super::tier::{NativeProgram, Regs, NO_REGION};
use super::{ProgState, Runtime};
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::kernels::{basic, sequence};
use softplc_ir::ops::MAX_NESTING;
use softplc_ir::ops::{Edge, Join, Op, Program};

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

/// Runs the program once from op `start` (0, or an interrupt pointer) to END/FEND
/// (or IRET). Faults of the "continue" class are recorded through
/// `rt.record_fault` and execution goes on after the failing op.
///
/// With `natives` (a native tier, `tier.rs`), a native region runs wherever
/// one starts and the interpreter runs the ops in between.
pub(crate) fn run(
    progs: &[Program],
    natives: &Natives,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    cur: usize,
    start: usize,
) -> Outcome {
    // Two instances, so the interpreter alone pays nothing for the tier.
    if natives.is_empty() {
        run_on::<false>(progs, natives, locals, rt, cur, start)
    } else {
        run_on::<true>(progs, natives, locals, rt, cur, start)
    }
}

fn run_on<const NATIVE: bool>(
    progs: &[Program],
    natives: &Natives,
    locals: &mut [ProgState],
    rt: &mut Runtime,
    cur: usize,
    start: usize,
) -> Outcome {
    let prog = &progs[cur];
    let native = natives.get(cur);
    let entries: &[u32] = native.map_or(&[], |n| n.entries());
    let ops = &prog.ops[..];
    let mut pc = start;
    let mut acc = false;
    let mut blocks: u32 = 0;
    let mut mps: u32 = 0;
    // POFF: the program runs once with every condition forced OFF.
    let off = rt.force_off;
    let mut mc_on = !off;
    rt.mc_off = 0;
    let mut back_jumps = 0u32;
    let watchdog = rt.watchdog;

    macro_rules! try_op {
        ($e:expr) => {
            if let Err(code) = $e {
                if rt.record_fault(prog, code, pc - 1) {
                    return Outcome::Fault(code, cur, pc - 1);
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
            }
        };
    }
    macro_rules! back_jump {
        ($target:expr) => {
            if ($target as usize) < pc {
                back_jumps += 1;
                if back_jumps % WDT_CHECK_EVERY == 0 {
                    // A loop that resets the watchdog (WDT) still stops on request.
                    if rt.abort.load(std::sync::atomic::Ordering::Relaxed) {
                        return Outcome::Abort;
                    }
                    if rt.wdt_start.elapsed() > watchdog {
                        return Outcome::Fault(ErrorCode::WDT, cur, pc - 1);
                    }
                }
            }
        };
    }

    loop {
        if NATIVE {
            let unit = entries.get(pc).copied().unwrap_or(NO_REGION);
            if let (true, Some(native)) = (unit != NO_REGION, native) {
                let mut regs = Regs {
                    acc: acc as u32,
                    blocks,
                    mps,
                    mc_on: mc_on as u32,
                };
                let next = native.run(unit, pc as u32, &mut regs, &mut rt.mem) as usize;
                acc = regs.acc != 0;
                blocks = regs.blocks;
                mps = regs.mps;
                if next != pc {
                    pc = next;
                    continue;
                }
            }
        }
        let op = &ops[pc];
        pc += 1;
        match op {
            Op::Ld(i) => acc = rt.mem.bits[*i as usize],
            Op::Ldi(i) => acc = !rt.mem.bits[*i as usize],
            Op::And(i) => acc &= rt.mem.bits[*i as usize],
            Op::Ani(i) => acc &= !rt.mem.bits[*i as usize],
            Op::Or(i) => acc |= rt.mem.bits[*i as usize],
            Op::Ori(i) => acc |= !rt.mem.bits[*i as usize],
            Op::Contact(c) => {
                let v = match rt.mem.read_bit(&c.src) {
                    Ok(v) => v,
                    Err(code) => {
                        try_op!(Err::<(), _>(code));
                        continue;
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
                join(&mut acc, c.join, v ^ c.negate);
            }
            Op::Compare(c) => match basic::compare(&rt.mem, c) {
                Ok(v) => join(&mut acc, c.join, v),
                Err(code) => try_op!(Err::<(), _>(code)),
            },
            Op::Cond(c) => match c.cond.eval(&rt.mem) {
                Ok(v) => join(&mut acc, c.join, v),
                Err(code) => try_op!(Err::<(), _>(code)),
            },
            Op::Push => blocks = blocks << 1 | acc as u32,
            Op::Anb => {
                acc &= blocks & 1 != 0;
                blocks >>= 1;
            }
            Op::Orb => {
                acc |= blocks & 1 != 0;
                blocks >>= 1;
            }
            Op::Mps => mps = mps << 1 | acc as u32,
            Op::Mrd => acc = mps & 1 != 0,
            Op::Mpp => {
                acc = mps & 1 != 0;
                mps >>= 1;
            }
            Op::Inv => acc = !acc,
            Op::Mep(s) => {
                let prev = std::mem::replace(&mut locals[cur].edges[*s as usize], acc);
                acc = acc && !prev;
            }
            Op::Mef(s) => {
                let prev = std::mem::replace(&mut locals[cur].edges[*s as usize], acc);
                acc = !acc && prev;
            }
            Op::EdgeRelay { rising, v } => {
                let prev = std::mem::replace(&mut rt.mem.bits[*v as usize], acc);
                acc = if *rising { acc && !prev } else { !acc && prev };
            }
            Op::Out(i) => rt.mem.bits[*i as usize] = acc & mc_on,
            Op::Set(i) => {
                if acc & mc_on {
                    rt.mem.bits[*i as usize] = true
                }
            }
            Op::Rst(i) => {
                if acc & mc_on {
                    rt.mem.bits[*i as usize] = false
                }
            }
            Op::Coil(c) => try_op!(sequence::coil(
                &mut rt.mem,
                &mut locals[cur].edges,
                c,
                acc & mc_on
            )),
            Op::Timer(t) => {
                let base = rt.timer_base_us[t.high_speed as usize];
                try_op!(sequence::timer(
                    &mut rt.mem,
                    &mut rt.timer_rem,
                    base,
                    rt.scan_us,
                    t,
                    acc & mc_on
                ))
            }
            Op::Counter(c) => try_op!(sequence::counter(&mut rt.mem, c, acc & mc_on)),
            // MC: when the condition is OFF, everything up to MCR runs with its
            // condition forced OFF (coils OFF, timers reset, SET/RST/counters hold).
            Op::Mc(m) => {
                let cond = acc & mc_on;
                try_op!(rt.mem.write_bit(&m.dst, cond));
                if cond {
                    rt.mc_off &= !(1 << m.level);
                } else {
                    rt.mc_off |= 1 << m.level;
                }
                mc_on = rt.mc_off == 0 && !off;
            }
            Op::Mcr(l) => {
                rt.mc_off &= (1u16 << l) - 1;
                mc_on = rt.mc_off == 0 && !off;
            }
            Op::Pulse(s) => {
                let cond = acc & mc_on;
                let prev = std::mem::replace(&mut locals[cur].edges[*s as usize], cond);
                if !cond || prev {
                    pc += 1;
                }
            }
            Op::MovK { k, d } => {
                if acc & mc_on {
                    rt.mem.words[*d as usize] = *k;
                }
            }
            Op::MovW { s, d } => {
                if acc & mc_on {
                    rt.mem.words[*d as usize] = rt.mem.words[*s as usize];
                }
            }
            Op::Apply(a) => {
                if acc & mc_on {
                    try_op!(basic::apply(&mut rt.mem, &mut rt.timer_rem, a));
                }
            }
            Op::Ext(x) => {
                if acc & mc_on {
                    let mut cx = exec_ctx!();
                    try_op!(prog.ext[*x as usize].exec(&mut cx));
                }
            }
            Op::ExtAlways(x) => {
                let mut cx = exec_ctx!();
                let instr = &prog.ext[*x as usize];
                try_op!(if acc & mc_on {
                    instr.exec(&mut cx)
                } else {
                    instr.off(&mut cx)
                });
            }
            Op::Cj { target, always } => {
                if *always || acc & mc_on {
                    back_jump!(*target);
                    pc = *target as usize;
                }
            }
            // SCJ: jumps from the scan after the condition turned ON.
            Op::Scj { target, slot } => {
                let cond = acc & mc_on;
                let prev = std::mem::replace(&mut locals[cur].edges[*slot as usize], cond);
                if cond && prev {
                    back_jump!(*target);
                    pc = *target as usize;
                }
            }
            Op::GoEnd => {
                if acc & mc_on {
                    return rt.end_checks(cur, pc - 1);
                }
            }
            Op::Call(target) => {
                if acc & mc_on {
                    if rt.calls.len() >= MAX_NESTING {
                        try_op!(Err::<(), _>(ErrorCode::CALL_NESTING));
                        continue;
                    }
                    rt.calls.push((cur as u32, pc as u32));
                    back_jump!(*target);
                    pc = *target as usize;
                }
            }
            // CALL of another file's subroutine (a common pointer): it runs as a
            // nested pass over that file's ops until its RET returns here.
            Op::CallFar { slot, pc: target } => {
                if acc & mc_on {
                    if rt.calls.len() >= MAX_NESTING {
                        try_op!(Err::<(), _>(ErrorCode::CALL_NESTING));
                        continue;
                    }
                    rt.calls.push((cur as u32, pc as u32));
                    let mc_off = rt.mc_off;
                    let out = run(progs, natives, locals, rt, *slot as usize, *target as usize);
                    rt.mc_off = mc_off;
                    match out {
                        Outcome::Return => {}
                        other => return other,
                    }
                }
            }
            // Linking replaces every CallCommon; one left means a bug, not input.
            Op::CallCommon(_) => try_op!(Err::<(), _>(ErrorCode::NO_PROGRAM)),
            Op::Ret => match rt.calls.pop() {
                // RET to another file: back to the nested pass that called it.
                Some((slot, _)) if slot as usize != cur => return Outcome::Return,
                Some((_, ret)) => pc = ret as usize,
                None => try_op!(Err::<(), _>(ErrorCode::RET_IN_MAIN)),
            },
            // FOR n: n of 0 or less runs once.
            Op::For(n) => {
                let n = match rt.mem.read16(n) {
                    Ok(v) => (v as i16).max(1),
                    Err(code) => {
                        try_op!(Err::<(), _>(code));
                        continue;
                    }
                };
                if rt.fors.len() >= MAX_NESTING {
                    try_op!(Err::<(), _>(ErrorCode::FOR_NESTING));
                    continue;
                }
                rt.fors.push((pc as u32, n));
            }
            Op::Next => match rt.fors.last_mut() {
                Some((start, left)) => {
                    *left -= 1;
                    if *left > 0 {
                        let target = *start;
                        back_jump!(target);
                        pc = target as usize;
                    } else {
                        rt.fors.pop();
                    }
                }
                None => try_op!(Err::<(), _>(ErrorCode::NEXT_WITHOUT_FOR)),
            },
            // BREAK d p: ends the innermost FOR, storing the repetitions left
            // (the interrupted one included) in d, and jumps to p.
            Op::Break(b) => {
                if acc & mc_on {
                    match rt.fors.pop() {
                        Some((_, left)) => {
                            try_op!(rt.mem.write16(&b.0, left as u16));
                            pc = b.1 as usize;
                        }
                        None => try_op!(Err::<(), _>(ErrorCode::BREAK_WITHOUT_FOR)),
                    }
                }
            }
            Op::Stop => {
                if acc & mc_on {
                    rt.stop_request = true;
                }
            }
            Op::Fend | Op::End => {
                // A scan longer than the watchdog is WDT ERROR even without a loop.
                if rt.wdt_start.elapsed() > watchdog {
                    return Outcome::Fault(ErrorCode::WDT, cur, pc - 1);
                }
                return rt.end_checks(cur, pc - 1);
            }
            Op::Nop => {}
            Op::Interrupts { enable, always } => {
                if *always || acc & mc_on {
                    rt.set_ei(*enable);
                }
            }
            Op::Imask(s) => {
                if acc & mc_on {
                    try_op!(rt.imask(s));
                }
            }
            Op::Iret => {
                if rt.in_interrupt {
                    return Outcome::End;
                }
                try_op!(Err::<(), _>(ErrorCode::IRET_IN_MAIN));
            }
            Op::Ann { kind, n } => {
                let cond = acc & mc_on;
                rt.annunciator(*kind, *n, cond);
            }
            Op::ProgCtl { kind, name } => {
                if acc & mc_on {
                    match rt.type_requests.get_mut(*name as usize) {
                        Some(r) => *r = Some(*kind),
                        None => try_op!(Err::<(), _>(ErrorCode::NO_PROGRAM)),
                    }
                }
            }
            Op::Wdt => {
                if acc & mc_on {
                    rt.wdt_start = Instant::now();
                }
            }
            Op::Duty(d) => {
                if acc & mc_on {
                    let n1 = rt.mem.read16(&d.0).map(|v| v as i16);
                    let n2 = rt.mem.read16(&d.1).map(|v| v as i16);
                    match (n1, n2) {
                        (Ok(n1), Ok(n2)) if n1 >= 0 && n2 >= 0 => {
                            let k = d.2 as usize;
                            let count = rt.duty[k].map_or(0, |c| c.2);
                            rt.duty[k] = Some((n1 as u16, n2 as u16, count));
                        }
                        (Err(code), _) | (_, Err(code)) => try_op!(Err::<(), _>(code)),
                        _ => try_op!(Err::<(), _>(ErrorCode::OPERATION)),
                    }
                }
            }
            Op::Trace { reset } => {
                if acc & mc_on {
                    if *reset {
                        rt.trace_reset = true;
                    } else {
                        rt.trace_trigger = true;
                    }
                }
            }
            Op::Ledr => {
                if acc & mc_on {
                    rt.ledr();
                }
            }
        }
    }
}
