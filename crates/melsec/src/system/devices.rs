//! Reading and writing MELSEC's special relays (SM) and registers (SD) by
//! number (004 App. 1, App. 2); a number the CPU's points lack is skipped.

use softplc_ir::device::{DeviceKind, DeviceMemory};

pub(crate) fn sm(mem: &mut DeviceMemory, n: i64, v: bool) {
    let _ = mem.set_bit(DeviceKind::SM, n, v);
}

pub(crate) fn sm_get(mem: &DeviceMemory, n: i64) -> bool {
    mem.get_bit(DeviceKind::SM, n).unwrap_or(false)
}

pub(crate) fn sd(mem: &mut DeviceMemory, n: i64, v: u16) {
    let _ = mem.set_word(DeviceKind::SD, n, v);
}

pub(crate) fn sd_get(mem: &DeviceMemory, n: i64) -> u16 {
    mem.get_word(DeviceKind::SD, n).unwrap_or(0)
}

/// Several relays at once (what every scan writes): SM's place looked up
/// once, not per relay.
pub(crate) fn sm_many(mem: &mut DeviceMemory, relays: &[(u32, bool)]) {
    let (at, n) = (mem.map.base(DeviceKind::SM), mem.map.points(DeviceKind::SM));
    let sm = &mut mem.bits[at as usize..(at + n) as usize];
    for &(r, v) in relays {
        if let Some(b) = sm.get_mut(r as usize) {
            *b = v;
        }
    }
}

/// Several registers at once, as [`sm_many`].
pub(crate) fn sd_many(mem: &mut DeviceMemory, registers: &[(u32, u16)]) {
    let (at, n) = (mem.map.base(DeviceKind::SD), mem.map.points(DeviceKind::SD));
    let sd = &mut mem.words[at as usize..(at + n) as usize];
    for &(r, v) in registers {
        if let Some(w) = sd.get_mut(r as usize) {
            *w = v;
        }
    }
}

/// Splits a time into the ms register and the 100 µs-resolution µs register
/// (SD520=23, SD521=600 for 23.6 ms, L10445-10447).
pub(crate) fn ms_us(us: u64) -> (u16, u16) {
    (
        (us / 1000).min(u16::MAX as u64) as u16,
        ((us % 1000) / 100 * 100) as u16,
    )
}

/// A time into register pair `reg` (ms), `reg + 1` (µs).
pub(crate) fn time_pair(mem: &mut DeviceMemory, reg: i64, us: u64) {
    let (ms, sub) = ms_us(us);
    sd(mem, reg, ms);
    sd(mem, reg + 1, sub);
}

pub(crate) fn bcd(v: u32) -> u16 {
    (((v / 10 % 10) << 4) | (v % 10)) as u16
}

pub(crate) fn from_bcd(b: u16) -> Option<u32> {
    let (hi, lo) = ((b >> 4) as u32, (b & 0xF) as u32);
    (hi < 10 && lo < 10).then_some(hi * 10 + lo)
}
