//! The CPU: program scheduling by execution type, the scan cycle and the
//! operating states RUN/STOP/PAUSE with RESET and latch clear (004 ch. 4).
//!
//! `mod.rs` builds the CPU and gives access to it; [`states`] changes its
//! operating state, [`door`] is the typed access from outside (names, spans,
//! values, the input image), [`schedule`] runs a scan (program execution types,
//! low-speed and fixed-scan programs), [`interrupts`] the interrupt requests
//! and their service, [`end`] is END processing
//! and the monitors, [`retained`] the battery-backed memory image,
//! [`journal`] tells a recording every change from outside.

mod door;
mod end;
mod force;
mod interrupts;
pub(crate) use interrupts::Requests;
mod journal;
pub use journal::{DoorEvent, Journal};
mod online;
pub use online::{OnlineLimits, Written};
mod rack;
pub(crate) use force::Force;
mod remote;
pub use remote::{Hold, Refusal};
mod retained;
mod schedule;
mod snapshot;
mod states;
mod system_block;

use std::time::Duration;

use super::exec::{self, Outcome};
use super::{
    Clock, CpuConfig, CpuError, CpuState, ErrorCode, ExecType, ProgState, RunClear, Runtime,
    StopToRunOutput,
};
use softplc_ir::calendar::PlcClock;
use softplc_ir::cpu::CpuServices;
use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::ops::Program;
use softplc_ir::ops::MAX_NESTING;

/// A compiled program with its execution type, as the PLC parameter lists it.
#[derive(Debug)]
pub struct LoadedProgram {
    pub program: Program,
    pub exec: ExecType,
    /// Interval of a fixed-scan program.
    pub interval: Option<Duration>,
    /// Simulated execution time of one run of the program (a softplc parameter
    /// for virtual time; `None` = instantaneous). It decides how much of the
    /// constant-scan spare time or low-speed execution time low-speed programs
    /// use (004 §4.2.3).
    pub sim_time: Option<Duration>,
    /// The program's "local device" file setting: `true` ("use the PLC
    /// file setting", the default) gives it its own copy of the local-device
    /// ranges; `false` ("not used") runs it on whatever local devices the
    /// program before it left (004 L1381, §10.13.1 (d) 3)).
    pub local_devices: bool,
}

/// One row of the program monitor list (004 §7.11, qcpu.md §4.9): execution
/// count (wraps at 65536) and execution time of a program file: the host's
/// wall-clock time in real time; in virtual time, where a program takes
/// no time but its simulated execution time, that time (0 without one).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgramMonitor {
    pub file: String,
    pub exec: ExecType,
    pub count: u16,
    /// Time of its last run and the longest run.
    pub last: Duration,
    pub max: Duration,
}

/// The index registers kept apart for low-speed programs and saved around
/// fixed-scan programs: Z0-Z15 (004 §10.6.1, §10.6.2).
const LOW_Z: usize = 16;

/// Scheduling state of a program file in the CPU.
struct Slot {
    exec: ExecType,
    interval_us: u64,
    /// POFF: run once with conditions OFF at the next scan.
    off_pending: bool,
    /// Simulated execution time of one run, µs.
    cost_us: u64,
    /// Program monitor: runs (wrapping) and host time of the last and longest run.
    count: u16,
    last_ns: u64,
    max_ns: u64,
    /// Engine time at which a fixed-scan program runs next.
    next_due_us: u64,
    /// Steps the file may grow to by writes during RUN: its steps at load
    /// and the reserve ([`OnlineLimits::reserve_steps`]).
    capacity_steps: u32,
}

