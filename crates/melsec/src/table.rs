//! Programming manual (common instructions) §7.7 table operations: FIFW, FIFR,
//! FPOP, FINS, FDEL.
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! A data table is a word block: its first word holds the number of data
//! stored (the pointer), the data follow from the second word, oldest first.
//! In every table instruction the data word comes first and the table second:
//! `FIFW S D` (S written to table D), `FIFR D S` and `FPOP D S` (read from
//! table S into D), `FINS S D n` (S inserted into table D), `FDEL D S n` (the
//! nth datum of table S deleted into D). The order of FIFR/FPOP/FDEL is a
//! decision from the manual's operand names (S = table read, D = datum
//! written, data word first as in FIFW/FINS); a GX Works2 export to the
//! contrary would settle it.
//!
//! Errors (decisions where the manual is terse):
//! - pointer negative: 4100 (not a count); a table whose pointer is 32767
//!   cannot take another datum (FIFW, FINS): 4100;
//! - reading from an empty table (FIFR, FPOP, FDEL with pointer 0): 4100;
//! - FINS n outside 1..pointer+1, FDEL n outside 1..pointer: 4100;
//! - the table (pointer + data, plus the new datum for FIFW/FINS) past the end
//!   of its device, or an index-modified operand out of range: 4101.
//!
//! A datum leaving the table leaves 0 in the word it vacates (the last one).
//! Nothing is written when an error is raised.

use super::data::read_i16;
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("FIFW", &TABLE_OPERATION, fifw),
    Def::app("FIFR", &TABLE_OPERATION, |a| read(a, ReadKind::Oldest)),
    Def::app("FPOP", &TABLE_OPERATION, |a| read(a, ReadKind::Newest)),
    Def::app("FINS", &TABLE_OPERATION, fins),
    Def::app("FDEL", &TABLE_OPERATION, |a| read(a, ReadKind::Nth)),
];

static TABLE_OPERATION: Doc = Doc {
    family: "table operation",
    cite: "PM §7.7",
    notes: "`FIFW S D`, `FIFR D S`, `FPOP D S`, `FINS S D n`, `FDEL D S n` (order unconfirmed)",
};

/// The table's flat word index and its pointer (number of data).
fn table(mem: &DeviceMemory, t: &Block) -> Result<(usize, i32), Fault> {
    let base = mem.block_start(t, 1)?;
    Ok((base, mem.words[base] as i16 as i32))
}

/// PM §7.7.1 FIFW(P) `S D`: writes S after the last datum of table D
/// (D + pointer + 1) and adds 1 to the pointer D. Errors: module header.
#[derive(Debug)]
struct Fifw {
    s: WordArg,
    d: Block,
}

fn fifw(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = a.block_dest(1);
    Some(Box::new(Fifw { s: s?, d: d? }))
}

impl Instr for Fifw {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let v = mem.read16(&self.s)?;
        let (t, count) = table(mem, &self.d)?;
        if !(0..i16::MAX as i32).contains(&count) {
            return Err(Fault::Operation);
        }
        mem.block_start(&self.d, count as u32 + 2)?;
        mem.words[t + count as usize + 1] = v;
        mem.words[t] = (count + 1) as u16;
        Ok(())
    }
}

/// Which datum a reading instruction takes out of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ReadKind {
    /// FIFR: the first (oldest) datum; the rest move up one word.
    Oldest,
    /// FPOP: the last (newest) datum.
    Newest,
    /// FDEL: the nth datum (n from 1); those after it move up one word.
    Nth,
}

/// PM §7.7.2 FIFR(P) `D S`: takes the oldest datum (S+1) of table S into D,
/// moves the others up one word and subtracts 1 from the pointer S.
/// PM §7.7.3 FPOP(P) `D S`: takes the newest datum (S + pointer) into D and
/// subtracts 1 from the pointer. PM §7.7.4 FDEL(P) `D S n`: takes the nth
/// datum into D, moves the data after it up one word and subtracts 1 from the
/// pointer. The vacated last word becomes 0. Errors: module header (empty
/// table or n outside 1..pointer: 4100).
#[derive(Debug)]
struct Read {
    d: WordArg,
    s: Block,
    n: Option<WordArg>,
    kind: ReadKind,
}

fn read(a: &mut Args<'_, '_>, kind: ReadKind) -> Option<Box<dyn Instr>> {
    let nth = kind == ReadKind::Nth;
    if !a.count(if nth { &[3] } else { &[2] }) {
        return None;
    }
    let d = a.word_dest(0, Num::I16, 1);
    // The table loses the value read.
    let s = a.block_dest(1);
    let n = if nth {
        Some(a.word_src(2, Num::I16)?)
    } else {
        None
    };
    Some(Box::new(Read {
        d: d?,
        s: s?,
        n,
        kind,
    }))
}

impl Instr for Read {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        // Checks an index-modified destination before the table changes.
        mem.read16(&self.d)?;
        let (t, count) = table(mem, &self.s)?;
        if count <= 0 {
            return Err(Fault::Operation);
        }
        let pos = match (self.kind, &self.n) {
            (ReadKind::Oldest, _) => 1,
            (ReadKind::Newest, _) => count,
            (ReadKind::Nth, Some(n)) => read_i16(mem, n)?,
            (ReadKind::Nth, None) => 1,
        };
        if !(1..=count).contains(&pos) {
            return Err(Fault::Operation);
        }
        mem.block_start(&self.s, count as u32 + 1)?;
        let (pos, last) = (t + pos as usize, t + count as usize);
        let v = mem.words[pos];
        mem.words.copy_within(pos + 1..=last, pos);
        mem.words[last] = 0;
        mem.words[t] = (count - 1) as u16;
        mem.write16(&self.d, v)
    }
}

/// PM §7.7.4 FINS(P) `S D n`: inserts S as the nth datum (n from 1) of table D;
/// the data from the nth on move down one word and the pointer D gets 1 more.
/// n = pointer + 1 appends. Errors: module header (n outside 1..pointer+1:
/// 4100).
#[derive(Debug)]
struct Fins {
    s: WordArg,
    d: Block,
    n: WordArg,
}

fn fins(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.word_src(0, Num::I16);
    let d = a.block_dest(1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Fins {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Fins {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let v = mem.read16(&self.s)?;
        let n = read_i16(mem, &self.n)?;
        let (t, count) = table(mem, &self.d)?;
        if !(0..i16::MAX as i32).contains(&count) || !(1..=count + 1).contains(&n) {
            return Err(Fault::Operation);
        }
        mem.block_start(&self.d, count as u32 + 2)?;
        let (pos, last) = (t + n as usize, t + count as usize);
        mem.words.copy_within(pos..=last, pos + 1);
        mem.words[pos] = v;
        mem.words[t] = (count + 1) as u16;
        Ok(())
    }
}
