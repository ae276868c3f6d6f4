//! EEPROM write EROMWR (002 §6.8.8 L6572-6628, §2.1.8 L985-991; spec
//! aplc.md §4.11, decisions D5 and D12).
//!
//! The EEPROM is an image of D6000-D6999 in hidden words (ZR0-ZR999, with
//! ZR1000-ZR1999 marking the words written, see `devices`) that power-on
//! keeps and the state directory persists; power-on and STOP→RUN load the
//! saved words into D6000-D6999 after the initial values, every other device
//! starts cleared (`system::load_eeprom`). EROMWR copies its block into the
//! image on the rising edge of its power flow. The write completes inside
//! the instruction (softplc spends no virtual time on it), so SM196 (EEPROM
//! write idle) stays ON and a second EROMWR in the same scan writes too.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::WordArg;
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};
use softplc_lang::Token;

use crate::constant::Width;
use crate::devices::{parse_device, Dev, EEPROM_FIRST, EEPROM_WORDS};
use crate::num::{self, E_VALUE};
use crate::resolve::ArgsExt;

static DOC: Doc = Doc {
    family: "EEPROM write",
    cite: "002 §6.8.8 L6572-6628, §2.1.8 L985-991",
    notes: "EROMWR S1 S2 on the rising edge: S1 a D6000-D6999 without index (load check), 0 ≤ S2 ≤ 16 and S1 + S2 ≤ 7000 or error 64 with nothing written (D12); the write completes at once, SM196 stays ON; power-on, RESET and STOP→RUN load the words EROMWR saved into D6000-D6999, over `[initial]` values (table 2-2), the state directory of `run`/`serve` keeps them (D5)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.8.8 L6572 EROMWR: 6 steps, 7 with an indexed S2 (L6576).
    Def::app("EROMWR", &DOC, eromwr)
        .on_rise()
        .steps(Steps::Rule(steps)),
];

/// 6 steps, 7 when S2 is index-modified (L6576, spec §4.11).
fn steps(ops: &[Token]) -> u32 {
    let indexed = ops
        .get(1)
        .and_then(|t| parse_device(&t.text.to_ascii_uppercase()).ok().flatten())
        .is_some_and(|d| d.index.is_some());
    6 + indexed as u32
}

#[derive(Debug)]
struct Eromwr {
    /// S1's number (6000-6999).
    first: u32,
    /// The flat word index of S1.
    from: usize,
    /// The flat index of S1's image word; its "saved" mark is 1000 words on.
    to: usize,
    count: WordArg,
}

fn eromwr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let d = parse_device(&a.text(0).to_ascii_uppercase()).ok().flatten();
    let first = match d {
        Some(d)
            if d.dev == Dev::D
                && d.group.is_none()
                && d.index.is_none()
                && (EEPROM_FIRST..EEPROM_FIRST + EEPROM_WORDS).contains(&d.n) =>
        {
            d.n
        }
        _ => {
            a.error(
                0,
                format!(
                    "`{}`: EROMWR writes from D6000-D6999, without index (APLC programming manual §6.8.8)",
                    a.text(0)
                ),
            );
            return None;
        }
    };
    let count = a.word_at(1, Width::W16, false)?;
    let map = a.map();
    Some(Box::new(Eromwr {
        first,
        from: (map.base(DeviceKind::D) + first) as usize,
        to: (map.base(DeviceKind::ZR) + first - EEPROM_FIRST) as usize,
        count,
    }))
}

/// Runs on the rising edge of the power flow only (`Drive::OnRise`).
impl Instr for Eromwr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = num::read16(cx.mem, &self.count)? as i32;
        if !(0..=16).contains(&n) || self.first as i32 + n > (EEPROM_FIRST + EEPROM_WORDS) as i32 {
            return Err(E_VALUE);
        }
        let n = n as usize;
        let words = &mut cx.mem.words;
        words.copy_within(self.from..self.from + n, self.to);
        words[self.to + EEPROM_WORDS as usize..][..n].fill(1);
        Ok(())
    }
}
