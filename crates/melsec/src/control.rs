//! Program control (PM §6.6-6.7, §7.6, §7.16-7.18): jumps, subroutine calls,
//! FOR/NEXT loops, interrupt control, execution-type changes, the watchdog
//! reset, the user timing clocks, the sampling trace and STOP. They move the
//! program counter or talk to the CPU, so the compiler lowers them into the
//! ladder machine's own ops, run by the interpreter and END processing.

use softplc_ir::device::{parse_operand, Constant, DeviceKind, Operand};
use softplc_ir::ops::*;
use softplc_lang::compile::{Compiler, MAX_NESTING};
use softplc_lang::isa::{Class, Def, Doc, Pulse, Steps, Use};

/// The program-control instructions.
pub static DEFS: &[Def] = &[
    Def::lower("CJ", Class::Output, &BRANCH, cj),
    Def::lower("SCJ", Class::Output, &BRANCH, cj),
    Def::lower("JMP", Class::Standalone, &BRANCH, jmp),
    Def::lower("GOEND", Class::Output, &BRANCH, stop_goend),
    Def::lower("EI", Class::Output, &INTERRUPTS, ei_di),
    Def::lower("DI", Class::Output, &INTERRUPTS, ei_di),
    Def::lower("IMASK", Class::Output, &INTERRUPTS, imask),
    Def::lower("IRET", Class::Standalone, &INTERRUPTS, iret),
    Def::lower("CALL", Class::Output, &SUBROUTINES, call).pulse(Pulse::Suffix),
    Def::lower("RET", Class::Standalone, &SUBROUTINES, ret).steps(Steps::Basic),
    Def::lower("FOR", Class::Standalone, &LOOPS, for_),
    Def::lower("NEXT", Class::Standalone, &LOOPS, next).steps(Steps::Basic),
    Def::lower("BREAK", Class::Output, &LOOPS, break_).pulse(Pulse::Suffix),
    Def::lower("PSCAN", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("PSTOP", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("POFF", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("PLOW", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("WDT", Class::Output, &WDT, wdt_trace).pulse(Pulse::Suffix),
    Def::lower("DUTY", Class::Output, &DUTY, duty),
    Def::lower("TRACE", Class::Output, &TRACE, wdt_trace),
    Def::lower("TRACER", Class::Output, &TRACE, wdt_trace),
    Def::lower("STOP", Class::Output, &STOP, stop_goend).steps(Steps::Basic),
];

static BRANCH: Doc = Doc {
    family: "program branch",
    cite: "PM §6.6",
    notes: "JMP is unconditional; jumps cannot leave their file",
};
static INTERRUPTS: Doc = Doc {
    family: "interrupt control",
    cite: "PM §6.7; 004 §4.1.3",
    notes: "I28-I31 fixed-cycle interrupts; I32-I49 rejected; EI/DI without a contact (opening a rung or after an output) run at every scan, after contacts while the condition is ON",
};
static SUBROUTINES: Doc = Doc {
    family: "subroutine",
    cite: "PM §7.6; 004 §10.9",
    notes: "16 levels; common pointers reach other files; no FX/FY/FD arguments",
};
static LOOPS: Doc = Doc {
    family: "structure creation",
    cite: "PM §7.6",
    notes: "16 levels; FOR n≤0 runs once",
};
static PROGRAMS: Doc = Doc {
    family: "program control",
    cite: "PM §7.16; 004 §4.2.6",
    notes: "take effect at END; the last request wins; unknown program → 2410",
};
static WDT: Doc = Doc {
    family: "watchdog reset",
    cite: "PM §7.18; 004 §7.9",
    notes: "restarts the watchdog, not the scan-time measurement",
};
static DUTY: Doc = Doc {
    family: "user timing clock",
    cite: "PM DUTY; 004 App. 1",
    notes: "SM420-SM424 / SM430-SM434 ON n1 scans, OFF n2 scans, counted at END",
};
static TRACE: Doc = Doc {
    family: "sampling trace",
    cite: "PM; 004 §7.12",
    notes: "trigger / reset the trace set up with `--trace` or `Cpu::set_trace`",
};
static STOP: Doc = Doc {
    family: "termination / other",
    cite: "PM §5.7",
    notes: "STOP: the CPU stops after END processing",
};

fn cj(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    let scj = match m {
        "CJ" => false,
        "SCJ" => true,
        _ => return c.unmatched(u),
    };
    if !c.count(i, m, &[1]) || !c.output(i, m) {
        return;
    }
    if let Some(p) = c.pointer(&ops[0]) {
        let op = if !scj {
            Op::Cj {
                target: 0,
                always: false,
            }
        } else {
            Op::Scj {
                target: 0,
                slot: c.slot(),
            }
        };
        let at = c.emit(op);
        c.fixups.push((at, p, ops[0].clone()));
    }
}

fn jmp(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if !c.count(i, m, &[1]) {
        return;
    }
    if c.has_rung && !c.after_output {
        c.err(
            &i.mnemonic,
            "JMP is unconditional; use CJ for a conditional jump",
        );
        return;
    }
    c.standalone(i, m);
    if let Some(p) = c.pointer(&ops[0]) {
        let at = c.emit(Op::Cj {
            target: 0,
            always: true,
        });
        c.fixups.push((at, p, ops[0].clone()));
    }
}

fn stop_goend(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let op = match m {
        "STOP" => Op::Stop,
        "GOEND" => Op::GoEnd,
        _ => return c.unmatched(u),
    };
    if c.count(i, m, &[0]) && c.output(i, m) {
        c.emit(op);
    }
}

/// EI/DI (PM §6.7): the manual writes them without a contact, and GX Works2
/// exports open a rung with them; softplc also accepts them after contacts
/// (then they run while the condition is ON, as softplc did before).
/// Decision: without a contact — at the start of a rung, or after another
/// rung's output — they run at every scan, never taking another rung's
/// condition.
fn ei_di(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if !c.count(i, m, &[0]) {
        return;
    }
    let enable = match m {
        "EI" => true,
        "DI" => false,
        _ => return c.unmatched(u),
    };
    let always = !c.has_rung || c.after_output;
    if always {
        c.standalone(i, m);
    } else if !c.output(i, m) {
        return;
    }
    c.emit(Op::Interrupts { enable, always });
}

fn imask(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if c.count(i, m, &[1]) && c.output(i, m) {
        if let Some(s) = c.word_dest(&ops[0], Num::I16, 16) {
            c.emit(Op::Imask(Box::new(s)));
        }
    }
}

fn iret(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if c.count(i, m, &[0]) && c.standalone(i, m) {
        c.emit(Op::Iret);
    }
}

fn call(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if ops.len() > 1 {
        c.err(
            &ops[1],
            "unsupported: CALL with arguments (FX/FY/FD) is not implemented yet",
        );
        return;
    }
    if !c.count(i, m, &[1]) || !c.output(i, m) {
        return;
    }
    if let Some(p) = c.pointer(&ops[0]) {
        if m == "CALLP" {
            let s = c.slot();
            c.emit(Op::Pulse(s));
        }
        let at = c.emit(Op::Call(0));
        c.fixups.push((at, p, ops[0].clone()));
    }
}

fn ret(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if c.count(i, m, &[0]) && c.standalone(i, m) {
        c.emit(Op::Ret);
    }
}

fn for_(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if !c.count(i, m, &[1]) || !c.standalone(i, m) {
        return;
    }
    if c.for_open.len() >= MAX_NESTING {
        c.err(
            &i.mnemonic,
            format!("FOR nested more than {MAX_NESTING} levels"),
        );
    }
    c.for_open.push(i.mnemonic.clone());
    if let Some(n) = c.word_src(&ops[0], Num::I16) {
        c.emit(Op::For(Box::new(n)));
    }
}

fn next(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if !c.count(i, m, &[0]) || !c.standalone(i, m) {
        return;
    }
    if c.for_open.pop().is_none() {
        c.err(&i.mnemonic, "NEXT without FOR");
    }
    c.emit(Op::Next);
}

fn break_(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if !c.count(i, m, &[2]) || !c.output(i, m) {
        return;
    }
    let d = c.word_dest(&ops[0], Num::I16, 1);
    let p = c.pointer(&ops[1]);
    if let (Some(d), Some(p)) = (d, p) {
        if m == "BREAKP" {
            let s = c.slot();
            c.emit(Op::Pulse(s));
        }
        let at = c.emit(Op::Break(Box::new((d, 0))));
        c.fixups.push((at, p, ops[1].clone()));
    }
}

fn prog_ctl(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if !c.count(i, m, &[1]) || !c.output(i, m) {
        return;
    }
    let name = match c.parse(&ops[0]) {
        Some(Operand::Const(Constant::Str(s))) if !s.is_empty() && s.len() <= 8 => s,
        Some(_) => {
            return c.err(
                &ops[0],
                format!("`{m}` needs a program name such as \"MAIN\" (up to 8 characters)"),
            )
        }
        None => return,
    };
    let (base, pulse) = match m {
        "PSCANP" | "PSTOPP" | "POFFP" | "PLOWP" => (&m[..m.len() - 1], true),
        _ => (m, false),
    };
    let kind = match base {
        "PSCAN" => TypeChange::Scan,
        "PSTOP" => TypeChange::Standby,
        "POFF" => TypeChange::Off,
        "PLOW" => TypeChange::LowSpeed,
        _ => return c.unmatched(u),
    };
    let id = c.prog_names.len() as u32;
    c.prog_names.push(name.to_ascii_uppercase());
    c.pulsed(pulse, Op::ProgCtl { kind, name: id });
}

fn wdt_trace(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if c.count(i, m, &[0]) && c.output(i, m) {
        let op = match m {
            "TRACE" => Op::Trace { reset: false },
            "TRACER" => Op::Trace { reset: true },
            "WDT" | "WDTP" => Op::Wdt,
            _ => return c.unmatched(u),
        };
        c.pulsed(m == "WDTP", op);
    }
}

fn duty(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if !c.count(i, m, &[3]) || !c.output(i, m) {
        return;
    }
    let n1 = c.word_src(&ops[0], Num::I16);
    let n2 = c.word_src(&ops[1], Num::I16);
    let clock = match parse_operand(&ops[2].text) {
        Ok(Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) if dev.kind == DeviceKind::SM && matches!(dev.number, 420..=424 | 430..=434) => {
            Some(if dev.number < 430 {
                dev.number - 420
            } else {
                dev.number - 425
            } as u8)
        }
        _ => {
            c.err(
                &ops[2],
                format!(
                    "`{}`: DUTY drives a user timing clock SM420-SM424 or SM430-SM434",
                    ops[2].text
                ),
            );
            None
        }
    };
    if let (Some(n1), Some(n2), Some(clock)) = (n1, n2, clock) {
        c.emit(Op::Duty(Box::new((n1, n2, clock))));
    }
}
