//! softplc-engine: the scan engine: input refresh → program → END processing (004 §4.3), in the
//! time of a [`Clock`] it is given.
//!
//! [`Cpu`] owns the device memory, its compiled programs and its model's
//! [`Profile`]. Everything a scan needs is allocated when the CPU is built;
//! `scan` itself does no allocation.

#![forbid(unsafe_code)]

mod call_args;
mod cpu;
mod exec;
mod link;
mod local_devices;
pub mod tier;
pub mod trace;

use std::time::Duration;

pub use cpu::{
    Cpu, DoorEvent, Hold, Journal, LoadedProgram, OnlineLimits, ProgramMonitor, Refusal, Written,
    VIRTUAL_WATCHDOG_FLOOR,
};
pub use softplc_ir::calendar;
pub use softplc_ir::clock::{Clock, MonotonicClock, VirtualClock};
pub use softplc_ir::fault::{CpuError, ErrorCode, Fault, HistoryEntry};

use exec::Outcome;
use softplc_ir::cpu::CpuServices;
use softplc_ir::device::{DeviceConfig, DeviceKind, DeviceMemory};
use softplc_ir::ops::Program;
pub use softplc_ir::profile::Profile;
pub use softplc_ir::snapshot::{Snap, StateError};
use softplc_ir::system::{ErrorReport, ErrorTimes, ModuleRef, Severity};

/// Operating state of the CPU (004 §4.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CpuState {
    Run,
    Stop,
    Pause,
}

impl CpuState {
    pub fn as_str(self) -> &'static str {
        match self {
            CpuState::Run => "RUN",
            CpuState::Stop => "STOP",
            CpuState::Pause => "PAUSE",
        }
    }
}

/// What to do on an error of a class the PLC RAS parameter sets (004
/// L4911-4922: operation error, intelligent module program execution error,
/// file access error).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ErrorMode {
    #[default]
    Stop,
    Continue,
}

/// Output (Y) at STOP→RUN (004 §7.5, PLC RAS parameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StopToRunOutput {
    /// Restore the Y image saved at RUN→STOP, then run (default).
    #[default]
    Previous,
    /// Start from Y OFF and let the program recalculate the outputs.
    Recalculate,
}

/// The external outputs while the CPU is in STOP (the APLC system block's
/// output table, 002 §2.2.1).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub enum StopOutputs {
    /// All outputs OFF (MELSEC-Q; the APLC's "disable").
    #[default]
    Off,
    /// Each output holds its state at RUN→STOP ("freeze").
    Hold,
    /// The outputs listed (Y numbers) ON, all others OFF ("configure").
    Table(Vec<u32>),
}

/// Device clear of a remote RUN with a clear mode ([`Cpu::remote_run_clear`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunClear {
    /// Clear mode 01: every device outside the latch ranges.
    OutsideLatch,
    /// Clear mode 02: the latch ranges too.
    All,
}

/// Execution type of a program file (004 §4.2, qcpu.md §2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ExecType {
    Initial,
    #[default]
    Scan,
    LowSpeed,
    Standby,
    FixedScan,
}

/// A latch range of one device (PLC parameter "device setting", 004 §7.4):
/// numbers `start..=end` keep their values across power-on and reset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LatchRange {
    pub kind: DeviceKind,
    pub start: u32,
    pub end: u32,
    /// Latch (1): cleared by latch clear. Latch (2): not cleared by the L.CLR switch.
    pub clearable: bool,
}

/// A local-device range (PLC parameter "device setting", 004 §10.13.1):
/// numbers `start..=end` of one device are each program's own. `kind` is
/// M, V, D, or the contact kind TS, STS, CS that stands for a timer's,
/// retentive timer's or counter's contact, coil and current value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LocalRange {
    pub kind: DeviceKind,
    pub start: u32,
    pub end: u32,
}

/// A device initial value (004 §10.13.2), written at power-on and STOP→RUN.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialValue {
    pub device: softplc_ir::access::DeviceSpec,
    pub value: String,
}

