//! Special relays (SM) and special registers (SD) kept by the system
//! (004 App. 1 and App. 2; notes qcpu.md §6 and §8).

use super::CpuState;
use softplc_ir::calendar::{DateTime, PlcClock};
use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::system::Severity;

fn sm(mem: &mut DeviceMemory, n: i64, v: bool) {
    let _ = mem.set_bit(DeviceKind::SM, n, v);
}

fn sd(mem: &mut DeviceMemory, n: i64, v: u16) {
    let _ = mem.set_word(DeviceKind::SD, n, v);
}

fn sd_get(mem: &DeviceMemory, n: i64) -> u16 {
    mem.get_word(DeviceKind::SD, n).unwrap_or(0)
}

/// Power-on values: SD414/SD415 (2n-second and 2n-ms clock factors) default 30.
pub(crate) fn power_on(mem: &mut DeviceMemory) {
    sd(mem, 414, 30);
    sd(mem, 415, 30);
    // File registers (004 App. 2): SD640 drive (1 = memory card), SD647
    // capacity in K words, SD648 block number (0 after power-on).
    let zr = mem.map.points(DeviceKind::ZR);
    sd(mem, 640, 1);
    sd(mem, 647, (zr / 1024).min(u16::MAX as u32) as u16);
    sd(mem, softplc_ir::access::SD_R_BLOCK as i64, 0);
    // SD290-SD304: device points X Y M L B F SB V S T ST C D W SW.
    use DeviceKind::*;
    for (i, k) in [X, Y, M, L, B, F, SB, V, S, TS, STS, CS, D, W, SW]
        .iter()
        .enumerate()
    {
        let p = mem.map.points(*k);
        sd(mem, 290 + i as i64, p.min(u16::MAX as u32) as u16);
    }
}

/// Relays set before the program runs: SM400/401 always ON/OFF, SM402/403 the
/// first-scan pulses, and the clocks SM409-SM415. The clocks start OFF at power-on
/// and toggle every half period of the time since power-on (L9629-9638).
pub(crate) fn scan_start(mem: &mut DeviceMemory, since_power_on_us: u64, first_scan: bool) {
    sm(mem, 400, true);
    sm(mem, 401, false);
    sm(mem, 402, first_scan);
    sm(mem, 403, !first_scan);
    let t = since_power_on_us;
    let half = |us: u64| (t / us.max(1)) & 1 == 1;
    let n414 = (sd_get(mem, 414) as i16).max(1) as u64;
    let n415 = (sd_get(mem, 415) as i16).max(1) as u64;
    sm(mem, 409, half(5_000));
    sm(mem, 410, half(50_000));
    sm(mem, 411, half(100_000));
    sm(mem, 412, half(500_000));
    sm(mem, 413, half(1_000_000));
    sm(mem, 414, half(n414 * 1_000_000));
    sm(mem, 415, half(n415 * 1_000));
}

/// Scan times measured at END.
pub(crate) struct ScanTimes {
    pub current_us: u64,
    pub min_us: u64,
    pub max_us: u64,
    pub since_run_us: u64,
}

/// Splits a time into the ms register and the 100 µs-resolution µs register
/// (SD520=23, SD521=600 for 23.6 ms, L10445-10447).
pub(crate) fn ms_us(us: u64) -> (u16, u16) {
    (
        (us / 1000).min(u16::MAX as u64) as u16,
        ((us % 1000) / 100 * 100) as u16,
    )
}

/// END processing of the scan registers: SD520-SD527 scan times, SD420 scan
/// counter, SD412 one-second counter (both wrap 32767 → -32768 → 0).
pub(crate) fn end(mem: &mut DeviceMemory, t: ScanTimes) {
    for (reg, us) in [(520, t.current_us), (524, t.min_us), (526, t.max_us)] {
        let (ms, sub) = ms_us(us);
        sd(mem, reg, ms);
        sd(mem, reg + 1, sub);
    }
    let count = sd_get(mem, 420).wrapping_add(1);
    sd(mem, 420, count);
    sd(mem, 412, (t.since_run_us / 1_000_000) as u16);
}

