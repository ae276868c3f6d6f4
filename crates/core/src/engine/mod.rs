//! The scan engine: input refresh → program → END processing (004 §4.3), in the
//! time of a [`Clock`] it is given.
//!
//! [`Cpu`] owns the device memory and one compiled program. Everything a scan
//! needs is allocated when the CPU is built; `scan` itself does no allocation.

pub mod calendar;
mod clock;
mod error;
mod exec;
mod operand;
mod special;

use std::time::Duration;

pub use clock::{Clock, MonotonicClock, VirtualClock};
pub use error::{CpuError, ErrorCode, Fault};

use crate::device::{DeviceConfig, DeviceKind, DeviceMemory};
use crate::program::compile::MAX_NESTING;
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
    /// Hidden edge memories of LDP/PLS/pulse forms/SCJ.
    pub edges: Box<[bool]>,
    /// Hidden state words of family instructions.
    pub state: Box<[u32]>,
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

/// A MELSEC-Q CPU running one program.
pub struct Cpu {
    program: Program,
    rt: Runtime,
    clock: Box<dyn Clock>,
    state: CpuState,
    /// Input image: what the input modules present; copied to X at input refresh.
    inputs: Box<[bool]>,
    /// Clock reading at power-on, at the last RUN and at the last END.
    power_on_us: u64,
    run_start_us: u64,
    last_end_us: u64,
    first_scan: bool,
    /// SM210 at the previous END, for its OFF→ON edge.
    sm210: bool,
    scans: u64,
    min_scan_us: Option<u64>,
    max_scan_us: Option<u64>,
}

impl Cpu {
    /// Powers on a CPU with `program` and puts it in RUN.
    pub fn new(program: Program, cfg: CpuConfig, clock: Box<dyn Clock>) -> Cpu {
        let mem = DeviceMemory::new(&cfg.devices);
        let timers = cfg.devices.points(DeviceKind::TS) + cfg.devices.points(DeviceKind::STS);
        let x = cfg.devices.points(DeviceKind::X) as usize;
        let now = clock.now_us();
        let mut cpu = Cpu {
            rt: Runtime {
                mem,
                edges: vec![false; program.edge_slots as usize].into_boxed_slice(),
                state: vec![0; program.state_words as usize].into_boxed_slice(),
                now_us: now,
                clock: calendar::PlcClock::new(cfg.clock_start, now),
                timer_rem: vec![0; timers as usize].into_boxed_slice(),
                timer_base_us: [
                    cfg.timer_low.as_micros().max(1) as u32,
                    cfg.timer_high.as_micros().max(1) as u32,
                ],
                scan_us: 0,
                mc_off: 0,
                calls: Vec::with_capacity(MAX_NESTING),
                fors: Vec::with_capacity(MAX_NESTING),
                stop_request: false,
                watchdog: cfg.watchdog,
                operation_error: cfg.operation_error,
                error: None,
            },
            program,
            clock,
            state: CpuState::Run,
            inputs: vec![false; x].into_boxed_slice(),
            power_on_us: now,
            run_start_us: now,
            last_end_us: now,
            first_scan: true,
            sm210: false,
            scans: 0,
            min_scan_us: None,
            max_scan_us: None,
        };
        special::power_on(&mut cpu.rt.mem);
        cpu
    }

    pub fn program(&self) -> &Program {
        &self.program
    }

    pub fn state(&self) -> CpuState {
        self.state
    }

    /// The latest self-diagnostic error (what SD0 holds), if any.
    pub fn error(&self) -> Option<&CpuError> {
        self.rt.error.as_ref()
    }

    /// Scans executed in RUN since power-on.
    pub fn scans(&self) -> u64 {
        self.scans
    }

    pub fn memory(&self) -> &DeviceMemory {
        &self.rt.mem
    }

    pub fn memory_mut(&mut self) -> &mut DeviceMemory {
        &mut self.rt.mem
    }

    /// Sets input X`n` as an input module would: it reaches X at the next input
    /// refresh and stays until set again.
    pub fn set_input(&mut self, n: u32, on: bool) {
        if let Some(b) = self.inputs.get_mut(n as usize) {
            *b = on;
        }
        let _ = self.rt.mem.set_bit(DeviceKind::X, n as i64, on);
    }

    /// The external output Y`n`: the Y device while running, OFF in STOP (004 §4.4).
    pub fn output(&self, n: u32) -> bool {
        self.state != CpuState::Stop
            && self
                .rt
                .mem
                .get_bit(DeviceKind::Y, n as i64)
                .unwrap_or(false)
    }

    /// Executes one scan: input refresh, the program, END processing. In STOP or
    /// PAUSE only END processing happens.
    pub fn scan(&mut self) {
        let now = self.clock.now_us();
        if self.state != CpuState::Run {
            self.last_end_us = now;
            return;
        }
        // Input refresh (004 §4.3): the input image into X.
        let xb = self.rt.mem.map.base(DeviceKind::X) as usize;
        self.rt.mem.bits[xb..xb + self.inputs.len()].copy_from_slice(&self.inputs);
        self.rt.now_us = now;
        special::scan_start(&mut self.rt.mem, now - self.power_on_us, self.first_scan);
        match exec::run(&self.program, &mut self.rt) {
            Outcome::End => {}
            Outcome::Fault(code, pc) => {
                self.rt.record_fault(&self.program, code, pc);
                self.state = CpuState::Stop;
                self.scans += 1;
                return;
            }
        }
        self.end_processing(now);
    }

    /// END processing: scan-time measurement and the scan SM/SD, STOP requests.
    fn end_processing(&mut self, now: u64) {
        let scan_us = now - self.last_end_us;
        self.last_end_us = now;
        self.rt.scan_us = scan_us.min(u32::MAX as u64) as u32;
        if !self.first_scan {
            // The first scan is excluded from the maximum (SD526/527).
            self.max_scan_us = Some(self.max_scan_us.unwrap_or(0).max(scan_us));
        }
        self.min_scan_us = Some(self.min_scan_us.map_or(scan_us, |m| m.min(scan_us)));
        self.scans += 1;
        special::end(
            &mut self.rt.mem,
            special::ScanTimes {
                current_us: scan_us,
                min_us: self.min_scan_us.unwrap_or(0),
                max_us: self.max_scan_us.unwrap_or(0),
                since_run_us: now - self.run_start_us,
            },
        );
        self.sm210 =
            special::clock_registers(&mut self.rt.mem, &mut self.rt.clock, now, self.sm210);
        self.first_scan = false;
        if self.rt.stop_request {
            self.rt.stop_request = false;
            self.state = CpuState::Stop;
        }
        special::set_status(&mut self.rt.mem, self.state);
    }
}

impl Cpu {
    /// Reads a device by name (`D10:f32`, `K4M0`, `TN0`).
    pub fn read_device(
        &self,
        spec: &crate::access::DeviceSpec,
    ) -> Result<crate::access::Value, String> {
        spec.read(&self.rt.mem)
    }

    /// Writes a device by name. Writes to X go to the input image as well, so the
    /// value survives the next input refresh.
    pub fn write_device(
        &mut self,
        spec: &crate::access::DeviceSpec,
        value: &str,
    ) -> Result<(), String> {
        spec.write(&mut self.rt.mem, value)?;
        if let Some((DeviceKind::X, first, count)) = spec.bit_span() {
            let xb = self.rt.mem.map.base(DeviceKind::X) as usize;
            for n in first as usize..(first + count) as usize {
                if let Some(b) = self.inputs.get_mut(n) {
                    *b = self.rt.mem.bits[xb + n];
                }
            }
        }
        Ok(())
    }
}
