//! Instruction families, one module per chapter of the MELSEC-Q/QnA programming
//! manual (common instructions): sequence instructions (contacts, coils, timers,
//! counters, master control) and basic instructions (comparison, arithmetic,
//! conversion, transfer). Program-control instructions (jumps, CALL, FOR/NEXT)
//! live in the engine's interpreter loop because they move the program counter.

pub mod basic;
pub mod catalog;
pub mod sequence;
