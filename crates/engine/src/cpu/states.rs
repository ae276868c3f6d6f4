//! Operating states: RUN, STOP, PAUSE, RESET, latch clear, power-on and
//! STOP→RUN (004 §4.4, §7.5, §7.8).

use super::retained::latch_spans;
use super::*;
use softplc_ir::system::{Cause, Status};

impl Cpu {
    /// The key switch to RUN. From STOP this is STOP→RUN: outputs per the
    /// "STOP→RUN output" parameter, device initial values written, the
    /// initial programs run again. Refused while a stop error is held (RESET
    /// first) or another source still says STOP (the RUN contact, a remote
    /// STOP: 004 §7.6.1 (3)); the switch is at RUN all the same.
    pub fn set_run(&mut self) -> Result<(), String> {
        self.set_switch_stop(false);
        let r = self.run_unless_stopped();
        self.note(DoorEvent::Run);
        r
    }

    /// STOP→RUN, or PAUSE→RUN.
    pub(super) fn go_run(&mut self) -> Result<(), String> {
        self.rt.x_touched();
        match self.state {
            CpuState::Run => Ok(()),
            CpuState::Pause => {
                self.state = CpuState::Run;
                self.show_status();
                self.remote_stopped();
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
                self.stop_to_run_devices();
                self.start_run();
                Ok(())
            }
        }
    }

    /// The key switch to STOP: the Y image is saved and the external
    /// outputs go OFF; device memory is kept. The CPU stays stopped until
    /// the switch is back at RUN ([`Self::set_run`]).
    pub fn set_stop(&mut self) {
        self.stopped_by_instruction = false;
        self.set_switch_stop(true);
        self.enter_stop(Cause::Switch);
        self.note(DoorEvent::Stop);
    }

    /// STOP from any cause (the switch, a remote STOP, the RUN contact, a
    /// stop error, the STOP instruction); an already stopped CPU keeps its
    /// first cause.
    pub(super) fn enter_stop(&mut self, cause: Cause) {
        self.rt.x_touched();
        if self.state != CpuState::Stop {
            self.cause = cause;
            let yb = self.rt.mem.map.base(DeviceKind::Y) as usize;
            let n = self.saved_y.len();
            self.saved_y.copy_from_slice(&self.rt.mem.bits[yb..yb + n]);
            self.state = CpuState::Stop;
            self.show_status();
        }
        self.remote_stopped();
    }

    /// Records an error that comes from outside the programs (another CPU
    /// of a multi-CPU system, a parameter check at power-on): a stop error
    /// stops the CPU until RESET, as one of its own would. The code
    /// recorded, `None` when the fault is no error in this family.
    pub fn raise(&mut self, fault: softplc_ir::fault::Fault) -> Option<ErrorCode> {
        self.raise_named(fault, crate::Named::default())
    }

    /// [`Self::raise`] for an error another CPU of a multi-CPU system
    /// caused: the error information names CPU `cpu` (1-4) and its I/O
    /// number (3E00H for CPU 1 …).
    pub fn raise_by_cpu(&mut self, fault: softplc_ir::fault::Fault, cpu: u32) -> Option<ErrorCode> {
        let unit = softplc_ir::device::CPU1_UNIT + cpu.saturating_sub(1);
        let module = softplc_ir::system::ModuleRef {
            io: unit << 4,
            slot: Some(cpu),
        };
        let named = crate::Named {
            time: None,
            module: Some(module),
        };
        self.raise_named(fault, named)
    }

    fn raise_named(
        &mut self,
        fault: softplc_ir::fault::Fault,
        named: crate::Named,
    ) -> Option<ErrorCode> {
        let code = self.rt.record(fault, None, None, None, None, named)?;
        if self.rt.stops(code) {
            self.stop_error = true;
            self.enter_stop(Cause::Error);
        }
        Some(code)
    }

    /// The CPU is held in STOP by a stop error (until RESET).
    pub fn has_stop_error(&self) -> bool {
        self.stop_error
    }

