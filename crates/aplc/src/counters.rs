//! Counters CTU, CTR, DCNT (002 §5.4 L3237-3345; spec aplc.md §4.3). They
//! count on the rising edge of the power flow, detected per instruction.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr, LocalSlot};
use softplc_ir::local_state;
use softplc_ir::ops::WordArg;
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::devices::{counter_word, is_counter32, Dev};
use crate::num;
use crate::resolve::{self, ArgsExt};

static DOC: Doc = Doc {
    family: "counters",
    cite: "002 §5.4 L3237-3345",
    notes: "CTU saturates at 32767, coil = value ≥ preset; CTR rings (coil = value == preset); DCNT on C200-C235, direction SM200+n (ON = down), wraps, coil = value ≥ preset in both directions (spec §10 item 7)",
};

pub static DEFS: &[Def] = &[
    // 002 §5.4 L3239 CTU
    Def::app("CTU", &DOC, ctu).always().steps(Steps::Fixed(5)),
    // 002 §5.4 L3272 CTR
    Def::app("CTR", &DOC, ctr).always().steps(Steps::Fixed(5)),
    // 002 §5.4 L3306 DCNT
    Def::app("DCNT", &DOC, dcnt).always().steps(Steps::Fixed(7)),
];

local_state! {
    struct Edge {
        prev: bool,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Up,
    Ring,
    UpDown,
}

#[derive(Debug)]
struct Counter {
    mode: Mode,
    contact: u32,
    value: WordArg,
    /// SM200+n for DCNT.
    down: u32,
    preset: WordArg,
    st: LocalSlot<Edge>,
}

fn compile(a: &mut Args<'_, '_>, mode: Mode) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let r = resolve::tc(a.text(0), Dev::C);
    let n = a.check(0, r)?;
    let ok = match mode {
        Mode::UpDown => (200..=235).contains(&n),
        _ => !is_counter32(n),
    };
    if !ok {
        let want = if mode == Mode::UpDown {
            "C200-C235"
        } else {
            "C0-C199"
        };
        a.error(
            0,
            format!(
                "`{}`: {} counts {want} (APLC programming manual §3.1.7)",
                a.text(0),
                a.mnemonic()
            ),
        );
        return None;
    }
    let width = if mode == Mode::UpDown {
        Width::W32
    } else {
        Width::W16
    };
    let preset = a.word_at(1, width, false)?;
    let map = a.map();
    Some(Box::new(Counter {
        mode,
        contact: map.base(DeviceKind::CS) + n,
        value: WordArg::Word(map.base(DeviceKind::CN) + counter_word(n)),
        down: map.base(DeviceKind::SM) + n,
        preset,
        st: a.local(),
    }))
}

fn ctu(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    compile(a, Mode::Up)
}
fn ctr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    compile(a, Mode::Ring)
}
fn dcnt(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    compile(a, Mode::UpDown)
}

impl Counter {
    fn step(&self, cx: &mut ExecCtx<'_>, pf: bool) -> Result<(), Fault> {
        let mut st = cx.local(&self.st);
        let rising = pf && !st.prev;
        st.prev = pf;
        cx.set_local(&self.st, st);
        let c = self.contact as usize;
        match self.mode {
            Mode::Up => {
                let preset = num::read16(cx.mem, &self.preset)? as i32;
                let mut v = num::read16(cx.mem, &self.value)? as i32;
                if rising && v < 32767 {
                    v += 1;
                    cx.mem.write16(&self.value, v as u16)?;
                }
                cx.mem.bits[c] = v >= preset;
            }
            Mode::Ring => {
                let preset = num::read16(cx.mem, &self.preset)? as i32;
                let mut v = num::read16(cx.mem, &self.value)? as i32;
                if rising && preset > 0 {
                    v = if v >= preset { 1 } else { v + 1 };
                    cx.mem.write16(&self.value, v as u16)?;
                }
                cx.mem.bits[c] = preset > 0 && v == preset;
            }
            Mode::UpDown => {
                let preset = num::read32(cx.mem, &self.preset)? as i32;
                let mut v = num::read32(cx.mem, &self.value)? as i32;
                if rising {
                    let down = cx.mem.bits[self.down as usize];
                    v = if down {
                        v.wrapping_sub(1)
                    } else {
                        v.wrapping_add(1)
                    };
                    num::write32(cx.mem, &self.value, v as u32)?;
                }
                cx.mem.bits[c] = v >= preset;
            }
        }
        Ok(())
    }
}

impl Instr for Counter {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx, true)
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.step(cx, false)
    }
}
