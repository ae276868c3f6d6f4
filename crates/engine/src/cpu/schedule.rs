//! One scan: the programs by execution type, low-speed programs, fixed-scan
//! programs and the interrupt service (004 §4.2; interrupts in `interrupts.rs`).

use super::*;
use crate::local_devices::Entry;
use softplc_ir::system::{Cause, LowSpeed, ScanStart, ScanTimes};

impl Cpu {
    /// Executes one scan. In RUN: input refresh, fixed-scan programs that are due,
    /// the scan programs in parameter order, one pass of the low-speed programs,
    /// END processing. Right after power-on, RESET or STOP→RUN the scan runs the
    /// initial programs instead, followed by one END (004 §4.2.1). In STOP and
    /// PAUSE only END processing happens.
    pub fn scan(&mut self) {
        // What the scan changes is the CPU's own doing, not the door's.
        self.untold(Cpu::scan_untold)
    }

    fn scan_untold(&mut self) {
        let now = self.clock.now_us();
        if self.state != CpuState::Run {
            // Leaving STOP/PAUSE the first scan refreshes the inputs in full.
            self.rt.x_touched();
            self.last_end_us = now;
            // The modules go on while the CPU is stopped.
            self.modules_end(now);
            self.remote_end();
            self.run_input_end();
            return;
        }
        self.rt.now_us = now;
        self.busy_us = 0;
        self.low_used_us = 0;
        // The watchdog covers the whole scan (004 §7.9), reset only by END and WDT.
        self.rt.cpu.reset_watchdog();
        self.rt.scan_input_refresh();
        self.interrupt_module_edges();
        if !self.rt.forces.is_empty() {
            self.unforce_outputs();
        }
        let start = ScanStart {
            since_power_on_us: now - self.power_on_us,
            since_run_us: now - self.run_start_us,
            first_scan: self.first_scan,
            input_rises: std::mem::take(&mut self.input_rises),
            input_falls: std::mem::take(&mut self.input_falls),
        };
        self.rt.system.scan_start(&mut self.rt.mem, start);
        let initial =
            self.initial_pending && self.slots.iter().any(|s| s.exec == ExecType::Initial);
        self.initial_pending = false;
        let ok = if initial {
            // The initial execution monitor time, when set, replaces the WDT for
            // the initial programs (004 L1446-1503).
            let (wdt, set) = (self.rt.watchdog, self.rt.watchdog_set);
            if let Some(t) = self.cfg.initial_monitor {
                self.rt.watchdog = self.wall_watchdog(t);
                self.rt.watchdog_set = t;
            }
            let ok = self.service_interrupts(now) && self.run_type(ExecType::Initial);
            self.rt.watchdog = wdt;
            self.rt.watchdog_set = set;
            ok
        } else {
            self.service_interrupts(now)
                && self.run_off_pending()
                && self.run_fixed_scan(now)
                && self.run_type(ExecType::Scan)
                && self.run_low_speed(now)
        };
        if !self.rt.forces.is_empty() {
            // Forced outputs win over the program (and inputs it wrote).
            self.apply_forces(DeviceKind::Y);
            self.apply_forces(DeviceKind::X);
        }
        let stop_instruction = std::mem::take(&mut self.rt.stop_now);
        if !ok && (self.aborted() || stop_instruction) {
            // Stopped by the host or a STOP that stops at once, mid-scan:
            // STOP, no error.
            let cause = match stop_instruction {
                true => Cause::Instruction,
                false => Cause::Switch,
            };
            self.set_switch_stop(true);
            self.enter_stop(cause);
            self.stopped_by_instruction = stop_instruction;
            self.scans += 1;
            return;
        }
        if !ok {
            // Stop error: the CPU stops at the point of detection, outputs
            // OFF, after its error interrupt (I32) when enabled.
            self.run_stop_interrupt();
            self.stop_error = true;
            self.enter_stop(Cause::Error);
            self.scans += 1;
            return;
        }
        self.end_processing(now, initial);
        self.modules_end(now);
    }

