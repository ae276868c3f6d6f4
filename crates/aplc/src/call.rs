//! Subroutine calls (002 §6.1 L3745-3800, §3.2.5 L2341-2473; contract §1.1
//! items 7-8): `CALL SBR_<n> args…` passes the IN, IN_OUT and OUT variables
//! of the subroutine's table in order (TEMP excluded). Every activation has
//! its own LM/V frame: the call saves the caller's frame, zeroes the locals,
//! copies IN/IN_OUT in, runs the subroutine, copies OUT/IN_OUT back to the
//! arguments after restoring the caller's frame (L1910, L1938, L2387-2389).
//!
//! Compiled as: `Ext(CallIn)` (with power flow) · `Call` · `ExtAlways(CallOut)`
//! (only if the call happened) · `Ld(call bit)`, which gives the rung its
//! power flow back after the subroutine's own logic.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr, LocalSlot, LocalState};
use softplc_ir::ops::{BitArg, Op, WordArg};
use softplc_lang::compile::Compiler;
use softplc_lang::isa::{Class, Def, Doc, Steps, Use};
use softplc_lang::{SourceInstr, Token};

use crate::constant::Width;
use crate::devices::CALL_BIT;
use crate::num;
use crate::pou::{Pou, PouKind, Unit};
use crate::resolve::{self, BitUse};

static DOC: Doc = Doc {
    family: "subroutines",
    cite: "002 §6.1 L3745-3800, §3.2.5 L2341-2473",
    notes: "CALL SBR_n with IN/OUT/IN_OUT arguments by table order, a fresh LM/V frame per activation; CSRET returns early; no recursion, at most 6 levels, no CALL in interrupt routines (load errors)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.1 L3745 CALL (compiled by the driver, which knows the POUs)
    Def::lower("CALL", Class::Output, &DOC, by_driver).steps(Steps::Operands),
    // 002 §6.1 L3792 CSRET
    Def::lower("CSRET", Class::Output, &DOC, by_driver).steps(Steps::Fixed(1)),
];

fn by_driver(c: &mut Compiler<'_>, u: &Use<'_>) {
    c.err(
        &u.instr.mnemonic,
        format!("`{}` is compiled by the POU driver", u.m),
    );
}

/// The hidden label of a subroutine's end (CSRET jumps there).
pub const RET_LABEL: u32 = 1 << 17;

/// The locals a call saves: V0-V63 and LM0-LM63.
const LOCALS: usize = 64;

/// What a call site keeps in its state words: the caller's V0-V63 and
/// LM0-LM63 while the subroutine runs, and whether the call ran (set by the
/// call, taken by the return half).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Saved {
    v: [u16; LOCALS],
    lm: u64,
    called: bool,
}

impl Default for Saved {
    fn default() -> Self {
        Saved {
            v: [0; LOCALS],
            lm: 0,
            called: false,
        }
    }
}

/// Its state words, in this order: V0-V63, LM0-LM31, LM32-LM63, called.
impl LocalState for Saved {
    const WORDS: u32 = LOCALS as u32 + 2 + 1;

    fn load(words: &[u32]) -> Self {
        let mut w = words.iter().copied();
        let mut next = move || w.next().unwrap_or(0);
        let v = [(); LOCALS].map(|_| next() as u16);
        let lm = next() as u64 | (next() as u64) << 32;
        Saved {
            v,
            lm,
            called: next() != 0,
        }
    }

