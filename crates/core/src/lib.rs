//! softplc core: the MELSEC-Q soft PLC, assembled from its crates (see
//! ARCHITECTURE.md), with a stable public surface for the CLI, protocols and
//! simulation:
//! - [`device`], [`access`]: device memory and the typed door to it (softplc-ir);
//! - [`program`]: loading `.il`/`.csv` against the MELSEC-Q instruction set
//!   (softplc-lang + softplc-melsec);
//! - [`instructions`]: the MELSEC-Q instruction set (softplc-melsec);
//! - [`engine`]: the scan cycle and CPU functions (softplc-engine);
//! - [`project`]: `plc.toml` projects; [`persist`]: latched data on disk;
//! - [`names`]: device names from outside in the CPU's dialect (MELSEC or APLC);
//! - [`tier`]: interpreter or native code (`[cpu] exec`, `--exec`, `SOFTPLC_EXEC`).

pub use softplc_engine as engine;
pub use softplc_ir::{access, device};
pub use softplc_melsec as instructions;

pub mod aplc;
pub mod names;
pub mod persist;
pub mod profile;
pub mod program;
pub mod project;
pub mod tier;