/// CPU parameters: the model's profile and the project's settings. Defaults
/// of the settings are the QnHCPU's (004 ch. 9 parameter list).
#[derive(Clone, Debug)]
pub struct CpuConfig {
    /// What the CPU is: its model, family, names and doors (asked by every
    /// door; the engine reads only its system devices).
    pub profile: &'static Profile,
    pub devices: DeviceConfig,
    /// Watchdog time, measured in wall-clock time (default 200 ms, 004 L4850).
    pub watchdog: Duration,
    pub operation_error: ErrorMode,
    /// Intelligent function module program execution errors (SP.UNIT ERROR).
    pub module_error: ErrorMode,
    /// File access errors (FILE OPE. ERROR).
    pub file_error: ErrorMode,
    /// Low-speed timer base (default 100 ms) and high-speed timer base (10 ms).
    pub timer_low: Duration,
    pub timer_high: Duration,
    /// Calendar clock at power-on (`run` uses 2000-01-01 00:00:00 so runs are
    /// reproducible).
    pub clock_start: calendar::DateTime,
    /// Constant scan period (0.5-2000 ms); `None` = off.
    pub constant_scan: Option<Duration>,
    /// Low-speed program execution time per scan; `None` = use constant-scan spare time.
    pub low_speed_time: Option<Duration>,
    /// Low-speed execution monitor time (10-2000 ms): a low-speed scan time
    /// measured longer at low-speed END is PRG.TIME OVER (004 §4.2.3 (7));
    /// `None` = off.
    pub low_speed_monitor: Option<Duration>,
    /// Initial-program execution monitor time; `None` = off.
    pub initial_monitor: Option<Duration>,
    pub stop_to_run_output: StopToRunOutput,
    /// The RUN-PAUSE contacts (004 §7.6.1, §7.6.2): the X number of the RUN
    /// contact (ON = STOP) and of the PAUSE contact (ON with the family's
    /// PAUSE enable = PAUSE); `None` = not set.
    pub run_contact: Option<u32>,
    pub pause_contact: Option<u32>,
    /// Remote RESET allowed (004 §7.6.3; not by default).
    pub remote_reset: bool,
    /// Device memory is kept at STOP→RUN (MELSEC-Q; the APLC's "keep device
    /// values"); `false`: every device but X and the file registers is
    /// cleared before the initial values (`Cpu::stop_to_run_devices`).
    pub keep_device_values: bool,
    /// The external outputs in STOP.
    pub stop_outputs: StopOutputs,
    /// The APLC's run input (002 §2.2.1, §2.3.2): the X number whose
    /// OFF→ON change in STOP starts RUN, and without which power-on and
    /// RESET stay in STOP; `None` = not set.
    pub run_input: Option<u32>,
    /// Latch ranges; by default L0-L8191 is latch (1). A part that is a
    /// local device is not latched (004 L3552).
    pub latch: Vec<LatchRange>,
    /// Local-device ranges, at most one per device (none by default: every
    /// device is global).
    pub local_devices: Vec<LocalRange>,
    /// Fixed-cycle interrupt periods of I28, I29, I30, I31 (default 100/40/20/10 ms).
    pub interrupt_periods: [Duration; 4],
    /// Interrupt counters: the counter numbers that count I0, I1 … I255
    /// from this first one (004 L6600-6645); `None`: none.
    pub interrupt_counters: Option<u32>,
    pub initial_values: Vec<InitialValue>,
    /// The family's system devices and error numbering (the profile's
    /// default, or one built with the project's parameters).
    pub system: std::sync::Arc<dyn softplc_ir::system::System>,
    /// The base units' slots and modules (empty: no I/O assignment, X and
    /// Y plain device memory).
    pub rack: std::sync::Arc<softplc_ir::rack::Rack>,
    /// The limits of writing a program during RUN (512 steps a write, a
    /// reserve of 500 steps per file).
    pub online: OnlineLimits,
}

impl CpuConfig {
    /// The settings' defaults for a CPU of `profile`, with the profile's
    /// device points and system devices.
    pub fn new(profile: &'static Profile) -> Self {
        CpuConfig {
            profile,
            devices: (profile.default_devices)(),
            watchdog: Duration::from_millis(200),
            operation_error: ErrorMode::Stop,
            module_error: ErrorMode::Stop,
            file_error: ErrorMode::Stop,
            timer_low: Duration::from_millis(100),
            timer_high: Duration::from_millis(10),
            clock_start: calendar::DateTime {
                year: 2000,
                month: 1,
                day: 1,
                hour: 0,
                minute: 0,
                second: 0,
            },
            constant_scan: None,
            low_speed_time: None,
            low_speed_monitor: None,
            initial_monitor: None,
            stop_to_run_output: StopToRunOutput::Previous,
            run_contact: None,
            pause_contact: None,
            remote_reset: false,
            keep_device_values: true,
            stop_outputs: StopOutputs::Off,
            run_input: None,
            latch: vec![LatchRange {
                kind: DeviceKind::L,
                start: 0,
                end: 8191,
                clearable: true,
            }],
            local_devices: Vec::new(),
            interrupt_periods: [
                Duration::from_millis(100),
                Duration::from_millis(40),
                Duration::from_millis(20),
                Duration::from_millis(10),
            ],
            interrupt_counters: None,
            initial_values: Vec::new(),
            system: (profile.default_system)(),
            rack: Default::default(),
            online: OnlineLimits::default(),
        }
    }
}

