//! Device names of `--set`/`--show` in the program's dialect (contract §2):
//! MELSEC's through the shared door, or the APLC's (octal X/Y, Dn as the
//! high word of 32-bit values).

use softplc_core::access::{DeviceSpec, Value};
use softplc_core::aplc::Name;
use softplc_core::engine::Cpu;

/// How a single program file is read (`--dialect`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DialectArg {
    Melsec,
    Aplc,
}

/// A device name of the program's dialect.
#[derive(Clone, Debug)]
pub enum DevName {
    Melsec(DeviceSpec),
    Aplc(Name),
}

impl DevName {
    pub fn parse(s: &str, aplc: bool) -> Result<DevName, String> {
        if aplc {
            Name::parse(s).map(DevName::Aplc)
        } else {
            DeviceSpec::parse(s).map(DevName::Melsec)
        }
    }

    /// The name as given, the key in reports.
    pub fn text(&self) -> &str {
        match self {
            DevName::Melsec(s) => &s.text,
            DevName::Aplc(n) => &n.spec.text,
        }
    }

    pub fn read(&self, cpu: &Cpu) -> Result<Value, String> {
        match self {
            DevName::Melsec(s) => cpu.read_device(s),
            DevName::Aplc(n) => cpu.read_device(&n.spec).map(|v| n.present(v)),
        }
    }

    pub fn write(&self, cpu: &mut Cpu, value: &str) -> Result<(), String> {
        match self {
            DevName::Melsec(s) => cpu.write_device(s, value),
            DevName::Aplc(n) => {
                let v = n.value(value)?;
                cpu.write_value(&n.spec, &v).map_err(|e| e.to_string())
            }
        }
    }
}
