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

use super::{Args, ExecCtx, Instr};
use crate::device::{Constant, DeviceKind, DeviceMemory, Operand};
use crate::engine::{ErrorCode, Fault};
use crate::program::compile::Block;
use crate::program::isa::{Def, Doc};
use crate::program::ops::{Num, WordArg};

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
fn sm701(a: &Args<'_, '_>) -> usize {
    (a.map().base(DeviceKind::SM) + 701) as usize
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
        .ok_or(ErrorCode::RANGE)
}

/// The byte offset of a destination that must hold `len` characters and, with
/// `nul`, their terminator; 4101 when they run past the end of the device.
fn dest(mem: &DeviceMemory, b: &Block, len: usize, nul: bool) -> Result<usize, Fault> {
    let (start, end) = span(mem, b)?;
    let words = if nul { len / 2 + 1 } else { len.div_ceil(2) };
    if start + words > end {
        return Err(ErrorCode::RANGE);
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

// ------------------------------------------------------------------ $MOV, $+

/// PM §6.5 (data transfer) $MOV(P) `S D`: transfers the character string S (a constant or the
/// string from device S to its NUL) to D onwards, NUL included. Errors: no NUL in
/// S's device (4101); D too short for the string and its NUL (4101, nothing
/// written). S and D may overlap.
#[derive(Debug)]
struct SMov {
    s: StrSrc,
    d: Block,
}

fn compile_smov(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.block(1);
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

fn compile_sadd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2, 3]) {
        return None;
    }
    let three = a.len() == 3;
    let s1 = if three { Some(str_src(a, 0)) } else { None };
    let s2 = str_src(a, three as usize);
    let d = a.block(a.len() - 1);
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
                return Err(ErrorCode::RANGE);
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

// ------------------------------------------------------------------ BIN/BCD → ASCII

/// Which fixed-width ASCII conversion a [`ToAsciiInstr`] performs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ToAscii {
    /// PM §7.11.1 BINDA(P): BIN 16 bits → sign (20H or 2DH) and 5 decimal
    /// digits, zeros before the first significant digit as 20H (space): −12345 →
    /// "-12345", 123 → "   123", 0 → "     0"; then 0000H in D+3.
    Dec16,
    /// PM §7.11.1 DBINDA(P): BIN 32 bits → sign and 10 digits, then 00H in the
    /// high byte of D+5.
    Dec32,
    /// PM §7.11.2 BINHA(P): BIN 16 bits → 4 hexadecimal digits "0"-"9", "A"-"F",
    /// no zero suppression (02A6H → "02A6"); then 0000H in D+2.
    Hex16,
    /// PM §7.11.2 DBINHA(P): 8 hexadecimal digits; then 0000H in D+4.
    Hex32,
    /// PM §7.11.3 BCDDA(P): BCD 4 digits → 4 decimal characters (0012H →
    /// "0012"); a nibble above 9 is 4100. Decision: no zero suppression, as for
    /// BINHA — the manual's layout is a fixed 4-digit field (BINDA's suppression
    /// is tied to its sign column).
    Bcd16,
    /// PM §7.11.3 DBCDDA(P): BCD 8 digits → 8 characters.
    Bcd32,
}

/// BINDA, DBINDA, BINHA, DBINHA, BCDDA, DBCDDA `S D`: S a 16/32-bit operand, the
/// characters from D on (4101 past the device end). The terminating 00H is
/// written only while SM701 is OFF.
#[derive(Debug)]
struct ToAsciiInstr {
    kind: ToAscii,
    s: WordArg,
    d: Block,
    sm701: usize,
}

fn compile_to_ascii(a: &mut Args<'_, '_>, kind: ToAscii) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let num = match kind {
        ToAscii::Dec16 | ToAscii::Hex16 | ToAscii::Bcd16 => Num::I16,
        _ => Num::I32,
    };
    let s = a.word_src(0, num);
    let d = a.block(1);
    Some(Box::new(ToAsciiInstr {
        kind,
        s: s?,
        d: d?,
        sm701: sm701(a),
    }))
}

