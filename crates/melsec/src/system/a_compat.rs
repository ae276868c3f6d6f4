//! The A-series compatibility area (004 App. 1 (9) L9760-9927, App. 2 (9)
//! L10697-10865): SM1000-SM1255 and SD1000-SD1255 hold what a converted
//! A-series program reads in M9000-M9255 / D9000-D9255. The parameter "A-series
//! CPU compatibility" (004 L5831) is ON by default; plc.toml `[cpu]
//! a_compatibility = false` turns it off, and these devices are then plain
//! memory.
//!
//! The devices are set by the system only (L9762-9765): each one that has a
//! Q device softplc maintains is copied from it when the Q device is written
//! — at scan start for the always-ON/OFF, first-scan and clock relays
//! ([`AT_SCAN_START`]), at END for the rest ([`AT_END`]), and again when an
//! error is reported or cleared; SD1015 also when the operating status
//! changes. SM1034 (the 1-minute clock, L9812-9815) has no Q equivalent
//! and is computed here; the clock data SD1025-SD1028 with its requests
//! SM1025/SM1026/SM1028 is the clock registers' A-series set ([`super::clock::A_SERIES`]).
//! SD1010 (D9010, L10743), the step of the latest operation error, is
//! written when the error is reported ([`operation_error`]).

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::system::{ErrorReport, ScanStart, Severity};

use super::devices::{bcd, sd, Sys};

/// How the Q value becomes the A-series value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Conv {
    /// The same value.
    Same,
    /// A time in ms as 10 ms units (SD1017-SD1019).
    TenMs,
    /// A binary value as BCD (SD1035: the A-series block number is BCD).
    Bcd,
}

/// One A-series device and the Q device it mirrors.
#[derive(Clone, Copy, Debug)]
pub struct Mirror {
    /// SM (relay) or SD (register).
    pub relay: bool,
    /// The A-series compatible number (SM1036 for M9036).
    pub a: u32,
    /// The Q device it is copied from.
    pub q: u32,
    pub conv: Conv,
}

const fn relay(a: u32, q: u32) -> Mirror {
    Mirror {
        relay: true,
        a,
        q,
        conv: Conv::Same,
    }
}

const fn register(a: u32, q: u32, conv: Conv) -> Mirror {
    Mirror {
        relay: false,
        a,
        q,
        conv,
    }
}

/// The relays copied at scan start, right after their Q relays are set
/// (the always-ON/OFF, first-scan and clock relays). A table of its own so
/// that each copy walks only its own entries.
pub static AT_SCAN_START: &[Mirror] = &[
    // 0.1 s, 0.2 s, 1 s, 2 s clocks (L9812-9815).
    relay(1030, 410),
    relay(1031, 411),
    relay(1032, 412),
    relay(1033, 413),
    relay(1036, 400), // always ON
    relay(1037, 401), // always OFF
    relay(1038, 402), // ON one scan after RUN
    relay(1039, 403), // RUN flag: OFF one scan after RUN
];

/// SD1015, the operating status: the mirror of SD203.
const OPERATING_STATUS: Mirror = register(1015, 203, Conv::Same);

/// The devices copied at END (and when an error is reported or cleared),
/// per the tables' "special relay/register for modification" column and
/// each row's description.
pub static AT_END: &[Mirror] = &[
    relay(1006, 52),  // battery low
    relay(1007, 51),  // battery low, latched
    relay(1008, 1),   // self-diagnostic error
    relay(1009, 62),  // annunciator detected
    relay(1011, 56),  // operation error
    relay(1012, 700), // carry
    // User timing clocks (M9020-M9024 = DUTY's clocks 0-4).
    relay(1020, 420),
    relay(1021, 421),
    relay(1022, 422),
    relay(1023, 423),
    relay(1024, 424),
    relay(1043, 805),               // sampling trace complete
    relay(1047, 801),               // sampling trace start (also an input: `TRACE_START`)
    relay(1044, 803),               // sampling trace trigger
    relay(1046, 802),               // sampling trace executing
    relay(1049, 701),               // characters output: 16 / up to NUL
    register(1008, 0, Conv::Same),  // self-diagnostic error code
    register(1009, 62, Conv::Same), // first annunciator
    OPERATING_STATUS,
    // Scan time min/current/max in 10 ms units and current in 1 ms. The
    // manual's modification column pairs SD1017 with SD520 and SD1018 with
    // SD524, but its descriptions say SD1017 is the minimum and SD1018 the
    // current scan time: SD524 is Q's minimum, SD520 its current.
    register(1017, 524, Conv::TenMs),
    register(1018, 520, Conv::TenMs),
    register(1019, 526, Conv::TenMs),
    register(1021, 520, Conv::Same),
    register(1022, 412, Conv::Same), // 1 s counter
    register(1035, 648, Conv::Bcd),  // file-register block number
    register(1038, 207, Conv::Same), // LED display priority 1-4
    register(1039, 208, Conv::Same), // LED display priority 5-8
    register(1124, 63, Conv::Same),  // annunciators detected
    register(1125, 64, Conv::Same),  // annunciator numbers in order
    register(1126, 65, Conv::Same),
    register(1127, 66, Conv::Same),
    register(1128, 67, Conv::Same),
    register(1129, 68, Conv::Same),
    register(1130, 69, Conv::Same),
    register(1131, 70, Conv::Same),
    register(1132, 71, Conv::Same),
];

