//! Programming manual (common instructions) §7.2 rotation (ROR, ROL, RCR, RCL,
//! DROR, DROL, DRCR, DRCL), §7.3 shift (SFR, SFL, BSFR, BSFL, DSFR, DSFL) and
//! the sequence instruction SFT (§5.4.1, bit device shift).
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! Rotation and n-bit shift counts follow the manual: n is 0-15 (0-31 for the
//! 32-bit forms) and a larger n uses the remainder of n / 16 (n / 32); for a
//! digit-specified bit device the operation runs within the specified bits and
//! uses the remainder of n / (number of bits) (n = 15 on K3 = 12 bits rotates
//! 3). The manual lists no operation error for them. n is a BIN 16-bit value:
//! a negative n is taken as unsigned (K-1 = 65535; decision, the manual gives
//! no meaning to negative counts). When the remainder is 0 nothing moves and
//! the carry flag SM700 keeps its value (decision).
//!
//! SFTBR/SFTBL/SFTWR/SFTWL (n-bit shifts of n bits/words) are QnU-only and not
//! implemented.

use super::transfer::{carry_flag, count, set_carry, Loc, WordBlock};
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::{DeviceKind, Operand};
use softplc_ir::fault::Fault;
use softplc_ir::ops::BitBlock;
use softplc_ir::ops::{BitArg, Indexed, IndexedKind, Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("ROR", &ROTATION, |a| rotate(a, Dir::Ror, Num::I16)),
    Def::app("ROL", &ROTATION, |a| rotate(a, Dir::Rol, Num::I16)),
    Def::app("RCR", &ROTATION, |a| rotate(a, Dir::Rcr, Num::I16)),
    Def::app("RCL", &ROTATION, |a| rotate(a, Dir::Rcl, Num::I16)),
    Def::app("DROR", &ROTATION, |a| rotate(a, Dir::Ror, Num::I32)),
    Def::app("DROL", &ROTATION, |a| rotate(a, Dir::Rol, Num::I32)),
    Def::app("DRCR", &ROTATION, |a| rotate(a, Dir::Rcr, Num::I32)),
    Def::app("DRCL", &ROTATION, |a| rotate(a, Dir::Rcl, Num::I32)),
    Def::app("SFR", &SHIFT, |a| rotate(a, Dir::Sfr, Num::I16)),
    Def::app("SFL", &SHIFT, |a| rotate(a, Dir::Sfl, Num::I16)),
    Def::app("BSFR", &SHIFT, |a| bit_shift(a, false)),
    Def::app("BSFL", &SHIFT, |a| bit_shift(a, true)),
    Def::app("DSFR", &SHIFT, |a| word_shift(a, false)),
    Def::app("DSFL", &SHIFT, |a| word_shift(a, true)),
    Def::app("SFT", &SHIFT_2, sft),
];

static ROTATION: Doc = Doc {
    family: "rotation",
    cite: "PM §7.2",
    notes: "SM700 carry; n mod width",
};
static SHIFT: Doc = Doc {
    family: "shift",
    cite: "PM §7.3",
    notes: "SM700 = last bit out",
};
static SHIFT_2: Doc = Doc {
    family: "shift",
    cite: "PM §5.4",
    notes: "D ← D-1, D-1 OFF",
};

// ------------------------------------------------------ rotation, n-bit shift

/// Direction and kind of a rotation or n-bit shift.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dir {
    /// Rotate right, not including the carry flag; SM700 = last bit rotated
    /// out (bit n-1 before the rotation).
    Ror,
    /// Rotate left, not including the carry flag; SM700 = last bit rotated
    /// out (bit w-n before the rotation).
    Rol,
    /// Rotate right through the carry flag (a ring of w + 1 bits).
    Rcr,
    /// Rotate left through the carry flag.
    Rcl,
    /// Shift right, the upper n bits filled with 0; SM700 = last bit shifted out.
    Sfr,
    /// Shift left, the lower n bits filled with 0; SM700 = last bit shifted out.
    Sfl,
}

/// PM §7.2.1 ROR/RCR, §7.2.2 ROL/RCL, §7.2.3 DROR/DRCR, §7.2.4 DROL/DRCL and
/// §7.3.1 SFR/SFL `D n`: rotates or shifts the 16-bit (D… forms: 32-bit) data
/// of D by n bits, within the specified bits when D is digit-specified
/// (K1-K4, K1-K8 for the 32-bit forms). ROR/ROL/SFR/SFL set the carry flag
/// SM700 to the last bit moved out; RCR/RCL/DRCR/DRCL rotate through it. n may
/// be a constant. No operation error (an index-modified D out of range is 4101).
#[derive(Debug)]
struct Rotate {
    dir: Dir,
    wide: bool,
    /// Bits rotated: 16/32, or 4·k for a digit-specified D.
    width: u32,
    d: WordArg,
    n: WordArg,
    carry: Option<u32>,
}