    fn store(self, words: &mut [u32]) {
        let mut w = words.iter_mut();
        let mut put = |x: u32| {
            if let Some(s) = w.next() {
                *s = x;
            }
        };
        for v in self.v {
            put(v as u32);
        }
        put(self.lm as u32);
        put((self.lm >> 32) as u32);
        put(self.called as u32);
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ty {
    Bit,
    W16,
    W32,
}

#[derive(Debug)]
enum Arg {
    Bit(BitArg),
    Word(WordArg),
}

#[derive(Debug)]
struct Param {
    copy_in: bool,
    copy_out: bool,
    ty: Ty,
    arg: Arg,
    /// Flat index of the local: an LM bit or the first V word.
    local: u32,
}

#[derive(Debug)]
struct Frame {
    lm: u32,
    v: u32,
    /// The call site's saved locals.
    save: LocalSlot<Saved>,
}

#[derive(Debug)]
struct CallIn {
    params: Box<[Param]>,
    frame: Frame,
}

#[derive(Debug)]
struct CallOut {
    params: Box<[Param]>,
    frame: Frame,
    bit: u32,
}

/// At most 16 bit and 16 word parameters (L2361).
const MAX_PARAMS: usize = 32;

fn read(cx: &ExecCtx<'_>, p: &Param, from_local: bool) -> Result<u32, Fault> {
    let local = WordArg::Word(p.local);
    Ok(match (&p.arg, p.ty, from_local) {
        (_, Ty::Bit, true) => cx.mem.bits[p.local as usize] as u32,
        (Arg::Bit(b), _, false) => cx.mem.read_bit(b)? as u32,
        (_, Ty::W16, true) => cx.mem.read16(&local)? as u32,
        (_, Ty::W32, true) => num::read32(cx.mem, &local)?,
        (Arg::Word(w), Ty::W16, false) => cx.mem.read16(w)? as u32,
        (Arg::Word(w), _, false) => num::read32(cx.mem, w)?,
    })
}

fn write(cx: &mut ExecCtx<'_>, p: &Param, to_local: bool, v: u32) -> Result<(), Fault> {
    let local = WordArg::Word(p.local);
    match (&p.arg, p.ty, to_local) {
        (_, Ty::Bit, true) => cx.mem.bits[p.local as usize] = v != 0,
        (Arg::Bit(b), _, false) => cx.mem.write_bit(b, v != 0)?,
        (_, Ty::W16, true) => cx.mem.write16(&local, v as u16)?,
        (_, Ty::W32, true) => num::write32(cx.mem, &local, v)?,
        (Arg::Word(w), Ty::W16, false) => cx.mem.write16(w, v as u16)?,
        (Arg::Word(w), _, false) => num::write32(cx.mem, w, v)?,
    }
    Ok(())
}

impl Frame {
    /// The caller's locals: V0-V63 and LM0-LM63 (bit k of `lm` is LMk).
    fn locals<'m>(&self, cx: &'m mut ExecCtx<'_>) -> (&'m mut [u16], &'m mut [bool]) {
        let (v, lm) = (self.v as usize, self.lm as usize);
        (
            &mut cx.mem.words[v..v + LOCALS],
            &mut cx.mem.bits[lm..lm + LOCALS],
        )
    }

    /// Saves the caller's locals and clears them for the callee.
    fn save(&self, cx: &mut ExecCtx<'_>) {
        let mut s = cx.local(&self.save);
        let (v, lm) = self.locals(cx);
        s.v.copy_from_slice(v);
        s.lm = lm
            .iter()
            .enumerate()
            .fold(0, |acc, (k, &b)| acc | (b as u64) << k);
        v.fill(0);
        lm.fill(false);
        cx.set_local(&self.save, s);
    }

    /// Whether the call was made since the last return (and clears it).
    fn take_called(&self, cx: &mut ExecCtx<'_>) -> bool {
        let mut s = cx.local(&self.save);
        let called = std::mem::take(&mut s.called);
        cx.set_local(&self.save, s);
        called
    }

    /// The call is made: its return half restores the caller's locals.
    fn mark_called(&self, cx: &mut ExecCtx<'_>) {
        let mut s = cx.local(&self.save);
        s.called = true;
        cx.set_local(&self.save, s);
    }

    fn restore(&self, cx: &mut ExecCtx<'_>) {
        let s = cx.local(&self.save);
        let (v, lm) = self.locals(cx);
        v.copy_from_slice(&s.v);
        for (k, b) in lm.iter_mut().enumerate() {
            *b = s.lm >> k & 1 != 0;
        }
    }
}

impl Instr for CallIn {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mut buf = [0u32; MAX_PARAMS];
        for (p, b) in self.params.iter().zip(buf.iter_mut()) {
            if p.copy_in {
                *b = read(cx, p, false)?;
            }
        }
        self.frame.save(cx);
        for (p, b) in self.params.iter().zip(buf.iter()) {
            if p.copy_in {
                write(cx, p, true, *b)?;
            }
        }
        self.frame.mark_called(cx);
        Ok(())
    }
}

impl CallOut {
    fn step(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let called = self.frame.take_called(cx);
        cx.mem.bits[self.bit as usize] = called;
        if !called {
            return Ok(());
        }
        let mut buf = [0u32; MAX_PARAMS];
        for (p, b) in self.params.iter().zip(buf.iter_mut()) {
            if p.copy_out {
                *b = read(cx, p, true)?;
            }
        }
        self.frame.restore(cx);
        for (p, b) in self.params.iter().zip(buf.iter()) {
            if p.copy_out {
                write(cx, p, false, *b)?;
            }
        }
        Ok(())
    }
}

impl Instr for CallOut {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx)
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx)
    }
}

/// The subroutine number of `SBR_<n>` (any case).
pub fn sbr_number(t: &str) -> Option<u8> {
    let u = t.to_ascii_uppercase();
    u.strip_prefix("SBR_")?.parse().ok().filter(|n| *n <= 63)
}

