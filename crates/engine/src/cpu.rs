//! The CPU: program scheduling by execution type, the scan cycle and the
//! operating states RUN/STOP/PAUSE with RESET and latch clear (004 ch. 4).

use std::time::Duration;

use super::exec::{self, Outcome};
use super::special;
use super::{
    Clock, CpuConfig, CpuError, CpuState, ErrorCode, ExecType, ProgState, Runtime, StopToRunOutput,
};
use softplc_ir::access::{DeviceSpec, Value};
use softplc_ir::calendar::PlcClock;
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
}

/// One row of the program monitor list (004 §7.11, qcpu.md §4.9): execution
/// count (wraps at 65536) and host execution time of a program file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgramMonitor {
    pub file: String,
    pub exec: ExecType,
    pub count: u16,
    /// Wall-clock time of its last run and the longest run.
    pub last: Duration,
    pub max: Duration,
}

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
}

/// A MELSEC-Q CPU with its programs.
pub struct Cpu {
    /// The program files in parameter order, their hidden state and scheduling.
    programs: Vec<Program>,
    locals: Vec<ProgState>,
    slots: Vec<Slot>,
    rt: Runtime,
    cfg: CpuConfig,
    clock: Box<dyn Clock>,
    state: CpuState,
    /// A stop error holds the CPU in STOP until RESET.
    stop_error: bool,
    /// Input image: what the input modules present; copied to X at input refresh.
    inputs: Box<[bool]>,
    /// Y device memory saved at RUN→STOP (STOP→RUN output mode "previous").
    saved_y: Box<[bool]>,
    /// Clock reading at power-on, at the last STOP→RUN and at the last END.
    power_on_us: u64,
    run_start_us: u64,
    last_end_us: u64,
    /// The initial programs have yet to run (power-on, RESET, STOP→RUN).
    initial_pending: bool,
    /// SM402/SM403: first scan after RUN.
    first_scan: bool,
    /// SM210 at the previous END, for its OFF→ON edge.
    sm210: bool,
    scans: u64,
    min_scan_us: Option<u64>,
    max_scan_us: Option<u64>,
    /// Interrupt programs: In → (slot, op index).
    interrupts: Vec<Option<(usize, u32)>>,
    /// Interrupt program executions per In (monitor list, wrapping).
    int_counts: Vec<u16>,
    /// Next occurrence of I28-I31 and causes remembered while disabled.
    int_due: [u64; 4],
    int_pending: [bool; 4],
    /// SM50 at the previous END, for its OFF→ON edge.
    sm50: bool,
    trace: Option<super::trace::Trace>,
    /// Simulated time used by the programs of the current scan, µs.
    busy_us: u64,
    /// Low-speed programs in progress: position in the cycle, simulated time
    /// still owed by the running program, start of the cycle (µs).
    low_pos: usize,
    low_left_us: u64,
    /// Simulated low-speed execution time of the current cycle, µs.
    low_exec_us: u64,
    /// Low-speed scan bookkeeping (SM404/405, SD528-SD535).
    low_first: bool,
    low_last_end_us: u64,
    low_min_us: Option<u64>,
    low_max_us: u64,
}