/// Every A-series device copied from a Q device.
pub fn mirrors() -> impl Iterator<Item = &'static Mirror> {
    AT_SCAN_START.iter().chain(AT_END).chain(AT_REMOTE)
}

/// SM1047 (M9047), SM801's A-series name: a converted program starts and
/// aborts the sampling trace with it (L9835), so a change the program made
/// since the last END is copied to SM801 before SM801 is mirrored back
/// ([`trace_start`]).
pub const TRACE_START: u32 = 1047;

/// At END, before the mirrors: SM1047 changed since the last END (`before`,
/// its value after that END's mirrors) turns SM801 the same way.
pub(crate) fn trace_start(sys: &mut Sys<'_>, before: bool) {
    let a = sys.sm(TRACE_START);
    if a != before {
        sys.set_sm(801, a);
    }
}

/// SM1034: the 1-minute clock, computed as the Q clocks are (OFF at
/// power-on, toggling every 30 s).
pub const MINUTE_CLOCK: u32 = 1034;

/// One past the highest SM/SD number any table reads or writes: a CPU
/// with at least these points takes the copies of [`Flat`] tables.
const SPAN: u32 = {
    let tables: [&[Mirror]; 3] = [AT_SCAN_START, AT_END, AT_REMOTE];
    let mut hi = 0;
    let mut t = 0;
    while t < tables.len() {
        let mut i = 0;
        while i < tables[t].len() {
            let m = tables[t][i];
            if m.a >= hi {
                hi = m.a + 1;
            }
            if m.q >= hi {
                hi = m.q + 1;
            }
            i += 1;
        }
        t += 1;
    }
    hi
};

/// A table of mirrors sorted into plain relay and register copies (A, Q
/// numbers) and converted registers, made at compile time: the copies at
/// every scan start and END then test no kind or conversion per device.
struct Flat<const R: usize, const W: usize, const C: usize> {
    relays: [(u16, u16); R],
    registers: [(u16, u16); W],
    converted: [Mirror; C],
}

/// Of `table`: its relays, plain registers and converted registers.
const fn counts(table: &[Mirror]) -> (usize, usize, usize) {
    let (mut r, mut w, mut c) = (0, 0, 0);
    let mut i = 0;
    while i < table.len() {
        match (table[i].relay, table[i].conv) {
            (true, _) => r += 1,
            (false, Conv::Same) => w += 1,
            _ => c += 1,
        }
        i += 1;
    }
    (r, w, c)
}

impl<const R: usize, const W: usize, const C: usize> Flat<R, W, C> {
    const fn of(table: &[Mirror]) -> Self {
        let mut f = Flat {
            relays: [(0, 0); R],
            registers: [(0, 0); W],
            converted: [relay(0, 0); C],
        };
        let (mut r, mut w, mut c) = (0, 0, 0);
        let mut i = 0;
        while i < table.len() {
            let m = table[i];
            match (m.relay, m.conv) {
                (true, _) => {
                    f.relays[r] = (m.a as u16, m.q as u16);
                    r += 1;
                }
                (false, Conv::Same) => {
                    f.registers[w] = (m.a as u16, m.q as u16);
                    w += 1;
                }
                _ => {
                    f.converted[c] = m;
                    c += 1;
                }
            }
            i += 1;
        }
        f
    }

    /// The copies, in SM and SD of at least [`SPAN`] points.
    #[inline]
    fn copy(&self, sm: &mut [bool], sd: &mut [u16]) {
        for &(a, q) in &self.relays {
            sm[a as usize] = sm[q as usize];
        }
        for &(a, q) in &self.registers {
            sd[a as usize] = sd[q as usize];
        }
        for m in &self.converted {
            sd[m.a as usize] = convert(sd[m.q as usize], m.conv);
        }
    }
}

