//! The seam for a PLC family's system: what the engine writes into special
//! relays and registers around each scan and when an error is recorded, and
//! how the family numbers errors. The engine names no system device; each
//! dialect implements [`System`] (MELSEC-Q's in `softplc-melsec`'s
//! `system`, the APLC's in `softplc-aplc`'s `system`).

use crate::calendar::{DateTime, PlcClock};
use crate::device::{DeviceMap, DeviceMemory};
use crate::fault::{ErrorCode, Fault};

/// Scan times measured at END, µs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanTimes {
    pub current_us: u64,
    pub min_us: u64,
    pub max_us: u64,
}

/// What an error does to the CPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// The CPU stops (until RESET).
    Stop,
    /// The CPU keeps running (a continuation error).
    Continue,
    /// An operation error: stops or continues as the CPU's "operation error"
    /// parameter says.
    Operation,
    /// An intelligent function module program execution error (a program's
    /// access to a module's buffer memory): as the CPU's parameter for that
    /// error class says.
    ModuleAccess,
    /// A file access error (an instruction naming a file that is not
    /// there): as the CPU's parameter for that error class says.
    FileAccess,
}

/// The operating state a system shows (004 §4.4), STOP and PAUSE with
/// what caused them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Run,
    Stop(Cause),
    Pause(Cause),
}

/// What stopped or paused the CPU (004 App. 2 SD203): the first cause
/// holds while the CPU stays stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    /// The RUN/STOP key switch (softplc: the host's STOP, e.g. `run`'s
    /// Ctrl-C, the HTTP monitor's stop).
    Switch,
    /// The RUN or PAUSE contact.
    Contact,
    /// A remote operation from a client (MC protocol, the web monitor's
    /// PAUSE and breakpoints).
    Remote,
    /// The STOP instruction.
    Instruction,
    /// A stop error.
    Error,
}

/// The remote-operation relays a system shows (004 §7.6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Remote {
    /// The CPU is held in STOP by the RUN contact.
    pub stop_by_contact: bool,
    /// A PAUSE was requested at an END: the CPU pauses at the next END and
    /// stays paused while the request holds.
    pub pause: bool,
}

/// What the CPU's front panel shows besides device memory: its switch and
/// LEDs (004 §7.19).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Panel {
    pub status: Status,
    /// The key switch is at STOP.
    pub switch_stop: bool,
    /// The CPU is held in STOP by a stop error.
    pub stop_error: bool,
    /// Forced I/O is registered.
    pub forced: bool,
}

/// The start of a scan, before the programs run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScanStart {
    /// Engine time since power-on and since the last STOP→RUN, µs.
    pub since_power_on_us: u64,
    pub since_run_us: u64,
    /// The first scan after power-on, RESET or STOP→RUN.
    pub first_scan: bool,
    /// Bit n: input X`n` (X0-X63) turned ON in the input image since the
    /// previous scan's start, however briefly (the APLC's pulse catch and
    /// edge interrupts).
    pub input_rises: u64,
    /// Bit n: input X`n` turned OFF in the input image since then.
    pub input_falls: u64,
}

/// END processing of a scan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct End {
    /// The END of the initial programs' scan: `times.current_us` is the
    /// initial scan time, min/max are not updated.
    pub initial: bool,
    pub times: ScanTimes,
    /// Where the scan time went.
    pub split: ScanSplit,
    /// Engine time since the last STOP→RUN, µs.
    pub since_run_us: u64,
}

/// Where a scan's time went, µs of engine time (programs take their
/// simulated execution time, none without one). The parts add up to the
/// scan time: END processing is what no program and no constant-scan wait
/// took.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanSplit {
    /// The scan programs, with the fixed-scan programs that ran in the scan.
    pub programs_us: u64,
    /// The low-speed programs in this scan.
    pub low_speed_us: u64,
    /// The low-speed programs since the current low-speed cycle began (0
    /// when one has just ended).
    pub low_speed_cycle_us: u64,
    /// The constant-scan wait (0 without constant scan).
    pub wait_us: u64,
    /// END processing: the rest of the scan time.
    pub end_us: u64,
}

