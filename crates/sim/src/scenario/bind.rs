//! Devices resolved once at build time and read/written every scan without
//! allocation or string work.

use std::fmt::Write as _;

use softplc_core::access::{DeviceSpec, ValueType};
use softplc_core::device::{parse_operand, DeviceKind, DeviceMemory, Operand};
use softplc_core::engine::Cpu;

use super::fmt::Kind;
use super::spec::Scale;
use crate::model::{from_raw_clamped, to_raw};

/// A device read as a number (bits 0/1; NaN when it cannot be read, e.g. an
/// index-modified device pushed out of range by Z).
#[derive(Clone, Debug)]
pub struct Probe {
    pub spec: DeviceSpec,
}

impl Probe {
    /// Parses `text` and checks it exists in `mem`.
    pub fn new(text: &str, mem: &DeviceMemory) -> Result<Probe, String> {
        let spec = DeviceSpec::parse(text.trim())?;
        if spec.ty == ValueType::Str {
            return Err(format!("`{text}`: strings cannot be bound or checked"));
        }
        spec.read_raw(mem)?;
        Ok(Probe { spec })
    }

    pub fn name(&self) -> &str {
        &self.spec.text
    }

    pub fn kind(&self) -> Kind {
        match self.spec.ty {
            ValueType::Bit => Kind::Bit,
            ValueType::F32 => Kind::Float,
            _ => Kind::Int,
        }
    }

    #[inline]
    pub fn read(&self, mem: &DeviceMemory) -> f64 {
        match self.spec.read_raw(mem) {
            Ok(raw) => decode(self.spec.ty, raw),
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

/// Where a model output is written.
#[derive(Clone, Debug)]
enum Target {
    /// X`n`: the input image, as an input module.
    Input(u32),
    Bit(DeviceKind, i64),
    Word(DeviceKind, i64),
    /// Digit-specified, bit-of-word or index-modified: through
    /// `Cpu::write_device` with the value formatted into a reused buffer.
    Other,
}

/// A model output bound to a device.
#[derive(Clone, Debug)]
pub struct Sink {
    spec: DeviceSpec,
    target: Target,
    scale: Scale,
    buf: String,
}

impl Sink {
    pub fn new(text: &str, scale: Scale, mem: &DeviceMemory) -> Result<Sink, String> {
        let probe = Probe::new(text, mem)?;
        let spec = probe.spec;
        let op = parse_operand(text.trim().split(':').next().unwrap_or(""))
            .map_err(|e| format!("`{text}`: {e}"))?;
        let target = match op {
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                index: None,
            } => {
                if dev.kind == DeviceKind::X {
                    Target::Input(dev.number)
                } else if dev.kind.is_bit() {
                    Target::Bit(dev.kind, i64::from(dev.number))
                } else {
                    Target::Word(dev.word_kind(), i64::from(dev.number))
                }
            }
            _ => Target::Other,
        };
        Ok(Sink {
            spec,
            target,
            scale,
            buf: String::with_capacity(32),
        })
    }

    /// Writes the model output `v`.
    #[inline]
    pub fn write(&mut self, cpu: &mut Cpu, v: f64) {
        let x = match self.scale {
            Scale::Analog { raw, eng } => f64::from(to_raw(v, eng, raw)),
            _ => v,
        };
        match self.target {
            Target::Input(n) => cpu.set_input(n, x > 0.5),
            Target::Bit(k, n) => {
                let _ = cpu.memory_mut().set_bit(k, n, x > 0.5);
            }
            Target::Word(k, n) => {
                let mem = cpu.memory_mut();
                let x = if x.is_nan() { 0.0 } else { x };
                match self.spec.ty {
                    ValueType::I16 => {
                        let w = x.round().clamp(-32768.0, 32767.0) as i16 as u16;
                        let _ = mem.set_word(k, n, w);
                    }
                    ValueType::U16 => {
                        let _ = mem.set_word(k, n, x.round().clamp(0.0, 65535.0) as u16);
                    }
                    ValueType::I32 | ValueType::U32 | ValueType::F32 => {
                        let d: u32 = match self.spec.ty {
                            ValueType::I32 => {
                                x.round().clamp(i32::MIN as f64, i32::MAX as f64) as i32 as u32
                            }
                            ValueType::U32 => x.round().clamp(0.0, u32::MAX as f64) as u32,
                            _ => (x as f32).to_bits(),
                        };
                        let _ = mem.set_word(k, n, d as u16);
                        let _ = mem.set_word(k, n + 1, (d >> 16) as u16);
                    }
                    ValueType::Bit | ValueType::Str => {}
                }
            }
            Target::Other => {
                self.buf.clear();
                let x = if x.is_nan() { 0.0 } else { x };
                let _ = match self.spec.ty {
                    ValueType::Bit => write!(self.buf, "{}", u8::from(x > 0.5)),
                    ValueType::F32 => write!(self.buf, "{x:?}"),
                    ValueType::I16 => {
                        write!(self.buf, "{}", x.round().clamp(-32768.0, 32767.0) as i64)
                    }
                    ValueType::U16 => write!(self.buf, "{}", x.round().clamp(0.0, 65535.0) as i64),
                    ValueType::I32 => write!(
                        self.buf,
                        "{}",
                        x.round().clamp(i32::MIN as f64, i32::MAX as f64) as i64
                    ),
                    _ => write!(self.buf, "{}", x.round().clamp(0.0, u32::MAX as f64) as i64),
                };
                let _ = cpu.write_device(&self.spec, &self.buf);
            }
        }
    }
}
