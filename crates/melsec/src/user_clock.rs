//! User timing clocks (PM DUTY; 004 App. 1): DUTY `n1 n2 SM42x` makes
//! SM420-SM424 / SM430-SM434 ON for n1 scans then OFF for n2 scans, counted
//! at END from the END of the scan that executed DUTY. n1 = 0 keeps the clock
//! OFF, n2 = 0 keeps it ON. The clocks are CPU state ([`UserClocks`]) that
//! the system's END processing ([`end`]) turns into the relays.

use softplc_ir::device::{parse_operand, DeviceKind, DeviceMemory, Operand};
use softplc_ir::fault::Fault;
use softplc_ir::instr::{CpuSlot, ExecCtx, Instr};
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::compile::Args;

/// Clocks SM420-SM424 then SM430-SM434.
const CLOCKS: usize = 10;
/// Words of one clock: set, ON scans, OFF scans, scans counted.
const CLOCK_WORDS: usize = 4;

softplc_ir::cpu_state! {
    /// The user timing clocks DUTY set: per clock (set, n1, n2, scans
    /// counted).
    pub struct UserClocks[CLOCKS * CLOCK_WORDS];
}

/// PM DUTY `n1 n2 D`: user timing clock D ON for n1 scans, OFF for n2
/// scans; a negative n1 or n2 is an operation error. Setting a clock again
/// keeps its count.
#[derive(Debug)]
struct Duty {
    n1: WordArg,
    n2: WordArg,
    clock: usize,
    clocks: CpuSlot<UserClocks>,
}

pub(crate) fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let n1 = a.word_src(0, Num::I16);
    let n2 = a.word_src(1, Num::I16);
    let clock = match parse_operand(a.text(2)) {
        Ok(Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) if dev.kind == DeviceKind::SM && matches!(dev.number, 420..=424 | 430..=434) => {
            Some(if dev.number < 430 {
                dev.number - 420
            } else {
                dev.number - 425
            } as usize)
        }
        _ => {
            let text = a.text(2).to_string();
            a.error(
                2,
                format!("`{text}`: DUTY drives a user timing clock SM420-SM424 or SM430-SM434"),
            );
            None
        }
    };
    Some(Box::new(Duty {
        n1: n1?,
        n2: n2?,
        clock: clock?,
        clocks: a.cpu(),
    }))
}

impl Instr for Duty {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n1 = cx.mem.read16(&self.n1)? as i16;
        let n2 = cx.mem.read16(&self.n2)? as i16;
        if n1 < 0 || n2 < 0 {
            return Err(Fault::Operation);
        }
        let w = &mut self.clocks.words(cx.shared)[self.clock * CLOCK_WORDS..];
        w[0] = 1;
        w[1] = n1 as u32;
        w[2] = n2 as u32;
        Ok(())
    }
}

/// END: each clock DUTY set drives its relay, then counts the scan.
pub(crate) fn end(mem: &mut DeviceMemory, shared: &mut [u32]) {
    let slot = CpuSlot::<UserClocks>::new();
    if (slot.end() as usize) > shared.len() {
        // No program uses DUTY.
        return;
    }
    for (k, w) in slot.words(shared).chunks_exact_mut(CLOCK_WORDS).enumerate() {
        if w[0] == 0 {
            continue;
        }
        let (on, off, count) = (w[1], w[2], w[3]);
        let period = (on + off).max(1);
        let v = on > 0 && (off == 0 || count % period < on);
        let n = if k < 5 { 420 + k } else { 425 + k };
        let _ = mem.set_bit(DeviceKind::SM, n as i64, v);
        w[3] = count.wrapping_add(1);
    }
}
