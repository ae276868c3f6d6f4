//! The scan engine: input refresh → program → END processing (004 §4.3), in the
//! time of a [`Clock`] it is given.
//!
//! [`Cpu`] owns the device memory and one compiled program. Everything a scan
//! needs is allocated when the CPU is built; `scan` itself does no allocation.

pub mod calendar;
mod clock;
mod cpu;
mod error;
mod exec;
mod operand;
mod special;

use std::time::Duration;

pub use clock::{Clock, MonotonicClock, VirtualClock};
pub use cpu::{Cpu, LoadedProgram};
pub use error::{CpuError, ErrorCode, Fault};

use crate::device::{DeviceConfig, DeviceKind, DeviceMemory};
use crate::program::ops::Program;
use exec::Outcome;

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

/// What to do on an operation error (PLC RAS parameter, 004 L4911-4922).
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

/// A device initial value (004 §10.13.2), written at power-on and STOP→RUN.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialValue {
    pub device: crate::access::DeviceSpec,
    pub value: String,
}

/// CPU parameters. Defaults are the Q06HCPU's (004 ch. 9 parameter list).
#[derive(Clone, Debug)]
pub struct CpuConfig {
    /// CPU model answered to "read CPU model" requests.
    pub model: String,
    pub devices: DeviceConfig,
    /// Watchdog time, measured in wall-clock time (default 200 ms, 004 L4850).
    pub watchdog: Duration,
    pub operation_error: ErrorMode,
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
    /// Initial-program execution monitor time; `None` = off.
    pub initial_monitor: Option<Duration>,
    pub stop_to_run_output: StopToRunOutput,
    /// Latch ranges; by default L0-L8191 is latch (1).
    pub latch: Vec<LatchRange>,
    /// Fixed-cycle interrupt periods of I28, I29, I30, I31 (default 100/40/20/10 ms).
    pub interrupt_periods: [Duration; 4],
    pub initial_values: Vec<InitialValue>,
}

impl Default for CpuConfig {
    fn default() -> Self {
        CpuConfig {
            model: "Q06HCPU".to_string(),
            devices: DeviceConfig::default(),
            watchdog: Duration::from_millis(200),
            operation_error: ErrorMode::Stop,
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
            initial_monitor: None,
            stop_to_run_output: StopToRunOutput::Previous,
            latch: vec![LatchRange {
                kind: DeviceKind::L,
                start: 0,
                end: 8191,
                clearable: true,
            }],
            interrupt_periods: [
                Duration::from_millis(100),
                Duration::from_millis(40),
                Duration::from_millis(20),
                Duration::from_millis(10),
            ],
            initial_values: Vec::new(),
        }
    }
}

/// State the interpreter works on, split from [`Program`] so both can be borrowed.
pub(crate) struct Runtime {
    pub mem: DeviceMemory,
    /// Clock reading at the start of this scan, µs.
    pub now_us: u64,
    /// The calendar clock (SD210-SD213, DATERD/DATEWR).
    pub clock: calendar::PlcClock,
    /// Sub-unit remainder of each timer, µs (T then ST).
    pub timer_rem: Box<[u32]>,
    /// [low, high] timer bases in µs.
    pub timer_base_us: [u32; 2],
    /// Scan time measured at the previous END, µs; added by OUT T.
    pub scan_us: u32,
    /// Master-control levels that are OFF, one bit per N.
    pub mc_off: u16,
    pub calls: Vec<u32>,
    pub fors: Vec<(u32, i16)>,
    pub stop_request: bool,
    pub watchdog: Duration,
    pub operation_error: ErrorMode,
    /// The latest error and whether it stopped the CPU.
    pub error: Option<CpuError>,
}

impl Runtime {
    /// Records a fault in SM0/SM1/SD0 and the error-location registers; returns
    /// true when the CPU must stop (004 §7.20).
    pub(crate) fn record_fault(&mut self, prog: &Program, code: ErrorCode, pc: usize) -> bool {
        let step = prog.op_step.get(pc).copied();
        special::report_error(&mut self.mem, code, &prog.file, step);
        self.error = Some(CpuError {
            code,
            step,
            file: Some(prog.file.clone()),
            line: prog.op_line.get(pc).copied(),
        });
        !(code.is_operation_error() && self.operation_error == ErrorMode::Continue)
    }

    /// END/FEND reached: a subroutine without RET or a FOR without NEXT is an error.
    pub(crate) fn end_checks(&mut self, _prog: &Program, pc: usize) -> Outcome {
        let code = if !self.calls.is_empty() {
            ErrorCode::NO_RET
        } else if !self.fors.is_empty() {
            ErrorCode::FOR_WITHOUT_NEXT
        } else {
            return Outcome::End;
        };
        self.calls.clear();
        self.fors.clear();
        Outcome::Fault(code, pc)
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
