//! BIN words ↔ hexadecimal characters (PM §7.11): ASC, HEX.

use super::bin_ascii::{hex_char, HEX};
use super::{dest, get_byte, put_nul, set_byte, sm701};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};

/// PM §7.11.13 ASC(P) `S D n`: the BIN words from S as hexadecimal characters,
/// n of them (four a word, the highest digit first) from D on; 00H follows
/// while SM701 is OFF. n = 0 does nothing; a negative n is 4100; a range past
/// the end of S's or D's device is 4101. S and D may overlap (the manual: the
/// result is correct even then).
#[derive(Debug)]
struct Asc {
    s: Block,
    d: Block,
    n: WordArg,
    sm701: Option<u32>,
}

pub(super) fn compile_asc(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.block_dest(1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Asc {
        s: s?,
        d: d?,
        n: n?,
        sm701: sm701(a),
    }))
}

impl Instr for Asc {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = cx.mem.read16(&self.n)? as i16;
        if n < 0 {
            return Err(Fault::Operation);
        }
        if n == 0 {
            return Ok(());
        }
        let n = n as usize;
        let nul = !self.sm701.is_some_and(|i| cx.mem.bits[i as usize]);
        let nw = n.div_ceil(4);
        let si = cx.mem.block_start(&self.s, nw as u32)?;
        let at = dest(cx.mem, &self.d, n, nul)?;
        let words = &mut cx.mem.words;
        // Character k is nibble k % 4 (from the top) of word k / 4 of S. The
        // output needs twice the words of its source, so no copying order is
        // safe for every overlap: the source words (at most 8192) are copied
        // first.
        let mut copy = [0u16; 8192];
        let src = &mut copy[..nw];
        src.copy_from_slice(&words[si..si + nw]);
        for k in 0..n {
            let c = HEX[(src[k / 4] >> (12 - 4 * (k % 4)) & 0xF) as usize];
            set_byte(words, at + k, c);
        }
        if nul {
            put_nul(words, at, n);
        }
        Ok(())
    }
}

/// PM §7.11.14 HEX(P) `S D n`: n hexadecimal characters from S ("0"-"9",
/// "A"-"F", four a word, the first as the highest digit) to BIN words from D on;
/// when n is not a multiple of 4 the remaining low digits of the last word are
/// 0. n = 0 does nothing; a negative n or another character is 4100 (D
/// unchanged); a range past the end of S's or D's device is 4101.
#[derive(Debug)]
struct Hex {
    s: Block,
    d: Block,
    n: WordArg,
}

pub(super) fn compile_hex(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.block_dest(1);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(Hex {
        s: s?,
        d: d?,
        n: n?,
    }))
}

impl Instr for Hex {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = cx.mem.read16(&self.n)? as i16;
        if n < 0 {
            return Err(Fault::Operation);
        }
        if n == 0 {
            return Ok(());
        }
        let n = n as usize;
        let si = cx.mem.block_start(&self.s, n.div_ceil(2) as u32)?;
        let nw = n.div_ceil(4);
        let di = cx.mem.block_start(&self.d, nw as u32)?;
        // The results (at most 8192 words) are built first, so D may overlap S
        // and an invalid character leaves D unchanged.
        let mut out = [0u16; 8192];
        let out = &mut out[..nw];
        for k in 0..n {
            let d = hex_char(get_byte(&cx.mem.words, 2 * si + k))? as u16;
            out[k / 4] |= d << (12 - 4 * (k % 4));
        }
        cx.mem.words[di..di + nw].copy_from_slice(out);
        Ok(())
    }
}
