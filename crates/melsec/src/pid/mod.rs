//! PID control instructions, seed 001 (MELSEC-Q/L/QnA Programming Manual, PID
//! Control Instructions, SH-080040 / Chinese SH(NA)-080240C; "001 §x" below).
//! Behaviour the manual leaves open follows the project's notes
//! `shared/spec/pid-instructions.md` ("\[DECISION\] …" citations).
//!
//! Two independent families (001 §1, notes §1.1), each with its own
//! registration, SM/SD control bits and errors:
//!
//! | purpose | incomplete derivative (001 ch. 8) | complete derivative (001 ch. 9) |
//! |---|---|---|
//! | register data | `S.PIDINIT`, `SP.PIDINIT` (§8.1.1) | `PIDINIT`, `PIDINITP` (§9.1.1) |
//! | PID operation | `S.PIDCONT`, `SP.PIDCONT` (§8.1.2) | `PIDCONT`, `PIDCONTP` (§9.1.2) |
//! | stop / restart a loop | `S.PIDSTOP`, `S.PIDRUN` + `SP.` (§8.1.3) | `PIDSTOP`, `PIDRUN` + `P` (§9.1.4) |
//! | change a loop's data | `S.PIDPRMW`, `SP.PIDPRMW` (§8.1.4) | `PIDPRMW`, `PIDPRMWP` (§9.1.5) |
//! | AD57 monitor | — | `PID57`, `PID57P` (§9.1.3): rejected at load |
//!
//! Modules: `params` (control data, 001 §5.1), `registry` (the registered
//! data inside the CPU), `work` (the I/O work-area encoding, 001 §5.2),
//! `algo` (the operation, 001 §3.1.2/§3.2.2), `cont` (PIDCONT scheduling,
//! 001 §5.1.1/§5.1.2).
//!
//! CPU profile: the High-performance/Universal QCPU one (Q06HCPU): 1..32
//! loops, range-limit switches SD774/SD775 and SD794/SD795 (the Basic QCPU's
//! 8 loops and the QnACPU's always-limited ranges are not modelled). No
//! instruction allocates when it executes.
//!
//! Scope of the registration: it is CPU-wide, in the shared state words
//! (`ExecCtx::shared`, see `registry`), so a PIDINIT in an initial program
//! serves the PIDCONT/PIDSTOP/PIDRUN/PIDPRMW of a scan program; it is cleared
//! at STOP→RUN and power-on, after which PIDINIT must run again (a loop's
//! running state is in the I/O data and survives if those devices do).

pub mod algo;
mod cont;
mod params;
pub(crate) mod registry;
mod work;

use super::{Args, ExecCtx, Instr};
use params::LoopParams;
use registry::Registry;
use softplc_ir::device::DeviceKind;
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::instr::CpuSlot;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc, LoopMemory, Pulse};

pub use algo::round_word;

/// Why a process CPU (QnPHCPU) rejects these instructions (001 §1 point:
/// "the process CPU does not support the PID control instructions of this
/// manual"; the redundant QnPRHCPU has them).
pub const NOT_ON_PROCESS_CPU: &str = "a PID control instruction, which the process CPUs \
     (Q02PHCPU, Q06PHCPU, Q12PHCPU, Q25PHCPU) do not have: on these models a PID loop is \
     written with the process-control instructions (S.PID or S.2PID, between S.IN and S.OUT1); \
     the PID control instructions run on the other MELSEC-Q models, the Universal models and \
     the redundant Q12PRHCPU/Q25PRHCPU";

/// Loops per family (001 §5.1 Table 5.2: 1..32 for High-performance/Universal
/// QCPU and LCPU; the Basic QCPU's 8 is not modelled).
pub const MAX_LOOPS: usize = 32;

/// Error 4103: instruction order (PIDCONT before PIDINIT …; 001 §8.1.2–§8.1.4,
/// §9.1.2–§9.1.5 "运算错误").
pub const ORDER: Fault = Fault::Family(ErrorCode(4103));

