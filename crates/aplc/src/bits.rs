//! Range set/reset ZRST, ZSET (002 §6.17 L8669-8724; spec aplc.md §4.17):
//! S consecutive bits from D (Y, M, S, LM, C, T; indexable); on T and C the
//! current values are cleared too. A range past the device is run error 65,
//! a negative count 64.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::WordArg;
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::devices::{counter_word, is_counter32, parse_device, Dev};
use crate::num::{E_RANGE, E_VALUE};
use crate::resolve::ArgsExt;

static DOC: Doc = Doc {
    family: "bit ranges",
    cite: "002 §6.17 L8669-8724",
    notes: "ZRST/ZSET D S on Y, M, S, LM, C, T (values of T and C cleared too); past the device is error 65",
};

pub static DEFS: &[Def] = &[
    // 002 §6.17.1 L8671 ZRST
    Def::app("ZRST", &DOC, |a| zrst(a, false))
        .no_pulse()
        .steps(Steps::Fixed(5)),
    // 002 §6.17.2 L8701 ZSET
    Def::app("ZSET", &DOC, |a| zrst(a, true))
        .no_pulse()
        .steps(Steps::Fixed(5)),
];

#[derive(Debug)]
struct Range {
    set: bool,
    dev: Dev,
    n: u32,
    points: u32,
    /// Flat index of bit 0 of the device, of its value words (T, C), of Zk.
    bits: u32,
    values: Option<u32>,
    z: Option<u32>,
    count: WordArg,
}

/// ZRST, or ZSET (`set`).
fn zrst(a: &mut Args<'_, '_>, set: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let text = a.text(0).to_ascii_uppercase();
    let d = match parse_device(&text) {
        Ok(Some(d))
            if d.group.is_none()
                && matches!(d.dev, Dev::Y | Dev::M | Dev::S | Dev::LM | Dev::C | Dev::T) =>
        {
            d
        }
        Ok(_) => {
            a.error(
                0,
                format!(
                    "`{}`: {} takes Y, M, S, LM, C or T",
                    a.text(0),
                    a.mnemonic()
                ),
            );
            return None;
        }
        Err(e) => {
            a.error(0, e);
            return None;
        }
    };
    let count = a.word_at(1, Width::W16, false)?;
    let map = a.map();
    let (kind, first) = d.dev.bit_storage(0)?;
    let values = match d.dev {
        Dev::T => Some(map.base(DeviceKind::TN)),
        Dev::C => Some(map.base(DeviceKind::CN)),
        _ => None,
    };
    Some(Box::new(Range {
        set,
        dev: d.dev,
        n: d.n,
        points: d.dev.points(),
        bits: map.base(kind) + first,
        values,
        z: d.index.map(|z| map.base(DeviceKind::Z) + z as u32),
        count,
    }))
}

impl Instr for Range {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let count = cx.mem.read16(&self.count)? as i16;
        if count < 0 {
            return Err(E_VALUE);
        }
        let z = self.z.map_or(0, |z| cx.mem.words[z as usize] as i16 as i64);
        let from = self.n as i64 + z;
        let to = from + count as i64;
        if from < 0 || to > self.points as i64 {
            return Err(E_RANGE);
        }
        let (from, to) = (from as u32, to as u32);
        let b = self.bits as usize;
        cx.mem.bits[b + from as usize..b + to as usize].fill(self.set);
        if let (Some(v), false) = (self.values, self.set) {
            for n in from..to {
                let (w, len) = match self.dev {
                    Dev::C => (counter_word(n), if is_counter32(n) { 2 } else { 1 }),
                    _ => (n, 1),
                };
                let at = (v + w) as usize;
                cx.mem.words[at..at + len].fill(0);
            }
        }
        Ok(())
    }
}
