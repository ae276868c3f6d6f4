//! The clock registers at END (qcpu.md §4.4): SM210 OFF→ON writes
//! SD210-SD213 (BCD) to the clock, SM211 flags invalid data; while SM213 is
//! ON the clock is read into SD210-SD213. SD210 = year (2 digits) | month,
//! SD211 = day | hour, SD212 = minute | second, SD213 = year's first 2
//! digits | day of week.
//!
//! The A-series compatibility area has the same registers on its own
//! numbers (004 App. 1 (9), App. 2 (9)): SM1025 OFF→ON writes SD1025-SD1028,
//! SM1026 flags invalid data, SM1028 ON reads the clock into SD1025-SD1028;
//! SD1028 holds the day of week only (its upper digits must be 0), so a
//! 2-digit year 80-99 is 19xx, else 20xx.

use super::devices::{bcd, from_bcd, Sys};
use softplc_ir::calendar::{DateTime, PlcClock};

/// One set of clock registers: its relays, its first register and whether
/// its fourth register holds the century.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Registers {
    pub set: u32,
    pub error: u32,
    pub read: u32,
    pub first: u32,
    pub century: bool,
}

/// SM210/SM211/SM213, SD210-SD213.
pub(crate) const Q: Registers = Registers {
    set: 210,
    error: 211,
    read: 213,
    first: 210,
    century: true,
};

/// SM1025/SM1026/SM1028, SD1025-SD1028.
pub(crate) const A_SERIES: Registers = Registers {
    set: 1025,
    error: 1026,
    read: 1028,
    first: 1025,
    century: false,
};

/// The clock registers `regs`; `set_before` is the set request at the
/// previous END. Returns the set request.
#[inline]
pub(crate) fn registers(
    sys: &mut Sys<'_>,
    regs: Registers,
    clock: &mut PlcClock,
    now_us: u64,
    set_before: bool,
) -> bool {
    let set = sys.sm(regs.set);
    if set && !set_before {
        let r = |n| sys.sd(regs.first + n);
        let (a, b, c, d) = (r(0), r(1), r(2), r(3));
        let d = if regs.century { d } else { d & 0xFF };
        let f = |w: u16| (from_bcd(w >> 8), from_bcd(w & 0xFF));
        let ((yy, mo), (dd, hh), (mi, ss), (cc, _)) = (f(a), f(b), f(c), f(d));
        let t = (|| {
            let century = match cc? {
                0 => {
                    if yy? >= 80 {
                        19
                    } else {
                        20
                    }
                }
                c => c,
            };
            Some(DateTime {
                year: (century * 100 + yy?) as i32,
                month: mo?,
                day: dd?,
                hour: hh?,
                minute: mi?,
                second: ss?,
            })
        })();
        match t.filter(DateTime::is_valid) {
            Some(t) => {
                clock.set(t, now_us);
                sys.set_sm(regs.error, false);
            }
            None => sys.set_sm(regs.error, true),
        }
    }
    if sys.sm(regs.read) {
        let t = clock.now(now_us);
        let y = t.year as u32;
        let century = if regs.century { bcd(y / 100) << 8 } else { 0 };
        sys.set_sd(regs.first, bcd(y % 100) << 8 | bcd(t.month));
        sys.set_sd(regs.first + 1, bcd(t.day) << 8 | bcd(t.hour));
        sys.set_sd(regs.first + 2, bcd(t.minute) << 8 | bcd(t.second));
        sys.set_sd(regs.first + 3, century | t.weekday() as u16);
    }
    set
}
