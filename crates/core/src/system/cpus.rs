//! What a driver runs (`softplc serve`, the scenarios, `tune`): one CPU or
//! a multi-CPU system, CPU `i` 0-based (a single CPU is 0).

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use super::System;
use crate::access::DeviceSpec;
use crate::device::DeviceKind;
use crate::engine::{Cpu, CpuState, Refusal};

/// One CPU or a multi-CPU system of 2-4 (contract §6).
// Built once per run and never moved in its scan loop: a boxed CPU would add
// an indirection to every access of the single CPU's loop.
#[allow(clippy::large_enum_variant)]
pub enum Cpus {
    One(Cpu),
    System(System),
}

impl Cpus {
    /// Number of CPUs (1-4).
    pub fn len(&self) -> usize {
        match self {
            Cpus::One(_) => 1,
            Cpus::System(s) => s.len(),
        }
    }

    /// Never empty: there is at least CPU 1.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// CPU `i` (`i < len()`; callers check the numbers users give).
    #[inline]
    pub fn get(&self, i: usize) -> &Cpu {
        match self {
            Cpus::One(c) => c,
            Cpus::System(s) => s.cpu(i),
        }
    }

    #[inline]
    pub fn get_mut(&mut self, i: usize) -> &mut Cpu {
        match self {
            Cpus::One(c) => c,
            Cpus::System(s) => s.cpu_mut(i),
        }
    }

    /// Every CPU, CPU 1 first.
    pub fn iter(&self) -> impl Iterator<Item = &Cpu> {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Each CPU's scan period, CPU 1 first: a system's CPU scans at its
    /// constant scan, else at `default`; a single CPU at `default` (which
    /// the caller chose from the command line and its project).
    pub fn periods(&self, default: Duration) -> Vec<Duration> {
        match self {
            Cpus::One(_) => vec![default],
            Cpus::System(s) => (0..s.len())
                .map(|i| s.cpu(i).config().constant_scan.unwrap_or(default))
                .collect(),
        }
    }

    /// The multi-CPU system, when running one.
    pub fn system(&self) -> Option<&System> {
        match self {
            Cpus::One(_) => None,
            Cpus::System(s) => Some(s),
        }
    }

    /// The CPU a write from outside to `spec`, named in CPU `cpu`, goes to:
    /// an input of a module goes to its control CPU's input image
    /// ([`System::input_owner`]), anything else to `cpu`.
    pub fn write_owner(&self, cpu: usize, spec: &DeviceSpec) -> usize {
        match (self, spec.bit_span()) {
            (Cpus::System(s), Some((DeviceKind::X, x, _))) => s.input_owner(cpu, x),
            _ => cpu,
        }
    }

    /// The first CPU in STOP, if any.
    pub fn first_stopped(&self) -> Option<usize> {
        self.iter().position(|c| c.state() == CpuState::Stop)
    }

    /// Remote RESET of CPU `i` (STOP only, when its parameter allows it):
    /// a system's follows [`System::reset`] (CPU 1's resets every CPU,
    /// another's brings the others down).
    pub fn remote_reset(&mut self, i: usize) -> Result<(), Refusal> {
        match self {
            Cpus::One(c) => c.remote_reset(),
            Cpus::System(s) => s.remote_reset(i),
        }
    }

    /// The flags that stop each CPU even inside a scan that never ends.
    pub fn abort_handles(&self) -> Vec<Arc<AtomicBool>> {
        self.iter().map(Cpu::abort_handle).collect()
    }
}
