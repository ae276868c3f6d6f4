//! Bit instructions on words: DECO (alias DATO), ENCO, BITS, DBITS
//! (002 §6.17 L8726-8831) and the word-bit contacts and coils BLD, BLDI,
//! BAND, BANI, BOR, BORI, BOUT, BSET, BRST (002 §6.18 L8833-9076; spec
//! aplc.md §4.17-§4.18). A bit number outside 0-15 is run error 64.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{CondOp, Condition, Join, Op, WordArg};
use softplc_lang::compile::{Args, Compiler};
use softplc_lang::isa::{Def, Doc, Steps, Test, Use};

use crate::calc::{self, Fl, Layout, Spec};
use crate::constant::Width;
use crate::num::E_VALUE;
use crate::resolve::{self, at, ArgsExt};

static BITS: Doc = Doc {
    family: "bit functions",
    cite: "002 §6.17 L8726-8831",
    notes: "DECO (IL also DATO) S outside 0-15 is error 64; ENCO gives the lowest set bit, S = 0 is error 64 (not stated); BITS/DBITS count ones",
};
static WORDBIT: Doc = Doc {
    family: "word-bit contacts and coils",
    cite: "002 §6.18 L8833-9076",
    notes: "S1 a word (no constant), S2 the bit 0-15 (else error 64); BOUT follows the power flow (OFF under an OFF MC)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.17.3 L8726 DECO / DATO
    Def::app("DECO", &BITS, |a| func(a, deco, Width::W16))
        .no_pulse()
        .steps(Steps::Fixed(5)),
    Def::app("DATO", &BITS, |a| func(a, deco, Width::W16))
        .no_pulse()
        .steps(Steps::Fixed(5)),
    // 002 §6.17.4 L8756 ENCO
    Def::app("ENCO", &BITS, |a| func(a, enco, Width::W16))
        .no_pulse()
        .steps(Steps::Fixed(5)),
    // 002 §6.17.5 L8787 BITS
    Def::app("BITS", &BITS, |a| func(a, bits, Width::W16))
        .no_pulse()
        .steps(Steps::Fixed(5)),
    // 002 §6.17.6 L8810 DBITS
    Def::app("DBITS", &BITS, |a| func(a, bits, Width::W32))
        .no_pulse()
        .steps(Steps::Fixed(6)),
    // 002 §6.18 L8835-9001 BLD … BORI
    Def::contact(
        "BLD",
        Join::Load,
        Test::WordBit { closed: false },
        &WORDBIT,
        contact,
    )
    .steps(Steps::Fixed(5)),
    Def::contact(
        "BLDI",
        Join::Load,
        Test::WordBit { closed: true },
        &WORDBIT,
        contact,
    )
    .steps(Steps::Fixed(5)),
    Def::contact(
        "BAND",
        Join::And,
        Test::WordBit { closed: false },
        &WORDBIT,
        contact,
    )
    .steps(Steps::Fixed(5)),
    Def::contact(
        "BANI",
        Join::And,
        Test::WordBit { closed: true },
        &WORDBIT,
        contact,
    )
    .steps(Steps::Fixed(5)),
    Def::contact(
        "BOR",
        Join::Or,
        Test::WordBit { closed: false },
        &WORDBIT,
        contact,
    )
    .steps(Steps::Fixed(5)),
    Def::contact(
        "BORI",
        Join::Or,
        Test::WordBit { closed: true },
        &WORDBIT,
        contact,
    )
    .steps(Steps::Fixed(5)),
    // 002 §6.18 L9003-9076 BOUT, BSET, BRST
    Def::app("BOUT", &WORDBIT, |a| coil(a, Coil::Out))
        .always()
        .steps(Steps::Fixed(5)),
    Def::app("BSET", &WORDBIT, |a| coil(a, Coil::Set))
        .no_pulse()
        .steps(Steps::Fixed(5)),
    Def::app("BRST", &WORDBIT, |a| coil(a, Coil::Rst))
        .no_pulse()
        .steps(Steps::Fixed(5)),
];

fn deco(s: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    if s > 15 {
        return Err(E_VALUE);
    }
    Ok(1 << s)
}
fn enco(s: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    if s as u16 == 0 {
        return Err(E_VALUE);
    }
    Ok((s as u16).trailing_zeros())
}
fn bits(s: u32, _: u32, _: &mut Fl) -> Result<u32, Fault> {
    Ok(s.count_ones())
}

/// DECO, ENCO, BITS, DBITS: `f` of a `src`-wide source into a word.
fn func(a: &mut Args<'_, '_>, f: calc::Fn2, src: Width) -> Option<Box<dyn Instr>> {
    calc::compile(a, Spec::new(f, src, Width::W16, Layout::SD))
}

fn bit_number(mem: &DeviceMemory, b: &WordArg) -> Result<u32, Fault> {
    let n = mem.read16(b)? as i16;
    if (0..16).contains(&n) {
        Ok(n as u32)
    } else {
        Err(E_VALUE)
    }
}

#[derive(Debug)]
struct WordBit {
    word: WordArg,
    bit: WordArg,
    negate: bool,
}

impl Condition for WordBit {
    fn eval(&self, mem: &DeviceMemory) -> Result<bool, Fault> {
        let n = bit_number(mem, &self.bit)?;
        Ok((mem.read16(&self.word)? >> n & 1 != 0) ^ self.negate)
    }
}

/// A word operand without constants.
fn word_no_const(text: &str, c: &Compiler<'_>, dest: bool) -> Result<WordArg, String> {
    if crate::constant::looks_like_constant(text) {
        return Err(format!("constant `{text}`: a word device is needed here"));
    }
    resolve::word(c.map, text, Width::W16, dest, false)
}

fn contact(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let (join, negate) = match u.m {
        "BLD" => (Join::Load, false),
        "BLDI" => (Join::Load, true),
        "BAND" => (Join::And, false),
        "BANI" => (Join::And, true),
        "BOR" => (Join::Or, false),
        "BORI" => (Join::Or, true),
        _ => return c.unmatched(u),
    };
    if !c.count(i, u.m, &[2]) {
        return;
    }
    let r = word_no_const(&i.operands[0].text, c, false);
    let word = at(c, &i.operands[0], r);
    let r = resolve::word(c.map, &i.operands[1].text, Width::W16, false, false);
    let bit = at(c, &i.operands[1], r);
    let (Some(word), Some(bit)) = (word, bit) else {
        return;
    };
    let op = Op::Cond(Box::new(CondOp {
        join,
        cond: Box::new(WordBit { word, bit, negate }),
    }));
    c.contact(i, join, op);
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Coil {
    Out,
    Set,
    Rst,
}

#[derive(Debug)]
struct BitCoil {
    kind: Coil,
    word: WordArg,
    bit: WordArg,
}

impl BitCoil {
    fn write(&self, cx: &mut ExecCtx<'_>, on: bool) -> Result<(), Fault> {
        let n = bit_number(cx.mem, &self.bit)?;
        let w = cx.mem.read16(&self.word)?;
        let v = if on { w | 1 << n } else { w & !(1 << n) };
        cx.mem.write16(&self.word, v)
    }
}

impl Instr for BitCoil {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.write(cx, self.kind != Coil::Rst)
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        if self.kind == Coil::Out {
            self.write(cx, false)?;
        }
        Ok(())
    }
}

fn coil(a: &mut Args<'_, '_>, kind: Coil) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let word = a.word_at(0, Width::W16, true);
    let bit = a.word_at(1, Width::W16, false)?;
    Some(Box::new(BitCoil {
        kind,
        word: word?,
        bit,
    }))
}
