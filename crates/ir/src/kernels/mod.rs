//! Dialect-neutral kernels of the ladder machine: comparison contacts, the
//! built-in arithmetic and MOV, coils, timers and counters, and the
//! CPU-function instructions every family shares.

pub mod basic;
pub mod cpu;
pub mod sequence;