const HEX: &[u8; 16] = b"0123456789ABCDEF";

/// Writes the `n` low hexadecimal digits of `v`, most significant first.
fn hex_digits(v: u32, out: &mut [u8]) {
    let n = out.len();
    for (k, c) in out.iter_mut().enumerate() {
        *c = HEX[(v >> (4 * (n - 1 - k)) & 0xF) as usize];
    }
}

/// Writes `v` in decimal right-aligned into `out`, zero-filled.
fn dec_digits(mut v: u128, out: &mut [u8]) {
    for c in out.iter_mut().rev() {
        *c = b'0' + (v % 10) as u8;
        v /= 10;
    }
}

impl Instr for ToAsciiInstr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mut buf = [0u8; 11];
        let n = match self.kind {
            ToAscii::Dec16 | ToAscii::Dec32 => {
                let (v, n) = match self.kind {
                    ToAscii::Dec16 => (cx.mem.read16(&self.s)? as i16 as i64, 6),
                    _ => (cx.mem.read32(&self.s)? as i32 as i64, 11),
                };
                buf[0] = if v < 0 { b'-' } else { b' ' };
                dec_digits(v.unsigned_abs() as u128, &mut buf[1..n]);
                // Zero suppression: every 0 before the first significant digit
                // (but not the units digit) becomes a space.
                for c in &mut buf[1..n - 1] {
                    if *c != b'0' {
                        break;
                    }
                    *c = b' ';
                }
                n
            }
            ToAscii::Hex16 | ToAscii::Bcd16 => {
                let v = cx.mem.read16(&self.s)? as u32;
                bcd_check(self.kind, v, 4)?;
                hex_digits(v, &mut buf[..4]);
                4
            }
            ToAscii::Hex32 | ToAscii::Bcd32 => {
                let v = cx.mem.read32(&self.s)?;
                bcd_check(self.kind, v, 8)?;
                hex_digits(v, &mut buf[..8]);
                8
            }
        };
        let nul = !cx.mem.bits[self.sm701];
        store_bytes(cx.mem, &self.d, &buf[..n], nul)
    }
}

/// For the BCD kinds: 4100 when one of the `n` nibbles is above 9.
fn bcd_check(kind: ToAscii, v: u32, n: u32) -> Result<(), Fault> {
    if matches!(kind, ToAscii::Bcd16 | ToAscii::Bcd32) && (0..n).any(|k| v >> (4 * k) & 0xF > 9) {
        return Err(ErrorCode::OPERATION);
    }
    Ok(())
}

// ------------------------------------------------------------------ ASCII → BIN/BCD

/// Which fixed-width ASCII conversion a [`FromAsciiInstr`] performs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FromAscii {
    /// PM §7.11.4 DABIN(P): 6 characters from S — sign (20H positive, 2DH
    /// negative) and 5 decimal digits, 20H in a digit counting as 0 — to BIN 16
    /// bits (−32768 … 32767).
    Dec16,
    /// PM §7.11.4 DDABIN(P): sign and 10 digits (11 characters) to BIN 32 bits.
    Dec32,
    /// PM §7.11.5 HABIN(P): 4 hexadecimal characters ("0"-"9", "A"-"F") to BIN 16.
    Hex16,
    /// PM §7.11.5 DHABIN(P): 8 hexadecimal characters to BIN 32 bits.
    Hex32,
    /// PM §7.11.6 DABCD(P): 4 decimal characters (20H counting as 0) to BCD 4
    /// digits.
    Bcd16,
    /// PM §7.11.6 DDABCD(P): 8 decimal characters to BCD 8 digits.
    Bcd32,
}

