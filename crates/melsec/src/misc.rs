//! The last QnH common instructions that need no hardware: RND/SRND and
//! ZPUSH/ZPOP (TIMCHK, RAMP and STMR are in `timing.rs`).
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions), SH-080039;
//! PM is not among the references at hand: its section numbers and the
//! behaviour below are as remembered from it, and every point it might settle
//! otherwise is marked as a decision.
//!
//! # CPU-wide state
//!
//! The RND/SRND random series is one per CPU: a [`CpuState`](softplc_ir::instr::CpuState)
//! of one word ([`RandomSeries`]).

use super::{Args, ExecCtx, Instr};
use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::CpuSlot;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

softplc_ir::cpu_state! {
    /// The RND/SRND series: the generator state xor the power-on seed, so that
    /// the cleared word is the series of seed 1.
    pub struct RandomSeries[1];
}

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("RND", &RND, rnd),
    Def::app("SRND", &RND, srnd),
    Def::app("ZPUSH", &ZSTACK, |a| zstack(a, false)),
    Def::app("ZPOP", &ZSTACK, |a| zstack(a, true)),
];

static RND: Doc = Doc {
    family: "random numbers",
    cite: "PM §7.12",
    notes: "C-standard LCG, seed 1 at power-on and STOP→RUN; one series per CPU",
};
static ZSTACK: Doc = Doc {
    family: "index register save",
    cite: "PM §7.18.7",
    notes: "16 words a save; ZPOP with nothing saved → 4100",
};

// --------------------------------------------------------------- RND / SRND

/// The series of a CPU after power-on or STOP→RUN (the shared word is zeroed
/// then; it holds the generator state xor this seed).
const DEFAULT_SEED: u32 = 1;

/// PM §7.12.12 RND(P) `D`: the next number of the CPU's random series, 0 …
/// 32767, to D.
///
/// The CPU's generator is not documented; softplc uses the linear congruential
/// generator of the C standard's `rand` example, so that runs are
/// reproducible: state = state × 1103515245 + 12345 (mod 2³²), number =
/// bits 16-30 of the state. The series starts from seed 1 at power-on and
/// STOP→RUN (first numbers 16838, 5758, 10113 …); SRND chooses another. One
/// series for the whole CPU, shared by every program file. No errors besides
/// 4101 for an index-modified D out of range.
#[derive(Debug)]
struct Rnd {
    d: WordArg,
    series: CpuSlot<RandomSeries>,
}

/// PM §7.12.12 SRND(P) `S`: restarts the random series from the seed S (any
/// 16-bit value, taken as 0 … 65535): RND then gives the numbers of that
/// series from its first. SRND K1 gives the series of power-on.
#[derive(Debug)]
struct Srnd {
    s: WordArg,
    series: CpuSlot<RandomSeries>,
}

fn rnd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    Some(Box::new(Rnd {
        d: a.word_dest(0, Num::I16, 1)?,
        series: a.cpu(),
    }))
}

fn srnd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    Some(Box::new(Srnd {
        s: a.word_src(0, Num::I16)?,
        series: a.cpu(),
    }))
}

impl Instr for Rnd {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let word = &mut self.series.words(cx.shared)[0];
        let state = (*word ^ DEFAULT_SEED)
            .wrapping_mul(1_103_515_245)
            .wrapping_add(12_345);
        // Checked before the series advances: an out-of-range D draws nothing.
        cx.mem.read16(&self.d)?;
        *word = state ^ DEFAULT_SEED;
        cx.mem.write16(&self.d, (state >> 16 & 0x7FFF) as u16)
    }
}

impl Instr for Srnd {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let seed = cx.mem.read16(&self.s)? as u32;
        self.series.words(cx.shared)[0] = seed ^ DEFAULT_SEED;
        Ok(())
    }
}

// ------------------------------------------------------------- ZPUSH / ZPOP

/// Index registers saved per ZPUSH.
const Z_REGS: u32 = 16;

/// PM §7.18.7 ZPUSH(P) `D` / ZPOP(P) `D` (batch save and recovery of the index
/// registers). D is the number of saves made so far; save k (k = 1, 2 …)
/// occupies D+16(k−1)+1 … D+16k, Z0 first (the QnH layout: 1 + 16 words a
/// save; the Universal models differ):
///
/// * ZPUSH writes Z0-Z15 as save n+1 (n = D) and makes D = n+1;
/// * ZPOP restores Z0-Z15 from save n (the last one) and makes D = n−1; the
///   save stays in the words (they are not cleared).
///
/// Nesting is by D (ZPUSH twice, ZPOP twice restores the first values). An
/// index-modified D is resolved before the index registers change.
///
/// Errors (nothing is written): ZPUSH with n negative or 32767, ZPOP with
/// n ≤ 0 (nothing saved): 4100 (decisions: the count cannot take them / there
/// is nothing to restore); the area D … D+16(n+1) (ZPUSH) or D … D+16n (ZPOP)
/// past the end of its device: 4101.
#[derive(Debug)]
struct ZStack {
    d: Block,
    /// Flat index of Z0 and the number of index registers (16 on the QnH).
    z: usize,
    nz: usize,
    pop: bool,
}

fn zstack(a: &mut Args<'_, '_>, pop: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    // ZPUSH writes the save area, ZPOP reads it.
    let d = if pop { a.block(0)? } else { a.block_dest(0)? };
    let map = a.map();
    Some(Box::new(ZStack {
        d,
        z: map.base(DeviceKind::Z) as usize,
        nz: map.points(DeviceKind::Z).min(Z_REGS) as usize,
        pop,
    }))
}

impl Instr for ZStack {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let s = mem.block_start(&self.d, 1)?;
        let n = mem.words[s] as i16 as i32;
        let (z, nz) = (self.z, self.nz);
        if self.pop {
            if n <= 0 {
                return Err(Fault::Operation);
            }
            let s = mem.block_start(&self.d, 1 + Z_REGS * n as u32)?;
            let at = s + 1 + Z_REGS as usize * (n as usize - 1);
            mem.words.copy_within(at..at + nz, z);
            mem.words[s] = (n - 1) as u16;
        } else {
            if !(0..i16::MAX as i32).contains(&n) {
                return Err(Fault::Operation);
            }
            let s = mem.block_start(&self.d, 1 + Z_REGS * (n as u32 + 1))?;
            let at = s + 1 + Z_REGS as usize * n as usize;
            mem.words.copy_within(z..z + nz, at);
            mem.words[at + nz..at + Z_REGS as usize].fill(0);
            mem.words[s] = (n + 1) as u16;
        }
        Ok(())
    }
}
