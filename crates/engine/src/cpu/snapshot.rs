//! The CPU's whole state at an END, walked for a state file (contract §7,
//! [`softplc_ir::snapshot::Snap`]): device memory and the input image, each
//! program's hidden state and scheduling, the runtime's (errors, history,
//! interrupts, EI/DI and masks, timers' remainders, calendar clock), the
//! operating state and its causes, the scan and low-speed bookkeeping, the
//! local devices' copies, the rack's modules and the clock's time.
//!
//! What is not in it: the compiled programs and the parameters (the file's
//! identity stands for them; the timer bases and the watchdog time stay
//! this CPU's), what exists only inside a scan (CALL and FOR
//! stacks, an instruction's pending requests: empty at END), the wall-clock
//! watchdog start and the host's measurements of program run times. The
//! sampling trace's samples are in it when the CPU has one, and come back
//! into a trace of the same settings (the client sets a trace up).

use super::*;
use softplc_ir::cpu::TypeChange;
use softplc_ir::fault::{CpuError, HistoryEntry};
use softplc_ir::snapshot::{Snap, StateError};
use softplc_ir::system::Cause;

/// How far beyond the file's clock a time to come may be, µs (a day:
/// more than any period the CPU schedules).
const AHEAD_US: u64 = 86_400_000_000;

/// The latest time a file may hold, µs (about 146,000 years): the clock
/// goes on adding to it.
const MAX_TIME_US: u64 = 1 << 62;

/// Longest file name an error names.
const MAX_NAME: usize = 4096;

/// A forced point as the file holds it.
#[derive(Default)]
struct ForceEntry {
    output: bool,
    n: u32,
    on: bool,
    under: bool,
}

impl Cpu {
    /// Walks this CPU's state: saves it, checks a file against it or loads
    /// it ([`Snap`]). Call between scans. After a load the clock reads the
    /// file's time.
    pub fn snapshot(&mut self, s: &mut Snap) {
        self.rt.x_touched();
        if s.loading() {
            self.note(super::DoorEvent::Unrecordable {
                why: "a state file was loaded",
            });
        }
        // Times of the past are at most the file's clock, times to come
        // at most a day beyond it: an edited file cannot make a later
        // scan's arithmetic overflow.
        // A look at the time (`peek_us`): saving drives nothing, so a
        // recording does not take it as a reading a replay must make.
        let mut now = self.clock.peek_us();
        s.section(*b"TIME", "clock", |s| {
            now = s.value(now);
            if !s.saving() && now > MAX_TIME_US {
                s.fail(StateError::Invalid {
                    what: "clock",
                    value: now,
                });
            }
            if s.loading() {
                self.clock.restore_us(now);
            }
            s.at_most(&mut self.rt.now_us, now);
            self.rt.clock.snapshot(s);
        });
        let ahead = now.saturating_add(AHEAD_US);
        s.section(*b"DEVS", "device memory", |s| {
            s.bools(&mut self.rt.mem.bits);
            s.words(&mut self.rt.mem.words);
            s.bools(&mut self.rt.inputs);
            s.bools(&mut self.saved_y);
        });
        s.section(*b"PROG", "program state", |s| {
            let n = self.locals.len();
            if !s.same(n > 0) {
                return;
            }
            for (l, slot) in self.locals.iter_mut().zip(&mut self.slots) {
                s.bools(&mut l.edges);
                s.u32s(&mut l.state);
                slot_state(s, slot, ahead);
            }
            s.u32s(&mut self.rt.shared);
            s.u32s(&mut self.rt.system_state);
        });
        s.section(*b"RUNT", "runtime", |s| self.runtime(s));
        s.section(*b"CPU ", "operating state", |s| self.operating(s, ahead));
        s.section(*b"SCAN", "scan times", |s| self.scan_state(s, now, ahead));
        s.section(*b"LOCL", "local devices", |s| {
            if s.same(self.rt.local_devices.is_some()) {
                if let Some(l) = &mut self.rt.local_devices {
                    l.snapshot(s);
                }
            }
        });
        s.section(*b"RACK", "modules", |s| self.rack.snapshot(s));
        // The sampling trace: restored into a trace of the same settings
        // this CPU runs; without one its samples are passed over.
        let key = self.trace.as_ref().map(|t| t.key()).unwrap_or_default();
        let here = self.trace.is_some();
        s.optional(*b"TRCE", "sampling trace", here, &key, |s| {
            if let Some(t) = &mut self.trace {
                t.snapshot(s);
            }
        });
        if s.loading() {
            // Nothing of a scan is in progress at END.
            self.rt.calls.clear();
            self.rt.fors.clear();
            self.rt.cpu.report = None;
            self.rt.cpu.input_refresh = false;
            self.rt.cpu.clear_error = false;
            self.rt.cpu.pending = false;
            self.rt.cpu.reset_watchdog();
            self.busy_us = 0;
        }
    }

