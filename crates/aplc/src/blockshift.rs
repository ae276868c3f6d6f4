//! Bit- and word-string shifts SFTR, SFTL (002 §6.7 L6386-6463) and WSFR,
//! WSFL (002 §6.2 L4193-4271): `OP S1 D S2 S3`, S2 the length of D's string,
//! S3 the shift count (S2 ≥ S3 ≥ 0, else error 64). "Right" is toward the
//! lower addresses: the S3 lowest elements drop out and S1's S3 elements
//! enter at the top; "left" the reverse. Strings past the device are 65.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{BitArg, BitBlock, Block, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::devices::{parse_device, Dev};
use crate::num::{self, E_VALUE};
use crate::resolve::{self, ArgsExt};

static DOC: Doc = Doc {
    family: "string shifts",
    cite: "002 §6.7 L6386-6463, §6.2 L4193-4271",
    notes: "SFTR/SFTL on bits (S1: X, Y, M, S, LM, SM, C, T; D: Y, M, S, LM, C, T), WSFR/WSFL on words; S2 ≥ S3 ≥ 0 else error 64; every scan with power flow",
};

pub static DEFS: &[Def] = &[
    // 002 §6.7.13 L6386 SFTR
    Def::app("SFTR", &DOC, |a| compile(a, true, true))
        .no_pulse()
        .steps(Steps::Fixed(9)),
    // 002 §6.7.14 L6427 SFTL
    Def::app("SFTL", &DOC, |a| compile(a, true, false))
        .no_pulse()
        .steps(Steps::Fixed(9)),
    // 002 §6.2.14 L4193 WSFR
    Def::app("WSFR", &DOC, |a| compile(a, false, true))
        .no_pulse()
        .steps(Steps::Fixed(9)),
    // 002 §6.2.15 L4233 WSFL
    Def::app("WSFL", &DOC, |a| compile(a, false, false))
        .no_pulse()
        .steps(Steps::Fixed(9)),
];

#[derive(Debug)]
enum Strings {
    Bits(BitBlock, BitBlock),
    Words(Block, Block),
}

#[derive(Debug)]
struct Shift {
    right: bool,
    s: Strings,
    len: WordArg,
    n: WordArg,
}

fn bit_block(a: &mut Args<'_, '_>, k: usize, dest: bool) -> Option<BitBlock> {
    let text = a.text(k).to_ascii_uppercase();
    let d = match parse_device(&text) {
        Ok(Some(d))
            if d.group.is_none()
                && d.dev.is_bit()
                && !(dest && matches!(d.dev, Dev::X | Dev::SM)) =>
        {
            d
        }
        Ok(_) => {
            a.error(k, format!("`{}`: a bit device is needed here", a.text(k)));
            return None;
        }
        Err(e) => {
            a.error(k, e);
            return None;
        }
    };
    let (kind, n) = d.dev.bit_storage(d.n)?;
    let map = a.map();
    let start = match d.index {
        None => BitArg::Bit(map.base(kind) + n),
        Some(z) => BitArg::Indexed(Box::new(softplc_ir::ops::Indexed {
            kind: softplc_ir::ops::IndexedKind::Bit,
            base: map.base(kind),
            number: n,
            points: d.dev.points(),
            z: map.base(DeviceKind::Z) + z as u32,
            window: softplc_ir::ops::Window::Device,
        })),
    };
    Some(BitBlock {
        start,
        limit: map.base(kind) + d.dev.points(),
    })
}

/// SFTR/SFTL (`bits`) or WSFR/WSFL, to the right (`right`) or left.
fn compile(a: &mut Args<'_, '_>, bits: bool, right: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let s = if bits {
        let s = bit_block(a, 0, false);
        let d = bit_block(a, 1, true);
        Strings::Bits(s?, d?)
    } else {
        let r = resolve::block(a.map(), a.text(0), false);
        let s = a.check(0, r);
        let r = resolve::block(a.map(), a.text(1), true);
        let d = a.check(1, r);
        Strings::Words(s?, d?)
    };
    let len = a.word_at(2, Width::W16, false);
    let n = a.word_at(3, Width::W16, false)?;
    Some(Box::new(Shift {
        right,
        s,
        len: len?,
        n,
    }))
}

/// Shifts `d[..len]` by `n` and fills from `s[..n]`, in one flat slice.
fn shift<T: Copy>(v: &mut [T], s: usize, d: usize, len: usize, n: usize, right: bool) {
    if right {
        v.copy_within(d + n..d + len, d);
        v.copy_within(s..s + n, d + len - n);
    } else {
        v.copy_within(d..d + len - n, d + n);
        v.copy_within(s..s + n, d);
    }
}

impl Instr for Shift {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (len, n) = (
            num::read16(cx.mem, &self.len)?,
            num::read16(cx.mem, &self.n)?,
        );
        if n < 0 || len < n {
            return Err(E_VALUE);
        }
        let (len, n) = (len as u32, n as u32);
        match &self.s {
            Strings::Bits(s, d) => {
                let (s, d) = (
                    cx.mem.bit_block_start(s, n)?,
                    cx.mem.bit_block_start(d, len)?,
                );
                shift(&mut cx.mem.bits, s, d, len as usize, n as usize, self.right);
            }
            Strings::Words(s, d) => {
                let (s, d) = (cx.mem.block_start(s, n)?, cx.mem.block_start(d, len)?);
                shift(
                    &mut cx.mem.words,
                    s,
                    d,
                    len as usize,
                    n as usize,
                    self.right,
                );
            }
        }
        Ok(())
    }
}
