//! softplc-ir: the leaf of softplc. Device memory and its typed door
//! ([`access`]), resolved operands and the compiled ladder machine ([`ops`])
//! with what it tells the tools that show it ([`listing`]),
//! faults, the instruction trait ([`instr`]), the shared kernels and time.
//! It depends on no other softplc crate; the language front end (softplc-lang),
//! the instruction set (softplc-melsec) and the engine (softplc-engine) all
//! build on it.

#![forbid(unsafe_code)]

pub mod access;
pub mod calendar;
pub mod clock;
pub mod cpu;
pub mod device;
pub mod fault;
pub mod instr;
pub mod kernels;
pub mod layout;
pub mod listing;
pub mod online;
mod operand;
pub mod ops;
pub mod profile;
pub mod rack;
pub mod snapshot;
pub mod system;
pub mod word_op;
