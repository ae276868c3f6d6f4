//! Devices resolved once at build time and read/written every scan without
//! allocation or string work. A name with a `CPUn/` prefix is CPU n's of a
//! multi-CPU system (contract §6); each binding keeps its CPU's index.

use softplc_core::access::ValueType;
use softplc_core::names::{DevName, Placed};

use super::fmt::Kind;
use super::plcs::Plcs;
use super::spec::{channel, Scale};
use crate::model::{from_raw_clamped, to_raw};

/// A device read as a number (bits 0/1; NaN when it cannot be read, e.g. an
/// index-modified device pushed out of range by Z), named in its CPU's
/// dialect (`softplc_core::names`) and resolved there once ([`Placed`]).
#[derive(Clone, Debug)]
pub struct Probe {
    pub dev: Placed,
    /// The CPU (0-based).
    pub cpu: usize,
    /// The name in reports: the device's, after the `CPUn/` prefix given.
    name: String,
}

impl Probe {
    /// Parses `text` in the dialect of its CPU and checks it exists there.
    pub fn new(text: &str, cpus: &Plcs) -> Result<Probe, String> {
        let (cpu, rest) = cpus.layout.split(text)?;
        let dev = DevName::parse_for(rest.trim(), cpus.get(cpu))?;
        if dev.ty() == ValueType::Str {
            return Err(format!("`{text}`: strings cannot be bound or checked"));
        }
        let prefix = &text.trim()[..text.trim().len() - rest.len()];
        Ok(Probe {
            name: format!("{prefix}{}", dev.text()),
            dev: Placed::new(dev, cpus.get(cpu))?,
            cpu,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// Both probes read the same value (the same storage of the same CPU
    /// in the same type).
    pub fn same(&self, other: &Probe) -> bool {
        let (a, b) = (self.dev.name(), other.dev.name());
        self.cpu == other.cpu && a.spec() == b.spec() && a.ty() == b.ty()
    }

    pub fn kind(&self) -> Kind {
        match self.dev.name().ty() {
            ValueType::Bit => Kind::Bit,
            ValueType::F32 => Kind::Float,
            _ => Kind::Int,
        }
    }

    /// The value now in its CPU.
    #[inline(always)]
    pub fn read(&self, cpus: &Plcs) -> f64 {
        match self.dev.raw(cpus.get(self.cpu)) {
            Ok(raw) => decode(self.dev.name().ty(), raw),
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

/// A channel of a simulated module in the rack, `U<n>\CH<k>`: its physical
/// value (mA or V) through the module (`softplc_ir::rack::Module`).
#[derive(Clone, Debug)]
pub struct Channel {
    slot: usize,
    channel: u32,
    /// The CPU (0-based).
    cpu: usize,
}

impl Channel {
    /// The module channel `text` names in the rack of its CPU, or `None`
    /// when `text` is a device name. In a multi-CPU system the module must
    /// be one its CPU controls.
    fn parse(text: &str, cpus: &Plcs) -> Option<Result<Channel, String>> {
        let (own, rest) = match cpus.layout.split(text) {
            Ok(split) => split,
            Err(e) => return channel(text).map(|_| Err(e)),
        };
        let parsed = channel(rest)?;
        let cpu = cpus.get(own);
        Some(parsed.and_then(|(unit, ch)| {
            let text = text.trim();
            let slot = cpu
                .rack()
                .unit(unit)
                .ok_or_else(|| format!("`{text}`: no slot of the rack is unit U{unit:X}"))?;
            let index = slot.index as usize;
            let name = slot.describe();
            if cpus.in_system(own) && slot.control_cpu as usize != cpus.own_index(own) + 1 {
                return Err(format!(
                    "`{text}`: {name} is controlled by CPU {c}: bind CPU{c}/{}",
                    rest.trim(),
                    c = slot.control_cpu
                ));
            }
            let module = cpu
                .module(index)
                .ok_or_else(|| format!("`{text}`: {name} holds no simulated module"))?;
            if module.channel(ch).is_none() {
                return Err(format!("`{text}`: {name} has no channel CH{ch}"));
            }
            Ok(Channel {
                slot: index,
                channel: ch,
                cpu: own,
            })
        }))
    }

    /// The channel's physical value, NaN when the module has none.
    #[inline]
    fn read(&self, cpus: &Plcs) -> f64 {
        cpus.get(self.cpu)
            .module(self.slot)
            .and_then(|m| m.channel(self.channel))
            .unwrap_or(f64::NAN)
    }
}

/// `v` mapped linearly from range `from` onto range `to`.
#[inline]
fn linear(v: f64, from: (f64, f64), to: (f64, f64)) -> f64 {
    to.0 + (v - from.0) / (from.1 - from.0) * (to.1 - to.0)
}

/// A model input.
#[derive(Clone, Debug)]
pub enum Source {
    Const(f64),
    Device {
        probe: Probe,
        scale: Scale,
    },
    /// An analog output's physical value, or its engineering value
    /// (`Scale::Signal`).
    Channel {
        channel: Channel,
        scale: Scale,
    },
}

impl Source {
    /// A model input bound to `text`, a device or a module channel.
    pub fn new(text: &str, scale: Scale, cpus: &Plcs) -> Result<Source, String> {
        match Channel::parse(text, cpus) {
            Some(channel) => Ok(Source::Channel {
                channel: channel?,
                scale,
            }),
            None => Ok(Source::Device {
                probe: Probe::new(text, cpus)?,
                scale,
            }),
        }
    }

    #[inline]
    pub fn read(&self, cpus: &Plcs) -> f64 {
        match self {
            Source::Const(v) => *v,
            Source::Channel { channel, scale } => {
                let x = channel.read(cpus);
                match *scale {
                    Scale::Signal { signal, eng } => linear(x, signal, eng),
                    _ => x,
                }
            }
            Source::Device { probe, scale } => {
                let v = probe.read(cpus);
                match *scale {
                    // Only module channels are bound with a signal range.
                    Scale::None | Scale::Signal { .. } => v,
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

/// A model output bound to a device, written as raw bits in its type through
/// the CPU's door (X reaches the input image, as from an input module), or
/// to a module channel (the physical value at an analog input).
#[derive(Clone, Debug)]
pub enum Sink {
    Device {
        /// Resolved in the CPU the write goes to.
        dev: Placed,
        cpu: usize,
        scale: Scale,
    },
    Channel {
        channel: Channel,
        scale: Scale,
    },
}

impl Sink {
    pub fn new(text: &str, scale: Scale, cpus: &mut Plcs) -> Result<Sink, String> {
        if let Some(channel) = Channel::parse(text, cpus) {
            let channel = channel?;
            // An output channel (D/A) refuses a value: say so now, not at
            // every scan. The model's initial value follows at once.
            if let Some(m) = cpus.get_mut(channel.cpu).module_mut(channel.slot) {
                m.set_channel(channel.channel, 0.0)
                    .map_err(|e| format!("`{}`: {e}", text.trim()))?;
            }
            return Ok(Sink::Channel { channel, scale });
        }
        let probe = Probe::new(text, cpus)?;
        let name = probe.dev.name().clone();
        // LM/V are refused here, not silently at every scan.
        name.door_raw(0)?;
        let cpu = cpus.write_owner(probe.cpu, name.spec());
        Ok(Sink::Device {
            dev: Placed::new(name, cpus.get(cpu))?,
            cpu,
            scale,
        })
    }

    /// Writes the model output `v`: bits ON above 0.5; integers rounded and
    /// clamped to the type's range (NaN is 0); `f32` as the nearest float;
    /// a channel's physical value (NaN is 0).
    #[inline]
    pub fn write(&mut self, cpus: &mut Plcs, v: f64) {
        let (dev, cpu, scale) = match self {
            Sink::Channel { channel, scale } => {
                let x = match *scale {
                    Scale::Signal { signal, eng } => linear(v, eng, signal),
                    _ => v,
                };
                let x = if x.is_nan() { 0.0 } else { x };
                if let Some(m) = cpus.get_mut(channel.cpu).module_mut(channel.slot) {
                    // Checked when the sink was bound.
                    let _ = m.set_channel(channel.channel, x);
                }
                return;
            }
            Sink::Device { dev, cpu, scale } => (dev, *cpu, *scale),
        };
        let ty = dev.name().ty();
        let raw = match scale {
            // Already a whole number in an i32: no rounding again.
            Scale::Analog { raw, eng } => encode_int(ty, i64::from(to_raw(v, eng, raw))),
            _ => encode(ty, if v.is_nan() { 0.0 } else { v }),
        };
        let Some(raw) = raw else {
            // Refused when the sink was bound.
            return;
        };
        // A device pushed out of range by its index register is not written.
        let _ = dev.write_raw(cpus.get_mut(cpu), raw);
    }
}

/// The raw bits of `x` (not NaN) in type `ty`: bits ON above 0.5; integers
/// rounded and clamped to the type's range; `f32` the nearest float. `None`
/// for strings.
#[inline]
fn encode(ty: ValueType, x: f64) -> Option<u64> {
    match ty {
        ValueType::Bit => Some((x > 0.5) as u64),
        ValueType::F32 => Some((x as f32).to_bits() as u64),
        ValueType::Str => None,
        // Clamped first to where an i64 holds it exactly.
        _ => encode_int(ty, x.round().clamp(-(2f64.powi(40)), 2f64.powi(40)) as i64),
    }
}

/// [`encode`] of the whole number `i`.
#[inline]
fn encode_int(ty: ValueType, i: i64) -> Option<u64> {
    Some(match ty {
        ValueType::Bit => (i > 0) as u64,
        ValueType::I16 => i.clamp(-32768, 32767) as u16 as u64,
        ValueType::U16 => i.clamp(0, 65535) as u64,
        ValueType::I32 => i.clamp(i32::MIN.into(), i32::MAX.into()) as u32 as u64,
        ValueType::U32 => i.clamp(0, u32::MAX.into()) as u64,
        ValueType::F32 => (i as f32).to_bits() as u64,
        ValueType::Str => return None,
    })
}
