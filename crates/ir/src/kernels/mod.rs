//! Dialect-neutral kernels of the ladder machine: comparison contacts, the
//! built-in arithmetic and MOV, coils, timers and counters, the
//! CPU-function instructions every family shares; and the value kernels both
//! dialects' instructions share (BCD, word logic).

pub mod basic;
pub mod bcd;
pub mod cpu;
pub mod logic;
pub mod sequence;