/// A MELSEC-Q CPU with its programs.
pub struct Cpu {
    /// The program files in parameter order, their hidden state and scheduling.
    programs: Vec<Program>,
    /// Native code of each program (`use_tier`), or empty: the interpreter.
    natives: Vec<Box<dyn crate::tier::NativeProgram>>,
    /// The tier that compiled them, for a program written during RUN.
    tier: Option<Box<dyn crate::tier::ExecTier + Send + Sync>>,
    tier_stats: Option<crate::tier::TierStats>,
    /// Programs written during RUN so far ([`Cpu::replace_program`]).
    program_writes: u64,
    locals: Vec<ProgState>,
    slots: Vec<Slot>,
    rt: Runtime,
    cfg: CpuConfig,
    clock: Box<dyn Clock>,
    /// The clock is virtual ([`Clock::is_virtual`]): the program monitor
    /// takes no wall-clock readings.
    virtual_time: bool,
    state: CpuState,
    /// A stop error holds the CPU in STOP until RESET.
    stop_error: bool,
    /// The STOP and PAUSE sources of the remote operations (004 §7.6).
    remote: remote::RemoteState,
    /// What stopped or paused the CPU (shown while it is stopped or paused).
    cause: softplc_ir::system::Cause,
    /// Y device memory saved at RUN→STOP (STOP→RUN output mode "previous").
    saved_y: Box<[bool]>,
    /// Bit n: X`n` (X0-X63) turned ON in the input image since the last
    /// scan start (the pulse catch) or, in STOP, since the last END (the
    /// run input).
    input_rises: u64,
    /// Bit n: X`n` (X0-X63) turned OFF in the input image since the last
    /// scan start.
    input_falls: u64,
    /// The STOP instruction stopped the CPU (the switch stays at RUN for
    /// the run input, `system_block.rs`); cleared by the next STOP or RUN.
    stopped_by_instruction: bool,
    /// Clock reading at power-on, at the last STOP→RUN and at the last END.
    power_on_us: u64,
    run_start_us: u64,
    last_end_us: u64,
    /// The initial programs have yet to run (power-on, RESET, STOP→RUN).
    initial_pending: bool,
    /// The first scan after RUN.
    first_scan: bool,
    scans: u64,
    min_scan_us: Option<u64>,
    max_scan_us: Option<u64>,
    /// Interrupt programs: In → (slot, op index).
    interrupts: Vec<Option<(usize, u32)>>,
    /// Interrupt program executions per In (monitor list, wrapping).
    int_counts: Vec<u16>,
    /// Next occurrence of I28-I31.
    int_due: [u64; 4],
    /// The program's error reset request at the previous END, for its
    /// rising edge (`System::error_reset`).
    error_reset: bool,
    trace: Option<crate::trace::Trace>,
    /// Simulated time used by the programs of the current scan, µs.
    busy_us: u64,
    /// Low-speed programs in progress: position in the cycle, simulated time
    /// still owed by the running program, start of the cycle (µs).
    low_pos: usize,
    low_left_us: u64,
    /// Simulated low-speed execution time of the current cycle, µs.
    low_exec_us: u64,
    /// Low-speed scan bookkeeping (first cycle, scan times).
    low_first: bool,
    /// Engine time of the last low-speed END.
    low_last_end_us: u64,
    /// The low-speed side of the context swapped at each switch between
    /// scan and low-speed programs (`Cpu::switch_low_speed_context`): its
    /// index registers Z0-Z15 (004 §10.6.1) and the time its timers add
    /// (§10.2.10 (f)).
    low_z: [u16; LOW_Z],
    low_timer_us: u32,
    /// Simulated time the low-speed programs used in this scan, µs.
    low_used_us: u64,
    low_min_us: Option<u64>,
    low_max_us: u64,
    /// The rack's modules and interrupt requests.
    rack: rack::RackState,
    /// Told every change from outside ([`journal`]).
    journal: Option<Box<dyn Journal>>,
}

impl Cpu {
    /// Powers on a CPU with one scan program and puts it in RUN.
    ///
    /// Panics when `program` was compiled for other device points than
    /// `cfg.devices` (use [`Cpu::with_programs`] to get an error instead).
    pub fn new(program: Program, cfg: CpuConfig, clock: Box<dyn Clock>) -> Cpu {
        let p = LoadedProgram {
            program,
            exec: ExecType::Scan,
            interval: None,
            sim_time: None,
            local_devices: true,
        };
        Cpu::with_programs(vec![p], cfg, clock)
            .expect("the program was compiled for the CPU's device points")
    }

