//! The CPUs a scenario runs: one CPU, or a multi-CPU system whose CPUs scan
//! in one virtual time (contract §6). Bound devices carry their CPU's index
//! (0 for a single CPU).

use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, CpuState};
use softplc_core::system::System;

// One per run, built once and never moved in the scan loop: a boxed CPU
// would add an indirection to every access of the single CPU's loop.
#[allow(clippy::large_enum_variant)]
pub(super) enum Cpus {
    One(Cpu),
    System(System),
}

impl Cpus {
    /// CPU `i` (0-based; a single CPU is 0).
    #[inline]
    pub fn get(&self, i: usize) -> &Cpu {
        match self {
            Cpus::One(cpu) => cpu,
            Cpus::System(sys) => sys.cpu(i),
        }
    }

    #[inline]
    pub fn get_mut(&mut self, i: usize) -> &mut Cpu {
        match self {
            Cpus::One(cpu) => cpu,
            Cpus::System(sys) => sys.cpu_mut(i),
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Cpus::One(_) => 1,
            Cpus::System(sys) => sys.len(),
        }
    }

    pub fn is_system(&self) -> bool {
        matches!(self, Cpus::System(_))
    }

    /// How reports name CPU `i`: "the CPU", or "CPU n" in a system.
    pub fn label(&self, i: usize) -> String {
        match self {
            Cpus::One(_) => "the CPU".into(),
            Cpus::System(_) => format!("CPU {}", i + 1),
        }
    }

    /// The CPU a write from outside to `spec`, named in CPU `cpu`, goes to:
    /// an input of a module goes to its control CPU's input image (contract
    /// §6, as `--set X…`), anything else to `cpu`.
    pub fn write_owner(&self, cpu: usize, spec: &DeviceSpec) -> usize {
        match (self, spec.bit_span()) {
            (Cpus::System(sys), Some((DeviceKind::X, x, _))) => sys.input_owner(cpu, x),
            _ => cpu,
        }
    }

    /// The first CPU in STOP, if any.
    pub fn first_stopped(&self) -> Option<usize> {
        (0..self.len()).find(|&i| self.get(i).state() == CpuState::Stop)
    }
}
