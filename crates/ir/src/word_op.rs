//! Word instructions described for native code: the few application
//! instructions a native tier implements inline (`softplc-jit`), told by the
//! instruction itself ([`crate::instr::Instr::word_op`]) so that there is one
//! definition of each. The interpreter runs `exec` as always; the description
//! says what `exec` does when its operands are plain words and constants, in
//! which case it cannot fault. A tier uses the description only then, and
//! its differential tests compare it with `exec`.

use crate::ops::{ResetTc, WordArg};

/// A binary operation of [`WordOp::Binary`], wrapping on 16 or 32 bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binary {
    Add,
    Sub,
    And,
    Or,
    Xor,
}

/// What a word instruction does (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub enum WordOp<'a> {
    /// `d = s1 op s2` on 16-bit (`wide` false) or 32-bit values, low word
    /// first; a 16-bit constant is the low half of its raw bits.
    Binary {
        op: Binary,
        wide: bool,
        s1: &'a WordArg,
        s2: &'a WordArg,
        d: &'a WordArg,
    },
    /// BSET/BRST: bit `n & 15` of word `d` set or cleared.
    Bit {
        set: bool,
        d: &'a WordArg,
        n: &'a WordArg,
    },
    /// RST of a timer or counter: current value 0, contact OFF, and a
    /// timer's sub-unit remainder 0.
    ResetTc(&'a ResetTc),
}