/// The derivative family (001 §1.1; notes §1.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Incomplete derivative, `S.` instructions (001 ch. 8, §3.1).
    Incomplete,
    /// Complete derivative, plain instructions (001 ch. 9, §3.2).
    Complete,
}

impl Family {
    /// Words of one loop's PID control data (001 §5.1(3)(a) 14, (b) 10).
    pub const fn param_words(self) -> usize {
        match self {
            Family::Incomplete => 14,
            Family::Complete => 10,
        }
    }

    /// Words of one loop's I/O data (001 §5.2(4)(a) 23, (b) 18).
    pub const fn io_words(self) -> usize {
        match self {
            Family::Incomplete => 23,
            Family::Complete => 18,
        }
    }

    /// Words of one loop's work area (16 / 11).
    pub const fn work_words(self) -> usize {
        self.io_words() - work::WORK
    }

    /// PID bumpless processing flag (001 §4.3.4): SM794 / SM774.
    pub const fn track_flag(self) -> u32 {
        match self {
            Family::Incomplete => 794,
            Family::Complete => 774,
        }
    }

    /// Range-limit switch registers for loops 1–16 and 17–32 (001 §4.3.5).
    pub const fn range_registers(self) -> [u32; 2] {
        match self {
            Family::Incomplete => [794, 795],
            Family::Complete => [774, 775],
        }
    }

    /// The family's registration in the CPU-wide shared state.
    fn registry(self, shared: &mut [u32]) -> Registry<'_> {
        let words = match self {
            Family::Incomplete => CpuSlot::<IncompleteRegistration>::new().words(shared),
            Family::Complete => CpuSlot::<CompleteRegistration>::new().words(shared),
        };
        Registry::at(words, 0)
    }

    /// Declares that an instruction uses the family's registration.
    fn declare(self, a: &mut Args<'_, '_>) {
        match self {
            Family::Incomplete => {
                a.cpu::<IncompleteRegistration>();
            }
            Family::Complete => {
                a.cpu::<CompleteRegistration>();
            }
        }
    }
}

softplc_ir::cpu_state! {
    /// The S. family's registration (S.PIDINIT, 001 §8.1.1), CPU-wide.
    struct IncompleteRegistration[registry::REGISTRY_WORDS];
}

softplc_ir::cpu_state! {
    /// The plain family's registration (PIDINIT, 001 §9.1.1), CPU-wide.
    struct CompleteRegistration[registry::REGISTRY_WORDS];
}

/// This family's instructions (001 §3.1.3/§3.2.3 instruction lists). The `S.`
/// family's pulse form is `SP.xxx` (001 §8.1); the other's a `P` suffix.
pub static DEFS: &[Def] = &[
    Def::app("S.PIDINIT", &INCOMPLETE, |a| PidInit::compile(a, INC))
        .pulse(Pulse::SPrefix)
        .loop_memory(0, &S_PID_DATA),
    Def::app("S.PIDCONT", &INCOMPLETE, |a| PidCont::compile(a, INC))
        .pulse(Pulse::SPrefix)
        .loop_memory(0, &S_PID_IO),
    Def::app("S.PIDSTOP", &INCOMPLETE, |a| {
        PidStopRun::compile(a, INC, false)
    })
    .pulse(Pulse::SPrefix),
    Def::app("S.PIDRUN", &INCOMPLETE, |a| {
        PidStopRun::compile(a, INC, true)
    })
    .pulse(Pulse::SPrefix),
    Def::app("S.PIDPRMW", &INCOMPLETE, |a| PidPrmw::compile(a, INC)).pulse(Pulse::SPrefix),
    Def::app("PIDINIT", &COMPLETE, |a| PidInit::compile(a, COMP)).loop_memory(0, &PID_DATA),
    Def::app("PIDCONT", &COMPLETE, |a| PidCont::compile(a, COMP)).loop_memory(0, &PID_IO),
    Def::app("PIDSTOP", &COMPLETE, |a| {
        PidStopRun::compile(a, COMP, false)
    }),
    Def::app("PIDRUN", &COMPLETE, |a| PidStopRun::compile(a, COMP, true)),
    Def::app("PIDPRMW", &COMPLETE, |a| PidPrmw::compile(a, COMP)),
    Def::rejected(
        "PID57",
        "PID57 needs an AD57(S1) CRT controller module (QnACPU only, PID Control Instructions manual §9.1.3), which \
         softplc does not emulate; read SV/PV/MV from the PIDCONT I/O data instead",
    ),
];

