//! softplc-jit: the native-code tier of the scan engine (issue #17), on
//! Cranelift (`opt_level=none`: the code is shaped by `codegen` itself).
//!
//! [`plan`] splits a program into chunks of at most [`plan::CHUNK_WEIGHT`] (ops weighed by their code)
//! and picks the ops that run as native code, [`codegen`] turns a chunk into
//! one function, and [`native`] owns the compiled code and the one place that
//! calls it. The interpreter runs every other op with the shared
//! implementations (`softplc_engine::tier`), so both tiers have one semantics.

// `unsafe` only in the modules marked `#[allow(unsafe_code)]`, each block with its SAFETY reason.
#![deny(unsafe_code)]

pub mod codegen;
// Calls into the generated machine code.
#[allow(unsafe_code)]
mod native;
pub mod plan;
pub mod shared;

use softplc_engine::tier::{ExecTier, NativeProgram};
use softplc_ir::ops::Program;

/// The Cranelift tier. `Cpu::use_tier(&Jit::default())` compiles the CPU's
/// programs.
#[derive(Clone, Copy, Debug)]
pub struct Jit {
    min_run: usize,
}

impl Default for Jit {
    fn default() -> Jit {
        Jit {
            min_run: plan::MIN_RUN,
        }
    }
}

impl Jit {
    /// Native code for runs of at least `n` native ops (1: every op that can
    /// be native is; tests use it to run the most native code, with the most
    /// calls between it and the interpreter).
    pub fn with_min_run(n: usize) -> Jit {
        Jit { min_run: n.max(1) }
    }
}

impl ExecTier for Jit {
    fn name(&self) -> &'static str {
        "jit"
    }

    fn compile(&self, prog: &Program) -> Result<Box<dyn NativeProgram>, String> {
        let plan = plan::plan(prog, self.min_run);
        Ok(Box::new(native::Compiled::new(prog, &plan)?))
    }

    fn min_run(&self) -> usize {
        self.min_run
    }

    fn boxed(&self) -> Box<dyn ExecTier + Send + Sync> {
        Box::new(*self)
    }
}

/// Whether Cranelift generates code for this host; the reason when not.
pub fn available() -> Result<(), String> {
    native::isa().map(|_| ())
}
