//! Programming manual (common instructions): character strings — $MOV (§6.5
//! data transfer: character string transfer), $+ (§6.2 arithmetic operations:
//! character string concatenation) and
//! the character string processing instructions of §7.11: BINDA, DBINDA, BINHA,
//! DBINHA, BCDDA, DBCDDA, DABIN, DDABIN, HABIN, DHABIN, DABCD, DDABCD, LEN, STR,
//! DSTR, VAL, DVAL, ESTR, EVAL, ASC, HEX, RIGHT, LEFT, MIDR, MIDW, INSTR.
//!
//! String format (PM §3.2.5, 004 §4.9): ASCII, two characters a word, the first
//! in the low byte, terminated by a NUL byte; a string of even length ends with a
//! whole 0000H word, one of odd length with 00H in the high byte of its last word.
//! A device string runs from its first word to the first NUL; no NUL before the
//! end of the device (or of the index-modified range) is 4101, and a result that
//! does not fit between its first word and the end of its device is 4101 with
//! nothing written. String constants (`"ABC"`) hold at most 32 ASCII characters
//! (004 L7540-7555, checked at load) and are turned into bytes at load time.
//!
//! ASCII results of the fixed-width conversions (BINDA, BINHA, BCDDA, ASC and
//! their 32-bit forms) end with 00H only while SM701 (number of output
//! characters) is OFF; with SM701 ON the word or byte after the characters is
//! left unchanged (PM §7.11.2, SM701). Everything else always writes its NUL.
//!
//! Character strings are moved with `memmove` semantics, so source and
//! destination may overlap; nothing in `exec` allocates.

use super::Args;
use softplc_ir::device::{Constant, DeviceMemory, Operand};
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::WordArg;
use softplc_lang::isa::{Def, Doc};

mod bin_ascii;
mod copy_concat;
mod hex_ascii;
mod len_str_val;
mod real_str;
mod substring;

use bin_ascii::{compile_from_ascii, compile_to_ascii, FromAscii, ToAscii};
use copy_concat::{compile_sadd, compile_smov};
use hex_ascii::{compile_asc, compile_hex};
use len_str_val::{compile_len, compile_str, compile_val};
use real_str::{compile_estr, compile_eval};
use substring::{compile_instr, compile_mid, compile_side};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("$MOV", &STRING_TRANSFER, compile_smov),
    Def::app("$+", &STRING_CONCATENATION, compile_sadd),
    Def::app("BINDA", &CHARACTER_STRINGS, |a| {
        compile_to_ascii(a, ToAscii::Dec16)
    }),
    Def::app("DBINDA", &CHARACTER_STRINGS, |a| {
        compile_to_ascii(a, ToAscii::Dec32)
    }),
    Def::app("BINHA", &CHARACTER_STRINGS, |a| {
        compile_to_ascii(a, ToAscii::Hex16)
    }),
    Def::app("DBINHA", &CHARACTER_STRINGS, |a| {
        compile_to_ascii(a, ToAscii::Hex32)
    }),
    Def::app("BCDDA", &CHARACTER_STRINGS, |a| {
        compile_to_ascii(a, ToAscii::Bcd16)
    }),
    Def::app("DBCDDA", &CHARACTER_STRINGS, |a| {
        compile_to_ascii(a, ToAscii::Bcd32)
    }),
    Def::app("DABIN", &CHARACTER_STRINGS, |a| {
        compile_from_ascii(a, FromAscii::Dec16)
    }),
    Def::app("DDABIN", &CHARACTER_STRINGS, |a| {
        compile_from_ascii(a, FromAscii::Dec32)
    }),
    Def::app("HABIN", &CHARACTER_STRINGS, |a| {
        compile_from_ascii(a, FromAscii::Hex16)
    }),
    Def::app("DHABIN", &CHARACTER_STRINGS, |a| {
        compile_from_ascii(a, FromAscii::Hex32)
    }),
    Def::app("DABCD", &CHARACTER_STRINGS, |a| {
        compile_from_ascii(a, FromAscii::Bcd16)
    }),
    Def::app("DDABCD", &CHARACTER_STRINGS, |a| {
        compile_from_ascii(a, FromAscii::Bcd32)
    }),
    Def::app("LEN", &CHARACTER_STRINGS, compile_len),
    Def::app("STR", &CHARACTER_STRINGS, |a| compile_str(a, false)),
    Def::app("DSTR", &CHARACTER_STRINGS, |a| compile_str(a, true)),
    Def::app("VAL", &CHARACTER_STRINGS, |a| compile_val(a, false)),
    Def::app("DVAL", &CHARACTER_STRINGS, |a| compile_val(a, true)),
    Def::app("ESTR", &CHARACTER_STRINGS, compile_estr),
    Def::app("EVAL", &CHARACTER_STRINGS, compile_eval),
    Def::app("ASC", &CHARACTER_STRINGS, compile_asc),
    Def::app("HEX", &CHARACTER_STRINGS, compile_hex),
    Def::app("RIGHT", &CHARACTER_STRINGS, |a| compile_side(a, true)),
    Def::app("LEFT", &CHARACTER_STRINGS, |a| compile_side(a, false)),
    Def::app("MIDR", &CHARACTER_STRINGS, |a| compile_mid(a, false)),
    Def::app("MIDW", &CHARACTER_STRINGS, |a| compile_mid(a, true)),
    Def::app("INSTR", &CHARACTER_STRINGS, compile_instr),
];