/// An error being recorded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ErrorReport<'a> {
    pub code: ErrorCode,
    /// Source file of the failing instruction, if an instruction failed.
    pub file: Option<&'a str>,
    /// Its step number.
    pub step: Option<u32>,
    /// Calendar time of detection.
    pub at: DateTime,
    /// Detail an instruction reported with the error (an annunciator number).
    pub detail: Option<u32>,
    /// The module a module-access error names.
    pub module: Option<ModuleRef>,
    /// The set and measured times of a time error (watchdog, constant scan).
    pub time: Option<ErrorTimes>,
}

/// A module an error names: its start I/O number and the slot holding it,
/// or for a multi-CPU system's CPU shared memory the CPU number (1-4);
/// `None` when neither holds that I/O number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModuleRef {
    pub io: u32,
    pub slot: Option<u32>,
}

/// The time a time error was set to exceed and the time measured, µs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ErrorTimes {
    pub set_us: u64,
    pub measured_us: u64,
}

/// Low-speed program execution (004 §4.2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LowSpeed {
    /// A scan's pass of the low-speed programs starts; `first`: the first
    /// since RUN.
    Pass { first: bool },
    /// Low-speed program `slot` (in parameter order, from 0) starts, or
    /// with `None` none is running any more.
    Running(Option<usize>),
    /// A low-speed cycle completed, with its execution times.
    End(ScanTimes),
}

/// Flat bit indices of the relays that show a sampling trace's state; the
/// start and trigger relays are also inputs (turning the start relay OFF
/// aborts the trace, ON starts it again; turning the trigger relay ON
/// triggers it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TraceRelays {
    pub ready: u32,
    pub start: u32,
    pub executing: u32,
    pub trigger: u32,
    pub after_trigger: u32,
    pub complete: u32,
    /// ON when a sample could not be taken.
    pub error: u32,
}

/// Flat bit indices of the relays that choose whose local devices run
/// (004 §10.13.1 (e), (f)): read whenever a subroutine of another file is
/// called or an interrupt or fixed-scan program starts, so a change takes
/// effect at once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LocalDeviceRelays {
    /// ON: a subroutine called in another file works on that file's local
    /// devices; OFF: on the caller's.
    pub at_call: u32,
    /// ON: an interrupt or fixed-scan program works on its own file's local
    /// devices; OFF: on those of the program it interrupted.
    pub in_interrupts: u32,
}

/// What the system sees at END besides device memory.
pub struct EndCtx<'a> {
    pub mem: &'a mut DeviceMemory,
    /// The CPU-wide state of instructions (`ExecCtx::shared`): instructions
    /// that work through the system at END (MELSEC's DUTY) keep theirs here.
    pub shared: &'a mut [u32],
    /// The calendar clock and the engine time now, µs.
    pub clock: &'a mut PlcClock,
    pub now_us: u64,
    /// The system's own words ([`System::state_words`]), cleared at power-on.
    pub state: &'a mut [u32],
}

