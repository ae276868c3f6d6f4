//! Execution tiers: native code next to the interpreter (issue #17).
//!
//! A tier compiles a [`Program`] into a [`NativeProgram`]: regions of native
//! code for straight-line ops (contacts, coils, block and MPS stacks, MOV and
//! comparisons on plain devices). The interpreter (`exec.rs`) stays the
//! driver: whenever it reaches an op where a region starts it runs the
//! region. The region calls back into the interpreter ([`Host::exec`]) for
//! every other op (application instructions, timers, anything that can
//! fault) and returns when control goes elsewhere than the next op (a taken
//! jump, CALL, END, a stopping fault). So there is one semantics, and faults,
//! their step numbers, the watchdog and interrupts are the interpreter's.
//!
//! The engine knows only these traits: `softplc-jit` implements them and
//! `softplc-core` (or a test) hands one to [`crate::Cpu::use_tier`], so the
//! dependency points from the JIT to the engine.

use std::time::Duration;

use softplc_ir::device::DeviceMemory;
use softplc_ir::ops::Program;

/// The rung registers the interpreter keeps in locals, as a native region
/// reads and writes them: the operation result, the ANB/ORB block stack and
/// the MPS stack (bit stacks, newest in bit 0), and whether no master control
/// or POFF forces conditions OFF. Booleans are 0 or 1.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Regs {
    pub acc: u32,
    pub blocks: u32,
    pub mps: u32,
    pub mc_on: u32,
}

/// Marks an op where no native region starts ([`NativeProgram::entries`]).
pub const NO_REGION: u32 = u32::MAX;

/// What [`Host::exec`] and [`NativeProgram::run`] return when an op ended
/// the pass (END, a fault that stops the CPU, RET to another file, an abort):
/// the host holds the outcome.
pub const LEAVE: u32 = u32::MAX;

/// What native code reads and writes while a region runs: device memory and
/// the timers' state ([`softplc_ir::kernels::sequence::timer`]).
pub struct NativeState<'a> {
    pub mem: &'a mut DeviceMemory,
    /// Sub-unit remainder of each timer, µs.
    pub timer_rem: &'a mut [u32],
    /// Time base of low-speed and high-speed timers, µs (never 0).
    pub timer_base_us: [u32; 2],
    /// The scan time timers count this pass, µs.
    pub scan_us: u32,
    /// The running program's edge memories (LDP/LDF, PLS/PLF, MEP/MEF).
    pub edges: &'a mut [bool],
}

/// The interpreter as native code sees it while a region runs.
pub trait Host {
    /// Device memory and timers. Native code re-reads them after every
    /// [`exec`](Host::exec).
    fn state(&mut self) -> NativeState<'_>;
    /// Runs ops from `from` with the interpreter's own implementation on
    /// `regs` (updated in place) for as long as control stays in `from..to`,
    /// and returns the op to go on at: `to`, a jump's target outside the
    /// stretch, or [`LEAVE`].
    fn exec(&mut self, from: u32, to: u32, regs: &mut Regs) -> u32;
}

/// A program's native code.
pub trait NativeProgram: Send {
    /// For every op of the program: the code unit whose region starts at that
    /// op, or [`NO_REGION`].
    fn entries(&self) -> &[u32];
    /// Runs the region of `unit` that starts at op `pc` on `regs` and the
    /// host's memory, calling [`Host::exec`] for the ops without native
    /// code, and returns the op index where the interpreter goes on, or
    /// [`LEAVE`]. Returns `pc` unchanged when it cannot run (memory of
    /// another size). The interpreter calls it only while `regs.mc_on` is 1
    /// (no master control or POFF forces conditions OFF; the ops in between
    /// it runs itself), and native code returns when a stretch of
    /// [`Host::exec`] turned it 0.
    fn run(&self, unit: u32, pc: u32, regs: &mut Regs, host: &mut dyn Host) -> u32;
    /// Ops of the program that run as native code.
    fn native_ops(&self) -> usize;
    /// Ops native code could run that the interpreter runs because their
    /// run is shorter than [`ExecTier::min_run`].
    fn short_run_ops(&self) -> usize {
        0
    }
}

/// A way of executing programs other than the interpreter.
pub trait ExecTier {
    /// Short name for reports (`jit`).
    fn name(&self) -> &'static str;
    /// Compiles `prog`; an error names why (the host or the program).
    fn compile(&self, prog: &Program) -> Result<Box<dyn NativeProgram>, String>;
    /// A copy the CPU keeps to compile a program written during RUN.
    fn boxed(&self) -> Box<dyn ExecTier + Send + Sync>;
    /// Fewest native ops in a row it compiles (shorter runs are interpreted).
    fn min_run(&self) -> usize {
        1
    }
}

/// What [`crate::Cpu::use_tier`] did: reported by `--stats`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TierStats {
    pub tier: &'static str,
    /// Wall-clock time compiling every program of the CPU.
    pub compile: Duration,
    pub ops: usize,
    pub native_ops: usize,
    /// Ops left to the interpreter in runs shorter than `min_run`.
    pub short_run_ops: usize,
    pub min_run: usize,
}
