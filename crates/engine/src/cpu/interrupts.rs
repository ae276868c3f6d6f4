//! Interrupts (004 §4.1.3, §7.15.1, §10.10, App. 3): every cause becomes a
//! request of its interrupt pointer — a fixed-cycle interrupt (I28-I31) when
//! its period elapses, a module's at END or at the input refresh
//! (`rack.rs`), an error's when it is recorded (`Runtime::error_interrupt`)
//! — and one service runs the requested pointers that EI and IMASK enable,
//! in the family's priority order, at the start of the scan after the input
//! refresh. A cause that occurs while disabled is remembered once and runs
//! when enabled (004 L1236-1238). The interrupt counters count each cause
//! taken.

use super::*;

/// Interrupt pointers requested and not yet run: bit n is I`n`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Requests([u64; 4]);

impl Requests {
    pub fn set(&mut self, n: u32) {
        if let Some(w) = self.0.get_mut(n as usize / 64) {
            *w |= 1 << (n % 64);
        }
    }

    pub fn has(&self, n: usize) -> bool {
        self.0.get(n / 64).is_some_and(|w| w >> (n % 64) & 1 != 0)
    }

    pub fn clear(&mut self, n: usize) {
        if let Some(w) = self.0.get_mut(n / 64) {
            *w &= !(1 << (n % 64));
        }
    }

    pub fn is_empty(&self) -> bool {
        self.0 == [0; 4]
    }

    pub fn snapshot(&mut self, s: &mut softplc_ir::snapshot::Snap) {
        s.u64s(&mut self.0);
    }
}

impl Cpu {
    /// Power-on and RESET: no cause is remembered.
    pub(super) fn interrupts_power_on(&mut self) {
        self.rt.requests = Requests::default();
        self.rt.stop_interrupt = None;
    }

    /// The interrupt service at the start of a scan: first the causes
    /// requested since the last service (modules, errors) and those
    /// remembered while disabled, by priority; then every fixed-cycle
    /// occurrence since the last scan in time order (I31 before I28 at the
    /// same instant, by priority), each with whatever it lets run. False on
    /// a stop error.
    pub(super) fn service_interrupts(&mut self, now: u64) -> bool {
        if !self.run_requests() {
            return false;
        }
        // I28-I31.
        let timers = 28usize..32;
        let taken = self.interrupts[timers.clone()].iter().any(Option::is_some)
            || self.cfg.interrupt_counters.is_some();
        if !taken {
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
            self.rt.requests.set((timers.start + k) as u32);
            if !self.run_requests() {
                return false;
            }
        }
        true
    }

    /// Runs the requested pointers that are enabled, highest priority first
    /// (004 L1246-1248: the others wait), each at most once a pass: a cause
    /// raised again while its program ran (an error in its own error
    /// interrupt) waits for the next service. False on a stop error.
    fn run_requests(&mut self) -> bool {
        if self.rt.requests.is_empty() {
            return true;
        }
        let order = self.rt.system.interrupt_priority();
        let mut ran = Requests::default();
        'pass: loop {
            for &n in order {
                let n = n as usize;
                if !self.rt.requests.has(n) || ran.has(n) {
                    continue;
                }
                let taken = self.interrupts[n].is_some() || self.cfg.interrupt_counters.is_some();
                if !taken {
                    // Nothing takes it: no program, no counter.
                    self.rt.requests.clear(n);
                    continue;
                }
                if self.rt.cpu.interrupt_enabled(n) {
                    self.rt.requests.clear(n);
                    ran.set(n as u32);
                    self.count_interrupt(n);
                    if !self.run_interrupt(n) {
                        return false;
                    }
                    // A cause its program raised may outrank the next one.
                    continue 'pass;
                }
            }
            return true;
        }
    }

    /// The interrupt counter of I`n` counts the cause taken (004 L6600-6645:
    /// no set value; a cause repeated while waiting counts once).
    fn count_interrupt(&mut self, n: usize) {
        let Some(first) = self.cfg.interrupt_counters else {
            return;
        };
        if let Some(i) = self.rt.mem.map.index(DeviceKind::CN, first + n as u32) {
            let w = &mut self.rt.mem.words[i as usize];
            *w = w.wrapping_add(1);
        }
    }

    /// A stop error: its error interrupt (MELSEC I32), when it was enabled,
    /// runs before the CPU stops (004 L10902 *3). The scan ended where the
    /// error was detected: an open subroutine or FOR is abandoned.
    pub(super) fn run_stop_interrupt(&mut self) {
        let Some(n) = self.rt.stop_interrupt.take() else {
            return;
        };
        self.rt.calls.clear();
        self.rt.fors.clear();
        self.count_interrupt(n as usize);
        self.run_interrupt(n as usize);
        self.rt.stop_interrupt = None;
    }

    /// Runs interrupt program `In`, saving and restoring Z0-Z15 around it (the
    /// default, not "high-speed execution", 004 L1270-1290), on its file's
    /// local devices or the interrupted program's (004 §10.13.1 (f)).
    /// Without a program nothing runs.
    pub(super) fn run_interrupt(&mut self, n: usize) -> bool {
        let Some((i, pc)) = self.interrupts[n] else {
            return true;
        };
        let zb = self.rt.mem.map.base(DeviceKind::Z) as usize;
        let zn = self.rt.mem.map.points(DeviceKind::Z) as usize;
        let mut z = [0u16; 16];
        z[..zn.min(16)].copy_from_slice(&self.rt.mem.words[zb..zb + zn.min(16)]);
        self.rt.in_interrupt = true;
        self.int_counts[n] = self.int_counts[n].wrapping_add(1);
        let back = self
            .rt
            .enter_locals(i, crate::local_devices::Entry::Interrupt);
        let out = exec::run(
            &self.programs,
            &self.natives,
            &mut self.locals,
            &mut self.rt,
            i,
            pc as usize,
        );
        self.rt.leave_locals(back);
        self.rt.in_interrupt = false;
        self.rt.mem.words[zb..zb + zn.min(16)].copy_from_slice(&z[..zn.min(16)]);
        self.outcome(out)
    }
}