/// State the interpreter works on, split from [`Program`] so both can be borrowed.
pub(crate) struct Runtime {
    pub mem: DeviceMemory,
    /// Clock reading at the start of this scan, µs.
    pub now_us: u64,
    /// The calendar clock (the system's clock registers, DATERD/DATEWR).
    pub clock: calendar::PlcClock,
    /// CPU-wide state of family instructions (see `ExecCtx::shared`).
    pub shared: Box<[u32]>,
    /// [low, high] timer bases in µs.
    pub timer_base_us: [u32; 2],
    /// Scan time measured at the previous END, µs; added by OUT T.
    pub scan_us: u32,
    /// Master-control levels that are OFF, one bit per N.
    pub mc_off: u16,
    /// CALL return addresses: (program, op index).
    pub calls: Vec<(u32, u32)>,
    pub fors: Vec<(u32, i16)>,
    pub stop_request: bool,
    /// A STOP that stops at once ([`softplc_ir::ops::Op::StopNow`]) ended the scan.
    pub stop_now: bool,
    pub watchdog: Duration,
    /// The watchdog time as set (the parameter, or the initial execution
    /// monitor time while the initial programs run): the error information
    /// of WDT ERROR.
    pub watchdog_set: Duration,
    /// Set by the host to stop the CPU even inside an endless loop; checked
    /// with the watchdog on backward jumps (`Cpu::abort_handle`).
    pub abort: std::sync::Arc<std::sync::atomic::AtomicBool>,
    pub operation_error: ErrorMode,
    pub module_error: ErrorMode,
    pub file_error: ErrorMode,
    /// The base units' slots: the slot a module-access error names.
    pub rack: std::sync::Arc<softplc_ir::rack::Rack>,
    /// The latest error and whether it stopped the CPU.
    pub error: Option<CpuError>,
    /// Error history, oldest first, at most [`HISTORY_LEN`] entries.
    pub history: std::collections::VecDeque<HistoryEntry>,
    /// An interrupt program is running (IRET ends it).
    pub in_interrupt: bool,
    /// Interrupt pointers requested and not yet run.
    pub requests: cpu::Requests,
    /// The error interrupt of a stop error, to run before the CPU stops.
    pub stop_interrupt: Option<u32>,
    /// What CPU-function instructions change: the watchdog start, the
    /// interrupt enable and mask, execution-type requests, the trace
    /// requests, the timers' remainders.
    pub cpu: CpuServices,
    /// Running a program for POFF: every condition forced OFF.
    pub force_off: bool,
    /// See [`CpuConfig::system`].
    pub system: std::sync::Arc<dyn softplc_ir::system::System>,
    /// The system's own state words (`System::state_words`).
    pub system_state: Box<[u32]>,
    /// Input image: what the input modules present; copied to X at input
    /// refresh.
    pub inputs: Box<[bool]>,
    /// The X the input refresh copies: (first, count) spans, every X
    /// without a rack, the slots with inputs with one.
    pub input_spans: Box<[(u32, u32)]>,
    /// Forced X/Y (`cpu/force.rs`).
    pub forces: Vec<cpu::Force>,
    /// A program may write X (`Program::may_write_x` of any program).
    pub programs_write_x: bool,
    /// X on the input spans holds the input image: nothing but an input
    /// refresh or a write of both (the door's `set_input`, its writes to X
    /// mirrored into the image) has changed either since the last full
    /// refresh, no program can write X and nothing is forced. The scan's
    /// input refresh would copy nothing new and is skipped.
    pub x_holds_image: bool,
    /// The programs' local devices; `None` without local-device ranges.
    pub local_devices: Option<local_devices::LocalDevices>,
}

/// What an error names besides where it happened (its error information).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Named {
    /// The set and measured times of a time error.
    pub time: Option<ErrorTimes>,
    /// The module or CPU that caused it.
    pub module: Option<ModuleRef>,
}

