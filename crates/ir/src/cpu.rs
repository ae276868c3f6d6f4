//! What the engine does for CPU-function instructions ([`CpuServices`], in
//! [`crate::instr::ExecCtx::cpu`]): reset the watchdog, enable and mask
//! interrupts by number, request an execution-type change of a program,
//! trigger or reset the sampling trace, reset a timer's sub-unit remainder,
//! report a continuation error, refresh the inputs. Dialect-neutral: an instruction of a family
//! writes its family's system devices itself and asks the engine for the rest.

use std::time::Instant;

use crate::fault::Fault;

/// Execution-type changes (004 §4.2.6, qcpu.md §2.2 table).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TypeChange {
    /// Becomes a scan program.
    Scan,
    /// Becomes a standby program.
    Standby,
    /// Its outputs are turned OFF at the next scan, then standby.
    Off,
    /// Becomes a low-speed program.
    LowSpeed,
}

/// Interrupt pointers a CPU numbers (I0-I255).
pub const INTERRUPTS: usize = 256;

/// The engine's state that CPU-function instructions change; the engine reads
/// it while scanning and at END.
#[derive(Debug)]
pub struct CpuServices {
    /// Wall-clock start of the watchdog: the scan's start, or the last reset.
    pub watchdog_start: Instant,
    /// Interrupts enabled (EI) or disabled (DI).
    pub interrupts_enabled: bool,
    /// One enable bit per interrupt pointer, 16 a word (IMASK).
    pub interrupt_mask: [u16; INTERRUPTS / 16],
    /// Execution-type change requested for each program slot, applied at END.
    pub type_requests: Box<[Option<TypeChange>]>,
    /// Sampling-trace trigger and reset requested this scan (applied at END).
    pub trace_trigger: bool,
    pub trace_reset: bool,
    /// Sub-unit remainder of each timer, µs (T then ST).
    pub timer_rem: Box<[u32]>,
    /// A continuation error an instruction reported, with its detail (an
    /// annunciator number); the engine records it right after the instruction.
    pub report: Option<(Fault, u32)>,
    /// An input refresh an instruction asked for (served right after it).
    pub input_refresh: bool,
    /// An instruction asked to clear the latest continuation error (MELSEC
    /// LEDR when an error outranks the annunciators); served right after it.
    pub clear_error: bool,
    /// Something above waits for the engine when the instruction returns.
    pub pending: bool,
}

impl CpuServices {
    /// Services of a CPU with `programs` program slots and `timers` timers
    /// (T and ST together); interrupts disabled, the mask as given.
    pub fn new(programs: usize, timers: usize, mask: [u16; INTERRUPTS / 16]) -> CpuServices {
        CpuServices {
            watchdog_start: Instant::now(),
            interrupts_enabled: false,
            interrupt_mask: mask,
            type_requests: vec![None; programs].into_boxed_slice(),
            trace_trigger: false,
            trace_reset: false,
            timer_rem: vec![0; timers].into_boxed_slice(),
            report: None,
            input_refresh: false,
            clear_error: false,
            pending: false,
        }
    }

    /// Restarts the watchdog (not the scan-time measurement).
    pub fn reset_watchdog(&mut self) {
        self.watchdog_start = Instant::now();
    }

    /// Enables (EI) or disables (DI) interrupts.
    pub fn enable_interrupts(&mut self, on: bool) {
        self.interrupts_enabled = on;
    }

    /// Sets the enable bits of I0-I255.
    pub fn mask_interrupts(&mut self, mask: [u16; INTERRUPTS / 16]) {
        self.interrupt_mask = mask;
    }

    /// Interrupt pointer `n` is enabled by EI and its mask bit.
    pub fn interrupt_enabled(&self, n: usize) -> bool {
        self.interrupts_enabled && self.interrupt_mask[n / 16] >> (n % 16) & 1 != 0
    }

    /// Asks for program `slot` to change its execution type at END (the last
    /// request wins); [`Fault::NoProgram`] when the CPU has no such program.
    pub fn change_type(&mut self, slot: u32, kind: TypeChange) -> Result<(), Fault> {
        match self.type_requests.get_mut(slot as usize) {
            Some(r) => {
                *r = Some(kind);
                Ok(())
            }
            None => Err(Fault::NoProgram),
        }
    }

    /// Triggers the sampling trace at END.
    pub fn trigger_trace(&mut self) {
        self.trace_trigger = true;
    }

    /// Resets the sampling trace at END.
    pub fn reset_trace(&mut self) {
        self.trace_reset = true;
    }

    /// Clears the sub-unit remainder of timer `slot` (RST of a timer).
    pub fn reset_timer(&mut self, slot: u32) {
        if let Some(r) = self.timer_rem.get_mut(slot as usize) {
            *r = 0;
        }
    }

    /// Reports a continuation error (an annunciator turning ON) with its
    /// detail; the engine records it when the instruction returns.
    pub fn report(&mut self, fault: Fault, detail: u32) {
        self.report = Some((fault, detail));
        self.pending = true;
    }

    /// Clears the latest error if it does not stop the CPU, right after the
    /// instruction returns (as the family's error reset does).
    pub fn clear_error(&mut self) {
        self.clear_error = true;
        self.pending = true;
    }

    /// Refreshes the inputs mid-scan (the input image into the input
    /// devices, forced inputs kept), right after the instruction returns.
    pub fn refresh_inputs(&mut self) {
        self.input_refresh = true;
        self.pending = true;
    }
}