/// A family's system devices and error numbering.
pub trait System: Send + Sync + std::fmt::Debug {
    /// Words of the system's own state ([`EndCtx::state`]): edge memories of
    /// its request relays.
    fn state_words(&self) -> usize {
        0
    }
    /// The interrupt enable mask at power-on (one bit per I0-I255): all
    /// enabled unless the family says otherwise.
    fn interrupt_mask(&self) -> [u16; crate::cpu::INTERRUPTS / 16] {
        [0xFFFF; crate::cpu::INTERRUPTS / 16]
    }
    /// The interrupt pointers in priority order, highest first; a pointer
    /// not listed never runs. Default: none (a family whose programs have
    /// no interrupt pointers of the engine's).
    fn interrupt_priority(&self) -> &'static [u8] {
        &[]
    }
    /// The error interrupt pointer error `code` requests: the one of a stop
    /// error when `stops`, else that of its error class; `None` for no
    /// error interrupt.
    fn error_interrupt(&self, _code: ErrorCode, _stops: bool) -> Option<u32> {
        None
    }
    /// Power-on (and RESET, remote latch clear) values of the system devices.
    fn power_on(&self, mem: &mut DeviceMemory);
    /// Right after the device initial values were written (power-on, RESET,
    /// STOP→RUN, the restore of battery-backed memory from a state
    /// directory): data of the family that outranks them (the APLC's EEPROM
    /// image into D6000-D6999, 002 table 2-2 L971-979).
    fn initialised(&self, _mem: &mut DeviceMemory) {}
    /// STOP→RUN, before the device initial values: the family's system
    /// devices re-initialised (the APLC's SM and SD, 002 App. 1/2). Default:
    /// kept.
    fn stop_to_run(&self, _mem: &mut DeviceMemory) {}
    /// Relays set before the program runs (always-ON, first scan, clocks).
    fn scan_start(&self, mem: &mut DeviceMemory, start: ScanStart);
    /// END processing: scan times, counters, clock registers, and what
    /// instructions left for END.
    fn end(&self, cx: &mut EndCtx<'_>, end: End);
    /// The operating state changed (or was set again).
    fn status(&self, _mem: &mut DeviceMemory, _status: Status) {}
    /// The remote-operation state changed (or was shown again at END).
    fn remote(&self, _mem: &mut DeviceMemory, _remote: Remote) {}
    /// The front panel, shown at every END (in every state) and whenever the
    /// operating state, the switch or the remote operations change; the
    /// system's own words ([`EndCtx::state`]) for its edge memories.
    fn panel(&self, _mem: &mut DeviceMemory, _state: &mut [u32], _panel: Panel) {}
    /// The program enables PAUSE by the PAUSE contact (MELSEC: SM206);
    /// `false` for a family without such a relay.
    fn pause_enabled(&self, _mem: &DeviceMemory) -> bool {
        false
    }
    /// The family's number for `fault`; `None` when the condition is no
    /// error in this family (nothing is recorded).
    fn code(&self, fault: Fault) -> Option<ErrorCode>;
    /// The family's message for error `code`.
    fn message(&self, code: ErrorCode) -> &'static str;
    /// What error `code` does to the CPU.
    fn severity(&self, code: ErrorCode) -> Severity;
    /// Records an error in the system devices.
    fn report_error(&self, mem: &mut DeviceMemory, report: &ErrorReport<'_>);
    /// A program's request to clear the latest error `current` (MELSEC: SM50
    /// ON with the code in SD50): `None` without a request, else whether it
    /// names `current`. The engine acts on the request's rising edge and
    /// clears only errors that do not stop the CPU.
    fn error_reset(&self, _mem: &DeviceMemory, _current: Option<ErrorCode>) -> Option<bool> {
        None
    }
    /// Clears the error registers after an error reset.
    fn clear_error(&self, _mem: &mut DeviceMemory) {}
    /// Program `slot` (in parameter order, from 0) starts running.
    fn program(&self, _mem: &mut DeviceMemory, _slot: usize) {}
    /// Low-speed program execution.
    fn low_speed(&self, _mem: &mut DeviceMemory, _event: LowSpeed) {}
    /// Low-speed programs run synchronously: at most one cycle a scan.
    fn low_speed_synchronous(&self, _mem: &DeviceMemory) -> bool {
        false
    }
    /// The word selecting the file-register block R addresses in a memory of
    /// `map` (flat word index), `None` when R is always block 0.
    fn r_block(&self, _map: &DeviceMap) -> Option<u32> {
        None
    }
    /// The relays of the sampling trace in a memory of `map`, `None` when
    /// the family shows none.
    fn trace_relays(&self, _map: &DeviceMap) -> Option<TraceRelays> {
        None
    }
    /// The relays that choose whose local devices a called subroutine and
    /// an interrupt or fixed-scan program use, in a memory of `map`; `None`
    /// when the family has none (both read OFF).
    fn local_device_relays(&self, _map: &DeviceMap) -> Option<LocalDeviceRelays> {
        None
    }
}
