//! Parts of character strings (PM §7.11): RIGHT, LEFT, MIDR, MIDW and the search INSTR.

use super::{copy_str, put_nul, read_dev_str, read_str, read_words, store, str_src, Loc, StrSrc};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// PM §7.11.15 RIGHT(P) / LEFT(P) `S D n`: the last / first n characters of
/// the string S as a string (with 00H) in D; n = 0 stores an empty string.
/// Errors (4101): n negative or larger than the length of S, no NUL in S.
#[derive(Debug)]
struct Side {
    right: bool,
    s: StrSrc,
    d: Block,
    n: WordArg,
}

pub(super) fn compile_side(a: &mut Args<'_, '_>, right: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.block_dest(1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Side {
        right,
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Side {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s = read_str(cx.mem, &self.s)?;
        let n = cx.mem.read16(&self.n)? as i16;
        if n < 0 || n as usize > s.len {
            return Err(Fault::Range);
        }
        let n = n as usize;
        let from = if self.right { s.len - n } else { 0 };
        store(cx.mem, &self.d, s.part(from, n))
    }
}

/// PM §7.11.16 MIDR(P) `S1 D S2`: the S2+1 characters of the string S1 from
/// character position S2 (1 = first) as a string in D; S2+1 = −1 or a count
/// running past the end takes the rest of S1; S2+1 = 0 stores an empty string.
/// Errors (4101): S2 < 1 or beyond the last character, S2+1 < −1, no NUL in S1,
/// D past the end of its device.
///
/// MIDW(P) `S1 D S2`: overwrites the string in D from position S2 with the first
/// S2+1 characters of S1 (S2+1 = −1 or more than S1 has: all of S1); D keeps its
/// length, characters that would go past its end are not written (manual
/// example: "ABCDEFGHI", 5, 8, "012345678" → "ABCD01234"). S2+1 = 0 stores 00H
/// at the start of D, as the manual states. Errors (4101): S2 < 1 or beyond the
/// last character of D, S2+1 < −1, no NUL in S1 or D.
#[derive(Debug)]
struct Mid {
    write: bool,
    s1: StrSrc,
    d: Block,
    s2: Block,
}

pub(super) fn compile_mid(a: &mut Args<'_, '_>, write: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = str_src(a, 0);
    let d = a.block_dest(1);
    let s2 = a.block(2);
    Some(Box::new(Mid {
        write,
        s1: s1?,
        d: d?,
        s2: s2?,
    }))
}

impl Instr for Mid {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s = read_str(cx.mem, &self.s1)?;
        let [pos, cnt] = read_words::<2>(cx.mem, &self.s2)?.map(|w| w as i16 as i32);
        if cnt < -1 || pos < 1 {
            return Err(Fault::Range);
        }
        let pos = pos as usize - 1;
        if !self.write {
            if pos >= s.len {
                return Err(Fault::Range);
            }
            let rest = s.len - pos;
            let n = if cnt == -1 {
                rest
            } else {
                (cnt as usize).min(rest)
            };
            return store(cx.mem, &self.d, s.part(pos, n));
        }
        let d = read_dev_str(cx.mem, &self.d)?;
        let Loc::Mem(at) = d.loc else {
            return Err(Fault::Range);
        };
        if pos >= d.len {
            return Err(Fault::Range);
        }
        if cnt == 0 {
            put_nul(&mut cx.mem.words, at, 0);
            return Ok(());
        }
        let n = if cnt == -1 {
            s.len
        } else {
            (cnt as usize).min(s.len)
        };
        let n = n.min(d.len - pos);
        copy_str(&mut cx.mem.words, s.part(0, n), at + pos);
        Ok(())
    }
}

// ------------------------------------------------------------------ INSTR

/// PM §7.11.17 INSTR(P) `S1 S2 D n`: searches the string S2 from its n-th
/// character (1 = first) for the string S1 and stores the position of the first
/// match (counted from the start of S2) in D, 0 when there is none (an empty
/// S1 never matches). Errors (4101): n < 1 or beyond the last character of S2,
/// no NUL in S1 or S2.
#[derive(Debug)]
struct InStr {
    s1: StrSrc,
    s2: StrSrc,
    d: WordArg,
    n: WordArg,
}

pub(super) fn compile_instr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let s1 = str_src(a, 0);
    let s2 = str_src(a, 1);
    let d = a.word_dest(2, Num::I16, 1);
    let n = a.word_src(3, Num::I16);
    Some(Box::new(InStr {
        s1: s1?,
        s2: s2?,
        d: d?,
        n: n?,
    }))
}

impl Instr for InStr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let pat = read_str(cx.mem, &self.s1)?;
        let hay = read_str(cx.mem, &self.s2)?;
        let n = cx.mem.read16(&self.n)? as i16;
        if n < 1 || n as usize > hay.len {
            return Err(Fault::Range);
        }
        let w = &cx.mem.words;
        let found = if pat.len == 0 || pat.len > hay.len {
            None
        } else {
            (n as usize - 1..=hay.len - pat.len)
                .find(|&i| (0..pat.len).all(|k| hay.byte(w, i + k) == pat.byte(w, k)))
        };
        cx.mem.write16(&self.d, found.map_or(0, |i| i as u16 + 1))
    }
}
