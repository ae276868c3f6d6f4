//! Programming manual (common instructions) §6.2 arithmetic operation
//! instructions: BCD 4-digit and 8-digit arithmetic (B+, B-, B*, B/, DB+, DB-,
//! DB*, DB/) and BIN block addition/subtraction (BK+, BK-). The BIN and real
//! forms (`+ - * /`, `D+` …, `E+` …, INC/DEC) are basic instructions compiled by
//! `program::compile`.
//!
//! Section numbers are those of the QCPU (Q mode)/QnACPU Programming Manual
//! (Common Instructions), SH-080039. No instruction here sets a carry flag: BCD
//! sums and differences wrap modulo 10⁴ / 10⁸ and BK+/BK- wrap like `+`/`-`.
//! Invalid BCD (a digit A-F) in a source and division by 0 are OPERATION ERROR
//! 4100; a block past the last device is 4101. The destination is left unchanged
//! when an instruction fails.

use super::conversion::{read_bcd, to_bcd};
use super::{Args, ExecCtx, Instr};
use softplc_ir::device::Operand;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{IndexedKind, Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("B+", &BCD_ARITHMETIC, |a| {
        BcdAddSub::compile(a, false, false)
    }),
    Def::app("B-", &BCD_ARITHMETIC, |a| {
        BcdAddSub::compile(a, false, true)
    }),
    Def::app("DB+", &BCD_ARITHMETIC, |a| {
        BcdAddSub::compile(a, true, false)
    }),
    Def::app("DB-", &BCD_ARITHMETIC, |a| {
        BcdAddSub::compile(a, true, true)
    }),
    Def::app("B*", &BCD_ARITHMETIC_2, |a| BcdMul::compile(a, false)),
    Def::app("DB*", &BCD_ARITHMETIC_2, |a| BcdMul::compile(a, true)),
    Def::app("B/", &BCD_ARITHMETIC_2, |a| BcdDiv::compile(a, false)),
    Def::app("DB/", &BCD_ARITHMETIC_2, |a| BcdDiv::compile(a, true)),
    Def::app("BK+", &BLOCK_ARITHMETIC, |a| BlockAddSub::compile(a, false)),
    Def::app("BK-", &BLOCK_ARITHMETIC, |a| BlockAddSub::compile(a, true)),
];

static BCD_ARITHMETIC: Doc = Doc {
    family: "BCD arithmetic",
    cite: "PM §6.2.5-6",
    notes: "mod 10⁴/10⁸, ten's complement; invalid BCD → 4100",
};
static BCD_ARITHMETIC_2: Doc = Doc {
    family: "BCD arithmetic",
    cite: "PM §6.2.7-8",
    notes: "3 operands; ÷0 → 4100",
};
static BLOCK_ARITHMETIC: Doc = Doc {
    family: "block arithmetic",
    cite: "PM §6.2.11",
    notes: "S2 block or constant; wraps; past device end → 4101",
};

/// BCD numbers of 4 digits (16-bit operands) or 8 digits (32-bit operands).
fn num(wide: bool) -> Num {
    if wide {
        Num::I32
    } else {
        Num::I16
    }
}

/// 10⁴ or 10⁸: BCD sums and differences are taken modulo this.
fn modulus(wide: bool) -> u64 {
    if wide {
        100_000_000
    } else {
        10_000
    }
}

fn is_digits(d: &WordArg) -> bool {
    match d {
        WordArg::Digits { .. } => true,
        WordArg::Indexed(ix) => matches!(ix.kind, IndexedKind::Digits(_)),
        _ => false,
    }
}

/// Three operands `S1 S2 D`: `D` written as `dest_num` over `dest_words` words.
fn three(
    a: &mut Args<'_, '_>,
    num: Num,
    dest_num: Num,
    dest_words: u32,
) -> Option<(WordArg, WordArg, WordArg)> {
    let s1 = a.word_src(0, num);
    let s2 = a.word_src(1, num);
    let d = a.word_dest(2, dest_num, dest_words);
    Some((s1?, s2?, d?))
}

/// PM §6.2.5 B+, B- (BCD 4 digits) and §6.2.6 DB+, DB- (BCD 8 digits, S+1/D+1
/// the upper digits). `S D` computes D ± S → D, `S1 S2 D` computes S1 ± S2 → D.
/// A sum beyond 9999 (99999999) drops the carry; a negative difference gives its
/// ten's complement (0000 − 0001 = 9999); the carry flag is not set. A source
/// (D of the two-operand form included) with a digit A-F is 4100. A
/// digit-specified source reads only its digits and a digit-specified D keeps the
/// low digits of the result ("digits beyond the designated number are 0").
#[derive(Debug)]
struct BcdAddSub {
    wide: bool,
    sub: bool,
    s1: WordArg,
    s2: WordArg,
    d: WordArg,
}

impl BcdAddSub {
    fn compile(a: &mut Args<'_, '_>, wide: bool, sub: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[2, 3]) {
            return None;
        }
        let n = num(wide);
        let (s1, s2, d) = if a.len() == 3 {
            three(a, n, n, n.words())?
        } else {
            let s = a.word_src(0, n);
            let d = a.word_dest(1, n, n.words());
            let (s, d) = (s?, d?);
            (d.clone(), s, d)
        };
        Some(Box::new(BcdAddSub {
            wide,
            sub,
            s1,
            s2,
            d,
        }))
    }
}