impl Named {
    /// A time error's information: the time set and the time measured, µs.
    pub(crate) fn time(set_us: u64, measured_us: u64) -> Named {
        Named {
            time: Some(ErrorTimes {
                set_us,
                measured_us,
            }),
            module: None,
        }
    }
}

/// Entries kept in the error history (004 §7.20.2).
pub const HISTORY_LEN: usize = 16;

impl Runtime {
    /// Records a fault of op `pc` in the system devices (the error code and
    /// where it happened); returns true when the CPU must stop
    /// (004 §7.20).
    #[cold]
    #[inline(never)]
    pub(crate) fn record_fault(&mut self, prog: &Program, fault: Fault, pc: usize) -> bool {
        let step = prog.op_step.get(pc).copied();
        let (file, line) = prog.source_of(pc);
        // WDT ERROR: the time set and the time the scan had taken.
        let named = if fault == Fault::Watchdog {
            Named::time(
                self.watchdog_set.as_micros() as u64,
                self.cpu.watchdog_start.elapsed().as_micros() as u64,
            )
        } else {
            Named::default()
        };
        self.record(fault, Some(file), step, line, None, named)
            .is_some_and(|code| self.stops(code))
    }

    /// Error `code` stops the CPU (its severity, for an error of a class
    /// the PLC RAS parameter sets that class's mode).
    pub(crate) fn stops(&self, code: ErrorCode) -> bool {
        let mode = match self.severity(code) {
            Severity::Stop => return true,
            Severity::Continue => return false,
            Severity::Operation => self.operation_error,
            Severity::ModuleAccess => self.module_error,
            Severity::FileAccess => self.file_error,
        };
        mode == ErrorMode::Stop
    }

    /// The module a module-access fault names: its start I/O number and
    /// the slot that holds it (a CPU shared memory: the CPU number).
    fn module_of(&self, fault: Fault) -> Option<ModuleRef> {
        let unit = fault.unit()?;
        let io = unit << 4;
        let cpus = softplc_ir::device::CPU1_UNIT..softplc_ir::device::CPU1_UNIT + 4;
        let slot = if cpus.contains(&unit) {
            Some(unit - softplc_ir::device::CPU1_UNIT + 1)
        } else {
            let slot = self.rack.slots.iter().find(|s| s.io().contains(&io));
            slot.map(|s| s.index)
        };
        Some(ModuleRef { io, slot })
    }

    /// What error `code` does to the CPU.
    pub(crate) fn severity(&self, code: ErrorCode) -> Severity {
        self.system.severity(code)
    }

    /// Records a self-diagnostic error in the system devices, the latest
    /// error and the error history; the code recorded, `None` when `fault`
    /// is no error in this family. `named`: what the error names besides
    /// its location (a module-access fault's module is found here).
    pub(crate) fn record(
        &mut self,
        fault: Fault,
        file: Option<&str>,
        step: Option<u32>,
        line: Option<u32>,
        detail: Option<u32>,
        named: Named,
    ) -> Option<ErrorCode> {
        let now = self.clock.now(self.now_us);
        let code = self.system.code(fault)?;
        let report = ErrorReport {
            code,
            file,
            step,
            at: now,
            detail,
            module: named.module.or_else(|| self.module_of(fault)),
            time: named.time,
        };
        self.system.report_error(&mut self.mem, &report);
        self.error = Some(CpuError {
            code,
            step,
            file: file.map(str::to_string),
            line,
        });
        if self.history.len() == HISTORY_LEN {
            self.history.pop_front();
        }
        self.history.push_back(HistoryEntry {
            code,
            time: now.to_unix(),
            detail: detail.or(step),
        });
        self.error_interrupt(code);
        Some(code)
    }

    /// Requests the error interrupt of error `code` (004 §7.15.1): the
    /// family names the pointer; it is taken only when EI and IMASK enable
    /// it as the error occurs, else it is lost (QCPU User's Manual
    /// (Function Explanation, Program Fundamentals) §3.1.3: error causes
    /// while disabled are discarded). A stop error's runs before the CPU
    /// stops, the others at the next interrupt service.
    fn error_interrupt(&mut self, code: ErrorCode) {
        let stops = self.stops(code);
        let Some(n) = self.system.error_interrupt(code, stops) else {
            return;
        };
        let n_ok = (n as usize) < softplc_ir::cpu::INTERRUPTS;
        if !n_ok || !self.cpu.interrupt_enabled(n as usize) {
            return;
        }
        if stops {
            self.stop_interrupt = Some(n);
        } else {
            self.requests.set(n);
        }
    }