    /// Powers on a CPU with the programs of a project (in parameter order) and puts
    /// it in RUN. Fails when the programs do not link: a CALL to a common pointer
    /// no program defines, a common or interrupt pointer defined twice.
    pub fn with_programs(
        programs: Vec<LoadedProgram>,
        mut cfg: CpuConfig,
        clock: Box<dyn Clock>,
    ) -> Result<Cpu, String> {
        cfg.latch = crate::local_devices::without_locals(&cfg.latch, &cfg.local_devices);
        let mut mem = DeviceMemory::new(&cfg.devices);
        let r_block = cfg.system.r_block(&mem.map);
        mem.map.set_r_block(r_block);
        let timers = cfg.devices.points(DeviceKind::TS) + cfg.devices.points(DeviceKind::STS);
        let x = cfg.devices.points(DeviceKind::X) as usize;
        let y = cfg.devices.points(DeviceKind::Y) as usize;
        let now = clock.now_us();
        let slots: Vec<Slot> = programs
            .iter()
            .map(|p| Slot {
                cost_us: p.sim_time.map_or(0, |d| d.as_micros() as u64),
                count: 0,
                last_ns: 0,
                max_ns: 0,
                interval_us: p.interval.map_or(0, |d| d.as_micros().max(1) as u64),
                next_due_us: now,
                off_pending: false,
                exec: p.exec,
                capacity_steps: p.program.steps.saturating_add(cfg.online.reserve_steps),
            })
            .collect();
        let uses_locals: Vec<bool> = programs.iter().map(|p| p.local_devices).collect();
        let local_devices = crate::local_devices::LocalDevices::new(
            &cfg.local_devices,
            &uses_locals,
            &mem,
            cfg.system.local_device_relays(&mem.map),
        )?;
        let mut programs: Vec<Program> = programs.into_iter().map(|p| p.program).collect();
        // Compiled indices are only valid for the device layout they were compiled
        // for (004 §10: device points are a parameter).
        if let Some(p) = programs
            .iter()
            .find(|p| p.bit_len != mem.map.bit_len() || p.word_len != mem.map.word_len())
        {
            return Err(format!(
                "{} was compiled for other device points than this CPU's parameters",
                p.file
            ));
        }
        let interrupts = crate::link::link(&mut programs, &*cfg.system)?;
        let locals = programs.iter().map(ProgState::new).collect();
        let rt = Runtime {
            mem,
            now_us: now,
            clock: PlcClock::new(cfg.clock_start, now),
            shared: vec![0; programs.iter().map(|p| p.shared_words).max().unwrap_or(0) as usize]
                .into_boxed_slice(),
            timer_base_us: [
                cfg.timer_low.as_micros().max(1) as u32,
                cfg.timer_high.as_micros().max(1) as u32,
            ],
            scan_us: 0,
            mc_off: 0,
            calls: Vec::with_capacity(MAX_NESTING),
            fors: Vec::with_capacity(MAX_NESTING),
            stop_request: false,
            stop_now: false,
            watchdog: wall_watchdog(cfg.watchdog, clock.is_virtual()),
            watchdog_set: cfg.watchdog,
            abort: Default::default(),
            operation_error: cfg.operation_error,
            module_error: cfg.module_error,
            file_error: cfg.file_error,
            rack: cfg.rack.clone(),
            error: None,
            history: std::collections::VecDeque::with_capacity(crate::HISTORY_LEN),
            in_interrupt: false,
            requests: Requests::default(),
            stop_interrupt: None,
            cpu: CpuServices::new(slots.len(), timers as usize, cfg.system.interrupt_mask()),
            force_off: false,
            system_state: vec![0; cfg.system.state_words()].into_boxed_slice(),
            inputs: vec![false; x].into_boxed_slice(),
            input_spans: rack::input_spans(&cfg.rack, x as u32),
            forces: Vec::new(),
            programs_write_x: programs.iter().any(|p| p.may_write_x),
            x_holds_image: false,
            local_devices,
            system: cfg.system.clone(),
        };
        let rack = rack::RackState::new(&cfg.rack, &rt.mem);
        let mut cpu = Cpu {
            rack,
            programs,
            natives: Vec::new(),
            tier: None,
            tier_stats: None,
            program_writes: 0,
            locals,
            slots,
            rt,
            cfg,
            virtual_time: clock.is_virtual(),
            clock,
            state: CpuState::Run,
            stop_error: false,
            remote: Default::default(),
            cause: softplc_ir::system::Cause::Switch,
            saved_y: vec![false; y].into_boxed_slice(),
            input_rises: 0,
            input_falls: 0,
            stopped_by_instruction: false,
            power_on_us: now,
            run_start_us: now,
            last_end_us: now,
            initial_pending: true,
            first_scan: true,
            scans: 0,
            min_scan_us: None,
            max_scan_us: None,
            interrupts,
            int_counts: vec![0; 256],
            int_due: [0; 4],
            error_reset: false,
            trace: None,
            busy_us: 0,
            low_pos: 0,
            low_left_us: 0,
            low_exec_us: 0,
            low_first: true,
            low_last_end_us: 0,
            low_z: [0; LOW_Z],
            low_timer_us: 0,
            low_used_us: 0,
            low_min_us: None,
            low_max_us: 0,
            journal: None,
        };
        cpu.power_on();
        Ok(cpu)
    }

