//! The dialect seam: what the compiler, the loaders and the doors ask of a PLC
//! family. A [`Dialect`] is chosen once (from `[cpu] model` or the file
//! extension) and carries the instruction set, the device table (names and
//! decimal/hex/octal numbering), the order of 32-bit word pairs, and the
//! system flags instructions use, named by role.
//!
//! MELSEC-Q is `softplc_melsec::dialect()` (the process CPU's
//! `process_dialect`), the APLC-TCP `softplc_aplc::dialect()`. Which one a
//! CPU compiles in follows its model's profile (`softplc_core::profile`).

use softplc_ir::device::{DeviceKind, DeviceTable};

use super::isa::Isa;
use super::settings::Settings;

/// A system flag an instruction reads or writes, by its role (MELSEC SM700,
/// SM701 …; the APLC has its own numbers for the same roles).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flag {
    /// The carry of rotations and shifts (MELSEC SM700).
    Carry,
    /// "Do not write the closing 00H" of string output (MELSEC SM701).
    NoNul,
    /// Binary instead of sequential search (MELSEC SM702).
    BinarySearch,
    /// Sort in descending order (MELSEC SM703).
    SortDescending,
    /// All results of a block comparison true (MELSEC SM704).
    AllTrue,
}

/// How a 32-bit value sits in two consecutive words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WordOrder {
    /// MELSEC: the low word first (D0 low, D1 high; 004 §2.8).
    LowFirst,
    /// APLC: the high word first (Dn high, Dn+1 low; contract §1.1).
    HighFirst,
}

/// A PLC dialect. A project may make its own copy with other
/// [`Settings`] (`Dialect { settings, ..base.clone() }`).
#[derive(Clone, Debug)]
pub struct Dialect {
    /// The family's name, for messages ("MELSEC-Q").
    pub name: &'static str,
    pub isa: &'static Isa,
    pub devices: &'static DeviceTable,
    pub word_order: WordOrder,
    /// Where each system flag lives.
    pub flags: &'static [(Flag, DeviceKind, u32)],
    /// The project's choices instructions read when they compile.
    pub settings: Settings,
}

impl Dialect {
    /// The device holding system flag `f`, if the dialect has it.
    pub fn flag(&self, f: Flag) -> Option<(DeviceKind, u32)> {
        self.flags
            .iter()
            .find(|(g, _, _)| *g == f)
            .map(|&(_, k, n)| (k, n))
    }
}
