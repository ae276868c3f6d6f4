//! Programming manual (common instructions) §6.5 data transfer: CML, DCML,
//! BMOV, FMOV, XCH, DXCH, BXCH, SWAP (MOV/DMOV/EMOV live in `basic.rs`).
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! Not QnH instructions, hence not here: DFMOV (Universal models only, in
//! [`crate::qnu::transfer`]), CMLB and DSWAP (not in the Q instruction set),
//! `$MOV` (string family).
//!
//! This module also holds the block-operand helpers the logic, rotation and bit
//! families share ([`WordBlock`], [`count`], [`carry_flag`]).

use super::{Args, ExecCtx, Instr};
use softplc_ir::device::{DeviceMemory, Operand, UnitAccess};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::dialect::Flag;
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("CML", &TRANSFER, |a| cml(a, Num::I16)),
    Def::app("DCML", &TRANSFER, |a| cml(a, Num::I32)),
    Def::app("BMOV", &TRANSFER, bmov),
    Def::app("FMOV", &TRANSFER, fmov),
    Def::app("XCH", &TRANSFER, |a| xch(a, Num::I16)),
    Def::app("DXCH", &TRANSFER, |a| xch(a, Num::I32)),
    Def::app("BXCH", &TRANSFER, bxch),
    Def::app("SWAP", &TRANSFER, swap),
];

static TRANSFER: Doc = Doc {
    family: "transfer",
    cite: "PM §6.5",
    notes: "BMOV overlap-safe; n=0 no-op; past end or n<0 → 4101",
};

// ------------------------------------------------------------ shared helpers

/// Reads the point count `n` of a block instruction. `Ok(None)` for 0 (the
/// instruction does nothing). A negative `n` is 4101: the manual lists only
/// the device-range error for these instructions, and a negative count read as
/// unsigned (65535 − …) runs past the end of every device but ZR.
#[inline]
pub(crate) fn count(mem: &DeviceMemory, n: &WordArg) -> Result<Option<u32>, Fault> {
    match mem.read16(n)? as i16 {
        0 => Ok(None),
        v if v < 0 => Err(Fault::Range),
        v => Ok(Some(v as u32)),
    }
}

/// Flat bit index of the carry flag SM700, `None` when the configuration has
/// fewer SM points (the flag is then not written).
pub(crate) fn carry_flag(a: &Args<'_, '_>) -> Option<u32> {
    a.flag(Flag::Carry)
}

#[inline]
pub(crate) fn set_carry(mem: &mut DeviceMemory, carry: Option<u32>, v: bool) {
    if let Some(c) = carry {
        mem.bits[c as usize] = v;
    }
}

/// A block of 16-bit elements of run-time length: consecutive word devices
/// (`D100`, `R0Z1`, `T0` current values) or consecutive groups of 4·k bits of a
/// digit-specified bit device (`K4M0`: M0-M15, M16-M31 …; `K1X0`: X0-X3, X4-X7 …).
#[derive(Clone, Debug)]
pub(crate) enum WordBlock {
    Words(Block),
    Digits {
        /// `WordArg::Digits` or an index-modified digit operand.
        start: WordArg,
        /// Flat bit index one past the last point of the bit device.
        limit: u32,
        digits: u8,
    },
}

/// A resolved [`WordBlock`]: the flat index of its first element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Loc {
    Word(usize),
    Digits { bit: usize, width: usize },
}

impl Loc {
    /// Element `k` of the block (a digit group zero-extended to 16 bits).
    #[inline]
    pub(crate) fn get(self, mem: &DeviceMemory, k: usize) -> u16 {
        match self {
            Loc::Word(i) => mem.words[i + k],
            Loc::Digits { bit, width } => mem.pack_bits(bit + k * width, width) as u16,
        }
    }

    /// Writes element `k` (a digit group takes the low 4·k bits).
    #[inline]
    pub(crate) fn set(self, mem: &mut DeviceMemory, k: usize, v: u16) {
        match self {
            Loc::Word(i) => mem.words[i + k] = v,
            Loc::Digits { bit, width } => mem.unpack_bits(bit + k * width, width, v as u32),
        }
    }

    /// True when `self` and `other` live in the same flat array and `self`
    /// starts after `other`: a copy from `other` to `self` must then run from
    /// the last element down, so that overlapping blocks move as a whole.
    #[inline]
    fn after(self, other: Loc) -> bool {
        match (self, other) {
            (Loc::Word(d), Loc::Word(s)) => d > s,
            (Loc::Digits { bit: d, .. }, Loc::Digits { bit: s, .. }) => d > s,
            _ => false,
        }
    }
}