    /// Runs the programs on `tier` from the next scan: each program is
    /// compiled now (the interpreter still runs whatever the tier leaves to
    /// it). On an error the CPU keeps the interpreter.
    pub fn use_tier(
        &mut self,
        tier: &dyn crate::tier::ExecTier,
    ) -> Result<&crate::tier::TierStats, String> {
        let t = std::time::Instant::now();
        let natives = self
            .programs
            .iter()
            .map(|p| tier.compile(p).map_err(|e| format!("{}: {e}", p.file)))
            .collect::<Result<Vec<_>, _>>()?;
        let stats = crate::tier::TierStats {
            tier: tier.name(),
            compile: t.elapsed(),
            ops: self.programs.iter().map(|p| p.ops.len()).sum(),
            native_ops: natives.iter().map(|n| n.native_ops()).sum(),
            short_run_ops: natives.iter().map(|n| n.short_run_ops()).sum(),
            min_run: tier.min_run(),
        };
        self.natives = natives;
        self.tier = Some(tier.boxed());
        Ok(self.tier_stats.insert(stats))
    }

    /// Back to the interpreter alone.
    pub fn use_interpreter(&mut self) {
        self.natives.clear();
        self.tier = None;
        self.tier_stats = None;
    }

    /// The tier in use and its compile time; `None` for the interpreter.
    pub fn tier_stats(&self) -> Option<&crate::tier::TierStats> {
        self.tier_stats.as_ref()
    }

    pub fn program_count(&self) -> usize {
        self.programs.len()
    }

    /// Program file `i` in parameter order.
    pub fn program_at(&self, i: usize) -> &Program {
        &self.programs[i]
    }

    /// The first program (the only one of a single-file CPU).
    pub fn program(&self) -> &Program {
        &self.programs[0]
    }