/// DABIN, DDABIN, HABIN, DHABIN, DABCD, DDABCD `S D`: a fixed number of
/// characters from S (no NUL needed; 4101 past the device end) to a 16/32-bit D.
/// A character outside the allowed set, a wrong sign or a value outside the BIN
/// range is 4100.
#[derive(Debug)]
struct FromAsciiInstr {
    kind: FromAscii,
    s: Block,
    d: WordArg,
}

fn compile_from_ascii(a: &mut Args<'_, '_>, kind: FromAscii) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let num = match kind {
        FromAscii::Dec16 | FromAscii::Hex16 | FromAscii::Bcd16 => Num::I16,
        _ => Num::I32,
    };
    let s = a.block(0);
    let d = a.word_dest(1, num, num.words());
    Some(Box::new(FromAsciiInstr { kind, s: s?, d: d? }))
}

/// A decimal digit, 20H counting as 0.
fn dec_char(c: u8) -> Result<u32, Fault> {
    match c {
        b'0'..=b'9' => Ok((c - b'0') as u32),
        b' ' => Ok(0),
        _ => Err(ErrorCode::OPERATION),
    }
}

fn hex_char(c: u8) -> Result<u32, Fault> {
    match c {
        b'0'..=b'9' => Ok((c - b'0') as u32),
        b'A'..=b'F' => Ok((c - b'A' + 10) as u32),
        _ => Err(ErrorCode::OPERATION),
    }
}

/// Sign and decimal digits (20H = 0) to a value within `min..=max`.
fn signed_dec(c: &[u8], min: i64, max: i64) -> Result<i64, Fault> {
    let neg = match c[0] {
        b' ' => false,
        b'-' => true,
        _ => return Err(ErrorCode::OPERATION),
    };
    let mut v: i64 = 0;
    for &d in &c[1..] {
        v = v * 10 + dec_char(d)? as i64;
    }
    let v = if neg { -v } else { v };
    if !(min..=max).contains(&v) {
        return Err(ErrorCode::OPERATION);
    }
    Ok(v)
}

/// Characters to the nibbles of a hexadecimal or BCD value, first = highest.
fn nibbles(c: &[u8], digit: fn(u8) -> Result<u32, Fault>) -> Result<u32, Fault> {
    c.iter().try_fold(0u32, |v, &d| Ok(v << 4 | digit(d)?))
}

impl Instr for FromAsciiInstr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let m = &*cx.mem;
        match self.kind {
            FromAscii::Dec16 => {
                let c: [u8; 6] = read_bytes(m, &self.s)?;
                let v = signed_dec(&c, -32768, 32767)?;
                cx.mem.write16(&self.d, v as u16)
            }
            FromAscii::Dec32 => {
                let c: [u8; 11] = read_bytes(m, &self.s)?;
                let v = signed_dec(&c, i32::MIN as i64, i32::MAX as i64)?;
                cx.mem.write32(&self.d, v as u32)
            }
            FromAscii::Hex16 => {
                let c: [u8; 4] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, hex_char)?;
                cx.mem.write16(&self.d, v as u16)
            }
            FromAscii::Hex32 => {
                let c: [u8; 8] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, hex_char)?;
                cx.mem.write32(&self.d, v)
            }
            FromAscii::Bcd16 => {
                let c: [u8; 4] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, dec_char)?;
                cx.mem.write16(&self.d, v as u16)
            }
            FromAscii::Bcd32 => {
                let c: [u8; 8] = read_bytes(m, &self.s)?;
                let v = nibbles(&c, dec_char)?;
                cx.mem.write32(&self.d, v)
            }
        }
    }
}

// ------------------------------------------------------------------ LEN

/// PM §7.11.8 LEN(P) `S D`: the number of characters of the string S (up to its
/// NUL) as BIN 16 bits in D. No NUL in S's device is 4101.
#[derive(Debug)]
struct Len {
    s: StrSrc,
    d: WordArg,
}

fn compile_len(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.word_dest(1, Num::I16, 1);
    Some(Box::new(Len { s: s?, d: d? }))
}

