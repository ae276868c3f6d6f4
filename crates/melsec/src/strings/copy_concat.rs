//! Character string transfer and concatenation: $MOV (PM §6.5) and $+ (PM §6.2).

use super::{copy_str, dest, put_nul, read_dev_str, read_str, store, str_src, Loc, Str, StrSrc};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;

/// PM §6.5 (data transfer) $MOV(P) `S D`: transfers the character string S (a constant or the
/// string from device S to its NUL) to D onwards, NUL included. Errors: no NUL in
/// S's device (4101); D too short for the string and its NUL (4101, nothing
/// written). S and D may overlap.
#[derive(Debug)]
struct SMov {
    s: StrSrc,
    d: Block,
}

pub(super) fn compile_smov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.block_dest(1);
    Some(Box::new(SMov { s: s?, d: d? }))
}

impl Instr for SMov {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s = read_str(cx.mem, &self.s)?;
        store(cx.mem, &self.d, s)
    }
}

/// PM §6.2 (arithmetic operations) $+(P): `S D` appends the string S to the string in D;
/// `S1 S2 D` stores S1 followed by S2 in D. Errors: a source without NUL in its
/// device (4101); a result running past the end of D's device (4101, nothing
/// written). Overlapping operands are handled; when both sources overlap the
/// destination crosswise (each lies where the other must go) the result is
/// assembled in a 16384-character buffer, and a longer result is 4101
/// (softplc limit; the manual does not define overlapping operands).
#[derive(Debug)]
struct SAdd {
    /// `None` for the 2-operand form (the first string is D's own).
    s1: Option<StrSrc>,
    s2: StrSrc,
    d: Block,
}

pub(super) fn compile_sadd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2, 3]) {
        return None;
    }
    let three = a.len() == 3;
    let s1 = if three { Some(str_src(a, 0)) } else { None };
    let s2 = str_src(a, three as usize);
    let d = a.block_dest(a.len() - 1);
    let s1 = match s1 {
        Some(s) => Some(s?),
        None => None,
    };
    Some(Box::new(SAdd { s1, s2: s2?, d: d? }))
}

/// Byte range of a string in memory, for overlap tests.
fn mem_range(s: &Str<'_>) -> Option<(usize, usize)> {
    match s.loc {
        Loc::Mem(at) => Some((at, at + s.len)),
        Loc::Const(_) => None,
    }
}

fn overlaps(a: Option<(usize, usize)>, b: (usize, usize)) -> bool {
    a.is_some_and(|(s, e)| s < b.1 && b.0 < e)
}

const BUF: usize = 16_384;

impl Instr for SAdd {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let b = read_str(cx.mem, &self.s2)?;
        let a = match &self.s1 {
            Some(s1) => read_str(cx.mem, s1)?,
            None => read_dev_str(cx.mem, &self.d)?,
        };
        let total = a.len + b.len;
        let at = dest(cx.mem, &self.d, total, true)?;
        let words = &mut cx.mem.words;
        let da = (at, at + a.len);
        let db = (at + a.len, at + total);
        // Move first the part whose move does not destroy the other.
        if !overlaps(mem_range(&b), da) {
            copy_str(words, a, at);
            copy_str(words, b, at + a.len);
        } else if !overlaps(mem_range(&a), db) {
            copy_str(words, b, at + a.len);
            copy_str(words, a, at);
        } else {
            if total > BUF {
                return Err(Fault::Range);
            }
            let mut buf = [0u8; BUF];
            for (i, c) in buf[..a.len].iter_mut().enumerate() {
                *c = a.byte(words, i);
            }
            for (i, c) in buf[a.len..total].iter_mut().enumerate() {
                *c = b.byte(words, i);
            }
            let s = Str {
                loc: Loc::Const(&buf[..total]),
                len: total,
            };
            copy_str(words, s, at);
        }
        put_nul(words, at, total);
        Ok(())
    }
}