const INC: Family = Family::Incomplete;
const COMP: Family = Family::Complete;

/// S.PIDINIT's block (001 §5.1(3)(a)): +0 the number of loops, +1 the
/// loops computed per scan, then 14 words of control data a loop.
pub static S_PID_DATA: LoopMemory = LoopMemory {
    name: "PID control data",
    fields: params::LoopData::FIELDS,
    first: 2,
    stride: Family::Incomplete.param_words() as u32,
    count: Some(0),
    settings: None,
};

/// PIDINIT's block (001 §5.1(3)(b)): as S.PIDINIT's, 10 words a loop.
pub static PID_DATA: LoopMemory = LoopMemory {
    name: "PID control data",
    fields: params::LoopData::FIELDS.split_at(params::PLAIN_FIELDS).0,
    first: 2,
    stride: Family::Complete.param_words() as u32,
    count: Some(0),
    settings: None,
};

/// S.PIDCONT's I/O data (001 §5.2(4)(a)): 10 common work words, then 23
/// words a loop, [`algo::LoopIo`] first; the loops' control data is the
/// S.PIDINIT block registered before it.
pub static S_PID_IO: LoopMemory = LoopMemory {
    name: "PID I/O data",
    fields: algo::LoopIo::FIELDS,
    first: 10,
    stride: Family::Incomplete.io_words() as u32,
    count: None,
    settings: Some(&S_PID_DATA),
};

/// PIDCONT's I/O data (001 §5.2(4)(b)): as S.PIDCONT's, 18 words a loop,
/// with PIDINIT's control data.
pub static PID_IO: LoopMemory = LoopMemory {
    name: "PID I/O data",
    fields: algo::LoopIo::FIELDS,
    first: 10,
    stride: Family::Complete.io_words() as u32,
    count: None,
    settings: Some(&PID_DATA),
};

static INCOMPLETE: Doc = Doc {
    family: "PID (incomplete derivative)",
    cite: "001 §8",
    notes: "value-exact per pid-instructions.md; state in the I/O work words",
};
static COMPLETE: Doc = Doc {
    family: "PID (complete derivative)",
    cite: "001 §9",
    notes: "as above",
};

/// Checks the operand count (S.PIDPRMW/PIDPRMW 2, the others 1; 001 §8.1,
/// §9.1 "设置数据"); `fam` is the definition's family (`S.` or plain).
fn prologue(a: &mut Args<'_, '_>, fam: Family, operands: usize) -> Option<Family> {
    fam.declare(a);
    a.count(&[operands]).then_some(fam)
}

/// Reads a loop number operand: `Ok(i)` 0-based for loops 1..=n, 4100
/// otherwise (001 §8.1.3/§8.1.4 "环路号不存在 … 超出 1 至 32 的范围").
fn loop_index(cx: &ExecCtx<'_>, n: &WordArg, loops: usize) -> Result<usize, Fault> {
    let v = cx.mem.read16(n)? as i16;
    if v < 1 || v as usize > MAX_LOOPS || v as usize > loops {
        return Err(Fault::Operation);
    }
    Ok(v as usize - 1)
}

// ------------------------------------------------------------------ PIDINIT

