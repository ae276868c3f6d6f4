//! MELSEC-Q's system (004 App. 1, App. 2; qcpu.md §4.4, §6, §8): its special
//! relays and registers around each scan and at END, its error numbering
//! ([`codes`]) and error registers, through the engine's [`System`] seam.
//! One job per file: [`scan`] power-on, scan start, scan times and status;
//! [`errors`] SD0-SD26 and SM50; [`clock`] SD210-SD213; [`low_speed`] the
//! low-speed registers; [`interrupts`] the interrupt priorities and error
//! interrupts; [`panel`] the switch and LEDs (SD200-SD209); [`a_compat`]
//! the A-series compatibility area SM1000/SD1000; [`file_register`] SM640,
//! SM672, SD640-SD647; [`bases`] SD240-SD244, SM250/SD250;
//! [`rows`] every SM/SD row of the manual and what softplc does with it; the
//! user timing clocks of DUTY are `user_clock`.

pub mod a_compat;
pub mod bases;
mod clock;
pub mod codes;
mod devices;
mod errors;
pub mod file_register;
pub mod interrupts;
mod low_speed;
pub(crate) mod panel;
pub mod rows;
mod scan;

use std::sync::Arc;

use devices::Sys;

use softplc_ir::device::{DeviceKind, DeviceMap, DeviceMemory};
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::system::{
    End, EndCtx, ErrorReport, LocalDeviceRelays, LowSpeed, Panel, Remote, ScanStart, Severity,
    Status, System, TraceRelays,
};

/// SD648: the file-register block number R addresses (004 §10.7, RSET).
pub const R_BLOCK: u32 = 648;

/// MELSEC-Q's system devices and error numbering.
#[derive(Debug, Default)]
pub struct Melsec {
    params: Params,
}

/// The project's parameters the system devices report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Params {
    /// The A-series compatibility area SM1000/SD1000 is maintained (the
    /// parameter "A-series CPU compatibility", ON by default: 004 L5831).
    pub a_compatibility: bool,
    /// The file-register file (SD640-SD646).
    pub file_register: file_register::FileRegisterFile,
    /// The base units the rack fills (SD240-SD244, SD250).
    pub bases: bases::Bases,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            a_compatibility: true,
            file_register: Default::default(),
            bases: Default::default(),
        }
    }
}

/// The MELSEC-Q system as a CPU takes it (default parameters).
pub fn system() -> Arc<dyn System> {
    Arc::new(Melsec::default())
}

/// The MELSEC-Q system of a Universal model whose standard RAM holds
/// `ZR` file-register points (default parameters).
pub fn qnu_system<const ZR: u32>() -> Arc<dyn System> {
    let mut params = Params::default();
    params.file_register.standard_ram = ZR;
    system_from(params)
}

/// The MELSEC-Q system with the A-series compatibility area on or off.
pub fn system_with(a_compatibility: bool) -> Arc<dyn System> {
    system_from(Params {
        a_compatibility,
        ..Params::default()
    })
}

/// The MELSEC-Q system with a project's parameters.
pub fn system_from(params: Params) -> Arc<dyn System> {
    Arc::new(Melsec { params })
}

/// [`EndCtx::state`]: SM210 (SM1025) at the previous END, for its OFF→ON
/// edge.
const STATE_SM210: usize = 0;
const STATE_SM1025: usize = 1;
/// SM250 at the previous END, for its OFF→ON edge.
const STATE_SM250: usize = 2;
/// SM1047 after the previous END's mirrors (`a_compat::trace_start`).
const STATE_SM1047: usize = 3;

impl Melsec {
    /// Copies the A-series devices from their Q devices when the area is on.
    fn a_refresh(&self, mem: &mut DeviceMemory) {
        if self.params.a_compatibility {
            a_compat::refresh(&mut Sys::of(mem));
        }
    }
}

impl System for Melsec {
    fn state_words(&self) -> usize {
        4 + panel::STATE_WORDS
    }

    /// Everything enabled except the error interrupts I32-I47, which need
    /// IMASK (004 L10902-10904).
    fn interrupt_mask(&self) -> [u16; softplc_ir::cpu::INTERRUPTS / 16] {
        let mut m = [0xFFFF; softplc_ir::cpu::INTERRUPTS / 16];
        m[2] = 0;
        m
    }

