//! Buffer memory of intelligent function modules and the CPU shared memory
//! of a multi-CPU system: FROM(P), DFRO(P), TO(P), DTO(P) (Programming
//! Manual (Common Instructions), "instructions for intelligent function
//! modules"; 004 ch. 8, L5420-5755; §16.2, L8949-8998).
//!
//! `n1` is the module's start I/O number without its last hex digit (H2 for
//! a module at X/Y20; 3E0H-3E3H for CPU 1-4's shared memory), `n2` the
//! buffer-memory address, `n3` the number of 16-bit words (FROM, TO) or
//! 32-bit values (DFRO, DTO). A slot with no intelligent function module,
//! or a CPU not installed, is SP.UNIT ERROR (2110, L8997); a transfer past
//! the module's buffer memory or the device's last point is 4101. In a
//! multi-CPU system FROM reads another CPU's shared memory and a module
//! another CPU controls; FROM or TO on the own CPU's shared memory is 2114,
//! TO to another CPU's 2115 (it writes its own with S.TO, `multi_cpu.rs`),
//! TO to a module another CPU controls 2116 (L8994-8997, L9199-9205).
//! `U<n>\G<addr>` operands are resolved by the compiler and need no
//! instruction.

use super::transfer::{Loc, WordBlock};
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::{DeviceKind, DeviceMemory, Operand, UnitAccess};
use softplc_ir::fault::Fault;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("FROM", &MODULE, |a| from(a, 1)),
    Def::app("DFRO", &MODULE, |a| from(a, 2)),
    Def::app("TO", &MODULE, |a| to(a, 1)),
    Def::app("DTO", &MODULE, |a| to(a, 2)),
];

static MODULE: Doc = Doc {
    family: "module access",
    cite: "PM FROM/DFRO, TO/DTO; 004 ch. 8",
    notes: "buffer memory of the rack's intelligent slots ([[slot]]) and, in a multi-CPU system, the CPU shared memories (n1 = 3E0H-3E3H); no module or CPU → 2110, past the buffer memory or the device → 4101; n3 = 0 does nothing; FROM/TO on the own CPU's shared memory → 2114, TO to another CPU's → 2115, TO to a module another CPU controls → 2116",
};

/// The buffer memory an instruction moves: `n1 n2 … n3` — module,
/// address and count (of 32-bit values for DFRO/DTO).
#[derive(Debug)]
struct Buffer {
    unit: WordArg,
    addr: WordArg,
    n: WordArg,
    /// Words per counted value: 1, or 2 for DFRO/DTO.
    per: u32,
}

impl Buffer {
    /// Operands 0 (n1), 1 (n2) and 3 (n3) of a four-operand instruction.
    fn compile(a: &mut Args<'_, '_>, per: u32) -> Option<Buffer> {
        let unit = a.word_src(0, Num::I16);
        let addr = a.word_src(1, Num::I16);
        let n = a.word_src(3, Num::I16);
        Some(Buffer {
            unit: unit?,
            addr: addr?,
            n: n?,
            per,
        })
    }

    /// The flat word index of the first word and the words moved (`None`
    /// for n3 = 0; a negative n3 is 4101 as in the block instructions): no
    /// module is 2110, memory the unit's owner refuses for `access` its
    /// error (`DeviceMap::program_buffer`), a transfer past its buffer
    /// memory 4101.
    #[inline]
    fn resolve(
        &self,
        mem: &DeviceMemory,
        access: UnitAccess,
    ) -> Result<Option<(usize, usize)>, Fault> {
        let (unit, addr) = (mem.read16(&self.unit)?, mem.read16(&self.addr)?);
        let Some(n) = super::transfer::count(mem, &self.n)? else {
            return Ok(None);
        };
        let words = n * self.per;
        let g = mem.map.base(DeviceKind::G)
            + mem
                .map
                .program_buffer(unit as u32, addr as u32, words, access)?;
        Ok(Some((g as usize, words as usize)))
    }
}

/// FROM(P) `n1 n2 D n3` / DFRO(P): reads n3 words (DFRO: 2·n3) of buffer
/// memory from address n2 of module n1 into the devices from D.
#[derive(Debug)]
struct From {
    buffer: Buffer,
    d: WordBlock,
}

fn from(a: &mut Args<'_, '_>, per: u32) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let buffer = Buffer::compile(a, per);
    let d = WordBlock::compile_dest(a, 2);
    Some(Box::new(From {
        buffer: buffer?,
        d: d?,
    }))
}

impl Instr for From {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let Some((g, n)) = self.buffer.resolve(mem, UnitAccess::Read)? else {
            return Ok(());
        };
        match self.d.resolve(mem, n as u32)? {
            Loc::Word(d) => mem.words.copy_within(g..g + n, d),
            d => {
                for k in 0..n {
                    let v = mem.words[g + k];
                    d.set(mem, k, v);
                }
            }
        }
        Ok(())
    }
}

/// Where TO takes its data: devices from S, or one constant written to
/// every word (DTO: every pair of words).
#[derive(Debug)]
enum Source {
    Block(WordBlock),
    Const(u32),
}

/// TO(P) `n1 n2 S n3` / DTO(P): writes n3 words (DTO: 2·n3) from S into
/// buffer memory from address n2 of module n1; a constant S is written to
/// each of them.
#[derive(Debug)]
struct To {
    buffer: Buffer,
    s: Source,
}

fn to(a: &mut Args<'_, '_>, per: u32) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let buffer = Buffer::compile(a, per);
    let s = match a.operand(2)? {
        Operand::Const(_) => {
            let num = if per == 2 { Num::I32 } else { Num::I16 };
            match a.word_src(2, num)? {
                WordArg::Const(k) => Some(Source::Const(k)),
                _ => None,
            }
        }
        _ => WordBlock::compile(a, 2).map(Source::Block),
    };
    Some(Box::new(To {
        buffer: buffer?,
        s: s?,
    }))
}

impl Instr for To {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let Some((g, n)) = self.buffer.resolve(mem, UnitAccess::Write)? else {
            return Ok(());
        };
        match &self.s {
            Source::Const(k) => {
                for i in 0..n {
                    let half = if self.buffer.per == 2 && i % 2 == 1 {
                        k >> 16
                    } else {
                        *k
                    };
                    mem.words[g + i] = half as u16;
                }
            }
            Source::Block(b) => match b.resolve(mem, n as u32)? {
                Loc::Word(s) => mem.words.copy_within(s..s + n, g),
                s => {
                    for k in 0..n {
                        let v = s.get(mem, k);
                        mem.words[g + k] = v;
                    }
                }
            },
        }
        Ok(())
    }
}