static STRING_TRANSFER: Doc = Doc {
    family: "string transfer",
    cite: "PM §6.5",
    notes: "constants ≤ 32 characters (load check)",
};
static STRING_CONCATENATION: Doc = Doc {
    family: "string concatenation",
    cite: "PM §6.2",
    notes: "2 and 3 operands; result past device end → 4101",
};
static CHARACTER_STRINGS: Doc = Doc {
    family: "character strings",
    cite: "PM §7.11",
    notes: "SM701 for the closing 00H; see golden_strings.rs",
};

/// A string comparison contact (`LD$=`, `AND$<>`, `OR$>` …, PM §6.1.3): the
/// strings are compared character by character by ASCII code; the first
/// difference decides, and when one string is the start of the other the longer
/// one is greater. A device string without a NUL before the end of its device is
/// 4101.
#[derive(Debug)]
pub struct StrCompare {
    a: StrSrc,
    b: StrSrc,
}

impl StrCompare {
    /// Compiles the two operands of a string comparison contact.
    pub fn compile(a: &mut Args<'_, '_>) -> Option<StrCompare> {
        if !a.count(&[2]) {
            return None;
        }
        let (x, y) = (str_src(a, 0), str_src(a, 1));
        Some(StrCompare { a: x?, b: y? })
    }

    pub fn ordering(&self, mem: &DeviceMemory) -> Result<std::cmp::Ordering, Fault> {
        let (x, y) = (read_str(mem, &self.a)?, read_str(mem, &self.b)?);
        for i in 0..x.len.min(y.len) {
            let (c, d) = (x.byte(&mem.words, i), y.byte(&mem.words, i));
            if c != d {
                return Ok(c.cmp(&d));
            }
        }
        Ok(x.len.cmp(&y.len))
    }
}

/// Longest string constant (004 L7540-7555).
const MAX_CONST: usize = 32;

// ------------------------------------------------------------------ operands

/// A character-string source operand.
#[derive(Debug)]
enum StrSrc {
    /// A `"…"` constant, as bytes without the NUL.
    Const(Box<[u8]>),
    /// A string in word devices from this word on.
    Dev(Block),
}

fn str_src(a: &mut Args<'_, '_>, k: usize) -> Option<StrSrc> {
    match a.operand(k)? {
        Operand::Const(Constant::Str(s)) => {
            if !s.is_ascii() {
                a.error(
                    k,
                    format!("`{}`: only ASCII characters are supported", a.text(k)),
                );
                return None;
            }
            if s.len() > MAX_CONST {
                a.error(
                    k,
                    format!(
                        "`{}`: a string constant holds at most {MAX_CONST} characters, found {}",
                        a.text(k),
                        s.len()
                    ),
                );
                return None;
            }
            Some(StrSrc::Const(s.into_bytes().into_boxed_slice()))
        }
        Operand::Const(_) => {
            a.error(
                k,
                format!(
                    "`{}`: a character string (\"ABC\") or a word device is needed here",
                    a.text(k)
                ),
            );
            None
        }
        _ => Some(StrSrc::Dev(a.block(k)?)),
    }
}

/// The flat index of SM701 (number of output characters selection).
fn sm701(a: &Args<'_, '_>) -> Option<u32> {
    a.flag(softplc_lang::dialect::Flag::NoNul)
}

// ------------------------------------------------------------------ memory

/// A string located at run time: bytes of a constant or a byte offset
/// (2·word + 0/1) in the word memory.
#[derive(Clone, Copy)]
enum Loc<'a> {
    Const(&'a [u8]),
    Mem(usize),
}

#[derive(Clone, Copy)]
struct Str<'a> {
    loc: Loc<'a>,
    len: usize,
}

impl Str<'_> {
    fn byte(&self, words: &[u16], i: usize) -> u8 {
        match self.loc {
            Loc::Const(b) => b[i],
            Loc::Mem(at) => get_byte(words, at + i),
        }
    }

    /// The part `from..from + len`.
    fn part(&self, from: usize, len: usize) -> Self {
        let loc = match self.loc {
            Loc::Const(b) => Loc::Const(&b[from..from + len]),
            Loc::Mem(at) => Loc::Mem(at + from),
        };
        Str { loc, len }
    }
}