/// S.PIDINIT/SP.PIDINIT (S) (001 §8.1.1) and PIDINIT/PIDINITP (S) (001 §9.1.1):
/// registers the PID control data starting at (S) (001 §5.1(3)).
///
/// * (S) any word device, no constant (\[DECISION\] notes §4 S.PIDINIT).
/// * n ∉ 1..32, k ∉ 1..32 or n < k → 4100; nothing runs until a good PIDINIT
///   (001 §5.1 Table 5.2 "不执行所有环路").
/// * `2 + 14n` / `2 + 10n` words past the device's end → 4101, nothing is
///   registered (001 §5.1(3)(c)).
/// * A loop with data out of range (see [`LoopParams::decode`]) → 4100; the
///   other loops are registered and run, that loop is skipped by PIDCONT.
/// * Loops stopped by PIDSTOP stay stopped (001 §8.1.3 功能(1)(a)).
#[derive(Debug)]
struct PidInit {
    fam: Family,
    data: Block,
}

impl PidInit {
    fn compile(a: &mut Args<'_, '_>, fam: Family) -> Option<Box<dyn Instr>> {
        let fam = prologue(a, fam, 1)?;
        let data = a.block(0)?;
        Some(Box::new(PidInit { fam, data }))
    }
}

impl Instr for PidInit {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let fam = self.fam;
        let mut reg = fam.registry(cx.shared);
        let s = cx.mem.block_start(&self.data, 2)?;
        let (n, k) = (cx.mem.words[s] as i16, cx.mem.words[s + 1] as i16);
        let max = MAX_LOOPS as i16;
        if !(1..=max).contains(&n) || !(1..=max).contains(&k) || n < k {
            reg.register_error();
            return Err(Fault::Operation);
        }
        let n = n as usize;
        let per = fam.param_words();
        let s = cx.mem.block_start(&self.data, (2 + per * n) as u32)?;
        reg.register(n, k as usize);
        let mut error = Ok(());
        for i in 0..n {
            let w = &cx.mem.words[s + 2 + per * i..s + 2 + per * (i + 1)];
            let ok = LoopParams::decode(fam, w).is_some();
            if !ok {
                error = Err(Fault::Operation);
            }
            reg.set_loop(i, w, ok);
        }
        error
    }
}

// ------------------------------------------------------------------ PIDCONT

/// S.PIDCONT/SP.PIDCONT (S) (001 §8.1.2) and PIDCONT/PIDCONTP (S) (001 §9.1.2):
/// the PID operation on the I/O data starting at (S) (001 §5.2(4)); see
/// `cont` for one execution and `algo` for the formulas.
#[derive(Debug)]
struct PidCont {
    fam: Family,
    io: Block,
    /// Flat bit index of SM794/SM774, flat word indices of SD794/SD795 (SD774/SD775).
    track_flag: Option<u32>,
    range_regs: [Option<u32>; 2],
}

impl PidCont {
    fn compile(a: &mut Args<'_, '_>, fam: Family) -> Option<Box<dyn Instr>> {
        let fam = prologue(a, fam, 1)?;
        let io = a.block_dest(0)?;
        let map = a.map();
        let track_flag = map.index(DeviceKind::SM, fam.track_flag());
        let [lo, hi] = fam.range_registers();
        let range_regs = [map.index(DeviceKind::SD, lo), map.index(DeviceKind::SD, hi)];
        Some(Box::new(PidCont {
            fam,
            io,
            track_flag,
            range_regs,
        }))
    }
}

impl Instr for PidCont {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let fam = self.fam;
        let mut reg = fam.registry(cx.shared);
        if !reg.registered() {
            return Err(ORDER);
        }
        if reg.common_error() {
            return Err(Fault::Operation);
        }
        let words = (10 + fam.io_words() * reg.loops()) as u32;
        let start = cx.mem.block_start(&self.io, words)?;
        reg.set_cont_seen();
        let sd = |i: Option<u32>| i.map_or(0, |i| cx.mem.words[i as usize] as u32);
        let env = cont::Env {
            scan_us: cx.scan_us,
            track: !self.track_flag.is_some_and(|i| cx.mem.bits[i as usize]),
            unlimited: sd(self.range_regs[0]) | sd(self.range_regs[1]) << 16,
        };
        cont::run(fam, &reg, cx.mem, start, &env)
    }
}