impl Instr for Len {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = read_str(cx.mem, &self.s)?.len;
        cx.mem.write16(&self.d, n.min(u16::MAX as usize) as u16)
    }
}

// ------------------------------------------------------------------ STR, VAL

/// Formats sign, right-aligned digits of `mag` with `dec` of them after a
/// decimal point, as `total` characters: the sign (20H or 2DH) first, spaces
/// between sign and number, at least one digit before the point ("0.05").
/// 4100 when the number needs more characters than `total`.
fn fixed(neg: bool, mag: u128, total: usize, dec: usize, out: &mut [u8]) -> Result<(), Fault> {
    let point = (dec > 0) as usize;
    let avail = total - 1 - point;
    let mut nd = 1;
    let mut t = mag / 10;
    while t > 0 {
        nd += 1;
        t /= 10;
    }
    let nd = nd.max(dec + 1);
    if nd > avail {
        return Err(ErrorCode::OPERATION);
    }
    out[0] = if neg { b'-' } else { b' ' };
    let spaces = avail - nd;
    out[1..1 + spaces].fill(b' ');
    let body = &mut out[1 + spaces..total];
    // Digits right-aligned, the point `dec` places from the right.
    let mut v = mag;
    let mut i = body.len();
    for k in 0..nd {
        if point == 1 && k == dec {
            i -= 1;
            body[i] = b'.';
        }
        i -= 1;
        body[i] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    Ok(())
}

/// PM §7.11.9 STR(P) / DSTR(P) `S1 S2 D`: the BIN value S2 (16/32 bits) as a
/// string of S1 characters (2-8 / 2-13, sign and point included) with S1+1
/// digits after the decimal point (0-5 / 0-10, at most S1 − 3): sign 20H or
/// 2DH, spaces between sign and number, "0." added for small values, then 00H.
/// Errors (4100): S1 or S1+1 out of range, or the value needs more digits.
/// Example: S1 = 6, S1+1 = 2, S2 = −1234 → "-12.34".
#[derive(Debug)]
struct StrInstr {
    wide: bool,
    s1: Block,
    s2: WordArg,
    d: Block,
}

fn compile_str(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = a.block(0);
    let s2 = a.word_src(1, if wide { Num::I32 } else { Num::I16 });
    let d = a.block(2);
    Some(Box::new(StrInstr {
        wide,
        s1: s1?,
        s2: s2?,
        d: d?,
    }))
}

impl Instr for StrInstr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let [total, dec] = read_words::<2>(cx.mem, &self.s1)?.map(|w| w as i16 as i32);
        let (max_total, max_dec) = if self.wide { (13, 10) } else { (8, 5) };
        // Decimals need a point and a digit before it: dec ≤ total − 3 when dec > 0.
        if !(2..=max_total).contains(&total)
            || !(0..=max_dec).contains(&dec)
            || (dec > 0 && dec > total - 3)
        {
            return Err(ErrorCode::OPERATION);
        }
        let v = if self.wide {
            cx.mem.read32(&self.s2)? as i32 as i64
        } else {
            cx.mem.read16(&self.s2)? as i16 as i64
        };
        let mut buf = [0u8; 13];
        let total = total as usize;
        fixed(
            v < 0,
            v.unsigned_abs() as u128,
            total,
            dec as usize,
            &mut buf,
        )?;
        store_bytes(cx.mem, &self.d, &buf[..total], true)
    }
}

/// PM §7.11.10 VAL(P) / DVAL(P) `S D1 D2`: the string S (2-8 / 2-13 characters:
/// a sign 20H or 2DH, digits, at most one decimal point) to D1 = number of
/// characters, D1+1 = digits after the point (0-5 / 0-10, at most D1 − 3) and
/// D2 = the digits without the point as BIN 16/32 bits: "-123.45" → 7, 2,
/// −12345. Spaces and zeros between the sign and the first significant digit are
/// ignored. Errors (4100): a length, sign, character or point count outside
/// these rules, or a value outside the BIN range; no NUL is 4101.
#[derive(Debug)]
struct Val {
    wide: bool,
    s: StrSrc,
    d1: Block,
    d2: WordArg,
}

