//! ASCII ASC and hex ↔ ASCII ITA, ATI (002 §6.5 L5695-5771; spec aplc.md §4.8) and the
//! I/O instructions REF, REFF (002 §6.9 L6510-6571) and RSUM (002 §6.4
//! L5206-5239).
//!
//! SM186 chooses the packing: OFF two characters a word, the first in the
//! low byte; ON one character a word (low byte). REF refreshes I/O at once:
//! in softplc the inputs change only between scans and outputs are read at
//! END, so it does nothing at run time; its operands are checked at load
//! (a start X/Y multiple of 8 without index, a constant count 8-256 in 8s).
//! REFF writes the quantised filter time (0, 8, 16, 32, 64 ms) to SD35.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{Block, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::{looks_like_constant, Width};
use crate::devices::{parse_device, Dev};
use crate::num::{self, E_VALUE};
use crate::resolve::{self, ArgsExt};

static HEX: Doc = Doc {
    family: "hex and ASCII",
    cite: "002 §6.5 L5695-5771",
    notes: "ASC S1…S8 D: up to 8 character codes 16#21-16#7E written as constants (fewer are filled with 0); ITA most significant nibble first, 1-256 characters (a constant gives at most 4); ATI upper-case hex only, a constant source at most 2 characters (1 with SM186 ON); bad characters or counts are error 64; SM186 packing",
};
static IO: Doc = Doc {
    family: "I/O refresh, REAL sum",
    cite: "002 §6.9 L6510-6571, §6.4 L5206-5239",
    notes: "REF checked at load, no effect at run time (I/O is exchanged between scans in softplc); REFF writes the quantised filter time to SD35; RSUM sums 0-255 REALs, stops accumulating on overflow",
};

pub static DEFS: &[Def] = &[
    // 002 §6.5.16 L5658 ASC
    Def::app("ASC", &HEX, asc)
        .no_pulse()
        .steps(Steps::Fixed(19)),
    // 002 §6.5.17 L5695 ITA
    Def::app("ITA", &HEX, |a| hex(a, true))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.5.18 L5731 ATI
    Def::app("ATI", &HEX, |a| hex(a, false))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.9 L6538 REF
    Def::app("REF", &IO, refresh)
        .no_pulse()
        .steps(Steps::Fixed(5)),
    // 002 §6.9 L6510 REFF
    Def::app("REFF", &IO, reff)
        .no_pulse()
        .steps(Steps::Fixed(3)),
    // 002 §6.4 L5206 RSUM
    Def::app("RSUM", &IO, rsum)
        .no_pulse()
        .steps(Steps::Fixed(9)),
];

#[derive(Debug)]
enum Source {
    Const(u16),
    Words(Block),
}

#[derive(Debug)]
struct Hex {
    to_ascii: bool,
    s: Source,
    d: Block,
    n: WordArg,
    /// SM186.
    packing: u32,
}

/// ITA (`to_ascii`) or ATI.
fn hex(a: &mut Args<'_, '_>, to_ascii: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = if looks_like_constant(a.text(0)) {
        a.word_at(0, Width::W16, false).map(|w| match w {
            WordArg::Const(k) => Source::Const(k as u16),
            _ => Source::Const(0),
        })
    } else {
        let r = resolve::block(a.map(), a.text(0), false);
        a.check(0, r).map(Source::Words)
    };
    let r = resolve::block(a.map(), a.text(1), true);
    let d = a.check(1, r);
    let n = a.word_at(2, Width::W16, false)?;
    let packing = a.map().base(DeviceKind::SM) + 186;
    Some(Box::new(Hex {
        to_ascii,
        s: s?,
        d: d?,
        n,
        packing,
    }))
}

fn ascii_of(nibble: u16) -> u16 {
    b"0123456789ABCDEF"[nibble as usize & 15] as u16
}

fn nibble_of(c: u16) -> Result<u16, Fault> {
    match c as u8 {
        c @ b'0'..=b'9' => Ok((c - b'0') as u16),
        c @ b'A'..=b'F' => Ok((c - b'A' + 10) as u16),
        _ => Err(E_VALUE),
    }
}

impl Hex {
    fn word(&self, cx: &ExecCtx<'_>, start: usize, k: usize) -> u16 {
        match self.s {
            Source::Const(v) => v,
            Source::Words(_) => cx.mem.words[start + k],
        }
    }
}

impl Instr for Hex {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let one = cx.mem.bits[self.packing as usize];
        let mut n = num::read16(cx.mem, &self.n)?;
        if !(1..=256).contains(&n) {
            return Err(E_VALUE);
        }
        let konst = matches!(self.s, Source::Const(_));
        if self.to_ascii {
            if konst {
                n = n.min(4);
            }
            let n = n as usize;
            let s = match &self.s {
                Source::Words(b) => cx.mem.block_start(b, n.div_ceil(4) as u32)?,
                Source::Const(_) => 0,
            };
            let out = if one { n } else { n.div_ceil(2) };
            let d = cx.mem.block_start(&self.d, out as u32)?;
            for k in 0..n {
                let w = self.word(cx, s, k / 4);
                let c = ascii_of(w >> (4 * (3 - k % 4)));
                let (at, shift) = if one {
                    (d + k, 0)
                } else {
                    (d + k / 2, 8 * (k % 2))
                };
                let old = if shift == 0 {
                    0
                } else {
                    cx.mem.words[at] & 0xFF
                };
                cx.mem.words[at] = old | c << shift;
            }
        } else {
            if konst {
                n = n.min(if one { 1 } else { 2 });
            }
            let n = n as usize;
            let words = if one { n } else { n.div_ceil(2) };
            let s = match &self.s {
                Source::Words(b) => cx.mem.block_start(b, words as u32)?,
                Source::Const(_) => 0,
            };
            let d = cx.mem.block_start(&self.d, n.div_ceil(4) as u32)?;
            let char_at = |cx: &ExecCtx<'_>, k: usize| {
                if one {
                    self.word(cx, s, k) & 0xFF
                } else {
                    self.word(cx, s, k / 2) >> (8 * (k % 2)) & 0xFF
                }
            };
            for k in 0..n {
                nibble_of(char_at(cx, k))?;
            }
            for w in 0..n.div_ceil(4) {
                let mut v = 0u16;
                for j in 0..4 {
                    let k = 4 * w + j;
                    if k < n {
                        v |= nibble_of(char_at(cx, k))? << (4 * (3 - j));
                    }
                }
                cx.mem.words[d + w] = v;
            }
        }
        Ok(())
    }
}

