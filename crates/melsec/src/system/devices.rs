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

/// SM and SD as two slices, their places looked up once: what scan start
/// and END read and write dozens of. A number the CPU's points lack reads
/// OFF/0 and is not written, as with [`sm`] and [`sd`].
pub(crate) struct Sys<'a> {
    pub sm: &'a mut [bool],
    pub sd: &'a mut [u16],
}

impl<'a> Sys<'a> {
    pub(crate) fn of(mem: &'a mut DeviceMemory) -> Sys<'a> {
        let map = &mem.map;
        let (sm_at, sm_n) = (map.base(DeviceKind::SM), map.points(DeviceKind::SM));
        let (sd_at, sd_n) = (map.base(DeviceKind::SD), map.points(DeviceKind::SD));
        let (sm_at, sd_at) = (sm_at as usize, sd_at as usize);
        Sys {
            sm: &mut mem.bits[sm_at..sm_at + sm_n as usize],
            sd: &mut mem.words[sd_at..sd_at + sd_n as usize],
        }
    }

    /// SM`first`-SM`first + N - 1` as an array when the CPU has them all:
    /// writes at constant places in it need no check each.
    #[inline]
    pub(crate) fn sm_window<const N: usize>(&mut self, first: usize) -> Option<&mut [bool; N]> {
        self.sm.get_mut(first..first + N)?.try_into().ok()
    }

    /// SD`first`-SD`first + N - 1` as an array, as [`Sys::sm_window`].
    #[inline]
    pub(crate) fn sd_window<const N: usize>(&mut self, first: usize) -> Option<&mut [u16; N]> {
        self.sd.get_mut(first..first + N)?.try_into().ok()
    }

    #[inline]
    pub(crate) fn sm(&self, n: u32) -> bool {
        self.sm.get(n as usize).copied().unwrap_or(false)
    }

    #[inline]
    pub(crate) fn set_sm(&mut self, n: u32, v: bool) {
        if let Some(b) = self.sm.get_mut(n as usize) {
            *b = v;
        }
    }

    #[inline]
    pub(crate) fn sd(&self, n: u32) -> u16 {
        self.sd.get(n as usize).copied().unwrap_or(0)
    }

    #[inline]
    pub(crate) fn set_sd(&mut self, n: u32, v: u16) {
        if let Some(w) = self.sd.get_mut(n as usize) {
            *w = v;
        }
    }
}