// ------------------------------------------------------------------ PIDSTOP / PIDRUN

/// S.PIDSTOP/S.PIDRUN (n) + SP. forms (001 §8.1.3) and PIDSTOP/PIDRUN (n) + P
/// forms (001 §9.1.4): stops / restarts loop n.
///
/// * (n) word device, digit-specified bits or K/H constant (001 §8.1.3 table).
/// * PIDINIT and PIDCONT of the family not both executed → 4103 (checked first).
/// * n ∉ 1..32 or n > loops registered → 4100.
/// * STOP keeps the loop's data; PIDINIT does not restart it. RUN on a running
///   loop is ignored. While stopped the accumulator stays 0, so after RUN the
///   loop resumes with its held history one Ts later (\[DECISION\] notes §4).
#[derive(Debug)]
struct PidStopRun {
    fam: Family,
    run: bool,
    n: WordArg,
}

impl PidStopRun {
    fn compile(a: &mut Args<'_, '_>, fam: Family, run: bool) -> Option<Box<dyn Instr>> {
        let fam = prologue(a, fam, 1)?;
        let n = a.word_src(0, Num::I16)?;
        Some(Box::new(PidStopRun { fam, run, n }))
    }
}

impl Instr for PidStopRun {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (loops, ready) = {
            let reg = self.fam.registry(cx.shared);
            (reg.loops(), reg.registered() && reg.cont_seen())
        };
        if !ready {
            return Err(ORDER);
        }
        let i = loop_index(cx, &self.n, loops)?;
        self.fam.registry(cx.shared).set_stopped(i, !self.run);
        Ok(())
    }
}

// ------------------------------------------------------------------ PIDPRMW

/// S.PIDPRMW/SP.PIDPRMW (n)(S) (001 §8.1.4) and PIDPRMW/PIDPRMWP (n)(S)
/// (001 §9.1.5): replaces loop n's registered data with the 14 / 10 words at
/// (S) (same layout as one loop of 001 §5.1(3)); no PIDINIT needed afterwards.
///
/// * PIDINIT not executed → 4103 for both families (\[DECISION\] notes §4: the
///   S.PIDPRMW page prints 4100, the PIDPRMW page 4103).
/// * n ∉ 1..32 or n > loops registered → 4100.
/// * (S) block past the device's end → 4101.
/// * Data out of range (including S. reserved words +10/+12/+13 ≠ 0) → 4100,
///   the loop keeps its previous data.
#[derive(Debug)]
struct PidPrmw {
    fam: Family,
    n: WordArg,
    data: Block,
}

impl PidPrmw {
    fn compile(a: &mut Args<'_, '_>, fam: Family) -> Option<Box<dyn Instr>> {
        let fam = prologue(a, fam, 2)?;
        let n = a.word_src(0, Num::I16);
        let data = a.block(1);
        Some(Box::new(PidPrmw {
            fam,
            n: n?,
            data: data?,
        }))
    }
}

impl Instr for PidPrmw {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let fam = self.fam;
        let (loops, registered) = {
            let reg = self.fam.registry(cx.shared);
            (reg.loops(), reg.registered())
        };
        if !registered {
            return Err(ORDER);
        }
        let i = loop_index(cx, &self.n, loops)?;
        let per = fam.param_words();
        let s = cx.mem.block_start(&self.data, per as u32)?;
        let w = &cx.mem.words[s..s + per];
        LoopParams::decode(fam, w).ok_or(Fault::Operation)?;
        self.fam.registry(cx.shared).set_loop(i, w, true);
        Ok(())
    }
}