#[derive(Debug)]
struct Nothing;

impl Instr for Nothing {
    fn exec(&self, _: &mut ExecCtx<'_>) -> Result<(), Fault> {
        Ok(())
    }
}

fn refresh(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let start = parse_device(&a.text(0).to_ascii_uppercase());
    match start {
        Ok(Some(d))
            if matches!(d.dev, Dev::X | Dev::Y)
                && d.group.is_none()
                && d.index.is_none()
                && d.n % 8 == 0 => {}
        _ => {
            a.error(0, format!("`{}`: REF starts at X or Y, a multiple of 8 (X0, X10 …), without index (APLC programming manual §6.8.7)", a.text(0)));
            return None;
        }
    }
    match a.text(1).parse::<u32>() {
        Ok(n) if (8..=256).contains(&n) && n % 8 == 0 => Some(Box::new(Nothing)),
        _ => {
            a.error(
                1,
                format!(
                    "`{}`: REF's count is a constant 8-256, a multiple of 8 (APLC programming manual §6.8.7)",
                    a.text(1)
                ),
            );
            None
        }
    }
}

#[derive(Debug)]
struct Reff {
    s: WordArg,
    sd35: u32,
}

fn reff(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    let s = a.word_at(0, Width::W16, false)?;
    Some(Box::new(Reff {
        s,
        sd35: a.map().base(DeviceKind::SD) + 35,
    }))
}

impl Instr for Reff {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let v = num::read16(cx.mem, &self.s)?;
        let q = match v {
            i16::MIN..=7 => 0,
            8..=15 => 8,
            16..=31 => 16,
            32..=63 => 32,
            _ => 64,
        };
        cx.mem.words[self.sd35 as usize] = q;
        Ok(())
    }
}

#[derive(Debug)]
struct Rsum {
    s: Block,
    n: WordArg,
    d: WordArg,
}

fn rsum(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let r = resolve::block32(a.map(), a.text(0));
    let s = a.check(0, r);
    let n = a.word_at(1, Width::W16, false);
    let d = a.word_at(2, Width::Real, true)?;
    Some(Box::new(Rsum { s: s?, n: n?, d }))
}

impl Instr for Rsum {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = num::read16(cx.mem, &self.n)?;
        if !(0..=255).contains(&n) {
            return Err(E_VALUE);
        }
        let s = cx.mem.block_start(&self.s, 2 * n as u32)?;
        let mut total = 0f32;
        for k in 0..n as usize {
            let w = &cx.mem.words[s + 2 * k..s + 2 * k + 2];
            let next = total + f32::from_bits((w[0] as u32) << 16 | w[1] as u32);
            if !next.is_finite() {
                break;
            }
            total = next;
        }
        num::write32(cx.mem, &self.d, total.to_bits())
    }
}

#[derive(Debug)]
struct Asc {
    chars: [u8; 8],
    d: Block,
    packing: u32,
}

fn asc(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    let n = a.len();
    if !(2..=9).contains(&n) {
        a.count(&[9]);
        return None;
    }
    let mut chars = [0u8; 8];
    for (k, c) in chars.iter_mut().enumerate().take(n - 1) {
        match crate::constant::parse(a.text(k), Width::W16) {
            Ok(v) if (0x21..=0x7E).contains(&v) => *c = v as u8,
            Ok(_) => {
                a.error(
                    k,
                    format!(
                        "`{}`: ASC takes character codes 16#21-16#7E (APLC programming manual §6.5.16)",
                        a.text(k)
                    ),
                );
                return None;
            }
            Err(e) => {
                a.error(k, e);
                return None;
            }
        }
    }
    let r = resolve::block(a.map(), a.text(n - 1), true);
    let d = a.check(n - 1, r)?;
    let packing = a.map().base(DeviceKind::SM) + 186;
    Some(Box::new(Asc { chars, d, packing }))
}

impl Instr for Asc {
    /// SM186 OFF: D..D+3 two characters a word, the first low; ON: D..D+7
    /// one a word (L5684-5693).
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let one = cx.mem.bits[self.packing as usize];
        if one {
            let d = cx.mem.block_start(&self.d, 8)?;
            for (k, c) in self.chars.iter().enumerate() {
                cx.mem.words[d + k] = *c as u16;
            }
        } else {
            let d = cx.mem.block_start(&self.d, 4)?;
            for k in 0..4 {
                cx.mem.words[d + k] =
                    u16::from_le_bytes([self.chars[2 * k], self.chars[2 * k + 1]]);
            }
        }
        Ok(())
    }
}