fn compile_val(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let num = if wide { Num::I32 } else { Num::I16 };
    let s = str_src(a, 0);
    let d1 = a.block(1);
    let d2 = a.word_dest(2, num, num.words());
    Some(Box::new(Val {
        wide,
        s: s?,
        d1: d1?,
        d2: d2?,
    }))
}

impl Instr for Val {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s = read_str(cx.mem, &self.s)?;
        let w = &cx.mem.words;
        let (max_total, max_dec) = if self.wide { (13, 10) } else { (8, 5) };
        let n = s.len;
        if !(2..=max_total).contains(&n) {
            return Err(ErrorCode::OPERATION);
        }
        let neg = match s.byte(w, 0) {
            b' ' => false,
            b'-' => true,
            _ => return Err(ErrorCode::OPERATION),
        };
        let mut v: i64 = 0;
        let mut point: Option<usize> = None;
        let mut leading = true;
        for i in 1..n {
            match s.byte(w, i) {
                b'.' if point.is_none() => {
                    point = Some(i);
                    leading = false;
                }
                b' ' | b'0' if leading => {}
                c @ b'0'..=b'9' => {
                    leading = false;
                    // At most 12 digits: no overflow.
                    v = v * 10 + (c - b'0') as i64;
                }
                _ => return Err(ErrorCode::OPERATION),
            }
        }
        let dec = point.map_or(0, |p| n - 1 - p);
        if dec > max_dec || (dec > 0 && dec + 3 > n) {
            return Err(ErrorCode::OPERATION);
        }
        let v = if neg { -v } else { v };
        let ok = if self.wide {
            (i32::MIN as i64..=i32::MAX as i64).contains(&v)
        } else {
            (-32768..=32767).contains(&v)
        };
        if !ok {
            return Err(ErrorCode::OPERATION);
        }
        let i = cx.mem.block_start(&self.d1, 2)?;
        cx.mem.words[i] = n as u16;
        cx.mem.words[i + 1] = dec as u16;
        if self.wide {
            cx.mem.write32(&self.d2, v as u32)
        } else {
            cx.mem.write16(&self.d2, v as u16)
        }
    }
}

// ------------------------------------------------------------------ ESTR, EVAL

/// 10^k for 0 ≤ k ≤ 22, exact in f64.
fn pow10(k: i32) -> f64 {
    const P: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    P[k as usize]
}

/// x·10^p. For |p| ≤ 22 multiplying or dividing by an exact power of ten rounds
/// once, so a decimal tie of a single-precision value stays an exact tie.
fn scale10(mut x: f64, mut p: i32) -> f64 {
    while p > 22 {
        x *= pow10(22);
        p -= 22;
    }
    while p < -22 {
        x /= pow10(22);
        p += 22;
    }
    if p >= 0 {
        x * pow10(p)
    } else {
        x / pow10(-p)
    }
}

/// PM §7.11.11 ESTR(P) `S1 S2 D`: the real S1 as a string in the format of
/// S2 (0 decimal-point format, 1 exponent format), S2+1 characters in total
/// (2-24), S2+2 digits after the point (0-7). Decimal-point format: sign, spaces,
/// integer part, point, fraction — S2+2 ≤ S2+1 − 3 when S2+2 > 0. Exponent
/// format: sign, spaces, one digit, point, fraction, "E", exponent sign ("+" or
/// "-") and two exponent digits — S2+1 ≥ 6, and S2+2 ≤ S2+1 − 7 when S2+2 > 0.
/// The fraction is rounded half away from zero at the last digit shown, and the
/// sign always comes first: −12.34567 with 8 characters and 2 decimals is
/// "-  12.35". Errors (4100): an invalid real, a format or digit count
/// outside these ranges, an integer part that does not fit.
#[derive(Debug)]
struct Estr {
    s1: WordArg,
    s2: Block,
    d: Block,
}