impl WordBlock {
    /// Operand `k` as a block the instruction reads: a word device or a
    /// digit-specified bit device (K1-K4), with or without index
    /// modification; no constants.
    pub(crate) fn compile(a: &mut Args<'_, '_>, k: usize) -> Option<WordBlock> {
        WordBlock::compile_as(a, k, UnitAccess::Read)
    }

    /// [`Self::compile`] for a block the instruction writes (`Args::block_dest`).
    pub(crate) fn compile_dest(a: &mut Args<'_, '_>, k: usize) -> Option<WordBlock> {
        WordBlock::compile_as(a, k, UnitAccess::Write)
    }

    fn compile_as(a: &mut Args<'_, '_>, k: usize, access: UnitAccess) -> Option<WordBlock> {
        if let Operand::Device {
            dev,
            digits: Some(digits),
            bit: None,
            ..
        } = a.operand(k)?
        {
            // Checks K1-K4 and that the first element exists.
            let start = a.word_dest(k, Num::I16, 1)?;
            let limit = a.map().base(dev.kind) + a.map().points(dev.kind);
            return Some(WordBlock::Digits {
                start,
                limit,
                digits,
            });
        }
        a.block_as(k, access).map(WordBlock::Words)
    }

    /// The first of `n` elements; 4101 when the block would run past the last
    /// point of its device (index modification included).
    #[inline]
    pub(crate) fn resolve(&self, mem: &DeviceMemory, n: u32) -> Result<Loc, Fault> {
        match self {
            WordBlock::Words(b) => mem.block_start(b, n).map(Loc::Word),
            WordBlock::Digits {
                start,
                limit,
                digits,
            } => {
                let width = 4 * *digits as u64;
                let span = width * n as u64;
                let bit = match start {
                    WordArg::Digits { bit, .. } if *bit as u64 + span <= *limit as u64 => {
                        *bit as u64
                    }
                    WordArg::Indexed(ix) => {
                        let z = mem.words[ix.z as usize] as i16 as i64;
                        let eff = ix.number as i64 + z;
                        if eff < 0 || eff as u64 + span > ix.points as u64 {
                            return Err(Fault::Range);
                        }
                        ix.base as u64 + eff as u64
                    }
                    _ => return Err(Fault::Range),
                };
                Ok(Loc::Digits {
                    bit: bit as usize,
                    width: width as usize,
                })
            }
        }
    }
}

// ------------------------------------------------------------------- CML

/// PM §6.5.4 CML(P)/DCML(P) `S D`: 16/32-bit negation transfer, D = NOT S.
/// S may be a constant. A digit-specified S is zero-extended before the
/// inversion, so the bits of a wider digit-specified D beyond S become 1 (as
/// the manual's K1X0 → K2Y0 example shows). No operation error.
#[derive(Debug)]
struct Cml {
    num: Num,
    s: WordArg,
    d: WordArg,
}

fn cml(a: &mut Args<'_, '_>, num: Num) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, num);
    let d = a.word_dest(1, num, num.words());
    Some(Box::new(Cml { num, s: s?, d: d? }))
}

impl Instr for Cml {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        match self.num {
            Num::I16 => {
                let v = cx.mem.read16(&self.s)?;
                cx.mem.write16(&self.d, !v)
            }
            _ => {
                let v = cx.mem.read32(&self.s)?;
                cx.mem.write32(&self.d, !v)
            }
        }
    }
}

// ------------------------------------------------------------------ BMOV

/// PM §6.5.5 BMOV(P) `S D n`: block transfer of n 16-bit points from S to D.
/// Overlapping blocks are transferred as a whole, as the manual states (the
/// copy runs from the top when D lies above S). S and D are word devices or
/// digit-specified bit devices (element k of `K4M0` is M16k-M16k+15). n = 0
/// does nothing; a block past the end of its device is 4101 (negative n as
/// well, see [`count`]). n may be a constant or a word device.
#[derive(Debug)]
struct Bmov {
    s: WordBlock,
    d: WordBlock,
    n: WordArg,
}

