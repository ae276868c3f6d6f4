//! File-register switching (004 §10.7): RSET selects the block that `R0`-`R32767`
//! address (block k covers ZR k×32768 … k×32768+32767). The block number is in
//! SD648, which `R` operands read when they execute.

use super::{Args, ExecCtx, Instr};
use softplc_ir::device::DeviceKind;
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[Def::app("RSET", &FILE_REGISTER_SWITCHING, compile_rset)];

static FILE_REGISTER_SWITCHING: Doc = Doc {
    family: "file register switching",
    cite: "PM §7.14; 004 §10.7",
    notes: "block in SD648; a block beyond the file register size → 4101",
};

/// `RSET S`: S = block number.
///
/// Decision: a block that does not exist in the configured file-register size
/// (block × 32768 ≥ ZR points) or a negative number is error 4101 and the block
/// stays as it was; the manual leaves accesses to unregistered areas undefined
/// (004 L7180-7194), softplc refuses to select them.
#[derive(Debug)]
struct Rset {
    s: WordArg,
    sd648: usize,
    blocks: i64,
}

fn compile_rset(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    let s = a.word_src(0, Num::I16)?;
    let map = a.map();
    let points = map.points(DeviceKind::ZR) as i64;
    Some(Box::new(Rset {
        s,
        sd648: (map.base(DeviceKind::SD) + 648) as usize,
        blocks: (points + 32767) / 32768,
    }))
}

impl Instr for Rset {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let block = cx.mem.read16(&self.s)? as i16 as i64;
        if block < 0 || block >= self.blocks {
            return Err(ErrorCode::RANGE);
        }
        cx.mem.words[self.sd648] = block as u16;
        Ok(())
    }
}