const START_N: (usize, usize, usize) = counts(AT_SCAN_START);
static START_FLAT: Flat<{ START_N.0 }, { START_N.1 }, { START_N.2 }> = Flat::of(AT_SCAN_START);
const END_N: (usize, usize, usize) = counts(AT_END);
static END_FLAT: Flat<{ END_N.0 }, { END_N.1 }, { END_N.2 }> = Flat::of(AT_END);
const REMOTE_N: (usize, usize, usize) = counts(AT_REMOTE);
static REMOTE_FLAT: Flat<{ REMOTE_N.0 }, { REMOTE_N.1 }, { REMOTE_N.2 }> = Flat::of(AT_REMOTE);

/// Copies `mirrors` (the table `flat` was made of) into SM/SD: the flat
/// copies when the CPU has [`SPAN`] points of each (the usual 2048).
fn copy_flat<const R: usize, const W: usize, const C: usize>(
    sys: &mut Sys<'_>,
    flat: &Flat<R, W, C>,
    mirrors: &[Mirror],
) {
    let span = SPAN as usize;
    if sys.sm.len() >= span && sys.sd.len() >= span {
        flat.copy(&mut sys.sm[..span], &mut sys.sd[..span]);
    } else {
        copy(sys, mirrors);
    }
}

/// The copies of `mirrors` checked device by device (a CPU with fewer
/// SM/SD points skips those it lacks).
fn copy(sys: &mut Sys<'_>, mirrors: &[Mirror]) {
    let (sm_n, sd_n) = (sys.sm.len() as u32, sys.sd.len() as u32);
    for m in mirrors {
        if m.relay {
            if m.a < sm_n && m.q < sm_n {
                sys.sm[m.a as usize] = sys.sm[m.q as usize];
            }
        } else if m.a < sd_n && m.q < sd_n {
            let v = sys.sd[m.q as usize];
            sys.sd[m.a as usize] = convert(v, m.conv);
        }
    }
}

/// The A-series value of Q value `v`.
#[inline]
fn convert(v: u16, conv: Conv) -> u16 {
    match conv {
        Conv::Same => v,
        Conv::TenMs => v / 10,
        Conv::Bcd => bcd(v as u32 % 100) | bcd(v as u32 / 100 % 100) << 8,
    }
}

/// The A-series PAUSE and STOP contacts, M9041 = SM204 and M9042 = SM203,
/// after the remote-operation relays are written.
pub(crate) fn remote(sys: &mut Sys<'_>) {
    copy_flat(sys, &REMOTE_FLAT, AT_REMOTE);
}

/// The relays copied when the remote-operation relays are written.
pub static AT_REMOTE: &[Mirror] = &[relay(1041, 204), relay(1042, 203)];

/// M9040 (SM1040), the A-series PAUSE enable: a converted program sets it
/// where a Q program sets SM206 (004 App. 1 SM1040 = SM206).
pub(crate) fn pause_enabled(mem: &DeviceMemory) -> bool {
    mem.get_bit(DeviceKind::SM, 1040).unwrap_or(false)
}

/// After the Q scan-start relays: the always-ON/OFF, first-scan and clock
/// relays, and the 1-minute clock.
pub(crate) fn scan_start(sys: &mut Sys<'_>, s: ScanStart) {
    copy_flat(sys, &START_FLAT, AT_SCAN_START);
    sys.set_sm(MINUTE_CLOCK, (s.since_power_on_us / 30_000_000) & 1 == 1);
}

/// After END processing, an error report or clear, a status change.
pub(crate) fn refresh(sys: &mut Sys<'_>) {
    copy_flat(sys, &END_FLAT, AT_END);
}

/// After the operating status changed (also in STOP, where no END runs):
/// SD1015, the only A-series device SD203 feeds.
pub(crate) fn status(sys: &mut Sys<'_>) {
    let m = OPERATING_STATUS;
    let v = sys.sd(m.q);
    sys.set_sd(m.a, v);
}

/// SD1010 (D9010): the step of an operation error, in binary, updated at
/// each one (004 App. 2 L10743); the low 16 bits of a larger step.
pub const OPERATION_ERROR_STEP: u32 = 1010;

/// After an error is reported: an operation error located at a step
/// writes its step into SD1010.
pub(crate) fn operation_error(mem: &mut DeviceMemory, r: &ErrorReport<'_>) {
    if super::codes::severity(r.code) != Severity::Operation {
        return;
    }
    if let Some(step) = r.step {
        sd(mem, OPERATION_ERROR_STEP as i64, step as u16);
    }
}
