//! Stacks and sums: PUSH, FIFO, LIFO (002 §6.2 L4080-4191; decision D15)
//! and SUM, DSUM (002 §6.3 L4795-4861). The count word (D or V) is followed
//! by the data; an illegal definition (size ≤ 0, count < 0 or > size) is
//! error 70, a stack past the device 65.

use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{Block, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::devices::{parse_device, Dev};
use crate::num::{self, E_VALUE};
use crate::resolve::{self, ArgsExt, Flags};

/// 70: illegal stack definition.
const E_STACK: Fault = Fault::Family(ErrorCode(70));

static STACK: Doc = Doc {
    family: "stacks",
    cite: "002 §6.2 L4080-4191",
    notes: "PUSH (full: SM181), FIFO, LIFO (SM180 = empty after the instruction, D15); error 70 for an illegal definition",
};
static SUMS: Doc = Doc {
    family: "sums",
    cite: "002 §6.3 L4795-4861",
    notes: "SUM of S2 signed words (0-255, else error 64) into a DINT, Z from the sum, C and B OFF; DSUM of double words (wraps)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.2.10 L4080 PUSH
    Def::app("PUSH", &STACK, |a| stack(a, Kind::Push))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.2.11 L4117 FIFO
    Def::app("FIFO", &STACK, |a| stack(a, Kind::Fifo))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.2.12 L4154 LIFO
    Def::app("LIFO", &STACK, |a| stack(a, Kind::Lifo))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.3 L4795 SUM
    Def::app("SUM", &SUMS, |a| sum(a, false))
        .no_pulse()
        .steps(Steps::Fixed(8)),
    // 002 §6.3 L4829 DSUM
    Def::app("DSUM", &SUMS, |a| sum(a, true))
        .no_pulse()
        .steps(Steps::Fixed(9)),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Push,
    Fifo,
    Lifo,
}

softplc_ir::layout! {
    /// The stack area of PUSH, FIFO and LIFO: the count word, then the data.
    pub struct StackArea[2] {
        /// The number of values stored.
        count: u16 @ 0,
        /// The first value (the oldest); value k is `data.nth(k)`.
        data: u16 @ 1,
    }
}

#[derive(Debug)]
struct Stack {
    kind: Kind,
    /// PUSH: the value; FIFO/LIFO: the output.
    value: WordArg,
    /// The count word and the data after it.
    area: Block,
    size: WordArg,
    flags: Flags,
}

fn count_word(a: &mut Args<'_, '_>, k: usize) -> Option<Block> {
    let ok = matches!(parse_device(&a.text(k).to_ascii_uppercase()), Ok(Some(d)) if d.group.is_none() && matches!(d.dev, Dev::D | Dev::V));
    if !ok {
        a.error(
            k,
            format!(
                "`{}`: the count word is D or V (APLC programming manual §6.2.10)",
                a.text(k)
            ),
        );
        return None;
    }
    let r = resolve::block(a.map(), a.text(k), true);
    a.check(k, r)
}

fn stack(a: &mut Args<'_, '_>, kind: Kind) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let (value, area) = if kind == Kind::Push {
        (a.word_at(0, Width::W16, false), count_word(a, 1))
    } else {
        let area = count_word(a, 0);
        (a.word_at(1, Width::W16, true), area)
    };
    let size = a.word_at(2, Width::W16, false)?;
    Some(Box::new(Stack {
        kind,
        value: value?,
        area: area?,
        size,
        flags: a.flags(),
    }))
}

impl Instr for Stack {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let size = num::read16(cx.mem, &self.size)? as i32;
        // The count word alone first: the size it allows is checked before the data.
        let at = cx
            .mem
            .block_start(&self.area, StackArea::data.offset() as u32)?;
        let count = StackArea::count.get(&cx.mem.words[at..]) as i16 as i32;
        if size <= 0 || count < 0 || count > size {
            return Err(E_STACK);
        }
        let (size, count) = (size as usize, count as usize);
        let words = StackArea::data.nth(size).offset();
        let base = cx.mem.block_start(&self.area, words as u32)?;
        let value = |k: usize| StackArea::data.nth(k);
        match self.kind {
            Kind::Push => {
                let full = count == size;
                cx.mem.bits[self.flags.carry as usize] = full;
                if !full {
                    let v = cx.mem.read16(&self.value)?;
                    let area = &mut cx.mem.words[base..base + words];
                    StackArea::count.set(area, (count + 1) as u16);
                    value(count).set(area, v);
                }
            }
            Kind::Fifo | Kind::Lifo if count == 0 => cx.mem.bits[self.flags.zero as usize] = true,
            Kind::Fifo => {
                let v = value(0).get(&cx.mem.words[base..]);
                cx.mem.write16(&self.value, v)?;
                // The others move down one place; the last becomes 0.
                let area = &mut cx.mem.words[base..base + words];
                area.copy_within(value(1).offset()..words, value(0).offset());
                value(size - 1).set(area, 0);
                StackArea::count.set(area, (count - 1) as u16);
                cx.mem.bits[self.flags.zero as usize] = count == 1;
            }
            Kind::Lifo => {
                let v = value(count - 1).get(&cx.mem.words[base..]);
                cx.mem.write16(&self.value, v)?;
                StackArea::count.set(&mut cx.mem.words[base..], (count - 1) as u16);
                cx.mem.bits[self.flags.zero as usize] = count == 1;
            }
        }
        Ok(())
    }
}

#[derive(Debug)]
struct Sum {
    wide: bool,
    data: Block,
    n: WordArg,
    d: WordArg,
    flags: Flags,
}

/// SUM, or DSUM (`wide`).
fn sum(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let r = if wide {
        resolve::block32(a.map(), a.text(0))
    } else {
        resolve::block(a.map(), a.text(0), false)
    };
    let data = a.check(0, r);
    let n = a.word_at(1, Width::W16, false);
    let d = a.word_at(2, Width::W32, true)?;
    Some(Box::new(Sum {
        wide,
        data: data?,
        n: n?,
        d,
        flags: a.flags(),
    }))
}

impl Instr for Sum {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = num::read16(cx.mem, &self.n)?;
        if !(0..=255).contains(&n) {
            return Err(E_VALUE);
        }
        let n = n as usize;
        let words = if self.wide { 2 * n } else { n };
        let s = cx.mem.block_start(&self.data, words as u32)?;
        let w = &cx.mem.words[s..s + words];
        let total: i32 = if self.wide {
            w.chunks(2).fold(0i32, |t, p| {
                t.wrapping_add(((p[0] as u32) << 16 | p[1] as u32) as i32)
            })
        } else {
            w.iter().fold(0i32, |t, v| t.wrapping_add(*v as i16 as i32))
        };
        num::write32(cx.mem, &self.d, total as u32)?;
        cx.mem.bits[self.flags.zero as usize] = total == 0;
        if !self.wide {
            cx.mem.bits[self.flags.carry as usize] = false;
            cx.mem.bits[self.flags.borrow as usize] = false;
        }
        Ok(())
    }
}