/// SD203 operating status, b0-b3: 0 RUN, 1 STOP, 2 PAUSE.
pub(crate) fn set_status(mem: &mut DeviceMemory, state: CpuState) {
    let v = match state {
        CpuState::Run => 0,
        CpuState::Stop => 1,
        CpuState::Pause => 2,
    };
    let old = sd_get(mem, 203);
    sd(mem, 203, old & !0xF | v);
}

/// Error information (004 §7.20, App. 2): SM0/SM1 ON, SD0 the code, SM56 for
/// operation errors, SD4 = common-information category 4 (program error location),
/// SD5-SD10 the program file name (8 + "." + 3 characters, ASCII, low byte first),
/// SD14/SD15 the step number (low/high word).
pub(crate) fn report_error(
    mem: &mut DeviceMemory,
    code: ErrorCode,
    file: &str,
    step: Option<u32>,
    at: &DateTime,
) {
    sm(mem, 0, true);
    sm(mem, 1, true);
    // SD1-SD3: time of detection in BCD (year/month, day/hour, minute/second).
    let y = at.year as u32 % 100;
    sd(mem, 1, bcd(y) << 8 | bcd(at.month));
    sd(mem, 2, bcd(at.day) << 8 | bcd(at.hour));
    sd(mem, 3, bcd(at.minute) << 8 | bcd(at.second));
    if severity(code) == Severity::Operation {
        sm(mem, 56, true);
    }
    sd(mem, 0, code.0);
    let Some(step) = step else {
        sd(mem, 4, 0);
        return;
    };
    sd(mem, 4, 4);
    let stem = std::path::Path::new(file)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("")
        .to_ascii_uppercase();
    let mut name = [b' '; 8];
    for (d, s) in name.iter_mut().zip(stem.bytes().filter(u8::is_ascii)) {
        *d = s;
    }
    let ext = *b".QPG";
    for i in 0..4 {
        sd(
            mem,
            5 + i,
            u16::from_le_bytes([name[2 * i as usize], name[2 * i as usize + 1]]),
        );
    }
    sd(mem, 9, u16::from_le_bytes([ext[0], ext[1]]));
    sd(mem, 10, u16::from_le_bytes([ext[2], ext[3]]));
    sd(mem, 14, step as u16);
    sd(mem, 15, (step >> 16) as u16);
}

fn bcd(v: u32) -> u16 {
    (((v / 10 % 10) << 4) | (v % 10)) as u16
}

fn from_bcd(b: u16) -> Option<u32> {
    let (hi, lo) = ((b >> 4) as u32, (b & 0xF) as u32);
    (hi < 10 && lo < 10).then_some(hi * 10 + lo)
}

/// Clock registers at END (qcpu.md §4.4): SM210 OFF→ON writes SD210-SD213 (BCD) to
/// the clock, SM211 flags invalid data; while SM213 is ON the clock is read into
/// SD210-SD213. SD210 = year (2 digits) | month, SD211 = day | hour, SD212 =
/// minute | second, SD213 = year's first 2 digits | day of week. Returns SM210.
pub(crate) fn clock_registers(
    mem: &mut DeviceMemory,
    clock: &mut PlcClock,
    now_us: u64,
    sm210_before: bool,
) -> bool {
    let sm210 = mem.get_bit(DeviceKind::SM, 210).unwrap_or(false);
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
    if mem.get_bit(DeviceKind::SM, 213).unwrap_or(false) {
        let t = clock.now(now_us);
        let y = t.year as u32;
        sd(mem, 210, bcd(y % 100) << 8 | bcd(t.month));
        sd(mem, 211, bcd(t.day) << 8 | bcd(t.hour));
        sd(mem, 212, bcd(t.minute) << 8 | bcd(t.second));
        sd(mem, 213, bcd(y / 100) << 8 | t.weekday() as u16);
    }
    sm210
}

/// SD4 individual information 6 (the annunciator number in SD16) of an
/// annunciator's error 9000.
pub(crate) fn annunciator_detail(mem: &mut DeviceMemory, n: u32) {
    sd(mem, 4, 0x0600);
    sd(mem, 16, n as u16);
}

