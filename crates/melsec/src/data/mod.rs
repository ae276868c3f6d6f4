//! Programming manual (common instructions) §7.5 data processing: SER, DSER,
//! SUM, DSUM, DECO, ENCO, SEG, DIS, UNI, NDIS, NUNI, WTOB, BTOW, MAX, MIN,
//! DMAX, DMIN, SORT, DSORT, WSUM, DWSUM.
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! Not implemented: MEAN/DMEAN (§7.5.14) are Universal model (QnU/LCPU)
//! instructions, not in the QnH set; they stay "unsupported" at load.
//!
//! Word blocks (search ranges, tables, destinations of several words) must be
//! word devices (`D100`, `R0Z1`, `W10`); digit-specified bit devices (`K4M0`)
//! are rejected at load for block operands. Every block is range-checked when
//! the instruction runs: a block past the last point of its device, or an
//! index-modified start out of range, is OPERATION ERROR 4101 and nothing is
//! written.
//!
//! This module also holds the block helpers the table and comparison modules
//! share (`fixed_block`, `Bits`, `sm_index`, `elem`).

use super::Args;
use softplc_ir::device::{DeviceMemory, Operand};
use softplc_ir::fault::Fault;
use softplc_ir::ops::{BitBlock, Block};
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

mod decode;
mod digits;
mod minmax_sort;
mod search_sum;
mod wsum;

use decode::{deco, enco, seg};
use digits::{dis, ndis, uni, wtob};
use minmax_sort::{maxmin, sort};
use search_sum::{ser, sum};
use wsum::wsum;

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("SER", &DATA_PROCESSING, |a| ser(a, false)),
    Def::app("DSER", &DATA_PROCESSING, |a| ser(a, true)),
    Def::app("SUM", &DATA_PROCESSING, |a| sum(a, false)),
    Def::app("DSUM", &DATA_PROCESSING, |a| sum(a, true)),
    Def::app("DECO", &DATA_PROCESSING, deco),
    Def::app("ENCO", &DATA_PROCESSING, enco),
    Def::app("SEG", &DATA_PROCESSING, seg),
    Def::app("DIS", &DATA_PROCESSING, dis),
    Def::app("UNI", &DATA_PROCESSING, uni),
    Def::app("NDIS", &DATA_PROCESSING, |a| ndis(a, false)),
    Def::app("NUNI", &DATA_PROCESSING, |a| ndis(a, true)),
    Def::app("WTOB", &DATA_PROCESSING, |a| wtob(a, false)),
    Def::app("BTOW", &DATA_PROCESSING, |a| wtob(a, true)),
    Def::app("MAX", &MAX_MIN_WSUM, |a| maxmin(a, false, true)),
    Def::app("MIN", &MAX_MIN_WSUM, |a| maxmin(a, false, false)),
    Def::app("DMAX", &MAX_MIN_WSUM, |a| maxmin(a, true, true)),
    Def::app("DMIN", &MAX_MIN_WSUM, |a| maxmin(a, true, false)),
    Def::app("SORT", &SORT, |a| sort(a, false)).no_pulse(),
    Def::app("DSORT", &SORT, |a| sort(a, true)).no_pulse(),
    Def::app("WSUM", &MAX_MIN_WSUM, |a| wsum(a, false)),
    Def::app("DWSUM", &MAX_MIN_WSUM, |a| wsum(a, true)),
];

static DATA_PROCESSING: Doc = Doc {
    family: "data processing",
    cite: "PM §7.5",
    notes: "see golden_data.rs",
};
static MAX_MIN_WSUM: Doc = Doc {
    family: "data processing",
    cite: "PM §7.5",
    notes: "n ≤ 0 does nothing",
};
static SORT: Doc = Doc {
    family: "data processing",
    cite: "PM §7.5.12",
    notes: "S2 comparisons per scan, D1 completion, SM703 order; no pulse form",
};

// ------------------------------------------------------------ shared helpers

