//! The CPUs `softplc serve` runs: one CPU, or a multi-CPU system of 2-4
//! (contract §6) whose CPUs scan at their own periods and exchange their
//! shared memories at each END ([`System::scan`]).

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use softplc_core::engine::{Cpu, Refusal};
use softplc_core::system::System;

/// One CPU or a multi-CPU system. CPU numbers are 0-based here: CPU 1 is 0.
pub enum Cpus {
    /// Boxed: a `Cpu` is large next to a `System` (which holds its CPUs).
    One(Box<Cpu>),
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

    /// CPU `i` (`i < len()`; callers check the numbers clients give).
    pub fn get(&self, i: usize) -> &Cpu {
        match self {
            Cpus::One(c) => c,
            Cpus::System(s) => s.cpu(i),
        }
    }

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

    /// The multi-CPU system, when serving one.
    pub fn system(&self) -> Option<&System> {
        match self {
            Cpus::One(_) => None,
            Cpus::System(s) => Some(s),
        }
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
    pub(crate) fn abort_handles(&self) -> Vec<Arc<AtomicBool>> {
        self.iter().map(Cpu::abort_handle).collect()
    }
}

/// The MC protocol's view: one station, a frame's destination picks the CPU.
impl softplc_mc::Station for Cpus {
    fn cpus(&self) -> usize {
        self.len()
    }

    fn cpu_mut(&mut self, i: usize) -> &mut Cpu {
        self.get_mut(i)
    }

    fn remote_reset(&mut self, i: usize) -> Result<(), Refusal> {
        Cpus::remote_reset(self, i)
    }
}