/// SM50 OFF→ON clears the continuation error whose code is in SD50; the lower
/// two digits are ignored (004 L5028-5055). Returns whether it cleared.
pub(crate) fn error_reset_requested(mem: &DeviceMemory) -> Option<u16> {
    mem.get_bit(DeviceKind::SM, 50)
        .ok()
        .filter(|on| *on)
        .map(|_| sd_get(mem, 50))
}

/// Clears the error registers SM0/SM1/SM56 and SD0-SD26.
pub(crate) fn clear_error(mem: &mut DeviceMemory) {
    sm(mem, 0, false);
    sm(mem, 1, false);
    sm(mem, 56, false);
    for n in 0..=26 {
        sd(mem, n, 0);
    }
}

/// User timing clocks (DUTY, SM420-SM424 and SM430-SM434): counted in scans at
/// END; ON for n1 scans then OFF for n2 scans. n1 = 0 keeps the clock OFF, n2 = 0
/// keeps it ON (PM DUTY).
pub(crate) fn user_clocks(mem: &mut DeviceMemory, duty: &mut [Option<(u16, u16, u32)>; 10]) {
    for (k, d) in duty.iter_mut().enumerate() {
        let Some((on, off, count)) = d else { continue };
        let period = (*on as u32 + *off as u32).max(1);
        let phase = *count % period;
        let v = *on > 0 && (*off == 0 || phase < *on as u32);
        let n = if k < 5 { 420 + k } else { 425 + k };
        sm(mem, n as i64, v);
        *count = count.wrapping_add(1);
    }
}

/// The MELSEC number of `fault` (004 §7.20; the codes of the QCPU User's
/// Manual (Hardware Design, Maintenance and Inspection)).
pub(crate) fn code(fault: Fault) -> ErrorCode {
    ErrorCode(match fault {
        Fault::Operation => 4100,
        Fault::Range => 4101,
        Fault::ForWithoutNext => 4200,
        Fault::NextWithoutFor => 4201,
        Fault::ForNesting => 4202,
        Fault::BreakWithoutFor => 4203,
        Fault::NoRet => 4211,
        Fault::RetInMain => 4212,
        Fault::CallNesting => 4213,
        Fault::NoIret => 4221,
        Fault::IretInMain => 4223,
        Fault::NoProgram => 2410,
        Fault::Watchdog => 5000,
        Fault::ScanOverrun => 5010,
        Fault::Battery => 1600,
        Fault::Annunciator => 9000,
        Fault::Family(c) => c.0,
    })
}

/// Operation errors follow the "operation error" parameter; BATTERY ERROR,
/// PRG.TIME OVER and annunciators keep the CPU running.
pub(crate) fn severity(code: ErrorCode) -> Severity {
    match code.0 {
        4100..=4199 => Severity::Operation,
        1600 | 5010 | 9000 => Severity::Continue,
        _ => Severity::Stop,
    }
}

/// The CPU's message for error `code`.
pub(crate) fn message(code: ErrorCode) -> &'static str {
    match code.0 {
        1600 => "BATTERY ERROR: battery-backed data lost (damaged state file)",
        2410 => "FILE OPE. ERROR: the specified program does not exist",
        4100 => "OPERATION ERROR: the instruction cannot process this data",
        4101 => "OPERATION ERROR: device range exceeded",
        4200 => "FOR NEXT ERROR: FOR without NEXT",
        4201 => "FOR NEXT ERROR: NEXT without FOR",
        4202 => "FOR NEXT ERROR: more than 16 FOR nesting levels",
        4203 => "FOR NEXT ERROR: BREAK without FOR",
        4211 => "CAN'T EXECUTE(P): no RET in the executed subroutine",
        4212 => "CAN'T EXECUTE(P): RET executed in the main program",
        4213 => "CAN'T EXECUTE(P): more than 16 CALL nesting levels",
        4221 => "CAN'T EXECUTE(I): no IRET in the executed interrupt program",
        4223 => "CAN'T EXECUTE(I): IRET executed outside an interrupt program",
        5000 => "WDT ERROR: scan time exceeded the watchdog",
        5010 => "PRG.TIME OVER: scan time exceeded the constant scan",
        9000 => "F****: annunciator ON",
        _ => "error",
    }
}