    /// PAUSE at once (the monitor's breakpoints and steps; a remote PAUSE
    /// is [`Self::remote_pause`]): the program stops with outputs held.
    pub fn set_pause(&mut self) -> Result<(), String> {
        match self.state {
            CpuState::Stop => Err("PAUSE is possible only from RUN".into()),
            _ => {
                self.state = CpuState::Pause;
                self.cause = Cause::Remote;
                self.show_status();
                self.note(DoorEvent::Pause);
                Ok(())
            }
        }
    }

    /// The RESET switch (accepted in STOP; a remote RESET is
    /// [`Self::remote_reset`]): the same processing as power-on — devices
    /// outside the latch ranges cleared, errors cleared, the remote
    /// operations cancelled, the key switch back at RUN — then RUN unless
    /// the RUN contact is ON.
    pub fn reset(&mut self) -> Result<(), String> {
        if self.state != CpuState::Stop {
            return Err("RESET is accepted only in STOP".into());
        }
        self.power_on();
        self.note(DoorEvent::Reset);
        Ok(())
    }

    /// Latch clear (accepted in STOP). The L.CLR switch clears the latch (1)
    /// ranges; a remote latch clear also clears latch (2), every device outside
    /// the latch ranges and the error (qcpu.md §4.2, [CONFLICT] 11). File
    /// registers are never cleared by latch clear (004 L7028-7031).
    pub fn latch_clear(&mut self, remote: bool) -> Result<(), String> {
        self.rt.x_touched();
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
            self.system_power_on();
        }
        self.note(DoorEvent::LatchClear { remote });
        Ok(())
    }

    /// Device clear of a remote RUN with a clear mode, done after
    /// [`Self::set_run`] from STOP: every device but X (refreshed from the input
    /// image), SM/SD (system) and the file registers R/ZR; the latch ranges are
    /// kept with [`RunClear::OutsideLatch`] and cleared too with
    /// [`RunClear::All`]. Device initial values are then written again.
    pub fn remote_run_clear(&mut self, mode: RunClear) {
        self.rt.x_touched();
        self.note(DoorEvent::RunClear(mode));
        let mem = &mut self.rt.mem;
        // Save the latch ranges (timers and counters latch contact, coil and value).
        let mut saved_bits: Vec<(usize, Vec<bool>)> = Vec::new();
        let mut saved_words: Vec<(usize, Vec<u16>)> = Vec::new();
        if mode == RunClear::OutsideLatch {
            for r in self.cfg.latch.iter().filter(|r| r.start <= r.end) {
                for (bit, start, len) in latch_spans(mem, r) {
                    if bit {
                        saved_bits.push((start, mem.bits[start..start + len].to_vec()));
                    } else {
                        saved_words.push((start, mem.words[start..start + len].to_vec()));
                    }
                }
            }
        }
        clear_user_devices(mem);
        for (start, v) in saved_bits {
            mem.bits[start..start + v.len()].copy_from_slice(&v);
        }
        for (start, v) in saved_words {
            mem.words[start..start + v.len()].copy_from_slice(&v);
        }
        self.write_initial_values();
    }

    /// Power-on / RESET processing (004 §4.3 table): devices outside the latch
    /// ranges and the file registers cleared, system registers set, device initial
    /// values written, RUN from the initial programs.
    pub(super) fn power_on(&mut self) {
        self.rt.x_touched();
        // Forces are released at power-off and RESET (docs/forcing.md).
        self.rt.forces.clear();
        self.clear_unlatched();
        self.modules_power_on();
        self.interrupts_power_on();
        self.rt.error = None;
        self.stop_error = false;
        self.rt.cpu.timer_rem.fill(0);
        self.rt.cpu.enable_interrupts(false);
        let mask = self.rt.system.interrupt_mask();
        self.rt.cpu.mask_interrupts(mask);
        let now = self.clock.now_us();
        self.power_on_us = now;
        self.min_scan_us = None;
        self.max_scan_us = None;
        // "Scans executed since power-on": RESET is power-on processing, and
        // the system's scan counter restarts from 0 with it (004 L10434).
        self.scans = 0;
        // The low-speed programs' index registers are device memory too.
        self.low_z = Default::default();
        self.system_power_on();
        self.start_run();
        self.remote_power_on();
        self.run_input_power_on();
    }

    /// Common part of power-on and STOP→RUN.
    pub(super) fn start_run(&mut self) {
        self.rt.x_touched();
        let now = self.clock.now_us();
        for l in &mut self.locals {
            l.clear();
        }
        // Local devices are cleared at power-on, RESET and STOP→RUN (004
        // L1952, §10.13.1 (g)), before the device initial values.
        if let Some(l) = &mut self.rt.local_devices {
            l.clear(&mut self.rt.mem, &mut self.rt.cpu.timer_rem);
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
        self.low_timer_us = 0;
        self.low_exec_us = 0;
        self.low_pos = 0;
        self.low_left_us = 0;
        self.low_first = true;
        self.initial_pending = true;
        self.first_scan = true;
        // The pulses caught in STOP are not shown (002 App. 1 SM90-SM97).
        self.input_rises = 0;
        self.input_falls = 0;
        self.stopped_by_instruction = false;
        self.state = CpuState::Run;
        self.show_status();
    }

    /// Device initial values, then the family's data that outranks them
    /// (`System::initialised`).
    pub(super) fn write_initial_values(&mut self) {
        self.rt.x_touched();
        for iv in &self.cfg.initial_values {
            // Validated when the project was loaded.
            let _ = iv.device.write(&mut self.rt.mem, &iv.value);
        }
        self.rt.system.initialised(&mut self.rt.mem);
    }

    /// Clears every device except the latch ranges, the file registers and
    /// the local devices (cleared only with the programs' copies, by
    /// power-on, RESET and STOP→RUN: 004 §10.13.1 (g)).
    ///
    /// Only the gaps between the kept spans are written: the file registers
    /// (1 MB by default) are neither copied nor touched, so power-on and RESET
    /// cost what the cleared devices cost.
    pub(super) fn clear_unlatched(&mut self) {
        self.rt.x_touched();
        let mem = &mut self.rt.mem;
        let zr = mem.map.base(DeviceKind::ZR) as usize;
        let mut keep_words = vec![(zr, mem.map.points(DeviceKind::ZR) as usize)];
        let mut keep_bits = Vec::new();
        for r in &self.cfg.latch {
            for (bit, start, len) in latch_spans(mem, r) {
                if bit {
                    keep_bits.push((start, len));
                } else {
                    keep_words.push((start, len));
                }
            }
        }
        if let Some(l) = &self.rt.local_devices {
            keep_bits.extend_from_slice(l.bit_spans());
            keep_words.extend_from_slice(l.word_spans());
        }
        fill_outside(&mut mem.bits, &mut keep_bits, false);
        fill_outside(&mut mem.words, &mut keep_words, 0);
    }

    // --- the scan ---
}

