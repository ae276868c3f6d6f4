//! softplc-sim: plant models bound to PLC devices, evaluated at every scan's
//! input refresh in virtual time, and scenario tests (issue 7).
//!
//! - [`model`]: the plant models (pure numerics, closed-form tested).

// `unsafe` only in the modules marked `#[allow(unsafe_code)]`, each block with its SAFETY reason.
#![deny(unsafe_code)]

pub mod model;
pub mod plot;
pub mod scenario;
