//! What a CPU model is, as one value the CPU owns and every door asks: its
//! name and family, how devices are named from outside its programs, its
//! capacities, the protocol doors it has and its system devices.
//!
//! A dialect crate declares the profiles of its models (`softplc-melsec`:
//! the Q, QnPH and QnU CPUs; `softplc-aplc`: the APLC-TCP); the engine keeps
//! the CPU's profile and reads nothing in it but [`Profile::default_system`]
//! (and [`Profile::default_devices`] when it builds a configuration's defaults).
//! Doors (CLI, MC, Modbus, HTTP, OPC UA, simulator) ask the CPU's profile
//! instead of comparing model names or keeping an enum of dialects.

use std::fmt;
use std::sync::Arc;

use crate::access::{DeviceSpec, Value, ValueType};
use crate::device::{DeviceConfig, DeviceKind};
use crate::system::System;

/// A CPU model.
#[derive(Clone, Copy)]
pub struct Profile {
    /// The model name, as "read CPU model" answers and reports show it
    /// (`Q06HCPU`, `APLC-TCP`).
    pub model: &'static str,
    /// The family as users know it (`MELSEC-Q`, `MELSEC-QnPH`, `APLC`); also
    /// the name `--dialect` and scenario files select a family by.
    pub family: &'static str,
    /// Device names given from outside programs (`--set`, scenarios, HTTP,
    /// OPC UA, the ladder view).
    pub naming: &'static dyn Naming,
    /// Program memory and program files.
    pub capacity: Capacity,
    /// The device points and file-register size of a CPU whose parameters
    /// set none (a project without `[devices]`, a single program file).
    pub default_devices: fn() -> DeviceConfig,
    /// Errors name the step of the failing instruction (MELSEC); without,
    /// reports give its file and line only (the APLC).
    pub step_numbers: bool,
    /// The protocol doors the model has.
    pub doors: Doors,
    /// X and Y points that can be forced ON/OFF at once: a force beyond is
    /// refused (MELSEC-Q 32, QCPU manual "forced ON/OFF"; APLC-TCP 128 bits).
    pub max_forces: usize,
    /// The model's system devices and error numbering with default
    /// parameters (a loader with the project's parameters builds its own).
    pub default_system: fn() -> Arc<dyn System>,
}

impl fmt::Debug for Profile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Profile")
            .field("model", &self.model)
            .field("family", &self.family)
            .field("capacity", &self.capacity)
            .field("doors", &self.doors)
            .finish_non_exhaustive()
    }
}

impl PartialEq for Profile {
    /// Profiles are static values: one per model.
    fn eq(&self, other: &Self) -> bool {
        self.model == other.model
    }
}

impl Eq for Profile {}

/// Program memory of a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capacity {
    /// Steps of program memory (file headers included).
    pub program_steps: u32,
    /// Program files the model can hold.
    pub programs: usize,
}

/// The protocol doors a model has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Doors {
    /// Answers the MC protocol (SLMP), with this model code to "read CPU
    /// model" (0 where no code is published); `None`: the model has no MC
    /// protocol.
    pub mc: Option<u16>,
    /// The Modbus map preset it serves (the `[modbus] dialect` value of
    /// plc.toml: `q`, `aplc`).
    pub modbus: &'static str,
    /// The unit identifier its Modbus slave answers by default.
    pub modbus_unit: u8,
    /// Serial ports its programs drive themselves (the APLC's PORT1 and
    /// PORT2: Modbus master, free port).
    pub serial_ports: u8,
    /// Serves OPC UA: its compiler records the devices programs use
    /// (`Program::used_devices`), which the server's Devices folder lists.
    pub opcua: bool,
}

/// A device name from outside programs, resolved to the storage it lives in.
#[derive(Clone, Debug)]
pub struct NamedDevice {
    /// The door's spec over the storage; `text` is the name as given.
    pub spec: DeviceSpec,
    /// The type shown and written (the spec's, except for swapped pairs).
    pub ty: ValueType,
    /// Two registers holding one value high word first: the door reads them
    /// as a low-word-first `u32`, turned on the way.
    pub swap: bool,
    /// Not writable from outside (program locals).
    pub read_only: bool,
}

/// How a dialect names devices and writes constants outside its programs.
pub trait Naming: Send + Sync {
    /// Parses `DEV` or `DEV:TYPE`.
    fn parse(&self, text: &str) -> Result<NamedDevice, String>;
    /// Parses a value given as text for `dev` in the dialect's constant
    /// syntax (MELSEC `H1F`; APLC `16#1F`).
    fn parse_value(&self, dev: &NamedDevice, text: &str) -> Result<Value, String>;
    /// The name of the current value of a timer or counter contact (`T0` →
    /// `TN0`), `None` for any other device.
    fn current_value(&self, dev: &str) -> Option<String>;
    /// The name of input or output point `n` of `kind` (X, Y): hexadecimal
    /// on MELSEC (`X1F`), octal on the APLC (`X17`).
    fn io_name(&self, kind: DeviceKind, n: u32) -> String;
    /// Whether a device name stands for a program local (read only from
    /// outside, and live only while its program runs).
    fn is_local(&self, _dev: &str) -> bool {
        false
    }
}