fn compile_estr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = a.word_src(0, Num::F32);
    let s2 = a.block(1);
    let d = a.block(2);
    Some(Box::new(Estr {
        s1: s1?,
        s2: s2?,
        d: d?,
    }))
}

impl Instr for Estr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let x = cx.mem.read_f32(&self.s1)? as f64;
        let [form, total, dec] = read_words::<3>(cx.mem, &self.s2)?.map(|w| w as i16 as i32);
        let bad = || Err(ErrorCode::OPERATION);
        if !(0..=7).contains(&dec) || total > 24 {
            return bad();
        }
        let (total, dec) = (total as usize, dec as usize);
        let neg = x < 0.0;
        let ax = x.abs();
        let mut buf = [0u8; 24];
        match form {
            0 => {
                if total < 2 || (dec > 0 && total < dec + 3) {
                    return bad();
                }
                let r = scale10(ax, dec as i32).round();
                if r >= 1e24 {
                    return bad();
                }
                fixed(neg, r as u128, total, dec, &mut buf)?;
            }
            1 => {
                let need = 6 + if dec > 0 { dec + 1 } else { 0 };
                if total < need {
                    return bad();
                }
                // Mantissa digits m (dec + 1 of them) and exponent e with
                // |x| ≈ m·10^(e − dec).
                let (m, e) = if ax == 0.0 {
                    (0u128, 0i32)
                } else {
                    let mut e = ax.log10().floor() as i32;
                    let lo = pow10(dec as i32);
                    let mut m = scale10(ax, dec as i32 - e).round();
                    if m >= 10.0 * lo {
                        e += 1;
                        m = scale10(ax, dec as i32 - e).round();
                    } else if m < lo {
                        e -= 1;
                        m = scale10(ax, dec as i32 - e).round();
                    }
                    (m as u128, e)
                };
                buf[0] = if neg { b'-' } else { b' ' };
                let spaces = total - need;
                buf[1..1 + spaces].fill(b' ');
                let mut digits = [0u8; 8];
                dec_digits(m, &mut digits[..dec + 1]);
                let mut i = 1 + spaces;
                buf[i] = digits[0];
                i += 1;
                if dec > 0 {
                    buf[i] = b'.';
                    buf[i + 1..i + 1 + dec].copy_from_slice(&digits[1..dec + 1]);
                    i += 1 + dec;
                }
                buf[i] = b'E';
                buf[i + 1] = if e < 0 { b'-' } else { b'+' };
                dec_digits(e.unsigned_abs() as u128, &mut buf[i + 2..i + 4]);
            }
            _ => return bad(),
        }
        store_bytes(cx.mem, &self.d, &buf[..total], true)
    }
}

/// PM §7.11.12 EVAL(P) `S D`: the string S (1-24 characters) in decimal-point
/// ("-12.345") or exponent format ("-1.2345E+02") to a real in D. An optional
/// sign ("+" or "-") leads the number and the exponent; spaces anywhere and
/// zeros before the first significant digit are ignored; only the first 6
/// significant digits count, later ones are cut off (truncated), as the manual
/// specifies. Errors (4100): no or more than 24 characters, a character outside
/// the format, two points or two exponents, no digit, a result outside 0 and
/// 2⁻¹²⁶ ≤ |x| < 2¹²⁸; no NUL is 4101.
#[derive(Debug)]
struct Eval {
    s: StrSrc,
    d: WordArg,
}

fn compile_eval(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.word_dest(1, Num::F32, 2);
    Some(Box::new(Eval { s: s?, d: d? }))
}