    fn runtime(&mut self, s: &mut Snap) {
        let rt = &mut self.rt;
        s.u32(&mut rt.scan_us);
        s.u16(&mut rt.mc_off);
        s.bool(&mut rt.stop_request);
        s.bool(&mut rt.stop_now);
        s.option(&mut rt.error, cpu_error);
        if let Some(h) = s.list(rt.history.iter_mut(), crate::HISTORY_LEN, history_entry) {
            rt.history.clear();
            rt.history.extend(h);
        }
        s.bool(&mut rt.in_interrupt);
        rt.requests.snapshot(s);
        let mut stop_interrupt = rt.stop_interrupt.unwrap_or(0);
        let mut has = rt.stop_interrupt.is_some();
        s.bool(&mut has);
        s.u32(&mut stop_interrupt);
        if s.loading() {
            rt.stop_interrupt = has.then_some(stop_interrupt);
        }
        let cpu = &mut rt.cpu;
        s.bool(&mut cpu.interrupts_enabled);
        s.words(&mut cpu.interrupt_mask);
        let changes = [
            None,
            Some(TypeChange::Scan),
            Some(TypeChange::Standby),
            Some(TypeChange::Off),
            Some(TypeChange::LowSpeed),
        ];
        if !s.same_len(cpu.type_requests.len()) {
            return;
        }
        for r in cpu.type_requests.iter_mut() {
            s.one_of(r, &changes);
        }
        s.bool(&mut cpu.trace_trigger);
        s.bool(&mut cpu.trace_reset);
        s.u32s(&mut cpu.timer_rem);
        s.bool(&mut rt.force_off);
        let (xb, yb) = (
            rt.mem.map.base(DeviceKind::X),
            rt.mem.map.base(DeviceKind::Y),
        );
        let mut current: Vec<ForceEntry> = rt
            .forces
            .iter()
            .map(|f| ForceEntry {
                output: f.kind == DeviceKind::Y,
                n: f.n,
                on: f.on,
                under: f.under,
            })
            .collect();
        let max = self.cfg.profile.max_forces;
        let points = [
            rt.mem.map.points(DeviceKind::X),
            rt.mem.map.points(DeviceKind::Y),
        ];
        let read = s.list(current.iter_mut(), max, |s, f| {
            s.bool(&mut f.output);
            s.u32(&mut f.n);
            s.bool(&mut f.on);
            s.bool(&mut f.under);
            if f.n >= points[f.output as usize] {
                s.fail(StateError::Invalid {
                    what: "forced devices",
                    value: u64::from(f.n),
                });
            }
        });
        if let Some(read) = read {
            rt.forces = read
                .into_iter()
                .map(|f| {
                    let (kind, base) = if f.output {
                        (DeviceKind::Y, yb)
                    } else {
                        (DeviceKind::X, xb)
                    };
                    Force {
                        kind,
                        n: f.n,
                        bit: (base + f.n) as usize,
                        on: f.on,
                        under: f.under,
                    }
                })
                .collect();
        }
    }

    fn operating(&mut self, s: &mut Snap, ahead: u64) {
        s.one_of(
            &mut self.state,
            &[CpuState::Run, CpuState::Stop, CpuState::Pause],
        );
        s.bool(&mut self.stop_error);
        self.remote.snapshot(s);
        s.one_of(
            &mut self.cause,
            &[
                Cause::Switch,
                Cause::Contact,
                Cause::Remote,
                Cause::Instruction,
                Cause::Error,
            ],
        );
        s.u64(&mut self.input_rises);
        s.u64(&mut self.input_falls);
        s.bool(&mut self.stopped_by_instruction);
        s.bool(&mut self.initial_pending);
        s.bool(&mut self.first_scan);
        s.bool(&mut self.error_reset);
        s.words(&mut self.int_counts);
        for t in &mut self.int_due {
            s.at_most(t, ahead);
        }
    }

    fn scan_state(&mut self, s: &mut Snap, now: u64, ahead: u64) {
        s.at_most(&mut self.power_on_us, now);
        s.at_most(&mut self.run_start_us, now);
        s.at_most(&mut self.last_end_us, now);
        s.u64(&mut self.scans);
        s.option(&mut self.min_scan_us, Snap::u64);
        s.option(&mut self.max_scan_us, Snap::u64);
        let programs = self.slots.len();
        s.index(&mut self.low_pos, programs.max(1) + 1);
        s.u64(&mut self.low_left_us);
        s.u64(&mut self.low_exec_us);
        s.bool(&mut self.low_first);
        // A low-speed END may lie ahead: its programs' simulated time.
        s.at_most(&mut self.low_last_end_us, ahead);
        s.words(&mut self.low_z);
        s.u32(&mut self.low_timer_us);
        s.u64(&mut self.low_used_us);
        s.option(&mut self.low_min_us, Snap::u64);
        s.u64(&mut self.low_max_us);
    }
}

/// A program file's scheduling: its execution type (PSCAN, PSTOP, PLOW
/// change it), POFF, its execution count and when a fixed-scan program runs.
fn slot_state(s: &mut Snap, slot: &mut Slot, ahead: u64) {
    s.one_of(
        &mut slot.exec,
        &[
            ExecType::Initial,
            ExecType::Scan,
            ExecType::LowSpeed,
            ExecType::Standby,
            ExecType::FixedScan,
        ],
    );
    s.bool(&mut slot.off_pending);
    s.u16(&mut slot.count);
    s.at_most(&mut slot.next_due_us, ahead);
}

fn cpu_error(s: &mut Snap, e: &mut CpuError) {
    s.u16(&mut e.code.0);
    s.option(&mut e.step, Snap::u32);
    s.option(&mut e.file, |s, f| s.string(f, MAX_NAME));
    s.option(&mut e.line, Snap::u32);
}

fn history_entry(s: &mut Snap, e: &mut HistoryEntry) {
    s.u16(&mut e.code.0);
    s.i64(&mut e.time);
    s.option(&mut e.detail, Snap::u32);
}