fn rotate(a: &mut Args<'_, '_>, dir: Dir, num: Num) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let d = a.word_dest(0, num, num.words());
    let n = a.word_src(1, Num::I16);
    let d = d?;
    let full = if num == Num::I16 { 16 } else { 32 };
    let width = match &d {
        WordArg::Digits { n, .. } => 4 * *n as u32,
        WordArg::Indexed(ix) => match ix.kind {
            IndexedKind::Digits(n) => 4 * n as u32,
            _ => full,
        },
        _ => full,
    };
    Some(Box::new(Rotate {
        dir,
        wide: num != Num::I16,
        width,
        d,
        n: n?,
        carry: carry_flag(a),
    }))
}

impl Instr for Rotate {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let w = self.width;
        let n = cx.mem.read16(&self.n)? as u32 % w;
        if n == 0 {
            // Still range-check an index-modified D.
            return if self.wide {
                cx.mem.read32(&self.d).map(drop)
            } else {
                cx.mem.read16(&self.d).map(drop)
            };
        }
        let mask = if w == 32 { u32::MAX } else { (1 << w) - 1 };
        let v = if self.wide {
            cx.mem.read32(&self.d)?
        } else {
            cx.mem.read16(&self.d)? as u32
        } & mask;
        let carry_in = self.carry.is_some_and(|c| cx.mem.bits[c as usize]) as u32;
        let (r, c) = match self.dir {
            Dir::Ror => ((v >> n | v << (w - n)) & mask, v >> (n - 1) & 1),
            Dir::Rol => ((v << n | v >> (w - n)) & mask, v >> (w - n) & 1),
            Dir::Sfr => (v >> n, v >> (n - 1) & 1),
            Dir::Sfl => (v << n & mask, v >> (w - n) & 1),
            Dir::Rcr => {
                let (mut v, mut c) = (v, carry_in);
                for _ in 0..n {
                    let out = v & 1;
                    v = v >> 1 | c << (w - 1);
                    c = out;
                }
                (v, c)
            }
            Dir::Rcl => {
                let (mut v, mut c) = (v, carry_in);
                for _ in 0..n {
                    let out = v >> (w - 1) & 1;
                    v = (v << 1 & mask) | c;
                    c = out;
                }
                (v, c)
            }
        };
        if self.wide {
            cx.mem.write32(&self.d, r)?;
        } else {
            cx.mem.write16(&self.d, r as u16)?;
        }
        set_carry(cx.mem, self.carry, c != 0);
        Ok(())
    }
}

// ------------------------------------------------------------- BSFR / BSFL

/// Rejects timer and counter contacts/coils as the head of a bit block (they
/// are driven by `OUT T`/`OUT C`).
fn plain_bits(a: &mut Args<'_, '_>, k: usize) -> Option<BitBlock> {
    if let Operand::Device { dev, .. } = a.operand(k)? {
        use DeviceKind::*;
        if matches!(dev.kind, TS | TC | STS | STC | CS | CC) {
            let t = a.text(k).to_string();
            a.error(
                k,
                format!("`{t}`: timer and counter contacts cannot be shifted; a bit device such as M or Y is needed"),
            );
            return None;
        }
    }
    a.bit_block(k)
}

/// PM §7.3.2 BSFR/BSFL `D n`: shifts the n bits starting at D by one bit.
/// BSFR: D+k takes D+k+1, D+(n-1) becomes 0 and the carry flag SM700 takes
/// the old D. BSFL: D+k takes D+k-1, D becomes 0 and SM700 takes the old
/// D+(n-1). D is a bit device (index modification allowed). n = 0 does
/// nothing; n bits past the end of the device is 4101 (negative n too).
#[derive(Debug)]
struct BitShift {
    left: bool,
    d: BitBlock,
    n: WordArg,
    carry: Option<u32>,
}

fn bit_shift(a: &mut Args<'_, '_>, left: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let d = plain_bits(a, 0);
    let n = a.word_src(1, Num::I16);
    Some(Box::new(BitShift {
        left,
        d: d?,
        n: n?,
        carry: carry_flag(a),
    }))
}

impl Instr for BitShift {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let s = cx.mem.bit_block_start(&self.d, n)?;
        let e = s + n as usize;
        let bits = &mut cx.mem.bits;
        let out = if self.left {
            let out = bits[e - 1];
            bits.copy_within(s..e - 1, s + 1);
            bits[s] = false;
            out
        } else {
            let out = bits[s];
            bits.copy_within(s + 1..e, s);
            bits[e - 1] = false;
            out
        };
        set_carry(cx.mem, self.carry, out);
        Ok(())
    }
}

