//! Program control (PM §6.6-6.7, §7.6, §7.16-7.18): jumps, subroutine calls,
//! FOR/NEXT loops, interrupt control, execution-type changes, the watchdog
//! reset, the user timing clocks, the sampling trace and STOP. Those that
//! move the program counter are lowered into the ladder machine's own ops;
//! those that talk to the CPU (EI/DI, IMASK, PSCAN…, WDT, TRACE) are
//! instructions asking the engine through `ExecCtx::cpu`.

use softplc_ir::cpu::TypeChange;
use softplc_ir::device::{Constant, DeviceKind, Operand};
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::kernels::cpu::ResetWatchdog;
use softplc_ir::ops::*;
use softplc_lang::compile::{Args, Compiler, MAX_NESTING};
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
    Def::lower("FCALL", Class::Output, &SUBROUTINES, call).pulse(Pulse::Suffix),
    Def::lower("ECALL", Class::Output, &SUBROUTINES, call).pulse(Pulse::Suffix),
    Def::lower("EFCALL", Class::Output, &SUBROUTINES, call).pulse(Pulse::Suffix),
    Def::lower("RET", Class::Standalone, &SUBROUTINES, ret).steps(Steps::Basic),
    Def::lower("FOR", Class::Standalone, &LOOPS, for_),
    Def::lower("NEXT", Class::Standalone, &LOOPS, next).steps(Steps::Basic),
    Def::lower("BREAK", Class::Output, &LOOPS, break_).pulse(Pulse::Suffix),
    Def::lower("PSCAN", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("PSTOP", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("POFF", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("PLOW", Class::Output, &PROGRAMS, prog_ctl).pulse(Pulse::Suffix),
    Def::lower("WDT", Class::Output, &WDT, wdt_trace).pulse(Pulse::Suffix),
    Def::app("DUTY", &DUTY, crate::user_clock::compile).no_pulse(),
    Def::lower("TRACE", Class::Output, &TRACE, wdt_trace),
    Def::lower("TRACER", Class::Output, &TRACE, wdt_trace),
    Def::lower("STOP", Class::Output, &STOP, stop_goend).steps(Steps::Basic),
    Def::app("COM", &REFRESH, com).no_pulse(),
];

static BRANCH: Doc = Doc {
    family: "program branch",
    cite: "PM §6.6",
    notes: "JMP is unconditional; jumps cannot leave their file",
};
static INTERRUPTS: Doc = Doc {
    family: "interrupt control",
    cite: "PM §6.7; 004 §4.1.3",
    notes: "I28-I31 fixed-cycle, I0-I15 from a QI60 slot, I50-I255 from intelligent modules' slot settings (else a load error), I32-I39 error interrupts (enabled by IMASK); App. 3 priorities; I33, I37, I40-I49 rejected; EI/DI without a contact (opening a rung or after an output) run at every scan, after contacts while the condition is ON",
};
static SUBROUTINES: Doc = Doc {
    family: "subroutine",
    cite: "PM §7.6; 004 §10.9",
    notes: "16 levels; common pointers reach other files; up to 5 arguments: argument n is FXn/FYn (bit) or FDn (4 words), copied in at the call and FY/FD copied back at RET; FCALL runs the subroutine with every condition OFF while its own is OFF; ECALL \"FILE\" Pn reaches a local pointer of another file (unknown file or pointer: load error)",
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
static REFRESH: Doc = Doc {
    family: "refresh",
    cite: "004 §4.2",
    notes: "the input refresh in mid-scan (input image into X, forced inputs kept); outputs are the Y devices at any time",
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
    let sm715 = c.map.index(DeviceKind::SM, SM_EI);
    c.emit_instr(
        false,
        always,
        Box::new(Interrupts {
            enable,
            always,
            sm715,
        }),
    );
}

/// SM715: ON while interrupts are enabled (EI).
const SM_EI: u32 = 715;

/// PM §6.7 EI / DI: enables or disables the interrupt programs; SM715
/// mirrors the state. Without a contact ([`ei_di`]) it runs at every
/// execution, under an OFF master control too.
#[derive(Debug)]
struct Interrupts {
    enable: bool,
    always: bool,
    sm715: Option<u32>,
}

impl Instr for Interrupts {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.cpu.enable_interrupts(self.enable);
        if let Some(b) = self.sm715 {
            cx.mem.bits[b as usize] = self.enable;
        }
        Ok(())
    }

    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        if self.always {
            self.exec(cx)?;
        }
        Ok(())
    }
}

fn imask(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if c.count(i, m, &[1]) && c.output(i, m) {
        if let Some(s) = c.word_dest(&ops[0], Num::I16, 16) {
            // SD715-SD717 (I0-I47) and SD781-SD793 (I48-I255) mirror the mask.
            let sd = c
                .map
                .index(DeviceKind::SD, 793)
                .map(|_| c.map.base(DeviceKind::SD));
            c.emit_instr(false, false, Box::new(Imask { s, sd }));
        }
    }
}

/// PM §6.7 IMASK `S`: 16 words of enable bits for I0-I255 (one bit per
/// pointer, I0 in bit 0 of S), mirrored in SD715-SD717 and SD781-SD793. An
/// index-modified or digit-specified S is a range error. The error
/// interrupts I32-I39 stay disabled from power-on and RESET until IMASK
/// enables them (004 L5019-5021, L10902-10904); the others only need EI.
#[derive(Debug)]
struct Imask {
    s: WordArg,
    /// Flat index of SD0, when the CPU has SD793.
    sd: Option<u32>,
}

impl Instr for Imask {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let WordArg::Word(first) = self.s else {
            return Err(Fault::Range);
        };
        let first = first as usize;
        let words: [u16; softplc_ir::cpu::INTERRUPTS / 16] =
            std::array::from_fn(|k| cx.mem.words[first + k]);
        cx.cpu.mask_interrupts(words);
        if let Some(sd) = self.sd {
            for (k, w) in words.iter().enumerate() {
                let n = if k < 3 { 715 + k } else { 781 + k - 3 };
                cx.mem.words[sd as usize + n] = *w;
            }
        }
        Ok(())
    }
}

