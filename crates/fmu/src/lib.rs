//! softplc as an FMI 3.0 co-simulation FMU (contract §8).
//!
//! - [`export`]: `softplc fmu` — modelDescription.xml from the chosen
//!   devices and the .fmu archive around this crate's shared library.
//! - [`plc`]: what `resources/` holds and the PLC loaded from it, stepped
//!   in virtual time as `softplc run` steps it.
//! - [`slave`]: one instance and FMI's modes, in safe Rust.
//! - `state`: the bytes of an FMU state (fmi3GetFMUState and serialization).
//! - `ffi`: the exported C functions, the crate's only `unsafe`.

// `unsafe` only at the C boundary, each block with its SAFETY reason.
#![deny(unsafe_code)]

pub mod export;
#[allow(unsafe_code)]
mod ffi;
pub mod plc;
pub mod slave;
mod state;