    /// 004 App. 3.
    fn interrupt_priority(&self) -> &'static [u8] {
        &interrupts::PRIORITY
    }

    /// 004 §7.15.1.
    fn error_interrupt(&self, code: ErrorCode, stops: bool) -> Option<u32> {
        interrupts::error_interrupt(code, stops)
    }

    fn power_on(&self, mem: &mut DeviceMemory) {
        scan::power_on(mem);
        self.params.file_register.power_on(mem);
        self.params.bases.power_on(mem);
        panel::power_on(mem);
        self.a_refresh(mem);
    }

    fn scan_start(&self, mem: &mut DeviceMemory, start: ScanStart) {
        let mut sys = Sys::of(mem);
        scan::scan_start(&mut sys, start);
        if self.params.a_compatibility {
            a_compat::scan_start(&mut sys, start);
        }
    }

    /// The scan-time registers, the clock registers, then the user timing
    /// clocks (counted at every END, the initial scan's too) and the
    /// completion devices of S.TO; SM672 and SD250.
    fn end(&self, cx: &mut EndCtx<'_>, end: End) {
        // SM and SD looked up once for the registers written at every END.
        scan::end(&mut Sys::of(cx.mem), end);
        self.params.file_register.end(cx.mem);
        let sm250 = self.params.bases.end(cx.mem, cx.state[STATE_SM250] != 0);
        cx.state[STATE_SM250] = sm250 as u32;
        let mut sys = Sys::of(cx.mem);
        let before = cx.state[STATE_SM210] != 0;
        let sm210 = clock::registers(&mut sys, clock::Q, cx.clock, cx.now_us, before);
        cx.state[STATE_SM210] = sm210 as u32;
        if self.params.a_compatibility {
            let before = cx.state[STATE_SM1025] != 0;
            let set = clock::registers(&mut sys, clock::A_SERIES, cx.clock, cx.now_us, before);
            cx.state[STATE_SM1025] = set as u32;
        }
        crate::user_clock::end(cx.mem, cx.shared);
        crate::multi_cpu::end(cx.mem, cx.shared);
        if self.params.a_compatibility {
            let mut sys = Sys::of(cx.mem);
            a_compat::trace_start(&mut sys, cx.state[STATE_SM1047] != 0);
            a_compat::refresh(&mut sys);
            cx.state[STATE_SM1047] = sys.sm(a_compat::TRACE_START) as u32;
        }
    }

    fn status(&self, mem: &mut DeviceMemory, status: Status) {
        let mut sys = Sys::of(mem);
        scan::status(&mut sys, status);
        if self.params.a_compatibility {
            a_compat::status(&mut sys);
        }
    }

    fn remote(&self, mem: &mut DeviceMemory, remote: Remote) {
        let mut sys = Sys::of(mem);
        scan::remote(&mut sys, remote);
        if self.params.a_compatibility {
            a_compat::remote(&mut sys);
        }
    }

    fn panel(&self, mem: &mut DeviceMemory, state: &mut [u32], panel: Panel) {
        panel::show(mem, state, panel);
    }

    /// SM206, or its A-series twin SM1040 (M9040) while the area is on.
    fn pause_enabled(&self, mem: &DeviceMemory) -> bool {
        scan::pause_enabled(mem) || (self.params.a_compatibility && a_compat::pause_enabled(mem))
    }

    fn code(&self, fault: Fault) -> Option<ErrorCode> {
        Some(codes::code(fault))
    }

    fn message(&self, code: ErrorCode) -> &'static str {
        codes::message(code)
    }

    fn severity(&self, code: ErrorCode) -> Severity {
        codes::severity(code)
    }

    fn report_error(&self, mem: &mut DeviceMemory, report: &ErrorReport<'_>) {
        errors::report(mem, report);
        if self.params.a_compatibility {
            a_compat::operation_error(mem, report);
        }
        self.a_refresh(mem);
    }

    fn error_reset(&self, mem: &DeviceMemory, current: Option<ErrorCode>) -> Option<bool> {
        errors::reset_request(mem, current)
    }

    fn clear_error(&self, mem: &mut DeviceMemory) {
        errors::clear(mem);
        self.a_refresh(mem);
    }

    fn program(&self, mem: &mut DeviceMemory, slot: usize) {
        scan::program(mem, slot);
    }

    fn low_speed(&self, mem: &mut DeviceMemory, event: LowSpeed) {
        low_speed::event(mem, event);
    }

    fn low_speed_synchronous(&self, mem: &DeviceMemory) -> bool {
        low_speed::synchronous(mem)
    }

    /// SD648 (RSET).
    fn r_block(&self, map: &DeviceMap) -> Option<u32> {
        map.index(DeviceKind::SD, R_BLOCK)
    }

    /// SM800 ready, SM801 start, SM802 executing, SM803 trigger, SM804
    /// after the trigger, SM805 complete, SM826 trace error (004 §7.12 (1)
    /// (f), L4590-4615).
    fn trace_relays(&self, map: &DeviceMap) -> Option<TraceRelays> {
        let sm = |n| map.index(DeviceKind::SM, n);
        Some(TraceRelays {
            ready: sm(800)?,
            start: sm(801)?,
            executing: sm(802)?,
            trigger: sm(803)?,
            after_trigger: sm(804)?,
            complete: sm(805)?,
            error: sm(826)?,
        })
    }

    /// SM776 local devices at CALL, SM777 local devices in interrupt and
    /// fixed-scan programs (004 §10.13.1 (e), (f), App. 1).
    fn local_device_relays(&self, map: &DeviceMap) -> Option<LocalDeviceRelays> {
        Some(LocalDeviceRelays {
            at_call: map.index(DeviceKind::SM, 776)?,
            in_interrupts: map.index(DeviceKind::SM, 777)?,
        })
    }
}