fn iret(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if c.count(i, m, &[0]) && c.standalone(i, m) {
        c.emit(Op::Iret);
    }
}

/// PM §7.6 CALL(P)/FCALL(P)/ECALL(P)/EFCALL(P) `[\"file\"] Pn [S1 … S5]`
/// (004 L1171-1200, §10.3.1, §10.9.1). CALL without arguments is a jump
/// into the subroutine (a pass over another file for a common pointer);
/// the others are [`Op::CallArgs`], a nested pass with the arguments.
fn call(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    let kind = |b: &str| match b {
        "CALL" => Some((false, false)),
        "FCALL" => Some((false, true)),
        "ECALL" => Some((true, false)),
        "EFCALL" => Some((true, true)),
        _ => None,
    };
    let (base, pulse) = match m.strip_suffix('P') {
        Some(b) if kind(b).is_some() => (b, true),
        _ => (m, false),
    };
    let Some((file, fcall)) = kind(base) else {
        return c.unmatched(u);
    };
    let first = usize::from(file);
    let counts: Vec<usize> = (first + 1..=first + 1 + MAX_ARGS).collect();
    if !c.count(i, m, &counts) || !c.output(i, m) {
        return;
    }
    if base == "CALL" && ops.len() == 1 {
        if let Some(p) = c.pointer(&ops[0]) {
            if pulse {
                let s = c.slot();
                c.emit(Op::Pulse(s));
            }
            let at = c.emit(Op::Call(0));
            c.fixups.push((at, p, ops[0].clone()));
        }
        return;
    }
    let callee = if file {
        match c.parse(&ops[0]) {
            Some(Operand::Const(Constant::Str(s))) if !s.is_empty() && s.len() <= 8 => {
                Some(s.to_ascii_uppercase())
            }
            Some(_) => {
                return c.err(
                    &ops[0],
                    format!("`{m}` needs a program name such as \"SUB\" (up to 8 characters)"),
                )
            }
            None => return,
        }
    } else {
        None
    };
    let p = c.pointer(&ops[first]);
    let mut args = Vec::new();
    for k in first + 1..ops.len() {
        if let Some(a) = fn_arg(c, u, k) {
            args.push(a);
        }
    }
    let Some(p) = p else { return };
    if args.len() != ops.len() - first - 1 {
        return;
    }
    let callee = match callee {
        Some(f) => Callee::File {
            file: f.into(),
            pointer: p,
        },
        None => Callee::Here(0),
    };
    let x = CallArgs {
        callee,
        args: args.into_boxed_slice(),
        fcall,
        pulse: pulse.then(|| c.slot()),
    };
    let at = c.emit(Op::CallArgs(Box::new(x)));
    if !file {
        c.fixups.push((at, p, ops[first].clone()));
    }
}