fn bmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = WordBlock::compile(a, 0);
    let d = WordBlock::compile_dest(a, 1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Bmov {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Bmov {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let s = self.s.resolve(cx.mem, n)?;
        let d = self.d.resolve(cx.mem, n)?;
        let n = n as usize;
        match (s, d) {
            (Loc::Word(s), Loc::Word(d)) => cx.mem.words.copy_within(s..s + n, d),
            (
                Loc::Digits { bit: s, width: ws },
                Loc::Digits {
                    bit: d, width: wd, ..
                },
            ) if ws == wd => cx.mem.bits.copy_within(s..s + n * ws, d),
            _ if d.after(s) => {
                for k in (0..n).rev() {
                    let v = s.get(cx.mem, k);
                    d.set(cx.mem, k, v);
                }
            }
            _ => {
                for k in 0..n {
                    let v = s.get(cx.mem, k);
                    d.set(cx.mem, k, v);
                }
            }
        }
        Ok(())
    }
}

// ------------------------------------------------------------------ FMOV

/// PM §6.5.6 FMOV(P) `S D n`: transfers the 16-bit value of S to the n points
/// starting at D. S (constant, word or digit-specified) is read once before
/// writing, so an S inside the block still fills it with its old value. n = 0
/// does nothing; a block past the device end is 4101.
#[derive(Debug)]
struct Fmov {
    s: WordArg,
    d: WordBlock,
    n: WordArg,
}

fn fmov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = WordBlock::compile_dest(a, 1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Fmov {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Fmov {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let v = cx.mem.read16(&self.s)?;
        match self.d.resolve(cx.mem, n)? {
            Loc::Word(d) => cx.mem.words[d..d + n as usize].fill(v),
            d => {
                for k in 0..n as usize {
                    d.set(cx.mem, k, v);
                }
            }
        }
        Ok(())
    }
}

// ------------------------------------------------------------------- XCH

/// PM §6.5.7 XCH(P)/DXCH(P) `D1 D2`: exchanges 16/32-bit data. Both operands
/// are devices (digit specification allowed; a narrower digit-specified
/// operand receives the low bits). No operation error.
#[derive(Debug)]
struct Xch {
    num: Num,
    d1: WordArg,
    d2: WordArg,
}

fn xch(a: &mut Args<'_, '_>, num: Num) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let d1 = a.word_dest(0, num, num.words());
    let d2 = a.word_dest(1, num, num.words());
    Some(Box::new(Xch {
        num,
        d1: d1?,
        d2: d2?,
    }))
}

impl Instr for Xch {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        match self.num {
            Num::I16 => {
                let (a, b) = (cx.mem.read16(&self.d1)?, cx.mem.read16(&self.d2)?);
                cx.mem.write16(&self.d1, b)?;
                cx.mem.write16(&self.d2, a)
            }
            _ => {
                let (a, b) = (cx.mem.read32(&self.d1)?, cx.mem.read32(&self.d2)?);
                cx.mem.write32(&self.d1, b)?;
                cx.mem.write32(&self.d2, a)
            }
        }
    }
}

// ------------------------------------------------------------------ BXCH

/// PM §6.5.8 BXCH(P) `D1 D2 n`: exchanges n points of 16-bit data between the
/// blocks at D1 and D2. n = 0 does nothing; either block past the device end
/// is 4101. The manual does not define overlapping blocks: the points are
/// exchanged one by one from the first (decision).
#[derive(Debug)]
struct Bxch {
    d1: WordBlock,
    d2: WordBlock,
    n: WordArg,
}

fn bxch(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let d1 = WordBlock::compile_dest(a, 0);
    let d2 = WordBlock::compile_dest(a, 1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Bxch {
        d1: d1?,
        d2: d2?,
        n: n?,
    }))
}

impl Instr for Bxch {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let d1 = self.d1.resolve(cx.mem, n)?;
        let d2 = self.d2.resolve(cx.mem, n)?;
        for k in 0..n as usize {
            let (a, b) = (d1.get(cx.mem, k), d2.get(cx.mem, k));
            d1.set(cx.mem, k, b);
            d2.set(cx.mem, k, a);
        }
        Ok(())
    }
}

// ------------------------------------------------------------------ SWAP

/// PM §6.5.9 SWAP(P) `D`: exchanges the upper and lower 8 bits of D. No
/// operation error.
#[derive(Debug)]
struct Swap {
    d: WordArg,
}

fn swap(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    Some(Box::new(Swap {
        d: a.word_dest(0, Num::I16, 1)?,
    }))
}

impl Instr for Swap {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = cx.mem.read16(&self.d)?;
        cx.mem.write16(&self.d, v.swap_bytes())
    }
}
