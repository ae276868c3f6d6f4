//! Sequence instructions: coils on general operands, timers and counters
//! (programming manual ch. 5; timer and counter behaviour per 004 §10.2.10-10.2.11).

use crate::device::DeviceMemory;
use crate::fault::Fault;
use crate::instr::{ExecCtx, Instr};
use crate::ops::{Coil, CoilKind, Counter, ResetTc, Timer};

/// OUT/SET/RST/PLS/PLF/FF on a general bit operand. `cond` is the rung condition.
#[inline]
pub fn coil(mem: &mut DeviceMemory, edges: &mut [bool], c: &Coil, cond: bool) -> Result<(), Fault> {
    match c.kind {
        CoilKind::Out => mem.write_bit(&c.dst, cond),
        CoilKind::Set if cond => mem.write_bit(&c.dst, true),
        CoilKind::Rst if cond => mem.write_bit(&c.dst, false),
        CoilKind::Set | CoilKind::Rst => Ok(()),
        // PLS: ON for one scan from the rising edge of the condition.
        CoilKind::Pls(s) => {
            let rising = cond && !edges[s as usize];
            edges[s as usize] = cond;
            mem.write_bit(&c.dst, rising)
        }
        // PLF: ON for one scan from the falling edge.
        CoilKind::Plf(s) => {
            let falling = !cond && edges[s as usize];
            edges[s as usize] = cond;
            mem.write_bit(&c.dst, falling)
        }
        // FF: inverts the device on the rising edge.
        CoilKind::Ff(s) => {
            let rising = cond && !edges[s as usize];
            edges[s as usize] = cond;
            if rising {
                let v = mem.read_bit(&c.dst)?;
                mem.write_bit(&c.dst, !v)?;
            }
            Ok(())
        }
    }
}

/// `OUT T`/`OUTH T`/`OUT ST`: 004 §10.2.10. Coil, current value and contact are
/// all processed here, never at END.
///
/// When the coil is ON at execution, the scan time measured at the previous END
/// (`scan_us`) is added to the current value (004 L6474-6490). Decision (the
/// timing figure is lost): the execution that turns the coil ON adds nothing, so
/// counting starts at the next execution, as on MELSEC CPUs of this generation;
/// the part of the scan time below one time-base unit is carried in `rem`.
/// Set value 0 turns the contact ON at once; a timer already timed out stays
/// timed out when its set value is raised (L6505-6510). A negative set value from a
/// word device is an operation error.
#[inline]
pub fn timer(
    mem: &mut DeviceMemory,
    rem: &mut [u32],
    base_us: u32,
    scan_us: u32,
    t: &Timer,
    cond: bool,
) -> Result<(), Fault> {
    let (coil, contact, value) = (t.coil as usize, t.contact as usize, t.value as usize);
    let slot = t.slot as usize;
    if !cond {
        mem.bits[coil] = false;
        if !t.retentive {
            mem.words[value] = 0;
            mem.bits[contact] = false;
            rem[slot] = 0;
        }
        return Ok(());
    }
    let set = mem.read16(&t.set)? as i16;
    if set < 0 {
        return Err(crate::fault::Fault::Operation);
    }
    let was_on = mem.bits[coil];
    mem.bits[coil] = true;
    if mem.bits[contact] {
        return Ok(());
    }
    let mut cur = mem.words[value] as i16 as i32;
    if was_on {
        let total = rem[slot] as u64 + scan_us as u64;
        if total < base_us as u64 {
            // Less than one unit so far (a 100 ms timer in 10 ms scans): no
            // division, which costs more than the rest of the timer.
            rem[slot] = total as u32;
        } else {
            let units = total / base_us as u64;
            rem[slot] = (total % base_us as u64) as u32;
            cur = (cur as i64 + units as i64).min(32767) as i32;
        }
    }
    if cur >= set as i32 {
        cur = set as i32;
        mem.bits[contact] = true;
    }
    mem.words[value] = cur as u16;
    Ok(())
}

/// `OUT C`: 004 §10.2.11. Counts +1 on the rising edge of the coil; the contact
/// turns ON when the count reaches the set value, after which counting stops. The
/// current value is kept when the coil goes OFF. Set value 0 is processed as 1
/// (MELSEC behaviour: the contact turns ON at the first count, never before).
#[inline]
pub fn counter(mem: &mut DeviceMemory, c: &Counter, cond: bool) -> Result<(), Fault> {
    let set = mem.read16(&c.set)? as i16;
    if set < 0 {
        return Err(crate::fault::Fault::Operation);
    }
    let set = set.max(1);
    let (coil, contact, value) = (c.coil as usize, c.contact as usize, c.value as usize);
    let rising = cond && !mem.bits[coil];
    mem.bits[coil] = cond;
    let mut cur = mem.words[value] as i16 as i32;
    if rising && !mem.bits[contact] && cur < 32767 {
        cur += 1;
    }
    if cur >= set as i32 {
        mem.bits[contact] = true;
    }
    mem.words[value] = cur as u16;
    Ok(())
}

/// `RST T`/`RST C` (PM §5.3): clears the current value and the contact at
/// once, and a timer's sub-unit remainder.
impl Instr for ResetTc {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.mem.words[self.value as usize] = 0;
        cx.mem.bits[self.contact as usize] = false;
        if self.slot != u32::MAX {
            cx.cpu.reset_timer(self.slot);
        }
        Ok(())
    }

    fn word_op(&self) -> Option<crate::word_op::WordOp<'_>> {
        Some(crate::word_op::WordOp::ResetTc(self))
    }
}
