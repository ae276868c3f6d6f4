//! Instruction families, one module per chapter of the MELSEC-Q/QnA programming
//! manual (common instructions): sequence instructions (contacts, coils, timers,
//! counters, master control) and basic instructions (comparison, arithmetic,
//! conversion, transfer). Program-control instructions (jumps, CALL, FOR/NEXT)
//! live in the engine's interpreter loop because they move the program counter.
//!
//! Further families plug in through [`FAMILIES`]: a family module offers a
//! `lookup` that maps a mnemonic (without its `P` suffix) to a compile function,
//! which reads operands through [`Args`] and returns an [`Instr`] the engine
//! executes when the rung condition is ON. Pulse forms are handled for them.

pub mod arithmetic;
pub mod basic;
pub mod bits;
pub mod catalog;
pub mod clock;
pub mod comparison;
pub mod conversion;
pub mod data;
pub mod file_register;
pub mod float;
pub mod limits;
pub mod logic;
pub mod misc;
pub mod pid;
pub mod rotation;
pub mod sequence;
pub mod strings;
pub mod table;
pub mod transfer;

use std::fmt::Debug;

use crate::device::DeviceMemory;
use crate::engine::Fault;
pub use crate::program::compile::Args;

/// Everything an application instruction may touch while it executes.
pub struct ExecCtx<'a> {
    pub mem: &'a mut DeviceMemory,
    /// Hidden per-instruction state words, allocated with [`Args::state_words`].
    pub state: &'a mut [u32],
    /// PLC clock reading (µs) and the scan time measured at the previous END (µs).
    pub now_us: u64,
    pub scan_us: u32,
    /// CPU-wide state shared by instructions of every program file (what the
    /// CPU keeps outside device memory, e.g. the PID registration), cleared at
    /// power-on and STOP→RUN; see [`SHARED_WORDS`].
    pub shared: &'a mut [u32],
    /// The calendar clock (read with `clock.now(now_us)`, set by DATEWR).
    pub clock: &'a mut crate::engine::calendar::PlcClock,
}

/// A compiled application instruction of a family module.
pub trait Instr: Debug + Send + Sync {
    /// Runs the instruction; called only when its condition is ON (for a pulse
    /// form, only on the rising edge).
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault>;
}

/// Compiles one instruction; `None` when a diagnostic was reported through `Args`.
pub type CompileFn = fn(&mut Args<'_, '_>) -> Option<Box<dyn Instr>>;

/// Finds a family's compile function for a mnemonic (pulse suffix already removed).
pub type LookupFn = fn(&str) -> Option<CompileFn>;

/// Size of [`ExecCtx::shared`]: the PID registrations of both families, then the
/// RND random series (`misc`).
pub const SHARED_WORDS: usize = misc::SHARED_AT + misc::SHARED_WORDS;

/// The registered families, tried in order.
pub const FAMILIES: &[LookupFn] = &[
    conversion::lookup,
    arithmetic::lookup,
    strings::lookup,
    transfer::lookup,
    logic::lookup,
    rotation::lookup,
    bits::lookup,
    data::lookup,
    table::lookup,
    limits::lookup,
    comparison::lookup,
    float::lookup,
    clock::lookup,
    pid::lookup,
    file_register::lookup,
    misc::lookup,
];

/// The compile function of an extension instruction, if any family has it.
pub fn lookup(m: &str) -> Option<CompileFn> {
    FAMILIES.iter().find_map(|f| f(m))
}