// ------------------------------------------------------------- DSFR / DSFL

/// PM §7.3.3 DSFR/DSFL `D n`: shifts the n words starting at D by one word.
/// DSFR: D+k takes D+k+1 and D+(n-1) becomes 0; DSFL: D+k takes D+k-1 and D
/// becomes 0. D is a word device or a digit-specified bit device (one element
/// = the specified digits). n = 0 does nothing; n points past the end of the
/// device is 4101 (negative n too). The carry flag is not affected.
#[derive(Debug)]
struct WordShift {
    left: bool,
    d: WordBlock,
    n: WordArg,
}

fn word_shift(a: &mut Args<'_, '_>, left: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let d = WordBlock::compile(a, 0);
    let n = a.word_src(1, Num::I16);
    Some(Box::new(WordShift { left, d: d?, n: n? }))
}

impl Instr for WordShift {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let n = n as usize;
        match (self.d.resolve(cx.mem, n as u32)?, self.left) {
            (Loc::Word(i), false) => {
                cx.mem.words.copy_within(i + 1..i + n, i);
                cx.mem.words[i + n - 1] = 0;
            }
            (Loc::Word(i), true) => {
                cx.mem.words.copy_within(i..i + n - 1, i + 1);
                cx.mem.words[i] = 0;
            }
            (d, false) => {
                for k in 0..n - 1 {
                    let v = d.get(cx.mem, k + 1);
                    d.set(cx.mem, k, v);
                }
                d.set(cx.mem, n - 1, 0);
            }
            (d, true) => {
                for k in (1..n).rev() {
                    let v = d.get(cx.mem, k - 1);
                    d.set(cx.mem, k, v);
                }
                d.set(cx.mem, 0, 0);
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------- SFT

/// Where SFT shifts to, resolved at load time when possible.
#[derive(Debug)]
enum SftAt {
    /// A bit device; `prev` is the device one before (none for number 0).
    Bit {
        at: u32,
        prev: Option<u32>,
    },
    /// Bit `bit` of a word device (`D0.5`).
    WordBit {
        word: u32,
        bit: u8,
    },
    Indexed(Box<Indexed>),
}

/// PM §5.4.1 SFT(P) `D`: bit device shift. For a bit device, D takes the
/// ON/OFF state of the device one before it (D-1), and D-1 turns OFF. For a
/// word device bit (`D0.5`), bit b takes bit b-1 and bit b-1 becomes 0. Used
/// from the highest device down to build a shift register (SFT M15, SFT M14 …).
/// No operation error (an index-modified D out of range is 4101).
///
/// Decision (not covered by the manual): for device number 0 or bit 0 there is
/// no preceding point; it counts as OFF, so D turns OFF.
#[derive(Debug)]
struct Sft {
    at: SftAt,
}

fn sft(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    let number = match a.operand(0)? {
        Operand::Device { dev, .. } => dev.number,
        _ => 0,
    };
    let at = match a.bit_dest(0)? {
        BitArg::Bit(at) => SftAt::Bit {
            at,
            prev: (number > 0).then(|| at - 1),
        },
        BitArg::WordBit { word, bit } => SftAt::WordBit { word, bit },
        BitArg::Indexed(ix) => SftAt::Indexed(ix),
    };
    Some(Box::new(Sft { at }))
}

/// The word-bit form of SFT: bit `b` takes bit `b-1`, which becomes 0.
#[inline]
fn sft_word(w: &mut u16, b: u8) {
    let v = if b == 0 {
        0
    } else {
        let v = *w >> (b - 1) & 1;
        *w &= !(1 << (b - 1));
        v
    };
    *w = *w & !(1 << b) | v << b;
}

impl Instr for Sft {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        match &self.at {
            SftAt::Bit { at, prev } => {
                let v = match prev {
                    Some(p) => std::mem::replace(&mut mem.bits[*p as usize], false),
                    None => false,
                };
                mem.bits[*at as usize] = v;
            }
            SftAt::WordBit { word, bit } => sft_word(&mut mem.words[*word as usize], *bit),
            SftAt::Indexed(ix) => {
                let z = mem.words[ix.z as usize] as i16 as i64;
                let eff = ix.number as i64 + z;
                if eff < 0 || eff >= ix.points as i64 {
                    return Err(Fault::Range);
                }
                let i = (ix.base as i64 + eff) as usize;
                match ix.kind {
                    IndexedKind::WordBit(b) => sft_word(&mut mem.words[i], b),
                    _ => {
                        let v = eff > 0 && std::mem::replace(&mut mem.bits[i - 1], false);
                        mem.bits[i] = v;
                    }
                }
            }
        }
        Ok(())
    }
}
