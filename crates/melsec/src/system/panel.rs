//! The CPU's front panel (004 §7.19, App. 1, App. 2): SD200 the switch,
//! SD201 the LEDs, SM202/SD202 the LED OFF command, SD207-SD209 the LED
//! display priority, and which cause LEDR turns off.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::ErrorCode;
use softplc_ir::system::{Panel, Status};

use super::codes::{self, ANNUNCIATOR};
use super::devices::{sd, Sys};

/// The panel's words at the end of the system's state
/// ([`softplc_ir::system::EndCtx::state`]): SM202 at the previous showing
/// (its OFF→ON edge), and the annunciator list when the USER LED was turned
/// off (0 while it is not).
pub(crate) const STATE_WORDS: usize = 2;

/// The default LED display priority (L5392-5406): cause numbers 1-4 in
/// SD207, 5-8 in SD208, 9 and A in SD209, priority 1 in the lowest digit.
const PRIORITY: [u16; 3] = [0x4321, 0x8765, 0x00A9];

/// Cause numbers of the annunciators and of BATTERY ERROR in the priority
/// table.
const CAUSE_ANNUNCIATOR: u8 = 7;
const CAUSE_BATTERY: u8 = 9;

/// Power-on: the default LED display priority.
pub(crate) fn power_on(mem: &mut DeviceMemory) {
    for (i, v) in PRIORITY.iter().enumerate() {
        sd(mem, 207 + i as i64, *v);
    }
}

/// The rank of cause `cause` in SD207-SD209 (0 the highest), `None` when
/// no digit holds it: its LED does not light (L5408-5418).
fn rank(sys: &Sys<'_>, cause: u8) -> Option<usize> {
    (0..10).find(|&k| {
        let word = sys.sd(207 + k as u32 / 4);
        (word >> (4 * (k % 4)) & 0xF) as u8 == cause
    })
}

/// The latest error (SD0 while SM0 is ON) when it is no annunciator.
fn error(sys: &Sys<'_>) -> Option<ErrorCode> {
    let code = ErrorCode(sys.sd(0));
    (sys.sm(0) && code != ANNUNCIATOR).then_some(code)
}

/// The rank of the latest error's cause, when shown.
fn error_rank(sys: &Sys<'_>) -> Option<usize> {
    rank(sys, codes::led_cause(error(sys)?)?)
}

/// LEDR turns off the cause shown first: the latest continuation error
/// when it ranks above the annunciators (or none is ON), else the first
/// annunciator (004 §10.2.4 L6294-6297, §7.19.1 (2)). True: clear the error.
pub(crate) fn ledr_clears_error(mem: &mut DeviceMemory) -> bool {
    let sys = Sys::of(mem);
    let Some(e) = error_rank(&sys) else {
        return false;
    };
    if !sys.sm(62) {
        return true;
    }
    rank(&sys, CAUSE_ANNUNCIATOR).is_none_or(|a| e < a)
}

/// The LED values of SD201: 0 OFF, 1 ON, 2 flashing.
const OFF: u16 = 0;
const ON: u16 = 1;
const FLASHING: u16 = 2;

/// SD200 switch status: b0-b3 0 RUN, 1 STOP (L.CLR is not modelled), the
/// memory card switch (b4) and the DIP switches (b8-b12) OFF (L10318-10329).
///
/// SD201 LED status, two bits an LED: RUN b0-b1, ERROR b2-b3, USER b4-b5,
/// BAT. b6-b7, BOOT b8-b9, MODE b14-b15, 0 OFF, 1 ON, 2 flashing (the
/// manual in hand has lost the figure; this is the QCPU layout):
/// - RUN ON in RUN, else OFF (the LED table names no PAUSE state);
/// - ERROR flashing on a stop error, ON with a continuation error (not the
///   battery's) whose cause SD207-SD209 show;
/// - USER ON while an annunciator is ON and shown, until SM202 turns it off
///   (SD202 b4) and no annunciator turns ON after;
/// - BAT. ON with BATTERY ERROR (SM52) when shown; BOOT OFF (no boot);
/// - MODE ON (Q mode), flashing while forced I/O is registered (L4237).
///
/// SM202 OFF→ON turns off the LEDs SD202 names: b4 USER, b8 BOOT (L5356-5370).
pub(crate) fn show(mem: &mut DeviceMemory, state: &mut [u32], p: Panel) {
    let mut sys = Sys::of(mem);
    sys.set_sd(200, p.switch_stop as u16);
    let user_off = user_led_off(&sys, state);
    let run = if p.status == Status::Run { ON } else { OFF };
    let shown = |c: u8| rank(&sys, c).is_some();
    let error = if p.stop_error {
        FLASHING
    } else {
        match error(&sys).and_then(codes::led_cause) {
            Some(c) if c != CAUSE_BATTERY && shown(c) => ON,
            _ => OFF,
        }
    };
    let user = if sys.sm(62) && shown(CAUSE_ANNUNCIATOR) && !user_off {
        ON
    } else {
        OFF
    };
    let bat = if sys.sm(52) && shown(CAUSE_BATTERY) {
        ON
    } else {
        OFF
    };
    let mode = if p.forced { FLASHING } else { ON };
    sys.set_sd(201, run | error << 2 | user << 4 | bat << 6 | mode << 14);
}

/// The USER LED is turned off: SM202's OFF→ON edge with SD202 b4 turns it
/// off and remembers the annunciator list (SD62, SD63); a change of the
/// list (an annunciator turning ON or OFF) lets it light again.
fn user_led_off(sys: &Sys<'_>, state: &mut [u32]) -> bool {
    let [.., sm202_before, off] = state else {
        return false;
    };
    let sm202 = sys.sm(202);
    let list = 1 << 31 | (sys.sd(63) as u32) << 16 | sys.sd(62) as u32;
    if sm202 && *sm202_before == 0 && sys.sd(202) & 0x10 != 0 {
        *off = list;
    } else if *off != list {
        *off = 0;
    }
    *sm202_before = sm202 as u32;
    *off != 0
}