    /// Input refresh: the input image into X, forced inputs kept forced
    /// (when an instruction asks mid-scan, and at the start of a scan
    /// unless X already holds the image: [`Runtime::scan_input_refresh`]).
    pub(crate) fn refresh_inputs(&mut self) {
        let xb = self.mem.map.base(DeviceKind::X) as usize;
        for &(first, n) in self.input_spans.iter() {
            let (first, n) = (first as usize, n as usize);
            self.mem.bits[xb + first..xb + first + n]
                .copy_from_slice(&self.inputs[first..first + n]);
        }
        if !self.forces.is_empty() {
            self.apply_forces(DeviceKind::X);
        }
        self.x_holds_image = self.forces.is_empty() && !self.programs_write_x;
    }

    /// The input refresh at the start of a scan: a copy that would change
    /// nothing is skipped (see [`Runtime::x_holds_image`]).
    pub(crate) fn scan_input_refresh(&mut self) {
        if !self.x_holds_image {
            self.refresh_inputs();
        }
    }

    /// Something other than an input refresh may have written X or the
    /// input image without the other: the next scan refreshes in full.
    pub(crate) fn x_touched(&mut self) {
        self.x_holds_image = false;
    }

    /// Direct input: X`n` takes the input module's value now, a forced
    /// point its forced value (004 L6054-6083, L4222-4231).
    pub(crate) fn direct_input(&mut self, n: u32) {
        let Some(&v) = self.inputs.get(n as usize) else {
            return;
        };
        let i = (self.mem.map.base(DeviceKind::X) + n) as usize;
        self.mem.bits[i] = v;
        if let Some(f) = self.forces.iter_mut().find(|f| f.bit == i) {
            f.under = v;
            self.mem.bits[i] = f.on;
        }
    }

    /// Forced points of `kind` take their forced value; the value under the
    /// force is kept.
    pub(crate) fn apply_forces(&mut self, kind: DeviceKind) {
        for f in &mut self.forces {
            if f.kind == kind {
                f.under = self.mem.bits[f.bit];
                self.mem.bits[f.bit] = f.on;
            }
        }
    }

    /// Serves what an instruction asked for when it returns
    /// ([`CpuServices::pending`]): an input refresh, a continuation error,
    /// the clear of the latest error.
    #[cold]
    #[inline(never)]
    pub(crate) fn serve_requests(&mut self) {
        self.cpu.pending = false;
        if std::mem::take(&mut self.cpu.input_refresh) {
            self.refresh_inputs();
        }
        if std::mem::take(&mut self.cpu.clear_error) {
            self.clear_continuation_error();
        }
        self.record_report();
    }

    /// Clears the latest error when it does not stop the CPU (the error
    /// reset of the program: SM50/SD50 at END, LEDR at once).
    pub(crate) fn clear_continuation_error(&mut self) {
        if self.error.as_ref().is_some_and(|e| !self.stops(e.code)) {
            self.error = None;
            self.system.clear_error(&mut self.mem);
        }
    }

    /// Records the continuation error an instruction reported
    /// ([`CpuServices::report`]): an annunciator and its number.
    fn record_report(&mut self) {
        if let Some((fault, detail)) = self.cpu.report.take() {
            self.record(fault, None, None, None, Some(detail), Named::default());
        }
    }

    /// END/FEND reached: a subroutine without RET or a FOR without NEXT is an error.
    pub(crate) fn end_checks(&mut self, slot: usize, pc: usize) -> Outcome {
        let code = if self.in_interrupt {
            Fault::NoIret
        } else if !self.calls.is_empty() {
            Fault::NoRet
        } else if !self.fors.is_empty() {
            Fault::ForWithoutNext
        } else {
            return Outcome::End;
        };
        self.calls.clear();
        self.fors.clear();
        Outcome::Fault(code, slot, pc)
    }
}

/// Per-program hidden state: edge memories (LDP, PLS, pulse forms, SCJ) and the
/// state words of family instructions. Cleared at power-on and STOP→RUN.
pub(crate) struct ProgState {
    pub edges: Box<[bool]>,
    pub state: Box<[u32]>,
}

impl ProgState {
    fn new(p: &Program) -> Self {
        ProgState {
            edges: vec![false; p.edge_slots as usize].into_boxed_slice(),
            state: vec![0; p.state_words as usize].into_boxed_slice(),
        }
    }

    fn clear(&mut self) {
        self.edges.fill(false);
        self.state.fill(0);
    }
}
