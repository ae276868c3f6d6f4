//! END processing, the calendar clock, and the monitors (004 §4.3).

use super::*;
use softplc_ir::system::Severity;

impl Cpu {
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
    pub(super) fn outcome(&mut self, out: Outcome) -> bool {
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
    pub(super) fn end_processing(&mut self, now: u64, initial: bool) {
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
            match &self.rt.system {
                Some(s) => s.scan_end(
                    &mut self.rt.mem,
                    softplc_ir::system::ScanTimes {
                        current_us: scan_us,
                        min_us: self.min_scan_us.unwrap_or(0),
                        max_us: self.max_scan_us.unwrap_or(0),
                    },
                ),
                None => special::end(
                    &mut self.rt.mem,
                    special::ScanTimes {
                        current_us: scan_us,
                        min_us: self.min_scan_us.unwrap_or(0),
                        max_us: self.max_scan_us.unwrap_or(0),
                        since_run_us: now - self.run_start_us,
                    },
                ),
            }
            self.first_scan = false;
        }
        self.scans += 1;
        // PRG.TIME OVER (5010): a scan longer than the constant scan; a
        // continuation error (004 §7.1).
        if let Some(cs) = self.cfg.constant_scan {
            if scan_us > cs.as_micros() as u64 && !initial {
                self.rt.record(crate::Fault::ScanOverrun, None, None, None);
            }
        }
        // SM50 OFF→ON: clear the continuation error named in SD50 (lower two
        // digits ignored); stop errors cannot be cleared this way.
        let sm50 = special::error_reset_requested(&self.rt.mem);
        if let (Some(code), false) = (sm50, self.sm50) {
            if let Some(e) = &self.rt.error {
                let clearable = self.rt.severity(e.code) != Severity::Stop;
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
        special::user_clocks(&mut self.rt.mem, &mut self.rt.duty);
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
            self.set_stop();
        }
        special::set_status(&mut self.rt.mem, self.state);
    }
}