fn get_byte(words: &[u16], b: usize) -> u8 {
    (words[b / 2] >> (8 * (b % 2))) as u8
}

fn set_byte(words: &mut [u16], b: usize, v: u8) {
    let w = &mut words[b / 2];
    *w = if b & 1 == 0 {
        (*w & 0xFF00) | v as u16
    } else {
        (*w & 0x00FF) | (v as u16) << 8
    };
}

/// Copies `s` to byte offset `dst` (memmove: `s` may overlap the destination).
fn copy_str(words: &mut [u16], s: Str<'_>, dst: usize) {
    match s.loc {
        Loc::Const(b) => {
            for (i, &c) in b[..s.len].iter().enumerate() {
                set_byte(words, dst + i, c);
            }
        }
        Loc::Mem(src) if dst == src => {}
        Loc::Mem(src) if dst < src => {
            for i in 0..s.len {
                let c = get_byte(words, src + i);
                set_byte(words, dst + i, c);
            }
        }
        Loc::Mem(src) => {
            for i in (0..s.len).rev() {
                let c = get_byte(words, src + i);
                set_byte(words, dst + i, c);
            }
        }
    }
}

/// Writes the NUL after a string of `len` bytes at byte offset `at`: 00H, and
/// for an even length the whole following word.
fn put_nul(words: &mut [u16], at: usize, len: usize) {
    set_byte(words, at + len, 0);
    if len & 1 == 0 {
        set_byte(words, at + len + 1, 0);
    }
}

/// Words from a block's first word to the end of its device (or index range).
fn span(mem: &DeviceMemory, b: &Block) -> Result<(usize, usize), Fault> {
    let start = mem.block_start(b, 1)?;
    let end = match &b.start {
        WordArg::Indexed(ix) => (ix.base + ix.points) as usize,
        _ => b.limit as usize,
    };
    Ok((start, end))
}

/// Locates a string source: 4101 when no NUL precedes the end of the device.
fn read_str<'a>(mem: &DeviceMemory, s: &'a StrSrc) -> Result<Str<'a>, Fault> {
    match s {
        StrSrc::Const(b) => Ok(Str {
            loc: Loc::Const(b),
            len: b.len(),
        }),
        StrSrc::Dev(b) => read_dev_str(mem, b),
    }
}

/// Locates the string in a device block (4101 without a NUL before its end).
fn read_dev_str(mem: &DeviceMemory, b: &Block) -> Result<Str<'static>, Fault> {
    let (start, end) = span(mem, b)?;
    let at = 2 * start;
    (0..2 * (end - start))
        .find(|&i| get_byte(&mem.words, at + i) == 0)
        .map(|len| Str {
            loc: Loc::Mem(at),
            len,
        })
        .ok_or(Fault::Range)
}

/// The byte offset of a destination that must hold `len` characters and, with
/// `nul`, their terminator; 4101 when they run past the end of the device.
fn dest(mem: &DeviceMemory, b: &Block, len: usize, nul: bool) -> Result<usize, Fault> {
    let (start, end) = span(mem, b)?;
    let words = if nul { len / 2 + 1 } else { len.div_ceil(2) };
    if start + words > end {
        return Err(Fault::Range);
    }
    Ok(2 * start)
}

/// Stores `s` at `d` with its NUL.
fn store(mem: &mut DeviceMemory, d: &Block, s: Str<'_>) -> Result<(), Fault> {
    let at = dest(mem, d, s.len, true)?;
    copy_str(&mut mem.words, s, at);
    put_nul(&mut mem.words, at, s.len);
    Ok(())
}

/// Stores generated characters at `d`, with the NUL when `nul`.
fn store_bytes(mem: &mut DeviceMemory, d: &Block, b: &[u8], nul: bool) -> Result<(), Fault> {
    let at = dest(mem, d, b.len(), nul)?;
    let s = Str {
        loc: Loc::Const(b),
        len: b.len(),
    };
    copy_str(&mut mem.words, s, at);
    if nul {
        put_nul(&mut mem.words, at, b.len());
    }
    Ok(())
}

/// `N` words of a block (4101 past the end of the device).
fn read_words<const N: usize>(mem: &DeviceMemory, b: &Block) -> Result<[u16; N], Fault> {
    let i = mem.block_start(b, N as u32)?;
    let mut w = [0u16; N];
    w.copy_from_slice(&mem.words[i..i + N]);
    Ok(w)
}

/// The `n` bytes of the words from a block's start (4101 past the device end).
fn read_bytes<const N: usize>(mem: &DeviceMemory, b: &Block) -> Result<[u8; N], Fault> {
    let i = mem.block_start(b, N.div_ceil(2) as u32)?;
    let mut out = [0u8; N];
    for (k, c) in out.iter_mut().enumerate() {
        *c = get_byte(&mem.words, 2 * i + k);
    }
    Ok(out)
}