/// Operand `k` as a word block of a fixed `n` words. Without index
/// modification the whole block is checked at load; with it, at run time.
pub(super) fn fixed_block(a: &mut Args<'_, '_>, k: usize, n: u32) -> Option<Block> {
    let b = a.block(k)?;
    if let WordArg::Word(i) = b.start {
        if i as u64 + n as u64 > b.limit as u64 {
            let msg = format!(
                "`{}`: this operand uses {n} words, beyond the last device",
                a.text(k)
            );
            a.error(k, msg);
            return None;
        }
    }
    Some(b)
}

#[inline]
pub(super) fn get_flag(mem: &DeviceMemory, f: Option<u32>) -> bool {
    f.is_some_and(|i| mem.bits[i as usize])
}

#[inline]
pub(super) fn set_flag(mem: &mut DeviceMemory, f: Option<u32>, v: bool) {
    if let Some(i) = f {
        mem.bits[i as usize] = v;
    }
}

/// A 16-bit count operand read as signed BIN.
#[inline]
pub(super) fn read_i16(mem: &DeviceMemory, a: &WordArg) -> Result<i32, Fault> {
    Ok(mem.read16(a)? as i16 as i32)
}

/// Element `k` of a block of 16-bit (`wide` = false) or 32-bit values, signed.
#[inline]
pub(super) fn elem(mem: &DeviceMemory, base: usize, k: usize, wide: bool) -> i32 {
    if wide {
        let i = base + 2 * k;
        (mem.words[i] as u32 | (mem.words[i + 1] as u32) << 16) as i32
    } else {
        mem.words[base + k] as i16 as i32
    }
}

#[inline]
pub(super) fn set_elem(mem: &mut DeviceMemory, base: usize, k: usize, wide: bool, v: i32) {
    if wide {
        let i = base + 2 * k;
        mem.words[i] = v as u16;
        mem.words[i + 1] = (v as u32 >> 16) as u16;
    } else {
        mem.words[base + k] = v as u16;
    }
}

/// A bit field of run-time length: consecutive bit devices (`M0`, `Y10Z1`) or
/// the bits of consecutive word devices, bit 0 of the first word first (`D0`).
#[derive(Clone, Debug)]
pub(super) enum Bits {
    Bit(BitBlock),
    Word(Block),
}

/// A resolved [`Bits`]: the flat index of the first bit or word.
#[derive(Clone, Copy, Debug)]
pub(super) enum BitsAt {
    Bit(usize),
    Word(usize),
}

impl Bits {
    /// Operand `k`: a bit device (not digit-specified) or a word device.
    pub(super) fn compile(a: &mut Args<'_, '_>, k: usize) -> Option<Bits> {
        match a.operand(k)? {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                ..
            } if dev.kind.is_bit() && !dev.generic => a.bit_block(k).map(Bits::Bit),
            _ => a.block(k).map(Bits::Word),
        }
    }

    /// The first of `n` bits; 4101 past the end of the device.
    #[inline]
    pub(super) fn resolve(&self, mem: &DeviceMemory, n: u32) -> Result<BitsAt, Fault> {
        Ok(match self {
            Bits::Bit(b) => BitsAt::Bit(mem.bit_block_start(b, n)?),
            Bits::Word(b) => BitsAt::Word(mem.block_start(b, n.div_ceil(16))?),
        })
    }
}

impl BitsAt {
    #[inline]
    pub(super) fn get(self, mem: &DeviceMemory, k: usize) -> bool {
        match self {
            BitsAt::Bit(i) => mem.bits[i + k],
            BitsAt::Word(i) => mem.words[i + k / 16] >> (k % 16) & 1 != 0,
        }
    }

    #[inline]
    pub(super) fn set(self, mem: &mut DeviceMemory, k: usize, v: bool) {
        match self {
            BitsAt::Bit(i) => mem.bits[i + k] = v,
            BitsAt::Word(i) => {
                let w = &mut mem.words[i + k / 16];
                if v {
                    *w |= 1 << (k % 16);
                } else {
                    *w &= !(1 << (k % 16));
                }
            }
        }
    }
}

fn num(wide: bool) -> Num {
    if wide {
        Num::I32
    } else {
        Num::I16
    }
}

fn width(wide: bool) -> u32 {
    if wide {
        2
    } else {
        1
    }
}