impl Instr for BcdAddSub {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = read_bcd(cx.mem, &self.s1, self.wide)?;
        let b = read_bcd(cx.mem, &self.s2, self.wide)?;
        let m = modulus(self.wide);
        let r = if self.sub {
            (a + m - b) % m
        } else {
            (a + b) % m
        };
        let v = to_bcd(r);
        if self.wide {
            cx.mem.write32(&self.d, v as u32)
        } else {
            cx.mem.write16(&self.d, v as u16)
        }
    }
}

/// PM §6.2.7 B* (BCD 4 digits × 4 digits → 8 digits in D, D+1) and §6.2.8 DB*
/// (8 digits × 8 digits → 16 digits in D to D+3, lowest digits first).
/// Three-operand form only, as on the CPU. A source with a digit A-F is 4100. A
/// digit-specified D takes K1-K8 and gets the lowest digits of the product.
#[derive(Debug)]
struct BcdMul {
    wide: bool,
    s1: WordArg,
    s2: WordArg,
    d: WordArg,
}

impl BcdMul {
    fn compile(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[3]) {
            return None;
        }
        let words = if wide { 4 } else { 2 };
        let (s1, s2, d) = three(a, num(wide), Num::I32, words)?;
        Some(Box::new(BcdMul { wide, s1, s2, d }))
    }
}

impl Instr for BcdMul {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = read_bcd(cx.mem, &self.s1, self.wide)?;
        let b = read_bcd(cx.mem, &self.s2, self.wide)?;
        // 9999 × 9999 has 8 digits, 99999999 × 99999999 has 16: both fit.
        let words = if self.wide { 4 } else { 2 };
        cx.mem.write_words(&self.d, to_bcd(a * b), words)
    }
}

/// PM §6.2.7 B/ (BCD 4 digits: quotient in D, remainder in D+1) and §6.2.8 DB/
/// (BCD 8 digits: quotient in D, D+1, remainder in D+2, D+3). Three-operand
/// form only. Division by 0 and a source with a digit A-F are 4100. A
/// digit-specified D (K1-K8) gets the quotient only, without the remainder, as
/// `/` does.
#[derive(Debug)]
struct BcdDiv {
    wide: bool,
    s1: WordArg,
    s2: WordArg,
    d: WordArg,
}

impl BcdDiv {
    fn compile(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[3]) {
            return None;
        }
        let words = if wide { 4 } else { 2 };
        let (s1, s2, d) = three(a, num(wide), Num::I32, words)?;
        Some(Box::new(BcdDiv { wide, s1, s2, d }))
    }
}

impl Instr for BcdDiv {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = read_bcd(cx.mem, &self.s1, self.wide)?;
        let b = read_bcd(cx.mem, &self.s2, self.wide)?;
        if b == 0 {
            return Err(Fault::Operation);
        }
        let (q, r) = (to_bcd(a / b), to_bcd(a % b));
        if is_digits(&self.d) {
            return cx.mem.write32(&self.d, q as u32);
        }
        if self.wide {
            cx.mem.write_words(&self.d, q | r << 32, 4)
        } else {
            cx.mem.write_words(&self.d, q | r << 16, 2)
        }
    }
}

/// The second operand of BK+/BK-: a block of words or one constant.
#[derive(Debug)]
enum Addend {
    Const(u16),
    Block(Block),
}

/// PM §6.2.11 BK+, BK- `S1 S2 D n`: adds to (subtracts from) the n words of BIN
/// 16 bits from S1 the n words from S2, or the constant S2 (K/H) for every word,
/// and stores the n results from D. Results wrap like `+`/`-` (32767 + 2 =
/// -32767), no carry flag. n words from S1, S2 or D past the last device is
/// 4101; n = 0 does nothing. Decisions (the manual is silent): n is taken as an
/// unsigned count, so a negative n names 32768-65535 words (4101 unless the
/// device is that large); the words are processed from the first to the last,
/// so a D overlapping S1 or S2 further on sees results already stored. Word
/// devices only (no digit specification).
#[derive(Debug)]
struct BlockAddSub {
    sub: bool,
    s1: Block,
    s2: Addend,
    d: Block,
    n: WordArg,
}

impl BlockAddSub {
    fn compile(a: &mut Args<'_, '_>, sub: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s1 = a.block(0);
        let s2 = match a.operand(1) {
            Some(Operand::Const(_)) => match a.word_src(1, Num::I16) {
                Some(WordArg::Const(k)) => Some(Addend::Const(k as u16)),
                _ => None,
            },
            Some(_) => a.block(1).map(Addend::Block),
            None => None,
        };
        let d = a.block_dest(2);
        let n = a.word_src(3, Num::I16);
        Some(Box::new(BlockAddSub {
            sub,
            s1: s1?,
            s2: s2?,
            d: d?,
            n: n?,
        }))
    }
}

impl Instr for BlockAddSub {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = mem.read16(&self.n)? as u32;
        if n == 0 {
            return Ok(());
        }
        let s1 = mem.block_start(&self.s1, n)?;
        let s2 = match &self.s2 {
            Addend::Const(k) => Err(*k),
            Addend::Block(b) => Ok(mem.block_start(b, n)?),
        };
        let d = mem.block_start(&self.d, n)?;
        let w = &mut mem.words;
        for i in 0..n as usize {
            let b = match s2 {
                Ok(s2) => w[s2 + i],
                Err(k) => k,
            };
            w[d + i] = if self.sub {
                w[s1 + i].wrapping_sub(b)
            } else {
                w[s1 + i].wrapping_add(b)
            };
        }
        Ok(())
    }
}
