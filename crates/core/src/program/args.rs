//! [`Args`]: operand access for a family instruction while it compiles, and
//! the run-time-length block operands [`Block`] and [`BitBlock`].

use super::compile::Compiler;
use super::ops::{BitArg, Num, WordArg};
use super::source::SourceInstr;
use crate::device::{DeviceMap, Operand};
use crate::instructions::{LocalSlot, LocalState};

/// A word-device block operand whose length is known only at run time (BMOV,
/// FMOV, SUM …): the first word and the flat index one past the device's last
/// point, which a block may not cross (4101).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    pub start: WordArg,
    /// Flat index one past the last point of the device kind; for an index-modified
    /// start the range is in its [`Indexed`].
    pub limit: u32,
}

/// A bit-device block operand whose length is known only at run time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BitBlock {
    pub start: BitArg,
    /// Flat bit index one past the last point of the device kind.
    pub limit: u32,
}

/// Operand access for a family module compiling one instruction. Every method
/// reports its own diagnostic (with the operand's position) and returns `None`
/// on error.
pub struct Args<'c, 'a> {
    c: &'c mut Compiler<'a>,
    i: &'c SourceInstr,
    m: &'c str,
}

impl<'c, 'a> Args<'c, 'a> {
    pub(crate) fn new(c: &'c mut Compiler<'a>, i: &'c SourceInstr, m: &'c str) -> Self {
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

    /// A word device starting a block (no constants, no digit specification).
    pub fn block(&mut self, k: usize) -> Option<Block> {
        let tok = &self.i.operands[k];
        let op = self.c.parse(tok)?;
        let kind = match &op {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                ..
            } if !dev.word_kind().is_bit() => dev.word_kind(),
            _ => {
                self.c
                    .err(tok, format!("`{}`: a word device is needed here", tok.text));
                return None;
            }
        };
        let start = self.c.word_device(tok, op, Num::I16, 1)?;
        Some(Block {
            start,
            limit: self.c.map.base(kind) + self.c.map.points(kind),
        })
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

    /// Allocates this instruction's typed state (see [`LocalState`]).
    pub fn local<T: LocalState>(&mut self) -> LocalSlot<T> {
        LocalSlot::new(self.state_words(T::WORDS))
    }

    pub fn map(&self) -> &DeviceMap {
        self.c.map
    }
}