/// Parses an EVAL string to (negative, significant digits, decimal exponent of
/// the last kept digit).
fn parse_real(s: Str<'_>, w: &[u16]) -> Result<(bool, u32, i32), Fault> {
    let bad = Err(ErrorCode::OPERATION);
    let mut neg = false;
    let mut seen_sign = false;
    let mut digits = 0u32; // significant digits kept (≤ 6)
    let mut mant = 0u32;
    let mut any_digit = false;
    let mut point = false;
    // Decimal exponent correction: + for integer digits dropped, − for kept
    // fraction digits.
    let mut shift = 0i32;
    let mut i = 0;
    while i < s.len {
        let c = s.byte(w, i);
        i += 1;
        match c {
            b' ' => {}
            b'+' | b'-' if !seen_sign && !any_digit && !point => {
                seen_sign = true;
                neg = c == b'-';
            }
            b'.' if !point => point = true,
            b'0'..=b'9' => {
                any_digit = true;
                let d = (c - b'0') as u32;
                if digits == 0 && d == 0 {
                    // Leading zero: only moves the point.
                    if point {
                        shift -= 1;
                    }
                } else if digits < 6 {
                    mant = mant * 10 + d;
                    digits += 1;
                    if point {
                        shift -= 1;
                    }
                } else if !point {
                    // A cut integer digit still counts for the magnitude.
                    shift += 1;
                }
            }
            b'E' if any_digit => {
                let mut eneg = false;
                let mut eany = false;
                let mut esign = false;
                let mut e: i32 = 0;
                while i < s.len {
                    let c = s.byte(w, i);
                    i += 1;
                    match c {
                        b' ' => {}
                        b'+' | b'-' if !esign && !eany => {
                            esign = true;
                            eneg = c == b'-';
                        }
                        b'0'..=b'9' => {
                            eany = true;
                            e = (e * 10 + (c - b'0') as i32).min(1000);
                        }
                        _ => return bad,
                    }
                }
                if !eany {
                    return bad;
                }
                shift += if eneg { -e } else { e };
            }
            _ => return bad,
        }
    }
    if !any_digit {
        return bad;
    }
    Ok((neg, mant, shift))
}

impl Instr for Eval {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s = read_str(cx.mem, &self.s)?;
        if s.len == 0 || s.len > 24 {
            return Err(ErrorCode::OPERATION);
        }
        let (neg, mant, shift) = parse_real(s, &cx.mem.words)?;
        if mant == 0 {
            return cx.mem.write_f32(&self.d, 0.0);
        }
        let v = scale10(mant as f64, shift.clamp(-100, 100)) as f32;
        if v.is_infinite() || v < f32::MIN_POSITIVE {
            return Err(ErrorCode::OPERATION);
        }
        cx.mem.write_f32(&self.d, if neg { -v } else { v })
    }
}

// ------------------------------------------------------------------ ASC, HEX

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
    sm701: usize,
}

fn compile_asc(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.block(1);
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
            return Err(ErrorCode::OPERATION);
        }
        if n == 0 {
            return Ok(());
        }
        let n = n as usize;
        let nul = !cx.mem.bits[self.sm701];
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

fn compile_hex(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = a.block(1);
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
            return Err(ErrorCode::OPERATION);
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

// ------------------------------------------------------------------ RIGHT, LEFT, MIDR, MIDW

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

fn compile_side(a: &mut Args<'_, '_>, right: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = str_src(a, 0);
    let d = a.block(1);
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
            return Err(ErrorCode::RANGE);
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

fn compile_mid(a: &mut Args<'_, '_>, write: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = str_src(a, 0);
    let d = a.block(1);
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
            return Err(ErrorCode::RANGE);
        }
        let pos = pos as usize - 1;
        if !self.write {
            if pos >= s.len {
                return Err(ErrorCode::RANGE);
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
            return Err(ErrorCode::RANGE);
        };
        if pos >= d.len {
            return Err(ErrorCode::RANGE);
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

fn compile_instr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
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
            return Err(ErrorCode::RANGE);
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
