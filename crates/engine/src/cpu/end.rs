//! END processing, the calendar clock, and the monitors (004 §4.3).

use super::*;
use softplc_ir::system::{End, EndCtx, ScanSplit, ScanTimes};

impl Cpu {
    /// The calendar clock now, µs since 1970.
    pub fn calendar_unix_us(&self) -> i64 {
        self.rt.clock.unix_us(self.clock.peek_us())
    }

    /// Sets the calendar clock (µs since 1970), e.g. from the state directory.
    pub fn set_calendar_unix_us(&mut self, us: i64) {
        let now = self.clock.now_us();
        let t = softplc_ir::calendar::DateTime::from_unix(us.div_euclid(1_000_000));
        self.rt.clock.set(t, now);
        self.note(DoorEvent::Calendar { unix_us: us });
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
    pub(super) fn outcome(&mut self, out: Outcome) -> bool {
        match out {
            // A RET with no caller in this pass cannot happen at top level:
            // `Ret` on an empty stack is `Fault::RetInMain`.
            Outcome::End | Outcome::Return => true,
            Outcome::Abort => false,
            Outcome::Fault(code, slot, pc) => {
                self.rt.record_fault(&self.programs[slot], code, pc);
                false
            }
        }
    }

    /// Where the scan time `scan_us` went (004 App. 2 SD540-SD549): the
    /// programs' simulated execution times, the constant-scan wait (the
    /// constant scan less the scan's execution time), and END processing,
    /// the rest — in virtual time the scan time the driver gave beyond the
    /// programs' execution (with none set, all of it).
    fn scan_split(&self, scan_us: u64) -> ScanSplit {
        let busy = self.busy_us;
        let wait_us = self
            .cfg
            .constant_scan
            .map_or(0, |c| (c.as_micros() as u64).saturating_sub(busy));
        ScanSplit {
            programs_us: busy - self.low_used_us.min(busy),
            low_speed_us: self.low_used_us,
            low_speed_cycle_us: self.low_exec_us,
            wait_us,
            end_us: scan_us.saturating_sub(busy).saturating_sub(wait_us),
        }
    }

    /// END processing: scan-time measurement, constant-scan overrun, error
    /// reset requests, the system's END (scan and clock registers, what
    /// instructions left for END), execution-type changes, the sampling
    /// trace, STOP requests.
    pub(super) fn end_processing(&mut self, now: u64, initial: bool) {
        let scan_us = now - self.last_end_us;
        self.last_end_us = now;
        self.rt.scan_us = scan_us.min(u32::MAX as u64) as u32;
        if !initial {
            if !self.first_scan {
                // The first scan is excluded from the maximum.
                self.max_scan_us = Some(self.max_scan_us.unwrap_or(0).max(scan_us));
            }
            self.min_scan_us = Some(self.min_scan_us.map_or(scan_us, |m| m.min(scan_us)));
        }
        let end = End {
            initial,
            times: ScanTimes {
                current_us: scan_us,
                min_us: self.min_scan_us.unwrap_or(0),
                max_us: self.max_scan_us.unwrap_or(0),
            },
            split: self.scan_split(scan_us),
            since_run_us: now - self.run_start_us,
        };
        if !initial {
            self.first_scan = false;
        }
        self.scans += 1;
        // A scan longer than the constant scan (a continuation error on
        // MELSEC, 004 §7.1).
        if let Some(cs) = self.cfg.constant_scan {
            if scan_us > cs.as_micros() as u64 && !initial {
                let named = crate::Named::time(cs.as_micros() as u64, scan_us);
                self.rt
                    .record(crate::Fault::ScanOverrun, None, None, None, None, named);
            }
        }
        // The program's error reset request, on its rising edge: clears the
        // latest error if it names it and it does not stop the CPU.
        let current = self.rt.error.as_ref().map(|e| e.code);
        let request = self.rt.system.error_reset(&self.rt.mem, current);
        if let (Some(names_it), false) = (request, self.error_reset) {
            if names_it {
                self.rt.clear_continuation_error();
            }
        }
        self.error_reset = request.is_some();
        let rt = &mut self.rt;
        rt.system.end(
            &mut EndCtx {
                mem: &mut rt.mem,
                shared: &mut rt.shared,
                clock: &mut rt.clock,
                now_us: now,
                state: &mut rt.system_state,
            },
            end,
        );
        // PSCAN/PSTOP/POFF/PLOW take effect at END; the last request wins.
        for i in 0..self.slots.len() {
            if let Some(kind) = self.rt.cpu.type_requests[i].take() {
                let slot = &mut self.slots[i];
                use softplc_ir::cpu::TypeChange;
                slot.off_pending = kind == TypeChange::Off;
                slot.exec = match kind {
                    TypeChange::Scan => ExecType::Scan,
                    TypeChange::Standby | TypeChange::Off => ExecType::Standby,
                    TypeChange::LowSpeed => ExecType::LowSpeed,
                };
            }
        }
        if let Some(t) = &mut self.trace {
            if std::mem::take(&mut self.rt.cpu.trace_reset) {
                t.reset(&mut self.rt.mem);
            }
            if std::mem::take(&mut self.rt.cpu.trace_trigger) {
                t.trigger();
            }
            t.sample(&mut self.rt.mem, self.scans, now);
        }
        if std::mem::take(&mut self.rt.stop_request) {
            self.enter_stop(softplc_ir::system::Cause::Instruction);
        }
        self.show_status();
        self.remote_end();
    }
}
