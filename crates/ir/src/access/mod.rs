//! The one door to device memory for everything outside the scan: the CLI
//! (`softplc run --set/--show`, contract §2), the simulator, the MC protocol and
//! Modbus servers.
//!
//! - [`DeviceSpec`]: a device by name and type (`D10:f32`, `K4M0`, `D0.F`,
//!   `TN0`), read as a [`Value`] and written from text or from a typed
//!   [`Value`] (no number is formatted to text to be written).
//! - [`Span`]: `len` consecutive points of one device kind, resolved from a
//!   name or a protocol's (kind, number) pair and range-checked once; read and
//!   written as words or bits ([`DeviceMemory::read_span_words`], …).
//! - [`Place`]: a plain name (`D10:f32`, `X0`, `D0.3`) resolved once to its
//!   points, read and written as raw bits without resolving it again
//!   ([`DeviceMemory::read_place`], [`DeviceMemory::write_place`]).
//! - The file-register rule (R addresses the block the CPU's selector word
//!   holds, 004 §10.7) lives here
//!   and only here: [`r_to_zr`], [`RBlock`].
//!
//! Errors are [`AccessError`]s naming the device as it was given.
//!
//! Writes to X that must survive the next input refresh go through the CPU
//! (`softplc_engine::Cpu::write_span_bits`, `write_value`), which keeps the input
//! image; this module sees device memory only.

mod place;
mod span;
mod spec;

use std::fmt;

use crate::device::OutOfRange;

pub use place::Place;
pub use span::{r_to_zr, selected_block, RBlock, Span, R_BLOCK};
pub use spec::DeviceSpec;

/// How a device's contents are presented.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueType {
    Bit,
    I16,
    U16,
    I32,
    U32,
    F32,
    Str,
}

/// A device value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::Int(i) => write!(f, "{i}"),
            Value::Float(x) => write!(f, "{x:?}"),
            Value::Str(s) => write!(f, "{s:?}"),
        }
    }
}

/// A read or write refused by the door. Every variant names the device as it
/// was given (`D10:f32`, `R0-R9`); nothing was written.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AccessError {
    /// A point outside the configured points (`source` names the first one).
    #[error("`{device}`: {source}")]
    Range { device: String, source: OutOfRange },
    /// Buffer memory of a unit with no intelligent function module.
    #[error("`{device}`: no intelligent function module has unit number {unit:X} (start I/O number {unit:X}0)")]
    NoModule { device: String, unit: u32 },
    /// An address past a module's buffer memory.
    #[error("`{device}`: past the module's buffer memory (G0-G{last})")]
    PastBuffer { device: String, last: u32 },
    /// Bits asked of a word device.
    #[error("`{device}` is a word device: it has no bit points")]
    NotBit { device: String },
    /// A value the device's type cannot hold.
    #[error("`{device}`: `{value}` is not a valid {ty:?} value")]
    Value {
        device: String,
        value: String,
        ty: ValueType,
    },
    /// A write whose values do not fill the span exactly.
    #[error("`{device}`: {given} values for {points} points")]
    Length {
        device: String,
        points: u32,
        given: usize,
    },
}

/// The text-returning wrappers (`DeviceSpec::read`, `write`, …) report errors
/// as strings; `?` converts.
impl From<AccessError> for String {
    fn from(e: AccessError) -> String {
        e.to_string()
    }
}

#[cfg(test)]
mod tests;
