//! Programming manual (common instructions) §7.4 bit processing: BSET, BRST,
//! TEST, DTEST, BKRST.
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! ZRST is not a MELSEC-Q instruction (it belongs to the FX/iQ-F set; the Q
//! equivalent is BKRST): it is rejected at load with a diagnostic that says so.

use super::transfer::count;
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::{DeviceKind, Operand};
use softplc_ir::fault::Fault;
use softplc_ir::ops::{BitArg, Num, WordArg};
use softplc_ir::ops::{BitBlock, Block};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("BSET", &BIT_PROCESSING, |a| bit_op(a, true)),
    Def::app("BRST", &BIT_PROCESSING, |a| bit_op(a, false)),
    Def::app("TEST", &BIT_PROCESSING, |a| test(a, Num::I16)),
    Def::app("DTEST", &BIT_PROCESSING, |a| test(a, Num::I32)),
    Def::app("BKRST", &BIT_PROCESSING, bkrst),
];

static BIT_PROCESSING: Doc = Doc {
    family: "bit processing",
    cite: "PM §7.4",
    notes: "BKRST of T/ST/C clears value and contact",
};

// ------------------------------------------------------------- BSET / BRST

/// PM §7.4.1 BSET/BRST `D n`: turns bit n of the word device D ON (BSET) or
/// OFF (BRST). n is 0-15; for a larger (or negative) n the low 4 bits are used,
/// as the manual says. n may be a constant. A digit-specified D is accepted
/// (bit n of the specified bits; a bit beyond them is not changed). No
/// operation error.
#[derive(Debug)]
struct BitOp {
    set: bool,
    d: WordArg,
    n: WordArg,
}

fn bit_op(a: &mut Args<'_, '_>, set: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let d = a.word_dest(0, Num::I16, 1);
    let n = a.word_src(1, Num::I16);
    Some(Box::new(BitOp { set, d: d?, n: n? }))
}

impl Instr for BitOp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let b = cx.mem.read16(&self.n)? & 15;
        let v = cx.mem.read16(&self.d)?;
        let v = if self.set { v | 1 << b } else { v & !(1 << b) };
        cx.mem.write16(&self.d, v)
    }

    fn word_op(&self) -> Option<softplc_ir::word_op::WordOp<'_>> {
        Some(softplc_ir::word_op::WordOp::Bit {
            set: self.set,
            d: &self.d,
            n: &self.n,
        })
    }
}

// ------------------------------------------------------------ TEST / DTEST

/// PM §7.4.2 TEST/DTEST `S1 S2 D`: writes bit S2 of the 16-bit (DTEST: 32-bit)
/// data S1 to the bit device D. S2 is 0-15 (0-31); a larger value uses its
/// low 4 (5) bits. S1 is a word device or a digit-specified bit device (not a
/// constant); S2 may be a constant; D is a bit device or a word device bit
/// (`D0.5`). No operation error.
#[derive(Debug)]
struct Test {
    wide: bool,
    s1: WordArg,
    s2: WordArg,
    d: BitArg,
}

fn test(a: &mut Args<'_, '_>, num: Num) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = match a.operand(0) {
        Some(Operand::Const(_)) => {
            let t = a.text(0).to_string();
            a.error(
                0,
                format!("constant `{t}`: the data to test (S1) must be a device"),
            );
            None
        }
        Some(_) => a.word_src(0, num),
        None => None,
    };
    let s2 = a.word_src(1, Num::I16);
    let d = a.bit_dest(2);
    Some(Box::new(Test {
        wide: num == Num::I32,
        s1: s1?,
        s2: s2?,
        d: d?,
    }))
}

impl Instr for Test {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let b = cx.mem.read16(&self.s2)?;
        let on = if self.wide {
            cx.mem.read32(&self.s1)? >> (b & 31) & 1 != 0
        } else {
            cx.mem.read16(&self.s1)? >> (b & 15) & 1 != 0
        };
        cx.mem.write_bit(&self.d, on)
    }
}

