//! The clock registers at END (qcpu.md §4.4): SM210 OFF→ON writes
//! SD210-SD213 (BCD) to the clock, SM211 flags invalid data; while SM213 is
//! ON the clock is read into SD210-SD213. SD210 = year (2 digits) | month,
//! SD211 = day | hour, SD212 = minute | second, SD213 = year's first 2
//! digits | day of week.

use softplc_ir::calendar::{DateTime, PlcClock};
use softplc_ir::device::DeviceMemory;

use super::devices::{bcd, from_bcd, sd, sd_get, sm, sm_get};

/// The clock registers; `sm210_before` is SM210 at the previous END.
/// Returns SM210.
pub(crate) fn registers(
    mem: &mut DeviceMemory,
    clock: &mut PlcClock,
    now_us: u64,
    sm210_before: bool,
) -> bool {
    let sm210 = sm_get(mem, 210);
    if sm210 && !sm210_before {
        let r = |n| sd_get(mem, n);
        let (a, b, c, d) = (r(210), r(211), r(212), r(213));
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
                sm(mem, 211, false);
            }
            None => sm(mem, 211, true),
        }
    }
    if sm_get(mem, 213) {
        let t = clock.now(now_us);
        let y = t.year as u32;
        sd(mem, 210, bcd(y % 100) << 8 | bcd(t.month));
        sd(mem, 211, bcd(t.day) << 8 | bcd(t.hour));
        sd(mem, 212, bcd(t.minute) << 8 | bcd(t.second));
        sd(mem, 213, bcd(y / 100) << 8 | t.weekday() as u16);
    }
    sm210
}