    /// Runs every program of one execution type in parameter order; false on a
    /// stop error.
    pub(super) fn run_type(&mut self, exec: ExecType) -> bool {
        for i in 0..self.slots.len() {
            if self.slots[i].exec == exec && !self.run_slot(i) {
                return false;
            }
        }
        true
    }

    /// POFF: the program runs once with its conditions forced OFF, which turns
    /// its coils OFF (qcpu.md §2.2 table), before becoming a standby program.
    pub(super) fn run_off_pending(&mut self) -> bool {
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
    /// virtual time, so a pass always fits the spare time). The system shows
    /// the pass, the program running and each completed cycle
    /// (`System::low_speed`). The low-speed programs run in their own
    /// context (`switch_low_speed_context`), swapped in and out only here:
    /// a project without low-speed programs pays nothing.
    pub(super) fn run_low_speed(&mut self, now: u64) -> bool {
        // The low-speed programs in parameter order, without allocating.
        let n_low = self
            .slots
            .iter()
            .filter(|s| s.exec == ExecType::LowSpeed)
            .count();
        if n_low == 0 {
            return true;
        }
        self.switch_low_speed_context();
        let ok = self.low_speed_pass(now, n_low);
        self.switch_low_speed_context();
        ok
    }

    /// Control passes between the scan programs and the low-speed programs
    /// (both ways): each side keeps its own Z0-Z15, saved when it is left
    /// and restored when it is entered again (004 §10.6.1), and its own
    /// time for the timers — the scan time for the scan programs', the
    /// time between the last two low-speed ENDs for the low-speed programs'
    /// (§10.2.10 (f)).
    fn switch_low_speed_context(&mut self) {
        let zb = self.rt.mem.map.base(DeviceKind::Z) as usize;
        let n = (self.rt.mem.map.points(DeviceKind::Z) as usize).min(self.low_z.len());
        self.rt.mem.words[zb..zb + n].swap_with_slice(&mut self.low_z[..n]);
        std::mem::swap(&mut self.rt.scan_us, &mut self.low_timer_us);
    }

    /// The low-speed programs of this scan, in their context.
    fn low_speed_pass(&mut self, now: u64, n_low: usize) -> bool {
        let first = self.low_first;
        self.low_speed(LowSpeed::Pass { first });
        let sync = self.rt.system.low_speed_synchronous(&self.rt.mem);
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
            self.low_speed_end(now + self.busy_us);
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
                self.low_speed_end(now + self.busy_us + used);
                if sync {
                    // Synchronous: no second cycle in the same scan.
                    break;
                }
            }
        }
        self.busy_us += used;
        self.low_used_us = used;
        self.low_speed(LowSpeed::Running(None));
        true
    }

    /// The slot of the `k`-th low-speed program in parameter order.
    pub(super) fn low_slot(&self, k: usize) -> usize {
        (0..self.slots.len())
            .filter(|&i| self.slots[i].exec == ExecType::LowSpeed)
            .nth(k)
            .unwrap_or(0)
    }

    fn low_speed(&mut self, event: LowSpeed) {
        self.rt.system.low_speed(&mut self.rt.mem, event);
    }

    /// Runs low-speed program `i`, shown as running (the simulated time is
    /// accounted by the caller).
    pub(super) fn run_low(&mut self, i: usize) -> bool {
        self.low_speed(LowSpeed::Running(Some(i)));
        let cost = self.slots[i].cost_us;
        let ok = self.run_slot(i);
        self.busy_us -= cost;
        self.low_speed(LowSpeed::Running(None));
        ok
    }

    /// Low-speed END processing (004 §4.2.3 (5)) at engine time `at`: the
    /// low-speed scan time — the execution time of the cycle's low-speed
    /// programs (§4.2.3 (6)) — and its minimum and maximum to the system,
    /// the low-speed execution monitor (§4.2.3 (7): PRG.TIME OVER, a
    /// continuation error), and the time the low-speed programs' timers add
    /// from now: the engine time since the previous low-speed END, over
    /// which each timer coil of the cycle ran once (§10.2.10 (f)). Called in
    /// the low-speed context, where that time is `rt.scan_us`.
    pub(super) fn low_speed_end(&mut self, at: u64) {
        let us = std::mem::take(&mut self.low_exec_us);
        if !self.low_first {
            self.low_max_us = self.low_max_us.max(us);
        }
        self.low_min_us = Some(self.low_min_us.map_or(us, |m| m.min(us)));
        let times = ScanTimes {
            current_us: us,
            min_us: self.low_min_us.unwrap_or(0),
            max_us: self.low_max_us,
        };
        self.low_speed(LowSpeed::End(times));
        if let Some(limit) = self.cfg.low_speed_monitor {
            let set_us = limit.as_micros() as u64;
            if us > set_us {
                // PRG.TIME OVER names the time set and the time measured.
                let named = crate::Named::time(set_us, us);
                self.rt
                    .record(crate::Fault::LowSpeedOverrun, None, None, None, None, named);
            }
        }
        let cycle = at.saturating_sub(self.low_last_end_us);
        self.rt.scan_us = cycle.min(u32::MAX as u64) as u32;
        self.low_last_end_us = at;
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
    /// the last scan runs the program once, before the scan programs. Like an
    /// interrupt program, each run gets the index registers Z0-Z15 of the
    /// program it interrupts, which get their values back after it (004
    /// §10.6.2 (1), the default: not "high-speed execution").
    pub(super) fn run_fixed_scan(&mut self, now: u64) -> bool {
        for i in 0..self.slots.len() {
            if self.slots[i].exec != ExecType::FixedScan {
                continue;
            }
            while self.slots[i].next_due_us <= now {
                let iv = self.slots[i].interval_us.max(1);
                self.slots[i].next_due_us += iv;
                let zb = self.rt.mem.map.base(DeviceKind::Z) as usize;
                let zn = (self.rt.mem.map.points(DeviceKind::Z) as usize).min(LOW_Z);
                let mut z = [0u16; LOW_Z];
                z[..zn].copy_from_slice(&self.rt.mem.words[zb..zb + zn]);
                let ok = self.run_slot(i);
                self.rt.mem.words[zb..zb + zn].copy_from_slice(&z[..zn]);
                if !ok {
                    return false;
                }
            }
        }
        true
    }

    /// Starts (or with `None` stops) a sampling trace, sampled at END; the
    /// system's relays show its state. Starting it turns the start relay
    /// ON, as a start request from a peripheral does (004 §7.12 (1) (f) 2)):
    /// the program aborts the trace by turning it OFF.
    pub fn set_trace(&mut self, trace: Option<crate::trace::Trace>) {
        let relays = self.rt.system.trace_relays(&self.rt.mem.map);
        if let (Some(r), true) = (relays, trace.is_some()) {
            self.rt.mem.bits[r.start as usize] = true;
        }
        self.trace = trace.map(|t| t.with_relays(relays));
    }

    pub fn trace(&self) -> Option<&crate::trace::Trace> {
        self.trace.as_ref()
    }

    /// The error history, oldest first (latest 16).
    pub fn error_history(&self) -> Vec<crate::HistoryEntry> {
        self.rt.history.iter().copied().collect()
    }

    pub(super) fn run_slot(&mut self, i: usize) -> bool {
        self.busy_us += self.slots[i].cost_us;
        self.rt.system.program(&mut self.rt.mem, i);
        // Whose local devices it runs on: a fixed-scan program's are an
        // interrupt program's (004 §10.13.1 (d), (f)).
        let entry = match self.slots[i].exec {
            ExecType::FixedScan => Entry::Interrupt,
            _ => Entry::Program,
        };
        let back = self.rt.enter_locals(i, entry);
        // The program monitor: wall-clock time in real time; in virtual
        // time the simulated execution time, without reading the host's clock.
        let t = (!self.virtual_time).then(std::time::Instant::now);
        let out = exec::run(
            &self.programs,
            &self.natives,
            &mut self.locals,
            &mut self.rt,
            i,
            0,
        );
        self.rt.leave_locals(back);
        let s = &mut self.slots[i];
        let ns = match t {
            Some(t) => t.elapsed().as_nanos() as u64,
            None => s.cost_us.saturating_mul(1000),
        };
        s.count = s.count.wrapping_add(1);
        s.last_ns = ns;
        s.max_ns = s.max_ns.max(ns);
        self.outcome(out)
    }
}