impl Cpu {
    /// Power-on values of the system devices; the system's own state
    /// starts cleared.
    fn system_power_on(&mut self) {
        self.rt.system_state.fill(0);
        self.rt.system.power_on(&mut self.rt.mem);
    }

    /// The operating state into the system devices.
    pub(super) fn show_status(&mut self) {
        let status = match self.state {
            CpuState::Run => Status::Run,
            CpuState::Stop => Status::Stop(self.cause),
            CpuState::Pause => Status::Pause(self.cause),
        };
        self.rt.system.status(&mut self.rt.mem, status);
    }
}

/// Fills `v` with `value` except the spans `(start, len)` of `keep` (in any
/// order, possibly overlapping).
fn fill_outside<T: Copy>(v: &mut [T], keep: &mut [(usize, usize)], value: T) {
    keep.sort_unstable();
    let mut at = 0;
    for &(start, len) in keep.iter() {
        if start > at {
            v[at..start].fill(value);
        }
        at = at.max(start + len);
    }
    if at < v.len() {
        v[at..].fill(value);
    }
}

/// Clears every device but X (refreshed from the input image), the file
/// registers and the system and module devices: the device clear of a
/// remote RUN and of the APLC's STOP→RUN without "keep device values".
pub(super) fn clear_user_devices(mem: &mut DeviceMemory) {
    for k in DeviceKind::ALL {
        use DeviceKind::*;
        if matches!(k, X | R | ZR) || k.is_system() || k.is_module() {
            continue;
        }
        let start = mem.map.base(k) as usize;
        let len = mem.map.points(k) as usize;
        if k.is_bit() {
            mem.bits[start..start + len].fill(false);
        } else {
            mem.words[start..start + len].fill(0);
        }
    }
}