/// IMASK at power-on: everything enabled except the error interrupts I32-I47,
/// which need IMASK (004 L10902-10904).
const DEFAULT_IMASK: [u16; 16] = {
    let mut m = [0xFFFF; 16];
    m[2] = 0;
    m
};

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
        };
        Cpu::with_programs(vec![p], cfg, clock)
            .expect("the program was compiled for the CPU's device points")
    }

    /// Powers on a CPU with the programs of a project (in parameter order) and puts
    /// it in RUN. Fails when the programs do not link: a CALL to a common pointer
    /// no program defines, a common or interrupt pointer defined twice.
    pub fn with_programs(
        programs: Vec<LoadedProgram>,
        cfg: CpuConfig,
        clock: Box<dyn Clock>,
    ) -> Result<Cpu, String> {
        let mem = DeviceMemory::new(&cfg.devices);
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
            })
            .collect();
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
        let interrupts = super::link::link(&mut programs)?;
        let locals = programs.iter().map(ProgState::new).collect();
        let rt = Runtime {
            mem,
            now_us: now,
            clock: PlcClock::new(cfg.clock_start, now),
            shared: vec![0; programs.iter().map(|p| p.shared_words).max().unwrap_or(0) as usize]
                .into_boxed_slice(),
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
            wdt_start: std::time::Instant::now(),
            abort: Default::default(),
            operation_error: cfg.operation_error,
            error: None,
            history: std::collections::VecDeque::with_capacity(super::HISTORY_LEN),
            ei: false,
            imask: DEFAULT_IMASK,
            in_interrupt: false,
            type_requests: vec![None; slots.len()].into_boxed_slice(),
            force_off: false,
            duty: [None; 10],
            trace_trigger: false,
            trace_reset: false,
        };
        let mut cpu = Cpu {
            programs,
            locals,
            slots,
            rt,
            cfg,
            clock,
            state: CpuState::Run,
            stop_error: false,
            inputs: vec![false; x].into_boxed_slice(),
            saved_y: vec![false; y].into_boxed_slice(),
            power_on_us: now,
            run_start_us: now,
            last_end_us: now,
            initial_pending: true,
            first_scan: true,
            sm210: false,
            scans: 0,
            min_scan_us: None,
            max_scan_us: None,
            interrupts,
            int_counts: vec![0; 256],
            int_due: [0; 4],
            int_pending: [false; 4],
            sm50: false,
            trace: None,
            busy_us: 0,
            low_pos: 0,
            low_left_us: 0,
            low_exec_us: 0,
            low_first: true,
            low_last_end_us: 0,
            low_min_us: None,
            low_max_us: 0,
        };
        cpu.power_on();
        Ok(cpu)
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

    pub fn config(&self) -> &CpuConfig {
        &self.cfg
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

    /// Reads the engine clock (µs).
    pub fn now_us(&self) -> u64 {
        self.clock.now_us()
    }

    /// Sets input X`n` as an input module would: it reaches X at the next input
    /// refresh and stays until set again.
    pub fn set_input(&mut self, n: u32, on: bool) {
        if let Some(b) = self.inputs.get_mut(n as usize) {
            *b = on;
        }
        let _ = self.rt.mem.set_bit(DeviceKind::X, n as i64, on);
    }

    /// The external output Y`n`: the Y device while running or paused, OFF in
    /// STOP (004 §4.4).
    pub fn output(&self, n: u32) -> bool {
        self.state != CpuState::Stop
            && self
                .rt
                .mem
                .get_bit(DeviceKind::Y, n as i64)
                .unwrap_or(false)
    }

    /// Reads a device by name (`D10:f32`, `K4M0`, `TN0`).
    pub fn read_device(&self, spec: &DeviceSpec) -> Result<Value, String> {
        spec.read(&self.rt.mem)
    }

    /// Writes a device by name. Writes to X go to the input image as well, so the
    /// value survives the next input refresh.
    pub fn write_device(&mut self, spec: &DeviceSpec, value: &str) -> Result<(), String> {
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

    // --- operating states (004 §4.4, §7.5, §7.8) ---

    /// RUN (key switch or remote RUN). From STOP this is STOP→RUN: outputs per the
    /// "STOP→RUN output" parameter, device initial values written, the initial
    /// programs run again. Refused while a stop error is held (RESET first).
    pub fn set_run(&mut self) -> Result<(), String> {
        match self.state {
            CpuState::Run => Ok(()),
            CpuState::Pause => {
                self.state = CpuState::Run;
                special::set_status(&mut self.rt.mem, self.state);
                Ok(())
            }
            CpuState::Stop if self.stop_error => Err(format!(
                "the CPU is stopped by error {}; RESET it first",
                self.rt.error.as_ref().map_or(0, |e| e.code.0)
            )),
            CpuState::Stop => {
                let yb = self.rt.mem.map.base(DeviceKind::Y) as usize;
                let y = &mut self.rt.mem.bits[yb..yb + self.saved_y.len()];
                match self.cfg.stop_to_run_output {
                    StopToRunOutput::Previous => y.copy_from_slice(&self.saved_y),
                    StopToRunOutput::Recalculate => y.fill(false),
                }
                self.start_run();
                Ok(())
            }
        }
    }

    /// STOP (key switch or remote STOP): the Y image is saved and the external
    /// outputs go OFF; device memory is kept.
    pub fn set_stop(&mut self) {
        if self.state != CpuState::Stop {
            let yb = self.rt.mem.map.base(DeviceKind::Y) as usize;
            let n = self.saved_y.len();
            self.saved_y.copy_from_slice(&self.rt.mem.bits[yb..yb + n]);
            self.state = CpuState::Stop;
            special::set_status(&mut self.rt.mem, self.state);
        }
    }

    /// PAUSE (remote PAUSE): the program stops with outputs held.
    pub fn set_pause(&mut self) -> Result<(), String> {
        match self.state {
            CpuState::Stop => Err("PAUSE is possible only from RUN".into()),
            _ => {
                self.state = CpuState::Pause;
                special::set_status(&mut self.rt.mem, self.state);
                Ok(())
            }
        }
    }

    /// RESET (switch or remote RESET, accepted in STOP): the same processing as
    /// power-on — devices outside the latch ranges cleared, errors cleared — then
    /// RUN as the key switch says.
    pub fn reset(&mut self) -> Result<(), String> {
        if self.state != CpuState::Stop {
            return Err("RESET is accepted only in STOP".into());
        }
        self.power_on();
        Ok(())
    }

    /// Latch clear (accepted in STOP). The L.CLR switch clears the latch (1)
    /// ranges; a remote latch clear also clears latch (2), every device outside
    /// the latch ranges and the error (qcpu.md §4.2, [CONFLICT] 11). File
    /// registers are never cleared by latch clear (004 L7028-7031).
    pub fn latch_clear(&mut self, remote: bool) -> Result<(), String> {
        if self.state != CpuState::Stop {
            return Err("latch clear is accepted only in STOP".into());
        }
        let ranges: Vec<_> = self
            .cfg
            .latch
            .iter()
            .filter(|r| r.clearable || remote)
            .copied()
            .collect();
        for r in &ranges {
            for (bit, start, len) in latch_spans(&self.rt.mem, r) {
                if bit {
                    self.rt.mem.bits[start..start + len].fill(false);
                } else {
                    self.rt.mem.words[start..start + len].fill(0);
                }
            }
        }
        if remote {
            self.clear_unlatched();
            self.rt.error = None;
            self.rt.history.clear();
            self.stop_error = false;
            special::power_on(&mut self.rt.mem);
        }
        Ok(())
    }

    /// Power-on / RESET processing (004 §4.3 table): devices outside the latch
    /// ranges and the file registers cleared, system registers set, device initial
    /// values written, RUN from the initial programs.
    fn power_on(&mut self) {
        self.clear_unlatched();
        self.rt.error = None;
        self.stop_error = false;
        self.rt.timer_rem.fill(0);
        self.rt.ei = false;
        self.rt.imask = DEFAULT_IMASK;
        self.rt.duty = [None; 10];
        let now = self.clock.now_us();
        self.power_on_us = now;
        self.min_scan_us = None;
        self.max_scan_us = None;
        special::power_on(&mut self.rt.mem);
        self.start_run();
    }

    /// Common part of power-on and STOP→RUN.
    fn start_run(&mut self) {
        let now = self.clock.now_us();
        for l in &mut self.locals {
            l.clear();
        }
        self.rt.shared.fill(0);
        for s in &mut self.slots {
            s.next_due_us = now + s.interval_us;
        }
        for (k, p) in self.cfg.interrupt_periods.iter().enumerate() {
            self.int_due[k] = now + p.as_micros().max(1) as u64;
        }
        self.write_initial_values();
        self.run_start_us = now;
        self.last_end_us = now;
        self.low_last_end_us = now;
        self.low_exec_us = 0;
        self.low_pos = 0;
        self.low_left_us = 0;
        self.low_first = true;
        self.initial_pending = true;
        self.first_scan = true;
        self.state = CpuState::Run;
        special::set_status(&mut self.rt.mem, self.state);
    }

    fn write_initial_values(&mut self) {
        for iv in &self.cfg.initial_values {
            // Validated when the project was loaded.
            let _ = iv.device.write(&mut self.rt.mem, &iv.value);
        }
    }

    /// Clears every device except the latch ranges and the file registers.
    fn clear_unlatched(&mut self) {
        let mem = &mut self.rt.mem;
        let keep_words = |mem: &DeviceMemory| {
            let zr = mem.map.base(DeviceKind::ZR) as usize;
            zr..zr + mem.map.points(DeviceKind::ZR) as usize
        };
        let zr = keep_words(mem);
        let mut saved_words: Vec<(usize, Vec<u16>)> =
            vec![(zr.start, mem.words[zr.clone()].to_vec())];
        let mut saved_bits: Vec<(usize, Vec<bool>)> = Vec::new();
        for r in &self.cfg.latch {
            for (bit, start, len) in latch_spans(mem, r) {
                if bit {
                    saved_bits.push((start, mem.bits[start..start + len].to_vec()));
                } else {
                    saved_words.push((start, mem.words[start..start + len].to_vec()));
                }
            }
        }
        mem.clear();
        for (start, v) in saved_bits {
            mem.bits[start..start + v.len()].copy_from_slice(&v);
        }
        for (start, v) in saved_words {
            mem.words[start..start + v.len()].copy_from_slice(&v);
        }
    }

    // --- the scan ---

    /// Executes one scan. In RUN: input refresh, fixed-scan programs that are due,
    /// the scan programs in parameter order, one pass of the low-speed programs,
    /// END processing. Right after power-on, RESET or STOP→RUN the scan runs the
    /// initial programs instead, followed by one END (004 §4.2.1). In STOP and
    /// PAUSE only END processing happens.
    pub fn scan(&mut self) {
        let now = self.clock.now_us();
        if self.state != CpuState::Run {
            self.last_end_us = now;
            return;
        }
        self.rt.now_us = now;
        self.busy_us = 0;
        // The watchdog covers the whole scan (004 §7.9), reset only by END and WDT.
        self.rt.wdt_start = std::time::Instant::now();
        let xb = self.rt.mem.map.base(DeviceKind::X) as usize;
        self.rt.mem.bits[xb..xb + self.inputs.len()].copy_from_slice(&self.inputs);
        special::scan_start(&mut self.rt.mem, now - self.power_on_us, self.first_scan);
        let initial =
            self.initial_pending && self.slots.iter().any(|s| s.exec == ExecType::Initial);
        self.initial_pending = false;
        let ok = if initial {
            // The initial execution monitor time, when set, replaces the WDT for
            // the initial programs (004 L1446-1503).
            let wdt = self.rt.watchdog;
            if let Some(t) = self.cfg.initial_monitor {
                self.rt.watchdog = t;
            }
            let ok = self.service_interrupts(now) && self.run_type(ExecType::Initial);
            self.rt.watchdog = wdt;
            ok
        } else {
            self.service_interrupts(now)
                && self.run_off_pending()
                && self.run_fixed_scan(now)
                && self.run_type(ExecType::Scan)
                && self.run_low_speed(now)
        };
        if !ok && self.aborted() {
            // Stopped by the host mid-scan: STOP, no error.
            self.set_stop();
            self.scans += 1;
            return;
        }
        if !ok {
            // Stop error: the CPU stops at the point of detection, outputs OFF.
            self.stop_error = true;
            self.set_stop();
            self.scans += 1;
            return;
        }
        self.end_processing(now, initial);
    }

    /// Runs every program of one execution type in parameter order; false on a
    /// stop error.
    fn run_type(&mut self, exec: ExecType) -> bool {
        for i in 0..self.slots.len() {
            if self.slots[i].exec == exec && !self.run_slot(i) {
                return false;
            }
        }
        true
    }

    /// POFF: the program runs once with its conditions forced OFF, which turns
    /// its coils OFF (qcpu.md §2.2 table), before becoming a standby program.
    fn run_off_pending(&mut self) -> bool {
        for i in 0..self.slots.len() {
            if std::mem::take(&mut self.slots[i].off_pending) {
                self.rt.force_off = true;
                let ok = self.run_slot(i);
                self.rt.force_off = false;
                if !ok {
                    return false;
                }
            }
        }
        true
    }

    /// One pass of the low-speed programs (see ARCHITECTURE.md: execution takes no
    /// virtual time, so a pass always fits the spare time). SM510 is ON and SD510
    /// holds the program number while one runs; SM404/SM405 are the low-speed
    /// first-scan pulses; low-speed END sets SD528-SD535 and counts SD430.
    fn run_low_speed(&mut self, _now: u64) -> bool {
        // The low-speed programs in parameter order, without allocating.
        let n_low = self
            .slots
            .iter()
            .filter(|s| s.exec == ExecType::LowSpeed)
            .count();
        if n_low == 0 {
            return true;
        }

        let first = self.low_first;
        self.sm(404, first);
        self.sm(405, !first);
        let sync = self.rt.mem.get_bit(DeviceKind::SM, 330).unwrap_or(false);
        let timed = self
            .slots
            .iter()
            .any(|s| s.exec == ExecType::LowSpeed && s.cost_us > 0);
        // The time low-speed programs may use in this scan (004 §4.2.3): the
        // low-speed execution time, or the constant-scan spare time less 0.5 ms
        // (none when the spare time is 0.5 ms or less).
        let budget = match (self.cfg.low_speed_time, self.cfg.constant_scan) {
            (Some(l), _) => l.as_micros() as u64,
            (None, Some(c)) => (c.as_micros() as u64)
                .saturating_sub(self.busy_us)
                .saturating_sub(500),
            (None, None) => 0,
        };
        if !timed {
            // Without simulated execution times a cycle takes no time: one
            // complete cycle per scan.
            self.low_pos = 0;
            self.low_left_us = 0;
            for k in 0..n_low {
                if !self.run_low(self.low_slot(k)) {
                    return false;
                }
            }
            self.low_speed_end();
            return true;
        }
        let mut used = 0u64;
        loop {
            if self.low_pos >= n_low {
                self.low_pos = 0;
            }
            if self.low_left_us > 0 {
                // The suspended program continues (004 §4.2.3 (3)(b)).
                let d = self.low_left_us.min(budget - used);
                self.low_left_us -= d;
                self.low_exec_us += d;
                used += d;
                if self.low_left_us > 0 {
                    break;
                }
            } else {
                if used >= budget {
                    break;
                }
                let i = self.low_slot(self.low_pos);
                if !self.run_low(i) {
                    return false;
                }
                self.low_left_us = self.slots[i].cost_us;
                continue;
            }
            // The running program completed.
            self.low_pos += 1;
            if self.low_pos == n_low {
                self.low_pos = 0;
                self.low_speed_end();
                if sync {
                    // Synchronous (SM330 ON): no second cycle in the same scan.
                    break;
                }
            }
        }
        self.busy_us += used;
        self.sm(510, false);
        true
    }

    /// The slot of the `k`-th low-speed program in parameter order.
    fn low_slot(&self, k: usize) -> usize {
        (0..self.slots.len())
            .filter(|&i| self.slots[i].exec == ExecType::LowSpeed)
            .nth(k)
            .unwrap_or(0)
    }

    fn sm(&mut self, n: i64, v: bool) {
        let _ = self.rt.mem.set_bit(DeviceKind::SM, n, v);
    }

    /// Runs low-speed program `i` with SM510 ON and SD510 = its number (the
    /// simulated time is accounted by the caller).
    fn run_low(&mut self, i: usize) -> bool {
        self.sm(510, true);
        let _ = self.rt.mem.set_word(DeviceKind::SD, 510, i as u16 + 1);
        let cost = self.slots[i].cost_us;
        let ok = self.run_slot(i);
        self.busy_us -= cost;
        self.sm(510, false);
        ok
    }

    /// Low-speed END processing (004 §4.2.3 (5)): the low-speed scan time — the
    /// execution time of the cycle's low-speed programs (§4.2.3 (6)) — into
    /// SD528-SD535; SD430 counts.
    fn low_speed_end(&mut self) {
        let us = std::mem::take(&mut self.low_exec_us);
        if !self.low_first {
            self.low_max_us = self.low_max_us.max(us);
        }
        self.low_min_us = Some(self.low_min_us.map_or(us, |m| m.min(us)));
        for (reg, v) in [
            (528, us),
            (532, self.low_min_us.unwrap_or(0)),
            (534, self.low_max_us),
        ] {
            let (ms, sub) = special::ms_us(v);
            let _ = self.rt.mem.set_word(DeviceKind::SD, reg, ms);
            let _ = self.rt.mem.set_word(DeviceKind::SD, reg + 1, sub);
        }
        let c = self
            .rt
            .mem
            .get_word(DeviceKind::SD, 430)
            .unwrap_or(0)
            .wrapping_add(1);
        let _ = self.rt.mem.set_word(DeviceKind::SD, 430, c);
        self.low_first = false;
    }

    /// Simulated execution time of the last scan (programs run, low-speed time
    /// used), µs. With constant scan the scan takes the longer of this and the
    /// constant-scan period; a virtual-time driver may advance its clock by it.
    pub fn busy_us(&self) -> u64 {
        self.busy_us
    }

    /// Fixed-scan programs whose interval has elapsed, in parameter order. In
    /// virtual time a scan is instantaneous, so every interval that elapsed since
    /// the last scan runs the program once, before the scan programs.
    fn run_fixed_scan(&mut self, now: u64) -> bool {
        for i in 0..self.slots.len() {
            if self.slots[i].exec != ExecType::FixedScan {
                continue;
            }
            while self.slots[i].next_due_us <= now {
                let iv = self.slots[i].interval_us.max(1);
                self.slots[i].next_due_us += iv;
                if !self.run_slot(i) {
                    return false;
                }
            }
        }
        true
    }

    /// Fixed-cycle interrupts I28-I31 (004 §4.1.3, App. 3): every occurrence since
    /// the previous scan, in time order (I31 before I28 at the same instant, by
    /// priority), runs its interrupt program when EI and IMASK allow it; a cause
    /// occurring while disabled is remembered once and runs when enabled.
    fn service_interrupts(&mut self, now: u64) -> bool {
        if self.interrupts[28..32].iter().all(Option::is_none) {
            return true;
        }
        const MAX_PER_SCAN: u32 = 100_000;
        let periods = self
            .cfg
            .interrupt_periods
            .map(|p| p.as_micros().max(1) as u64);
        let mut runs = 0;
        loop {
            // The earliest due cause; ties go to the higher I number.
            let k = (0..4).rev().min_by_key(|&k| self.int_due[k]).unwrap_or(0);
            if self.int_due[k] > now {
                break;
            }
            runs += 1;
            if runs > MAX_PER_SCAN {
                // Pathological period/scan ratio: skip ahead instead of looping.
                self.int_due[k] = now + periods[k];
                continue;
            }
            self.int_due[k] += periods[k];
            let n = 28 + k;
            if self.interrupts[n].is_some() {
                if self.rt.interrupt_enabled(n) {
                    if !self.run_interrupt(n) {
                        return false;
                    }
                } else {
                    self.int_pending[k] = true;
                }
            }
        }
        for k in (0..4).rev() {
            if self.int_pending[k] && self.rt.interrupt_enabled(28 + k) {
                self.int_pending[k] = false;
                if !self.run_interrupt(28 + k) {
                    return false;
                }
            }
        }
        true
    }

    /// Runs interrupt program `In`, saving and restoring Z0-Z15 around it (the
    /// default, not "high-speed execution", 004 L1270-1290).
    fn run_interrupt(&mut self, n: usize) -> bool {
        let Some((i, pc)) = self.interrupts[n] else {
            return true;
        };
        let zb = self.rt.mem.map.base(DeviceKind::Z) as usize;
        let zn = self.rt.mem.map.points(DeviceKind::Z) as usize;
        let mut z = [0u16; 16];
        z[..zn.min(16)].copy_from_slice(&self.rt.mem.words[zb..zb + zn.min(16)]);
        self.rt.in_interrupt = true;
        self.int_counts[n] = self.int_counts[n].wrapping_add(1);
        let out = exec::run(
            &self.programs,
            &mut self.locals,
            &mut self.rt,
            i,
            pc as usize,
        );
        self.rt.in_interrupt = false;
        self.rt.mem.words[zb..zb + zn.min(16)].copy_from_slice(&z[..zn.min(16)]);
        self.outcome(out)
    }

    /// Starts (or with `None` stops) a sampling trace, sampled at END.
    pub fn set_trace(&mut self, trace: Option<super::trace::Trace>) {
        self.trace = trace;
    }

    pub fn trace(&self) -> Option<&super::trace::Trace> {
        self.trace.as_ref()
    }

    /// The error history, oldest first (latest 16).
    pub fn error_history(&self) -> Vec<super::HistoryEntry> {
        self.rt.history.iter().copied().collect()
    }

    fn run_slot(&mut self, i: usize) -> bool {
        self.busy_us += self.slots[i].cost_us;
        let t = std::time::Instant::now();
        let out = exec::run(&self.programs, &mut self.locals, &mut self.rt, i, 0);
        let ns = t.elapsed().as_nanos() as u64;
        let s = &mut self.slots[i];
        s.count = s.count.wrapping_add(1);
        s.last_ns = ns;
        s.max_ns = s.max_ns.max(ns);
        self.outcome(out)
    }

    /// The calendar clock now, µs since 1970.
    pub fn calendar_unix_us(&self) -> i64 {
        self.rt.clock.unix_us(self.clock.now_us())
    }

    /// Sets the calendar clock (µs since 1970), e.g. from the state directory.
    pub fn set_calendar_unix_us(&mut self, us: i64) {
        let now = self.clock.now_us();
        let t = softplc_ir::calendar::DateTime::from_unix(us.div_euclid(1_000_000));
        self.rt.clock.set(t, now);
    }

    /// The program monitor list: every program file in parameter order.
    pub fn program_monitor(&self) -> Vec<ProgramMonitor> {
        self.programs
            .iter()
            .zip(&self.slots)
            .map(|(p, s)| ProgramMonitor {
                file: p.file.clone(),
                exec: s.exec,
                count: s.count,
                last: Duration::from_nanos(s.last_ns),
                max: Duration::from_nanos(s.max_ns),
            })
            .collect()
    }

    /// The interrupt program monitor list: executions of I0-I255 (wrapping).
    pub fn interrupt_counts(&self) -> &[u16] {
        &self.int_counts
    }

    /// Records a stop error of a program run; true when it ended normally.
    fn outcome(&mut self, out: Outcome) -> bool {
        match out {
            // A RET with no caller in this pass cannot happen at top level:
            // `Ret` on an empty stack is 4212.
            Outcome::End | Outcome::Return => true,
            Outcome::Abort => false,
            Outcome::Fault(code, slot, pc) => {
                self.rt.record_fault(&self.programs[slot], code, pc);
                false
            }
        }
    }

    /// END processing: scan-time measurement and the scan SM/SD, clock registers,
    /// constant-scan overrun, STOP requests.
    fn end_processing(&mut self, now: u64, initial: bool) {
        let scan_us = now - self.last_end_us;
        self.last_end_us = now;
        self.rt.scan_us = scan_us.min(u32::MAX as u64) as u32;
        if initial {
            // SD522/SD523: initial scan time.
            let (ms, sub) = special::ms_us(scan_us);
            let _ = self.rt.mem.set_word(DeviceKind::SD, 522, ms);
            let _ = self.rt.mem.set_word(DeviceKind::SD, 523, sub);
        } else {
            if !self.first_scan {
                // The first scan is excluded from the maximum (SD526/527).
                self.max_scan_us = Some(self.max_scan_us.unwrap_or(0).max(scan_us));
            }
            self.min_scan_us = Some(self.min_scan_us.map_or(scan_us, |m| m.min(scan_us)));
            special::end(
                &mut self.rt.mem,
                special::ScanTimes {
                    current_us: scan_us,
                    min_us: self.min_scan_us.unwrap_or(0),
                    max_us: self.max_scan_us.unwrap_or(0),
                    since_run_us: now - self.run_start_us,
                },
            );
            self.first_scan = false;
        }
        self.scans += 1;
        // PRG.TIME OVER (5010): a scan longer than the constant scan; a
        // continuation error (004 §7.1).
        if let Some(cs) = self.cfg.constant_scan {
            if scan_us > cs.as_micros() as u64 && !initial {
                self.rt.record(ErrorCode::PRG_TIME_OVER, None, None, None);
            }
        }
        // SM50 OFF→ON: clear the continuation error named in SD50 (lower two
        // digits ignored); stop errors cannot be cleared this way.
        let sm50 = special::error_reset_requested(&self.rt.mem);
        if let (Some(code), false) = (sm50, self.sm50) {
            if let Some(e) = &self.rt.error {
                let clearable = e.code.is_continuation() || e.code.is_operation_error();
                if clearable && e.code.0 / 100 == code / 100 {
                    self.rt.error = None;
                    special::clear_error(&mut self.rt.mem);
                }
            }
        }
        self.sm50 = sm50.is_some();
        self.sm210 =
            special::clock_registers(&mut self.rt.mem, &mut self.rt.clock, now, self.sm210);
        // PSCAN/PSTOP/POFF/PLOW take effect at END; the last request wins.
        for i in 0..self.slots.len() {
            if let Some(kind) = self.rt.type_requests[i].take() {
                let slot = &mut self.slots[i];
                use softplc_ir::ops::TypeChange;
                slot.off_pending = kind == TypeChange::Off;
                slot.exec = match kind {
                    TypeChange::Scan => ExecType::Scan,
                    TypeChange::Standby | TypeChange::Off => ExecType::Standby,
                    TypeChange::LowSpeed => ExecType::LowSpeed,
                };
            }
        }
        special::user_clocks(&mut self.rt.mem, &mut self.rt.duty);
        if let Some(t) = &mut self.trace {
            if std::mem::take(&mut self.rt.trace_reset) {
                t.reset(&mut self.rt.mem);
            }
            if std::mem::take(&mut self.rt.trace_trigger) {
                t.trigger();
            }
            t.sample(&mut self.rt.mem, self.scans, now);
        }
        if std::mem::take(&mut self.rt.stop_request) {
            self.set_stop();
        }
        special::set_status(&mut self.rt.mem, self.state);
    }
}

/// Bytes per error-history entry in the retained image: code u16, detail u32
/// (`u32::MAX` = none), time i64, all little-endian.
const HISTORY_ENTRY: usize = 14;

impl Cpu {
    /// The battery-backed memory of this CPU as named byte regions: each latch
    /// range (bit devices one byte per point, words little-endian), the file
    /// registers and the error history (004 §4.3 data clear table).
    pub fn retained_layout(&self) -> Vec<(String, usize)> {
        let mut v: Vec<(String, usize)> = self
            .retained_spans()
            .into_iter()
            .map(|(name, bit, _, len)| (name, if bit { len } else { 2 * len }))
            .collect();
        v.push(("history".into(), 2 + super::HISTORY_LEN * HISTORY_ENTRY));
        v
    }

    /// Fills `bufs` (sized as [`Self::retained_layout`]) with the current values.
    pub fn save_retained(&self, bufs: &mut [Vec<u8>]) {
        let mem = &self.rt.mem;
        let spans = self.retained_spans();
        for ((_, bit, start, len), buf) in spans.iter().zip(bufs.iter_mut()) {
            if *bit {
                for (b, v) in buf.iter_mut().zip(&mem.bits[*start..start + len]) {
                    *b = *v as u8;
                }
            } else {
                for (b, w) in buf.chunks_exact_mut(2).zip(&mem.words[*start..start + len]) {
                    b.copy_from_slice(&w.to_le_bytes());
                }
            }
        }
        if let Some(h) = bufs.get_mut(spans.len()) {
            h.fill(0);
            h[..2].copy_from_slice(&(self.rt.history.len() as u16).to_le_bytes());
            for (k, e) in self.rt.history.iter().enumerate() {
                let o = 2 + k * HISTORY_ENTRY;
                h[o..o + 2].copy_from_slice(&e.code.0.to_le_bytes());
                h[o + 2..o + 6].copy_from_slice(&e.detail.unwrap_or(u32::MAX).to_le_bytes());
                h[o + 6..o + 14].copy_from_slice(&e.time.to_le_bytes());
            }
        }
    }

    /// Restores battery-backed memory read at power-on (`None`: that region was
    /// never saved or its size changed). Device initial values are written again
    /// afterwards because they override latched data (004 L7738-7740).
    pub fn restore_retained(&mut self, data: &[Option<Vec<u8>>]) {
        let spans = self.retained_spans();
        let mem = &mut self.rt.mem;
        for ((_, bit, start, len), d) in spans.iter().zip(data) {
            let Some(d) = d else { continue };
            if *bit {
                for (v, b) in mem.bits[*start..start + len].iter_mut().zip(d) {
                    *v = *b != 0;
                }
            } else {
                for (w, b) in mem.words[*start..start + len]
                    .iter_mut()
                    .zip(d.chunks_exact(2))
                {
                    *w = u16::from_le_bytes([b[0], b[1]]);
                }
            }
        }
        if let Some(Some(h)) = data.get(spans.len()) {
            self.rt.history.clear();
            let n = u16::from_le_bytes([h[0], h[1]]) as usize;
            for k in 0..n.min(super::HISTORY_LEN) {
                let o = 2 + k * HISTORY_ENTRY;
                let detail = u32::from_le_bytes(h[o + 2..o + 6].try_into().unwrap_or([0xFF; 4]));
                self.rt.history.push_back(super::HistoryEntry {
                    code: ErrorCode(u16::from_le_bytes([h[o], h[o + 1]])),
                    detail: (detail != u32::MAX).then_some(detail),
                    time: i64::from_le_bytes(h[o + 6..o + 14].try_into().unwrap_or([0; 8])),
                });
            }
        }
        self.write_initial_values();
    }

    /// A flag that stops the CPU when set, even in the middle of a scan stuck
    /// in an endless loop (checked where the watchdog is, on backward jumps):
    /// the scan ends, the CPU goes to STOP without an error. For Ctrl-C,
    /// SIGTERM and wall-clock limits.
    pub fn abort_handle(&self) -> std::sync::Arc<std::sync::atomic::AtomicBool> {
        self.rt.abort.clone()
    }

    /// Whether the abort flag is set.
    pub fn aborted(&self) -> bool {
        self.rt.abort.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Reports battery-backed data lost at power-on: BATTERY ERROR (1600) in
    /// SD0 and the error history; with `stop` the CPU holds it as a stop error
    /// (RESET clears it).
    pub fn report_battery_error(&mut self, stop: bool) {
        self.rt.record(ErrorCode::BATTERY, None, None, None);
        if stop {
            self.stop_error = true;
            self.set_stop();
        }
    }

    /// (region name, is bit array, flat start, points) of every retained span.
    fn retained_spans(&self) -> Vec<(String, bool, usize, usize)> {
        let mem = &self.rt.mem;
        let mut v = Vec::new();
        for r in &self.cfg.latch {
            for (kind, bit, start, len) in latch_kind_spans(mem, r) {
                let name = format!(
                    "latch:{}{}-{}",
                    kind.name(),
                    r.start,
                    r.start as usize + len - 1
                );
                v.push((name, bit, start, len));
            }
        }
        let zr = mem.map.base(DeviceKind::ZR) as usize;
        v.push((
            "file-register".into(),
            false,
            zr,
            mem.map.points(DeviceKind::ZR) as usize,
        ));
        v
    }
}

/// Flat spans of a latch range: (is bit array, start, length). Timers and
/// counters latch contact, coil and current value together.
fn latch_spans(mem: &DeviceMemory, r: &super::LatchRange) -> Vec<(bool, usize, usize)> {
    latch_kind_spans(mem, r)
        .into_iter()
        .map(|(_, bit, start, len)| (bit, start, len))
        .collect()
}

fn latch_kind_spans(
    mem: &DeviceMemory,
    r: &super::LatchRange,
) -> Vec<(DeviceKind, bool, usize, usize)> {
    use DeviceKind::*;
    let kinds: &[DeviceKind] = match r.kind {
        TS | TC | TN => &[TS, TC, TN],
        STS | STC | STN => &[STS, STC, STN],
        CS | CC | CN => &[CS, CC, CN],
        _ => std::slice::from_ref(&r.kind),
    };
    kinds
        .iter()
        .filter_map(|k| {
            let points = mem.map.points(*k);
            if r.start >= points {
                return None;
            }
            let end = r.end.min(points - 1);
            let start = (mem.map.base(*k) + r.start) as usize;
            Some((*k, k.is_bit(), start, (end - r.start + 1) as usize))
        })
        .collect()
}
