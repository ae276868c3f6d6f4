//! Dialect-neutral kernels of the ladder machine: comparison contacts, the
//! built-in arithmetic and MOV, coils, timers and counters.

pub mod basic;
pub mod sequence;
