//! The shared machinery of the value instructions (word logic, shifts,
//! REAL arithmetic, conversions): an operation on raw operand values with
//! the flags it defines (decision D8: each execution writes exactly the flags
//! its text defines), read and written with the APLC word order.

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::WordArg;
use softplc_lang::compile::Args;

use crate::constant::Width;
use crate::num;
use crate::resolve::{ArgsExt, Flags};

/// Flags an operation reports; `None` is not written. `carry_in` is SM181
/// before the instruction (the rotations through carry).
#[derive(Clone, Copy, Debug, Default)]
pub struct Fl {
    pub zero: Option<bool>,
    pub carry: Option<bool>,
    pub borrow: Option<bool>,
    pub carry_in: bool,
}

/// An operation on raw values (16-bit values in the low half, REAL as bits).
pub type Fn2 = fn(u32, u32, &mut Fl) -> Result<u32, Fault>;

/// The order of the operands as written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// `OP S D`.
    SD,
    /// `OP S1 S2 D`.
    S1S2D,
    /// `OP S1 D S2` (shifts and rotations, L5991-6463).
    S1DS2,
}

/// What one mnemonic is.
#[derive(Clone, Copy, Debug)]
pub struct Spec {
    pub f: Fn2,
    /// Width of the first source and of the destination.
    pub src: Width,
    pub dst: Width,
    pub layout: Layout,
    /// A bit group source must be K4 (K8 for 32 bits): ROR, SHL … (L1996).
    pub full_groups: bool,
}

impl Spec {
    pub const fn new(f: Fn2, src: Width, dst: Width, layout: Layout) -> Spec {
        Spec {
            f,
            src,
            dst,
            layout,
            full_groups: false,
        }
    }
    pub const fn full(mut self) -> Spec {
        self.full_groups = true;
        self
    }
}

#[derive(Debug)]
struct Calc {
    f: Fn2,
    src: Width,
    dst: Width,
    s1: WordArg,
    /// The second operand (16-bit for the shift count).
    s2: Option<(WordArg, Width)>,
    d: WordArg,
    flags: Flags,
}

/// Compiles the instruction `spec` describes.
pub fn compile(a: &mut Args<'_, '_>, spec: Spec) -> Option<Box<dyn Instr>> {
    let (n, s1, s2, d) = match spec.layout {
        Layout::SD => (2, 0, None, 1),
        Layout::S1S2D => (3, 0, Some((1, spec.src)), 2),
        Layout::S1DS2 => (3, 0, Some((2, Width::W16)), 1),
    };
    if !a.count(&[n]) {
        return None;
    }
    let first = a.word_at(s1, spec.src, false);
    let second = s2.map(|(k, w)| a.word_at(k, w, false).map(|x| (x, w)));
    let dest = a.word_at(d, spec.dst, true)?;
    let first = first?;
    let s2 = match second {
        Some(x) => Some(x?),
        None => None,
    };
    if spec.full_groups {
        let need = if spec.src == Width::W16 { 4 } else { 8 };
        if matches!(first, WordArg::Digits { n, .. } if n != need) {
            a.error(
                s1,
                format!(
                    "`{}`: a bit group here must be K{need} (APLC programming manual §3.2.1)",
                    a.text(s1)
                ),
            );
            return None;
        }
    }
    Some(Box::new(Calc {
        f: spec.f,
        src: spec.src,
        dst: spec.dst,
        s1: first,
        s2,
        d: dest,
        flags: a.flags(),
    }))
}

fn read(cx: &ExecCtx<'_>, a: &WordArg, w: Width) -> Result<u32, Fault> {
    match w {
        Width::W16 => Ok(cx.mem.read16(a)? as u32),
        Width::W32 => num::read32(cx.mem, a),
        Width::Real => num::read_real(cx.mem, a).map(f32::to_bits),
    }
}

impl Instr for Calc {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = read(cx, &self.s1, self.src)?;
        let b = match &self.s2 {
            Some((x, w)) => read(cx, x, *w)?,
            None => 0,
        };
        let mut fl = Fl {
            carry_in: cx.mem.bits[self.flags.carry as usize],
            ..Fl::default()
        };
        let v = (self.f)(a, b, &mut fl)?;
        match self.dst {
            Width::W16 => cx.mem.write16(&self.d, v as u16)?,
            _ => num::write32(cx.mem, &self.d, v)?,
        }
        for (f, at) in [
            (fl.zero, self.flags.zero),
            (fl.carry, self.flags.carry),
            (fl.borrow, self.flags.borrow),
        ] {
            if let Some(v) = f {
                cx.mem.bits[at as usize] = v;
            }
        }
        Ok(())
    }
}
