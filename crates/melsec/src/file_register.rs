//! File registers (004 §10.7): RSET selects the block that `R0`-`R32767`
//! address (block k covers ZR k×32768 … k×32768+32767; the block number is in
//! SD648, which `R` operands read when they execute); ZRRDB/ZRWRB read and
//! write them byte by byte. Reading or writing R or ZR outside the
//! registered range is no error (004 §10.7.5 (1), L7180-7194): reads give 0,
//! writes are ignored, and SM672 turns ON at END when the file registers are
//! on the memory card (`system::file_register`).

use super::{Args, ExecCtx, Instr};
use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("RSET", &FILE_REGISTER_SWITCHING, compile_rset),
    Def::app("ZRRDB", &BYTE_ACCESS, |a| compile_byte(a, false)),
    Def::app("ZRWRB", &BYTE_ACCESS, |a| compile_byte(a, true)),
];

static FILE_REGISTER_SWITCHING: Doc = Doc {
    family: "file register switching",
    cite: "PM §7.14; 004 §10.7",
    notes: "block 0-31 in SD648, one beyond the registered file registers too (its R read 0, writes ignored, no error); a negative block or one past 31 → 4101",
};
static BYTE_ACCESS: Doc = Doc {
    family: "file register byte access",
    cite: "PM §7.18 ZRRDB/ZRWRB; 004 §10.7",
    notes: "byte n (32-bit) of ZR: 2k = low byte of ZRk, 2k+1 = high byte; ZRRDB clears D's high byte; beyond the file registers → 4101",
};

/// `RSET S`: S = block number.
///
/// A block beyond the registered file registers is selected with no error:
/// the manual has the program check SD647 before it switches (004 §10.7.5
/// (2) (a)) and makes accesses outside the registered range no error
/// (§10.7.5 (1)). Decision: a negative block or one past 31 (the largest
/// file-register file, 1018K points = ZR0-1042431, Table 10.1, holds blocks
/// 0-31) is error 4101 and the block stays as it was.
#[derive(Debug)]
struct Rset {
    s: WordArg,
    sd648: usize,
}

/// The last block of the largest file-register file (1042432 points).
const LAST_BLOCK: i64 = 31;

fn compile_rset(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    let s = a.word_src(0, Num::I16)?;
    let map = a.map();
    Some(Box::new(Rset {
        s,
        sd648: (map.base(DeviceKind::SD) + crate::system::R_BLOCK) as usize,
    }))
}

impl Instr for Rset {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let block = cx.mem.read16(&self.s)? as i16 as i64;
        if !(0..=LAST_BLOCK).contains(&block) {
            return Err(Fault::Range);
        }
        cx.mem.words[self.sd648] = block as u16;
        Ok(())
    }
}

/// `ZRRDB n D` / `ZRWRB n S` (PM §7.18, reading and writing file registers in
/// 1-byte units): n is the byte number counted over all file registers, two a
/// register, low byte first (byte 2k is the low byte of ZRk, 2k+1 its high
/// byte). ZRRDB stores the byte in the low byte of D and clears the high byte;
/// ZRWRB writes the low byte of S and leaves the other byte of the register.
///
/// Decisions (the manual is not among the references at hand): n is a 32-bit
/// BIN value (the byte numbers of a 1 MB card exceed 16 bits); n negative or
/// at or beyond 2 × the file-register points is 4101 and nothing is written.
#[derive(Debug)]
struct ByteAccess {
    n: WordArg,
    data: WordArg,
    /// Flat word index of ZR0 and the file-register points.
    zr: usize,
    points: u32,
    write: bool,
}

fn compile_byte(a: &mut Args<'_, '_>, write: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let n = a.word_src(0, Num::I32);
    let data = if write {
        a.word_src(1, Num::I16)
    } else {
        a.word_dest(1, Num::I16, 1)
    };
    let map = a.map();
    Some(Box::new(ByteAccess {
        n: n?,
        data: data?,
        zr: map.base(DeviceKind::ZR) as usize,
        points: map.points(DeviceKind::ZR),
        write,
    }))
}

impl Instr for ByteAccess {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = cx.mem.read32(&self.n)? as i32 as i64;
        if n < 0 || n >= 2 * self.points as i64 {
            return Err(Fault::Range);
        }
        let word = self.zr + (n / 2) as usize;
        let shift = 8 * (n % 2) as u32;
        if self.write {
            let byte = cx.mem.read16(&self.data)? & 0xFF;
            let w = &mut cx.mem.words[word];
            *w = *w & !(0xFF << shift) | byte << shift;
            Ok(())
        } else {
            let byte = cx.mem.words[word] >> shift & 0xFF;
            cx.mem.write16(&self.data, byte)
        }
    }
}
