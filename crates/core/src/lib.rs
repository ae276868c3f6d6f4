//! softplc core: a MELSEC-Q compatible soft PLC.
//!
//! Layers, bottom up (see ARCHITECTURE.md):
//! - [`device`]: device memory and operand syntax (004 §10).
//! - [`program`]: parsers for `.il` and GX Works2 `.csv`, diagnostics, and the
//!   compiler to the pre-resolved [`program::Program`] form.
//! - [`instructions`]: the instruction families, one module per manual chapter.
//! - [`engine`]: the scan cycle, timers, special relays/registers, error handling.
//! - [`access`]: reading and writing devices by name, for the CLI and protocols.
//! - [`project`]: `plc.toml` projects; [`persist`]: latched data on disk.

pub mod access;
pub mod device;
pub mod engine;
pub mod instructions;
pub mod persist;
pub mod program;
pub mod project;