    /// What this CPU is (its model, names and doors): what every door asks.
    pub fn profile(&self) -> &'static crate::Profile {
        self.cfg.profile
    }

    pub fn config(&self) -> &CpuConfig {
        &self.cfg
    }

    pub fn state(&self) -> CpuState {
        self.state
    }

    /// The latest self-diagnostic error, if any.
    pub fn error(&self) -> Option<&CpuError> {
        self.rt.error.as_ref()
    }

    /// The message of error `code` in this CPU's family.
    pub fn error_message(&self, code: ErrorCode) -> &'static str {
        self.rt.system.message(code)
    }

    /// The error history, oldest first (004 §7.20.2).
    pub fn history(&self) -> impl Iterator<Item = &crate::HistoryEntry> {
        self.rt.history.iter()
    }

    /// Scans executed in RUN since power-on.
    pub fn scans(&self) -> u64 {
        self.scans
    }

    /// Time on the engine clock since power-on (or RESET, which is power-on
    /// processing), µs.
    pub fn since_power_on_us(&self) -> u64 {
        self.clock.now_us().saturating_sub(self.power_on_us)
    }

    pub fn memory(&self) -> &DeviceMemory {
        &self.rt.mem
    }

    /// The program file (slot in parameter order) whose local devices
    /// device memory holds — what names, MC and HTTP read and write in a
    /// local range —, `None` when no program's are (no local devices, or
    /// none has run since they were cleared).
    pub fn local_devices_owner(&self) -> Option<usize> {
        self.rt.local_devices.as_ref().and_then(|l| l.owner())
    }

    /// Runs `f` on this CPU with device memory holding program file
    /// `slot`'s local devices, as that program sees them when it runs: the
    /// monitor's "chosen program" (004 §10.13.1). What `f` writes to a
    /// local device stays in that program's copy; the devices of the
    /// program whose local devices were in memory come back afterwards. A
    /// program without local devices (or a CPU without them) sees device
    /// memory as it is. Between scans only: at END, in STOP or PAUSE.
    pub fn with_local_devices_of<R>(&mut self, slot: usize, f: impl FnOnce(&mut Cpu) -> R) -> R {
        self.note(DoorEvent::LocalsOf { slot });
        let back = self.rt.show_locals(slot);
        let r = f(self);
        self.rt.leave_locals(back);
        self.note(DoorEvent::LocalsEnd);
        r
    }

    /// Whether program file `slot` has its own copy of device `kind` `n`: it
    /// uses local devices and the device is in a local range.
    pub fn is_local_to(&self, slot: usize, kind: DeviceKind, n: u32) -> bool {
        self.rt
            .local_devices
            .as_ref()
            .is_some_and(|l| l.used_by(slot))
            && self
                .cfg
                .local_devices
                .iter()
                .any(|r| r.kind.range_kind() == kind.range_kind() && (r.start..=r.end).contains(&n))
    }

    /// The program file named `name`: its file name as given in the
    /// project, or that name's last component with or without its
    /// extension, in any case.
    pub fn program_slot(&self, name: &str) -> Option<usize> {
        let name = name.to_ascii_lowercase();
        self.programs.iter().position(|p| {
            let path = std::path::Path::new(&p.file);
            let full = p.file.to_ascii_lowercase();
            let file = path
                .file_name()
                .map(|f| f.to_string_lossy().to_ascii_lowercase());
            let stem = path
                .file_stem()
                .map(|f| f.to_string_lossy().to_ascii_lowercase());
            full == name || file.as_deref() == Some(&name) || stem.as_deref() == Some(&name)
        })
    }

    /// The watchdog time the scan checks in wall-clock time (see
    /// [`wall_watchdog`]).
    pub(crate) fn wall_watchdog(&self, t: std::time::Duration) -> std::time::Duration {
        wall_watchdog(t, self.clock.is_virtual())
    }

    /// Reads the engine clock (µs), for a tool outside the scan (a serial
    /// port's timeouts): a look that drives nothing in the CPU
    /// ([`Clock::peek_us`]).
    pub fn now_us(&self) -> u64 {
        self.clock.peek_us()
    }

    /// The external output Y`n`: the Y device while running or paused, in
    /// STOP as the STOP output setting says (OFF on MELSEC-Q, 004 §4.4); a
    /// forced output's forced value.
    pub fn output(&self, n: u32) -> bool {
        if let Some(f) = self
            .rt
            .forces
            .iter()
            .find(|f| f.kind == DeviceKind::Y && f.n == n)
        {
            // A forced output is output in every state (docs/forcing.md).
            return f.on;
        }
        if self.state == CpuState::Stop {
            return self.stop_output(n);
        }
        self.rt
            .mem
            .get_bit(DeviceKind::Y, n as i64)
            .unwrap_or(false)
    }

    // --- operating states (004 §4.4, §7.5, §7.8) ---
}

/// Under virtual time the watchdog is at least this long in wall-clock time.
/// Instructions take no virtual time, so a real CPU's WDT ERROR from a long
/// scan has no deterministic counterpart; the watchdog still stops an
/// endless scan, but a machine under load (a preempted engine thread) does
/// not turn an ordinary scan into a watchdog error (COMPATIBILITY.md "Watchdog").
pub const VIRTUAL_WATCHDOG_FLOOR: std::time::Duration = std::time::Duration::from_secs(1);

fn wall_watchdog(t: std::time::Duration, virtual_time: bool) -> std::time::Duration {
    if virtual_time {
        t.max(VIRTUAL_WATCHDOG_FLOOR)
    } else {
        t
    }
}

#[cfg(test)]
mod watchdog_tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn virtual_time_raises_the_wall_clock_watchdog_to_its_floor() {
        let ms = Duration::from_millis;
        assert_eq!(wall_watchdog(ms(200), true), VIRTUAL_WATCHDOG_FLOOR);
        assert_eq!(wall_watchdog(ms(200), false), ms(200));
        assert_eq!(wall_watchdog(ms(2000), true), ms(2000));
    }
}
