//! Low-speed program execution's system devices (004 §4.2.3): SM404/SM405
//! the low-speed first-scan pulses, SM510 ON and SD510 the program number
//! while one runs, SM330 ON for synchronous execution, SD528-SD535 the
//! low-speed scan times and SD430 the low-speed scan counter.

use softplc_ir::device::DeviceMemory;
use softplc_ir::system::LowSpeed;

use super::devices::{sd, sd_get, sm, sm_get, time_pair};

pub(crate) fn event(mem: &mut DeviceMemory, e: LowSpeed) {
    match e {
        LowSpeed::Pass { first } => {
            sm(mem, 404, first);
            sm(mem, 405, !first);
        }
        LowSpeed::Running(Some(slot)) => {
            sm(mem, 510, true);
            sd(mem, 510, slot as u16 + 1);
        }
        LowSpeed::Running(None) => sm(mem, 510, false),
        LowSpeed::End(t) => {
            time_pair(mem, 528, t.current_us);
            time_pair(mem, 532, t.min_us);
            time_pair(mem, 534, t.max_us);
            let c = sd_get(mem, 430).wrapping_add(1);
            sd(mem, 430, c);
        }
    }
}

/// SM330 ON: synchronous, at most one low-speed cycle a scan.
pub(crate) fn synchronous(mem: &DeviceMemory) -> bool {
    sm_get(mem, 330)
}
