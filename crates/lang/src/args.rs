//! [`Args`]: operand access for a family instruction while it compiles.

use super::compile::Compiler;
use super::dialect::Flag;
use super::source::SourceInstr;
use softplc_ir::device::{DeviceKind, DeviceMap, Operand, Reach, UnitAccess};
use softplc_ir::instr::{CpuSlot, CpuState, LocalSlot, LocalState};
use softplc_ir::ops::{BitArg, BitBlock, Block, Num, WordArg};

/// Operand access for a family module compiling one instruction. Every method
/// reports its own diagnostic (with the operand's position) and returns `None`
/// on error.
pub struct Args<'c, 'a> {
    c: &'c mut Compiler<'a>,
    i: &'c SourceInstr,
    m: &'c str,
}

impl<'c, 'a> Args<'c, 'a> {
    pub fn new(c: &'c mut Compiler<'a>, i: &'c SourceInstr, m: &'c str) -> Self {
        Args { c, i, m }
    }

    /// The mnemonic as written, upper case (with its `P` suffix, if any).
    pub fn mnemonic(&self) -> &str {
        self.m
    }

    pub fn len(&self) -> usize {
        self.i.operands.len()
    }

    pub fn is_empty(&self) -> bool {
        self.i.operands.is_empty()
    }

    /// Checks the operand count; reports and returns false otherwise.
    pub fn count(&mut self, allowed: &[usize]) -> bool {
        self.c.count(self.i, self.m, allowed)
    }

    /// The text of operand `k`.
    pub fn text(&self, k: usize) -> &str {
        &self.i.operands[k].text
    }

    /// Operand `k` as parsed syntax (for constants and special operands).
    pub fn operand(&mut self, k: usize) -> Option<Operand> {
        self.c.parse(&self.i.operands[k])
    }

    pub fn word_src(&mut self, k: usize, num: Num) -> Option<WordArg> {
        self.c.word_src(&self.i.operands[k], num)
    }

    /// A destination of `words` words read or written as `num`.
    pub fn word_dest(&mut self, k: usize, num: Num, words: u32) -> Option<WordArg> {
        self.c.word_dest(&self.i.operands[k], num, words)
    }

    pub fn bit_src(&mut self, k: usize) -> Option<BitArg> {
        self.c.bit_operand(&self.i.operands[k])
    }

    pub fn bit_dest(&mut self, k: usize) -> Option<BitArg> {
        self.c.bit_dest(&self.i.operands[k])
    }

    /// A word device starting a block the instruction reads (no constants,
    /// no digit specification).
    pub fn block(&mut self, k: usize) -> Option<Block> {
        self.block_as(k, UnitAccess::Read)
    }

    /// A word device starting a block the instruction writes: in a
    /// multi-CPU system, another CPU's shared memory or a module another
    /// CPU controls is refused when it runs (`UnitOwner::refuses`).
    pub fn block_dest(&mut self, k: usize) -> Option<Block> {
        self.block_as(k, UnitAccess::Write)
    }

    /// A word device starting a block the instruction reads or, with
    /// [`UnitAccess::Write`], writes ([`Self::block`], [`Self::block_dest`]).
    pub fn block_as(&mut self, k: usize, access: UnitAccess) -> Option<Block> {
        let tok = &self.i.operands[k];
        let op = self.c.parse(tok)?;
        let (kind, reach) = match &op {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                ..
            } if !dev.word_kind().is_bit() => (dev.word_kind(), dev.reach),
            _ => {
                self.c
                    .err(tok, format!("`{}`: a word device is needed here", tok.text));
                return None;
            }
        };
        let start = self.c.word_device(tok, op, Num::I16, 1, access)?;
        let map = &self.c.map;
        // A block in buffer memory ends with its module's.
        let limit = match reach {
            Reach::Unit(u) => map
                .unit(u)
                .map_or(0, |w| map.base(DeviceKind::G) + w.first + w.words),
            _ => map.word_at(kind, map.points(kind)),
        };
        Some(Block { start, limit })
    }

    /// A bit device starting a block of bits (BKRST, SFT, BSFR …).
    pub fn bit_block(&mut self, k: usize) -> Option<BitBlock> {
        let tok = &self.i.operands[k];
        let kind = match self.c.parse(tok)? {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                ..
            } if dev.kind.is_bit() => dev.kind,
            _ => {
                self.c
                    .err(tok, format!("`{}`: a bit device is needed here", tok.text));
                return None;
            }
        };
        let start = self.c.bit_operand(tok)?;
        Some(BitBlock {
            start,
            limit: self.c.map.base(kind) + self.c.map.points(kind),
        })
    }

    /// Reports a diagnostic at operand `k` (or at the mnemonic when `k` is out of
    /// range).
    pub fn error(&mut self, k: usize, msg: impl Into<String>) {
        let tok = self.i.operands.get(k).unwrap_or(&self.i.mnemonic).clone();
        self.c.err(&tok, msg);
    }

    /// Allocates `n` hidden state words for this instruction; returns the first index.
    pub fn state_words(&mut self, n: u32) -> u32 {
        self.c.state_words += n;
        self.c.state_words - n
    }

    /// Declares that the instruction uses the first `words` CPU-wide state
    /// words (`ExecCtx::shared`).
    fn need_shared(&mut self, words: u32) {
        self.c.shared_words = self.c.shared_words.max(words);
    }

    /// The flat bit index of system flag `f` in this dialect, `None` when the
    /// dialect or the configured points lack it.
    pub fn flag(&self, f: Flag) -> Option<u32> {
        let (kind, n) = self.c.dialect.flag(f)?;
        self.c.map.index(kind, n)
    }

    /// The CPU-wide state `T` this instruction uses (see [`CpuState`]).
    pub fn cpu<T: CpuState>(&mut self) -> CpuSlot<T> {
        let slot = CpuSlot::new();
        self.need_shared(slot.end());
        slot
    }

    /// Allocates this instruction's typed state (see [`LocalState`]).
    pub fn local<T: LocalState>(&mut self) -> LocalSlot<T> {
        LocalSlot::new(self.state_words(T::WORDS))
    }

    /// The project's setting of type `T` (see [`crate::settings`]), or its default.
    pub fn setting<T: std::any::Any + Clone + Default>(&self) -> T {
        self.c
            .dialect
            .settings
            .get::<T>()
            .cloned()
            .unwrap_or_default()
    }

    pub fn map(&self) -> &DeviceMap {
        self.c.map
    }
}
