//! Devices resolved once at build time and read/written every scan without
//! allocation or string work.

use softplc_core::access::{Value, ValueType};
use softplc_core::device::DeviceMemory;
use softplc_core::engine::Cpu;
use softplc_core::names::DevName;

use super::fmt::Kind;
use super::spec::Scale;
use crate::model::{from_raw_clamped, to_raw};

/// A device read as a number (bits 0/1; NaN when it cannot be read, e.g. an
/// index-modified device pushed out of range by Z), named in the CPU's
/// dialect (`softplc_core::names`).
#[derive(Clone, Debug)]
pub struct Probe {
    pub dev: DevName,
}

impl Probe {
    /// Parses `text` in the dialect of `cpu` and checks it exists there.
    pub fn new(text: &str, cpu: &Cpu) -> Result<Probe, String> {
        let dev = DevName::parse_for(text.trim(), cpu)?;
        if dev.ty() == ValueType::Str {
            return Err(format!("`{text}`: strings cannot be bound or checked"));
        }
        Ok(Probe { dev })
    }

    pub fn name(&self) -> &str {
        self.dev.text()
    }

    /// Both probes read the same value (the same storage in the same type).
    pub fn same(&self, other: &Probe) -> bool {
        self.dev.spec() == other.dev.spec() && self.dev.ty() == other.dev.ty()
    }

    pub fn kind(&self) -> Kind {
        match self.dev.ty() {
            ValueType::Bit => Kind::Bit,
            ValueType::F32 => Kind::Float,
            _ => Kind::Int,
        }
    }

    #[inline]
    pub fn read(&self, mem: &DeviceMemory) -> f64 {
        match self.dev.raw(mem) {
            Ok(raw) => decode(self.dev.ty(), raw),
            Err(_) => f64::NAN,
        }
    }
}

#[inline]
fn decode(ty: ValueType, raw: u64) -> f64 {
    match ty {
        ValueType::Bit => (raw & 1) as f64,
        ValueType::I16 => f64::from(raw as u16 as i16),
        ValueType::U16 => f64::from(raw as u16),
        ValueType::I32 => f64::from(raw as u32 as i32),
        ValueType::U32 => f64::from(raw as u32),
        ValueType::F32 => f64::from(f32::from_bits(raw as u32)),
        ValueType::Str => f64::NAN,
    }
}

/// A model input.
#[derive(Clone, Debug)]
pub enum Source {
    Const(f64),
    Device { probe: Probe, scale: Scale },
}

impl Source {
    #[inline]
    pub fn read(&self, mem: &DeviceMemory) -> f64 {
        match self {
            Source::Const(v) => *v,
            Source::Device { probe, scale } => {
                let v = probe.read(mem);
                match *scale {
                    Scale::None => v,
                    // A D/A module clamps the digital value to its range.
                    Scale::Analog { raw, eng } => {
                        if v.is_nan() {
                            f64::NAN
                        } else {
                            from_raw_clamped(
                                v.clamp(i32::MIN as f64, i32::MAX as f64) as i32,
                                raw,
                                eng,
                            )
                        }
                    }
                    Scale::Bit { off, on } => {
                        if v > 0.5 {
                            on
                        } else {
                            off
                        }
                    }
                }
            }
        }
    }
}

/// A model output bound to a device, written as a typed value through the
/// CPU's door (X reaches the input image, as from an input module).
#[derive(Clone, Debug)]
pub struct Sink {
    dev: DevName,
    scale: Scale,
}

impl Sink {
    pub fn new(text: &str, scale: Scale, cpu: &Cpu) -> Result<Sink, String> {
        let probe = Probe::new(text, cpu)?;
        // LM/V are refused here, not silently at every scan.
        probe.dev.door_value(&Value::Int(0))?;
        Ok(Sink {
            dev: probe.dev,
            scale,
        })
    }

    /// Writes the model output `v`: bits ON above 0.5; integers rounded and
    /// clamped to the type's range (NaN is 0); `f32` as the nearest float.
    #[inline]
    pub fn write(&mut self, cpu: &mut Cpu, v: f64) {
        let x = match self.scale {
            Scale::Analog { raw, eng } => f64::from(to_raw(v, eng, raw)),
            _ => v,
        };
        let x = if x.is_nan() { 0.0 } else { x };
        let int = |lo: f64, hi: f64| Value::Int(x.round().clamp(lo, hi) as i64);
        let value = match self.dev.ty() {
            ValueType::Bit => Value::Bool(x > 0.5),
            ValueType::I16 => int(-32768.0, 32767.0),
            ValueType::U16 => int(0.0, 65535.0),
            ValueType::I32 => int(i32::MIN as f64, i32::MAX as f64),
            ValueType::U32 => int(0.0, u32::MAX as f64),
            ValueType::F32 => Value::Float(x),
            // Refused when the sink was bound.
            ValueType::Str => return,
        };
        // A device pushed out of range by its index register is not written.
        let _ = self.dev.write_value(cpu, &value);
    }
}
