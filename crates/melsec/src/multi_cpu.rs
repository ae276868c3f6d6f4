//! Multi-CPU instructions between QCPUs: S(P).TO writes the own CPU's
//! shared memory (Programming Manual (Common Instructions) S.TO; 004 §16.2,
//! §16.4, L8949-9111). The other CPUs read it with FROM and `U3En\G`
//! (`module_access.rs`, the compiler's unit operands); a QCPU has no S.FROM.
//! The motion-CPU instructions (S.SFCS … S.GINT) are rejected
//! (`rejected.rs`): softplc simulates no motion CPU.

use super::transfer::{count, Loc, WordBlock};
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::{DeviceKind, DeviceMemory, UnitOwner};
use softplc_ir::fault::Fault;
use softplc_ir::instr::CpuSlot;
use softplc_ir::ops::{BitBlock, Num, WordArg};
use softplc_lang::isa::{Def, Doc, Pulse};

/// This family's instructions.
pub static DEFS: &[Def] = &[Def::app("S.TO", &SHARED, compile).pulse(Pulse::SPrefix)];

static SHARED: Doc = Doc {
    family: "multi-CPU",
    cite: "PM S.TO; 004 §16.2, §16.4",
    notes: "n1 n2 S n3 D: n3 words from S into the own CPU's shared memory from address n2, \
            written at execution; n2..n2+n3-1 must lie in the user area (800H plus the CPU's \
            auto-refresh words, to FFFH), else 4101; n1 another CPU → 2115, a CPU not \
            installed → 2110, a module → 4100; D ON (and D+1 OFF: no error completion is \
            simulated) from the END of the scan that executed it to the next END; a 33rd \
            S.TO before END → 4107; n3 = 0 writes nothing and completes",
};

/// Inter-CPU instructions a QCPU holds waiting to complete; one more is
/// OPERATION ERROR 4107 (004 L9020-9024).
const MAX_PENDING: usize = 32;

softplc_ir::cpu_state! {
    /// The completion devices of the S.TO instructions: those executed
    /// since the last END (completed at the next END) and those that END
    /// turned ON (turned OFF at the next). [`Pending`] reads it.
    pub struct InterCpu[2 * (1 + MAX_PENDING)];
}

/// [`InterCpu`]'s two lists, each a length then flat bit indices of the
/// completion devices D (D+1 follows).
struct Pending<'a>(&'a mut [u32]);

impl Pending<'_> {
    /// Executed since the last END.
    const WAITING: usize = 0;
    /// Turned ON at the last END.
    const SHOWN: usize = 1 + MAX_PENDING;

    fn list(&self, at: usize) -> &[u32] {
        let len = (self.0[at] as usize).min(MAX_PENDING);
        &self.0[at + 1..at + 1 + len]
    }

    /// Queues completion device `d`; [`Fault::TooManyPending`] when
    /// [`MAX_PENDING`] wait already.
    fn push(&mut self, d: u32) -> Result<(), Fault> {
        let len = self.0[Self::WAITING] as usize;
        if len >= MAX_PENDING {
            return Err(Fault::TooManyPending);
        }
        self.0[Self::WAITING + 1 + len] = d;
        self.0[Self::WAITING] += 1;
        Ok(())
    }
}

/// S(P).TO `n1 n2 S n3 D`: writes n3 words from S into the own CPU's
/// shared memory (n1 = its head I/O number 3E0H + CPU number - 1) from
/// address n2 of its user area, at execution, as the manual's example
/// shows data written for the other CPUs to read with FROM (004 L8953-8971).
/// Writing another CPU's shared memory is 2115 (L8994); the own-operation,
/// system and auto-refresh areas cannot be written (L9053-9069, L9106):
/// OPERATION ERROR 4101, as the block instructions' range error. Decision:
/// an n1 of an intelligent function module, which has no user area, is
/// OPERATION ERROR 4100. The completion device D turns ON for one scan
/// from the END of the scan it completed in, as the dedicated instructions'
/// completion devices (004 §8.1.5, L5584-5586); D+1 (error completion)
/// stays OFF: every error softplc detects is an error of the instruction
/// at execution, which writes nothing and completes nothing.
#[derive(Debug)]
struct STo {
    unit: WordArg,
    addr: WordArg,
    s: WordBlock,
    n: WordArg,
    d: BitBlock,
    pending: CpuSlot<InterCpu>,
}

fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[5]) {
        return None;
    }
    let unit = a.word_src(0, Num::I16);
    let addr = a.word_src(1, Num::I16);
    let s = WordBlock::compile(a, 2);
    let n = a.word_src(3, Num::I16);
    let d = a.bit_block(4);
    Some(Box::new(STo {
        unit: unit?,
        addr: addr?,
        s: s?,
        n: n?,
        d: d?,
        pending: a.cpu(),
    }))
}

impl STo {
    /// The flat word index in `G` of the n3 words from n2 of the own user
    /// area, and n3.
    fn target(&self, mem: &DeviceMemory) -> Result<(usize, usize), Fault> {
        let unit = mem.read16(&self.unit)? as u32;
        let addr = mem.read16(&self.addr)? as u32;
        let n = count(mem, &self.n)?.unwrap_or(0);
        let w = mem
            .map
            .unit(unit)
            .ok_or(Fault::NoModule { unit: unit as u16 })?;
        match w.owner {
            UnitOwner::OwnCpu => {}
            UnitOwner::OtherCpu => return Err(Fault::OtherSharedMemory { unit: unit as u16 }),
            UnitOwner::Module | UnitOwner::OtherCpusModule => return Err(Fault::Operation),
        }
        // Below the user area is 4101, as past the shared memory (the
        // window's range check, FROM's too).
        if addr < mem.map.shared_user_area() {
            return Err(Fault::Range);
        }
        let first = w.span(addr, n).map_err(|_| Fault::Range)?;
        let g = mem.map.base(DeviceKind::G) + first;
        Ok((g as usize, n as usize))
    }
}

impl Instr for STo {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let (g, n) = self.target(mem)?;
        let d = mem.bit_block_start(&self.d, 2)?;
        let s = match n {
            0 => None,
            n => Some(self.s.resolve(mem, n as u32)?),
        };
        Pending(self.pending.words(cx.shared)).push(d as u32)?;
        match s {
            None => {}
            Some(Loc::Word(s)) => mem.words.copy_within(s..s + n, g),
            Some(s) => {
                for k in 0..n {
                    let v = s.get(mem, k);
                    mem.words[g + k] = v;
                }
            }
        }
        Ok(())
    }
}

/// END: the completion devices the last END turned ON go OFF, those of the
/// S.TO executed since turn ON (their D+1 OFF).
pub(crate) fn end(mem: &mut DeviceMemory, shared: &mut [u32]) {
    let slot = CpuSlot::<InterCpu>::new();
    if (slot.end() as usize) > shared.len() {
        // No program uses S.TO.
        return;
    }
    let pending = Pending(slot.words(shared));
    let mut set = |d: u32, v: bool| {
        if let Some(b) = mem.bits.get_mut(d as usize) {
            *b = v;
        }
    };
    for &d in pending.list(Pending::SHOWN) {
        set(d, false);
        set(d + 1, false);
    }
    for &d in pending.list(Pending::WAITING) {
        set(d, true);
        set(d + 1, false);
    }
    let Pending(w) = pending;
    w.copy_within(Pending::WAITING..Pending::SHOWN, Pending::SHOWN);
    w[Pending::WAITING] = 0;
}
