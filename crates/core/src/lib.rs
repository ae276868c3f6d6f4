//! softplc core: the soft PLC (MELSEC-Q, QnPH and APLC-TCP CPUs), assembled
//! from its crates (see ARCHITECTURE.md), with a stable public surface for the
//! CLI, protocols and simulation:
//! - [`profile`]: the CPU models, what each door asks of a CPU;
//! - [`device`], [`access`]: device memory and the typed door to it (softplc-ir);
//! - [`program`]: loading `.il`/`.csv` in a MELSEC dialect (softplc-lang +
//!   softplc-melsec); [`aplc`]: loading `.apl` files (softplc-aplc);
//! - [`instructions`]: the MELSEC-Q instruction set (softplc-melsec);
//! - [`engine`]: the scan cycle and CPU functions (softplc-engine);
//! - [`project`]: `plc.toml` projects; [`single`]: one program file on its
//!   own; [`persist`]: latched data on disk;
//! - [`system`]: multi-CPU systems (`system.toml`);
//! - [`snapshot`]: state files, a CPU's or system's whole state at an END;
//! - [`names`]: device names from outside in the CPU's dialect (MELSEC or APLC);
//! - [`tier`]: interpreter or native code (`[cpu] exec`, `--exec`, `SOFTPLC_EXEC`).

// `unsafe` only in the modules marked `#[allow(unsafe_code)]`, each block with its SAFETY reason.
#![deny(unsafe_code)]

pub use softplc_engine as engine;
pub use softplc_ir::{access, device, rack};
pub use softplc_melsec as instructions;

pub mod aplc;
pub mod names;
pub mod online;
pub mod persist;
pub mod profile;
pub mod program;
pub mod project;
pub mod single;
pub mod snapshot;
pub mod system;
pub mod tier;