/// Compiles `CALL SBR_<n> args…`; returns the callee and the op index of
/// its `Call` for linking.
pub fn call(
    c: &mut Compiler<'_>,
    unit: &Unit,
    caller: PouKind,
    i: &SourceInstr,
) -> Option<(u8, usize, Token)> {
    if matches!(caller, PouKind::Int { .. }) {
        c.err(
            &i.mnemonic,
            "CALL in an interrupt routine: interrupt routines cannot call subroutines (APLC programming manual §4.4.2)",
        );
        return None;
    }
    let Some(target) = i.operands.first() else {
        c.err(&i.mnemonic, "`CALL` needs a subroutine: CALL SBR_<n> args…");
        return None;
    };
    if !c.output(i, "CALL") {
        return None;
    }
    let Some(n) = sbr_number(&target.text) else {
        c.err(
            target,
            format!(
                "`{}`: a subroutine is SBR_0-SBR_63 (APLC programming manual §4.4.5)",
                target.text
            ),
        );
        return None;
    };
    let Some(callee) = unit.pous.iter().find(|p| p.kind == PouKind::Sbr(n)) else {
        c.err(
            target,
            format!(
                "CALL of `{}`: no POU SBR_{n} in the program (APLC programming manual §6.1.11)",
                target.text
            ),
        );
        return None;
    };
    let params = params(c, callee, i)?;
    let frame = |save| Frame {
        lm: c.map.base(DeviceKind::B),
        v: c.map.base(DeviceKind::W),
        save: LocalSlot::new(save),
    };
    let save = c.state_words;
    c.state_words += Saved::WORDS;
    let (f_in, f_out) = (frame(save), frame(save));
    let bit = c.map.base(DeviceKind::V) + CALL_BIT;
    let params_out = params
        .iter()
        .map(|p| Param {
            arg: match &p.arg {
                Arg::Bit(b) => Arg::Bit(b.clone()),
                Arg::Word(w) => Arg::Word(w.clone()),
            },
            ..*p
        })
        .collect();
    let x = c.ext.len() as u32;
    c.ext.push(Box::new(CallIn {
        params: params.into_boxed_slice(),
        frame: f_in,
    }));
    c.emit(Op::Ext(x));
    let at = c.emit(Op::Call(0));
    let x = c.ext.len() as u32;
    c.ext.push(Box::new(CallOut {
        params: params_out,
        frame: f_out,
        bit,
    }));
    c.emit(Op::ExtAlways(x));
    c.emit(Op::Ld(bit));
    Some((n, at, target.clone()))
}

/// Resolves the arguments against the callee's table (L3757-3790).
fn params(c: &mut Compiler<'_>, callee: &Pou, i: &SourceInstr) -> Option<Vec<Param>> {
    let vars: Vec<_> = callee.vars.iter().filter(|v| v.kind != "TEMP").collect();
    let args = &i.operands[1..];
    if args.len() != vars.len() {
        let names: Vec<&str> = vars.iter().map(|v| v.name.as_str()).collect();
        c.err(
            &i.operands[0],
            format!(
                "CALL {}: takes {} argument(s) ({}), found {} (APLC programming manual §6.1.11)",
                i.operands[0].text,
                vars.len(),
                names.join(", "),
                args.len()
            ),
        );
        return None;
    }
    let mut out = Vec::new();
    let mut ok = true;
    for (v, tok) in vars.iter().zip(args) {
        let copy_in = v.kind != "OUT";
        let copy_out = v.kind != "IN";
        let local_n: u32 = v
            .addr
            .trim_start_matches(|ch: char| ch.is_ascii_alphabetic())
            .parse()
            .unwrap_or(0);
        let (ty, arg, local) = if v.ty == "BOOL" {
            let what = if copy_out {
                BitUse::Coil
            } else {
                BitUse::Contact
            };
            let r = resolve::bit(c.map, &tok.text, what);
            (
                Ty::Bit,
                resolve::at(c, tok, r).map(Arg::Bit),
                c.map.base(DeviceKind::B) + local_n,
            )
        } else {
            let (ty, w) = match v.ty.as_str() {
                "INT" | "WORD" => (Ty::W16, Width::W16),
                "REAL" => (Ty::W32, Width::Real),
                _ => (Ty::W32, Width::W32),
            };
            let r = resolve::word(c.map, &tok.text, w, copy_out, false)
                .map_err(|e| format!("{e} (argument {} {} {})", v.name, v.kind, v.ty));
            (
                ty,
                resolve::at(c, tok, r).map(Arg::Word),
                c.map.base(DeviceKind::W) + local_n,
            )
        };
        match arg {
            Some(arg) => out.push(Param {
                copy_in,
                copy_out,
                ty,
                arg,
                local,
            }),
            None => ok = false,
        }
    }
    ok.then_some(out)
}
