//! The scan's system devices (004 App. 1, App. 2; qcpu.md §6, §8): power-on
//! values, the relays set before the programs run, the scan-time registers
//! at END and the operating status.

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::system::{Cause, End, Remote, ScanStart, Status};

use super::devices::{ms_us, sd, sm_get, Sys};
use super::R_BLOCK;

/// Power-on values: SD414/SD415 (2n-second and 2n-ms clock factors) default
/// 30; the file registers' SD648 block number 0 (the rest of them:
/// `file_register`); SD290-SD304 the device points of X Y M L B F SB V S T
/// ST C D W SW.
pub(crate) fn power_on(mem: &mut DeviceMemory) {
    sd(mem, 414, 30);
    sd(mem, 415, 30);
    sd(mem, R_BLOCK as i64, 0);
    use DeviceKind::*;
    for (i, k) in [X, Y, M, L, B, F, SB, V, S, TS, STS, CS, D, W, SW]
        .iter()
        .enumerate()
    {
        let p = mem.map.points(*k);
        sd(mem, 290 + i as i64, p.min(u16::MAX as u32) as u16);
    }
}

/// SM400/401 always ON/OFF, SM402/403 the first-scan pulses, and the clocks
/// SM409-SM415. The clocks start OFF at power-on and toggle every half
/// period of the time since power-on (L9629-9638).
pub(crate) fn scan_start(sys: &mut Sys<'_>, s: ScanStart) {
    let t = s.since_power_on_us;
    let half = |us: u64| (t / us.max(1)) & 1 == 1;
    let n414 = (sys.sd(414) as i16).max(1) as u64;
    let n415 = (sys.sd(415) as i16).max(1) as u64;
    let relays = [
        (400, true),
        (401, false),
        (402, s.first_scan),
        (403, !s.first_scan),
        (409, half(5_000)),
        (410, half(50_000)),
        (411, half(100_000)),
        (412, half(500_000)),
        (413, half(1_000_000)),
        (414, half(n414 * 1_000_000)),
        (415, half(n415 * 1_000)),
    ];
    match sys.sm_window::<16>(400) {
        Some(w) => relays.iter().for_each(|&(n, v)| w[n - 400] = v),
        None => relays.iter().for_each(|&(n, v)| sys.set_sm(n as u32, v)),
    }
}

/// SD522/SD523 the initial scan time; else SD520-SD527 the scan times, SD420
/// the scan counter, SD412 the one-second counter (both wrap 32767 → -32768
/// → 0), and the scan's split (App. 2 L10459-10478, each a ms word and a
/// 100 µs word 0-900 as SD520/SD521): SD540/SD541 END processing, SD542/SD543
/// the constant-scan wait, SD544/SD545 the low-speed programs' time in the
/// current low-speed cycle (0 after a low-speed END), SD546/SD547 the
/// low-speed programs' time in this scan, SD548/SD549 the scan programs'
/// (App. 2 prints the last pair as SD548/SD559, its list L1323 SD548/SD549).
pub(crate) fn end(sys: &mut Sys<'_>, e: End) {
    if e.initial {
        let (ms, sub) = ms_us(e.times.current_us);
        sys.set_sd(522, ms);
        sys.set_sd(523, sub);
        return;
    }
    let t = e.times;
    let s = e.split;
    let times = [
        (520, t.current_us),
        (524, t.min_us),
        (526, t.max_us),
        (540, s.end_us),
        (542, s.wait_us),
        (544, s.low_speed_cycle_us),
        (546, s.low_speed_us),
        (548, s.programs_us),
    ];
    match sys.sd_window::<30>(520) {
        Some(w) => times.iter().for_each(|&(reg, us)| {
            (w[reg - 520], w[reg - 519]) = ms_us(us);
        }),
        None => times.iter().for_each(|&(reg, us)| {
            let (ms, sub) = ms_us(us);
            sys.set_sd(reg as u32, ms);
            sys.set_sd(reg as u32 + 1, sub);
        }),
    }
    let count = sys.sd(420).wrapping_add(1);
    sys.set_sd(420, count);
    sys.set_sd(412, (e.since_run_us / 1_000_000) as u16);
}

/// SD203 operating status (App. 2 L10333): b0-b3 0 RUN, 1 STOP, 2 PAUSE;
/// b4-b7 the STOP/PAUSE cause, 0 the key switch, 1 the remote contact, 2 a
/// remote operation (peripheral, computer), 3 an instruction in the
/// program, 4 an error (0 in RUN); the first cause holds while stopped
/// (App. 2's figure is lost in 004: the codes are the QCPU User's Manual's,
/// qcpu.md §8 SD203).
pub(crate) fn status(sys: &mut Sys<'_>, status: Status) {
    let cause = |c: Cause| match c {
        Cause::Switch => 0,
        Cause::Contact => 1,
        Cause::Remote => 2,
        Cause::Instruction => 3,
        Cause::Error => 4,
    };
    let v = match status {
        Status::Run => 0,
        Status::Stop(c) => 1 | cause(c) << 4,
        Status::Pause(c) => 2 | cause(c) << 4,
    };
    let old = sys.sd(203);
    sys.set_sd(203, old & !0xFF | v);
}

/// SD500: the number of the program running (its place in the parameter's
/// program list, from 1; App. 2 L10443).
pub(crate) fn program(mem: &mut DeviceMemory, slot: usize) {
    sd(mem, 500, (slot + 1).min(u16::MAX as usize) as u16);
}

/// SM203 STOP contact (STOP by the RUN contact), SM204 PAUSE status
/// contact (004 L9567, §7.6.2).
pub(crate) fn remote(sys: &mut Sys<'_>, r: Remote) {
    sys.set_sm(203, r.stop_by_contact);
    sys.set_sm(204, r.pause);
}

/// SM206 PAUSE enable coil (004 §7.6.2 (2) (a)).
pub(crate) fn pause_enabled(mem: &DeviceMemory) -> bool {
    sm_get(mem, 206)
}