// ------------------------------------------------------------------ BKRST

/// What BKRST clears.
#[derive(Debug)]
enum Target {
    /// n bit devices from the head.
    Bits(BitBlock),
    /// n timers (T/ST) or counters (C): current value and contact.
    Tc {
        contact_base: u32,
        value_base: u32,
        number: u32,
        points: u32,
        /// Flat word index of the index register, if index-modified.
        z: Option<u32>,
    },
    /// n word devices set to 0.
    Words(Block),
}

/// PM §7.4.3 BKRST `D n`: resets n points from D. A bit device: n bits turn
/// OFF. Timers/retentive timers/counters (`T0`, `ST0`, `C0`, also written
/// `TS0`/`TC0`): as RST, the current value becomes 0 and the contact turns OFF,
/// for n of them; the coil is left alone and (limitation) the timer's hidden
/// sub-unit remainder is not cleared, as the family interface cannot reach it —
/// it is below one time-base unit and is cleared when the timer coil goes OFF.
/// A word device (`D0`, `TN0`, `CN0`): n words become 0 (decision: the manual
/// describes bit devices; a word head is accepted as a block clear). Digit-specified operands and word device bits are
/// rejected. n = 0 does nothing; n points past the device end is 4101
/// (negative n too).
#[derive(Debug)]
struct Bkrst {
    target: Target,
    n: WordArg,
}

fn bkrst(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let target = bkrst_target(a);
    let n = a.word_src(1, Num::I16);
    Some(Box::new(Bkrst {
        target: target?,
        n: n?,
    }))
}

fn bkrst_target(a: &mut Args<'_, '_>) -> Option<Target> {
    let op = a.operand(0)?;
    let Operand::Device {
        dev,
        digits: None,
        bit: None,
        index,
    } = op
    else {
        let t = a.text(0).to_string();
        a.error(
            0,
            format!("`{t}`: BKRST needs the head of a bit device, timer, counter or word device"),
        );
        return None;
    };
    use DeviceKind::*;
    let tc = match dev.kind {
        TS | TC => Some((TS, TN)),
        STS | STC => Some((STS, STN)),
        CS | CC => Some((CS, CN)),
        _ => None,
    };
    if let Some((contact, value)) = tc {
        let map = a.map();
        let points = map.points(contact);
        let (contact_base, value_base) = (map.base(contact), map.base(value));
        if dev.number >= points {
            // Let the general operand check word the range diagnostic.
            a.bit_block(0)?;
            return None;
        }
        let z = index.map(|z| map.base(Z) + z as u32);
        return Some(Target::Tc {
            contact_base,
            value_base,
            number: dev.number,
            points,
            z,
        });
    }
    if dev.kind.is_bit() {
        a.bit_block(0).map(Target::Bits)
    } else {
        a.block_dest(0).map(Target::Words)
    }
}

impl Instr for Bkrst {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(n) = count(cx.mem, &self.n)? else {
            return Ok(());
        };
        let n = n as usize;
        match &self.target {
            Target::Bits(b) => {
                let s = cx.mem.bit_block_start(b, n as u32)?;
                cx.mem.bits[s..s + n].fill(false);
            }
            Target::Words(b) => {
                let s = cx.mem.block_start(b, n as u32)?;
                cx.mem.words[s..s + n].fill(0);
            }
            Target::Tc {
                contact_base,
                value_base,
                number,
                points,
                z,
            } => {
                let z = z.map_or(0, |z| cx.mem.words[z as usize] as i16 as i64);
                let eff = *number as i64 + z;
                if eff < 0 || eff + n as i64 > *points as i64 {
                    return Err(Fault::Range);
                }
                let (c, v) = (
                    (*contact_base as i64 + eff) as usize,
                    (*value_base as i64 + eff) as usize,
                );
                cx.mem.bits[c..c + n].fill(false);
                cx.mem.words[v..v + n].fill(0);
            }
        }
        Ok(())
    }
}