/// Arguments of a subroutine call: S1-S5 (PM §7.6).
const MAX_ARGS: usize = 5;

/// Operand `k` as an argument (004 §10.3.1 (2)): a bit device passes through
/// FXn/FYn (FY written back except to X and contacts, which a subroutine
/// cannot output to), a word device through FDn's 4 words, a constant into
/// FDn only.
fn fn_arg(c: &mut Compiler<'_>, u: &Use<'_>, k: usize) -> Option<FnArg> {
    let tok = &u.instr.operands[k];
    match c.parse(tok)? {
        Operand::Const(Constant::Int { value, .. }) => {
            let v = value as u64;
            Some(FnArg::Const([
                v as u16,
                (v >> 16) as u16,
                (v >> 32) as u16,
                (v >> 48) as u16,
            ]))
        }
        Operand::Const(Constant::Real(v)) => {
            let b = (v as f32).to_bits();
            Some(FnArg::Const([b as u16, (b >> 16) as u16, 0, 0]))
        }
        Operand::Device {
            digits: Some(_), ..
        } => {
            c.err(
                tok,
                format!(
                    "`{}`: a digit-specified argument is not supported; pass the bit device or a word device",
                    tok.text
                ),
            );
            None
        }
        Operand::Device { dev, bit, .. } if bit.is_some() || dev.kind.is_bit() => {
            use DeviceKind::*;
            let input = matches!(dev.kind, X | FX | TS | TC | STS | STC | CS | CC);
            let d = if input {
                c.bit_operand(tok)?
            } else {
                c.bit_dest(tok)?
            };
            Some(FnArg::Bit {
                dev: d,
                back: !input,
            })
        }
        Operand::Device { .. } => {
            let dev = Args::new(c, u.instr, u.m).block_dest(k)?;
            Some(FnArg::Word { dev, back: true })
        }
        _ => {
            c.err(
                tok,
                format!(
                    "`{}`: an argument is a bit device, a word device or a constant",
                    tok.text
                ),
            );
            None
        }
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
    let x = ProgramControl {
        kind,
        name: name.to_ascii_uppercase(),
        slot: u32::MAX,
    };
    c.emit_instr(pulse, false, Box::new(x));
}

/// PM §7.16 PSCAN/PSTOP/POFF/PLOW `"name"`: the named program becomes a scan,
/// standby or low-speed program at END (POFF: its outputs OFF at the next
/// scan first); the last request wins. A name no program has is FILE OPE.
/// ERROR 2410 when executed.
#[derive(Debug)]
struct ProgramControl {
    kind: TypeChange,
    name: String,
    /// The program's slot, found when the CPU is built (`u32::MAX`: none).
    slot: u32,
}

impl Instr for ProgramControl {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.cpu.change_type(self.slot, self.kind)
    }

    fn link(&mut self, programs: &[String]) {
        self.slot = programs
            .iter()
            .position(|p| *p == self.name)
            .map_or(u32::MAX, |i| i as u32);
    }
}

fn wdt_trace(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if c.count(i, m, &[0]) && c.output(i, m) {
        let x: Box<dyn Instr> = match m {
            "TRACE" => Box::new(Trace { reset: false }),
            "TRACER" => Box::new(Trace { reset: true }),
            "WDT" | "WDTP" => Box::new(ResetWatchdog),
            _ => return c.unmatched(u),
        };
        c.emit_instr(m == "WDTP", false, x);
    }
}

/// 004 §7.12 TRACE (trigger the sampling trace) / TRACER (reset it), both
/// applied at END.
#[derive(Debug)]
struct Trace {
    reset: bool,
}

impl Instr for Trace {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        if self.reset {
            cx.cpu.reset_trace();
        } else {
            cx.cpu.trigger_trace();
        }
        Ok(())
    }
}

fn com(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    a.count(&[0]).then(|| Box::new(Refresh) as Box<dyn Instr>)
}

/// 004 §4.2 (L1504-1575) COM: the END's refresh in mid-scan. softplc's
/// outputs are the Y devices themselves, read by the host whenever it reads
/// them, so what COM refreshes is the inputs: the input image (what the input
/// modules present) into X, forced inputs kept forced. Decisions (the
/// programming manual is not at hand): it runs while its condition is ON and
/// has no pulse form; SM775 (no link refresh) selects nothing, softplc has
/// no networks.
#[derive(Debug)]
struct Refresh;

impl Instr for Refresh {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.cpu.refresh_inputs();
        Ok(())
    }
}
