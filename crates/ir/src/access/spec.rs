//! Devices by name and type: `D10:f32`, `K4M0`, `D0.F`, `TN0`.

use super::place::{Place, Shape};
use super::span::{RBlock, Span};
use super::{AccessError, Value, ValueType};
use crate::device::{parse_operand, BufferError, DeviceKind, DeviceMemory, Operand, OutOfRange};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    Bit(DeviceKind, u32),
    WordBit(DeviceKind, u32, u8),
    Word(DeviceKind, u32),
    Digits(DeviceKind, u32, u8),
}

/// A parsed `DEV[:TYPE]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceSpec {
    /// The text as given, used as the key in reports.
    pub text: String,
    /// The text [`Self::parse`] read (a dialect may rename `text`): parsing
    /// it again gives the same device (a recording's writes by name).
    door: String,
    target: Target,
    index: Option<u8>,
    /// `U<unit>\\G<n>`: the number is an address in that module's buffer
    /// memory.
    unit: Option<u32>,
    pub ty: ValueType,
}

/// Characters read for `:str` before giving up on a missing NUL.
const MAX_STR: usize = 256;

impl DeviceSpec {
    /// Parses `DEV` or `DEV:TYPE`. `T0`, `C0`, `ST0` alone mean the contact.
    pub fn parse(s: &str) -> Result<DeviceSpec, String> {
        let (dev, ty) = match s.split_once(':') {
            Some((d, t)) => (d, Some(t)),
            None => (s, None),
        };
        let op = parse_operand(dev).map_err(|e| format!("`{s}`: {e}"))?;
        let Operand::Device {
            dev: name,
            digits,
            bit,
            index,
        } = op
        else {
            return Err(format!("`{s}` is not a device"));
        };
        let target = match (digits, bit) {
            (Some(n), _) => Target::Digits(name.kind, name.number, n),
            (_, Some(b)) => Target::WordBit(name.kind, name.number, b),
            _ if name.kind.is_bit() => Target::Bit(name.kind, name.number),
            _ => Target::Word(name.kind, name.number),
        };
        let is_bit = matches!(target, Target::Bit(..) | Target::WordBit(..));
        let ty = match (ty.map(|t| t.to_ascii_lowercase()), is_bit) {
            (None, true) => ValueType::Bit,
            (None, false) => match target {
                Target::Digits(_, _, n) if n > 4 => ValueType::I32,
                _ => ValueType::I16,
            },
            (Some(t), false) => match t.as_str() {
                "i16" => ValueType::I16,
                "u16" => ValueType::U16,
                "i32" => ValueType::I32,
                "u32" => ValueType::U32,
                "f32" => ValueType::F32,
                "str" if !matches!(target, Target::Digits(..)) => ValueType::Str,
                _ => {
                    return Err(format!(
                        "`{s}`: unknown type `{t}` (i16, u16, i32, u32, f32, str)"
                    ))
                }
            },
            (Some(t), true) if t == "bool" || t == "bit" => ValueType::Bit,
            (Some(t), true) => return Err(format!("`{s}`: a bit device takes no type `{t}`")),
        };
        let unit = match name.reach {
            crate::device::Reach::Unit(u) => Some(u),
            _ => None,
        };
        Ok(DeviceSpec {
            text: s.to_string(),
            door: s.to_string(),
            target,
            index,
            unit,
            ty,
        })
    }

    /// The door's own text of this device (`DeviceSpec::parse` of it gives
    /// the same device, whatever name a dialect shows).
    pub fn door_text(&self) -> &str {
        &self.door
    }

    /// The device kind and first number written, for bit devices without index.
    pub fn bit_span(&self) -> Option<(DeviceKind, u32, u32)> {
        match (self.target, self.index) {
            (Target::Bit(k, n), None) => Some((k, n, 1)),
            (Target::Digits(k, n, d), None) => Some((k, n, 4 * d as u32)),
            _ => None,
        }
    }

    /// The device kind and number named, before index modification and
    /// without a module's buffer memory (`None` for `U<n>\\G<addr>`).
    pub fn device(&self) -> Option<(DeviceKind, u32)> {
        if self.unit.is_some() {
            return None;
        }
        Some(match self.target {
            Target::Bit(k, n) | Target::WordBit(k, n, _) | Target::Word(k, n) => (k, n),
            Target::Digits(k, n, _) => (k, n),
        })
    }

    /// This device's place in `mem` when its name is plain: a bit, a bit of a
    /// word, a numeric word device (one word, two for 32-bit types) or a
    /// digit-specified bit device, named without index modification (R is
    /// block 0's, a module's buffer memory its window). `None` for
    /// index-modified names and `:str`: their points are found again at
    /// every access.
    pub fn place(&self, mem: &DeviceMemory) -> Option<Result<Place, AccessError>> {
        if self.index.is_some() || self.ty == ValueType::Str {
            return None;
        }
        let (k, n, shape, len) = match self.target {
            Target::Bit(k, n) => (k, n, Shape::Bit, 1),
            Target::WordBit(k, n, b) => (k, n, Shape::WordBit(b), 1),
            Target::Word(k, n) => (k, n, Shape::Words, self.words()),
            Target::Digits(k, n, d) if k.is_bit() => (k, n, Shape::Digits, 4 * d as u32),
            Target::Digits(..) => return None,
        };
        Some(self.span(mem, k, n, len).map(|s| Place::new(s, shape)))
    }

    fn number(&self, mem: &DeviceMemory, n: u32) -> i64 {
        let z = self
            .index
            .and_then(|z| mem.get_word(DeviceKind::Z, z as i64).ok())
            .map_or(0, |v| v as i16 as i64);
        n as i64 + z
    }

    fn words(&self) -> u32 {
        match self.ty {
            ValueType::I32 | ValueType::U32 | ValueType::F32 => 2,
            _ => 1,
        }
    }

    /// `len` points of `kind` from `n` after index modification; R names block
    /// 0 (the documented window R0-R32767 = ZR0-ZR32767).
    fn span(
        &self,
        mem: &DeviceMemory,
        kind: DeviceKind,
        n: u32,
        len: u32,
    ) -> Result<Span, AccessError> {
        let number = self.number(mem, n);
        let Some(unit) = self.unit else {
            return mem
                .locate_span(kind, number, len, RBlock::First)
                .map_err(|source| self.range_error(source));
        };
        // Buffer memory: the address within the module's words (a negative
        // one, after index modification, is past them too).
        let addr = u32::try_from(number).unwrap_or(u32::MAX);
        let g = mem.map.buffer(unit, addr, len).map_err(|e| match e {
            BufferError::NoModule => AccessError::NoModule {
                device: self.text.clone(),
                unit,
            },
            BufferError::Past { last } => AccessError::PastBuffer {
                device: self.text.clone(),
                last,
            },
        })?;
        mem.locate_span(kind, g as i64, len, RBlock::First)
            .map_err(|source| self.range_error(source))
    }

    fn range_error(&self, source: OutOfRange) -> AccessError {
        AccessError::Range {
            device: self.text.clone(),
            source,
        }
    }

    /// Reads the device.
    pub fn read(&self, mem: &DeviceMemory) -> Result<Value, String> {
        Ok(self.read_value(mem)?)
    }

    /// Reads the device as a typed value.
    pub fn read_value(&self, mem: &DeviceMemory) -> Result<Value, AccessError> {
        if let (Target::Word(k, n), ValueType::Str) = (self.target, self.ty) {
            let mut bytes = Vec::new();
            'words: for i in 0..(MAX_STR / 2) as u32 {
                let Ok(s) = self.span(mem, k, n + i, 1) else {
                    break;
                };
                for b in mem.words[s.start()].to_le_bytes() {
                    if b == 0 {
                        break 'words;
                    }
                    bytes.push(b);
                }
            }
            return Ok(Value::Str(String::from_utf8_lossy(&bytes).into_owned()));
        }
        Ok(self.present(self.raw(mem)?))
    }

    /// Reads the device's raw bits (not for `:str`): bits as 0/1, words and
    /// digit-specified devices low word first. Allocates only on error.
    pub fn read_raw(&self, mem: &DeviceMemory) -> Result<u64, String> {
        Ok(self.raw(mem)?)
    }

    /// [`Self::read_raw`] with a typed error.
    pub fn raw(&self, mem: &DeviceMemory) -> Result<u64, AccessError> {
        match self.target {
            Target::Bit(k, n) => {
                let s = self.span(mem, k, n, 1)?;
                Ok(mem.bits[s.start()] as u64)
            }
            Target::WordBit(k, n, b) => {
                let s = self.span(mem, k, n, 1)?;
                Ok((mem.words[s.start()] >> b & 1) as u64)
            }
            Target::Digits(k, n, d) => {
                let s = self.span(mem, k, n, 4 * d as u32)?;
                Ok(mem.pack_bits(s.start(), 4 * d as usize) as u64)
            }
            Target::Word(k, n) => {
                let s = self.span(mem, k, n, self.words())?;
                let words = &mem.words[s.start()..s.start() + s.len() as usize];
                Ok(words
                    .iter()
                    .enumerate()
                    .fold(0u64, |v, (i, &w)| v | (w as u64) << (16 * i)))
            }
        }
    }

    /// Presents raw bits from [`Self::read_raw`] in this spec's type.
    pub fn present_raw(&self, raw: u64) -> Value {
        self.present(raw)
    }

    fn present(&self, raw: u64) -> Value {
        match self.ty {
            ValueType::I16 => Value::Int(raw as u16 as i16 as i64),
            ValueType::U16 => Value::Int(raw as u16 as i64),
            ValueType::I32 => Value::Int(raw as u32 as i32 as i64),
            ValueType::U32 => Value::Int(raw as u32 as i64),
            ValueType::F32 => Value::Float(f32::from_bits(raw as u32) as f64),
            ValueType::Bit => Value::Bool(raw & 1 != 0),
            ValueType::Str => Value::Int(raw as i64),
        }
    }

    /// Writes `value` (decimal, `H1F`/`0x1F` hex, a float for `:f32`, text for
    /// `:str`, `true`/`false`/`1`/`0` for bits).
    pub fn write(&self, mem: &mut DeviceMemory, value: &str) -> Result<(), String> {
        Ok(self.write_text(mem, value)?)
    }

    /// [`Self::write`] with a typed error.
    pub fn write_text(&self, mem: &mut DeviceMemory, value: &str) -> Result<(), AccessError> {
        // A numeric word device reports a missing device before a bad value.
        if let (Target::Word(k, n), false) = (self.target, self.ty == ValueType::Str) {
            self.span(mem, k, n, self.words())?;
        }
        let v = self.parse_value(value)?;
        self.write_value(mem, &v).map_err(|e| match e {
            AccessError::Value { .. } => self.bad_value(value),
            e => e,
        })
    }

    fn bad_value(&self, value: &str) -> AccessError {
        AccessError::Value {
            device: self.text.clone(),
            value: value.to_string(),
            ty: self.ty,
        }
    }

    /// Parses the text of a value for this device: `true`/`false`/`on`/`off`/
    /// `1`/`0` for bits, a finite float for `:f32`, the text itself for
    /// `:str`, otherwise a decimal or `H1F`/`0x1F` hex integer (its width is
    /// checked by [`Self::write_value`]).
    pub fn parse_value(&self, s: &str) -> Result<Value, AccessError> {
        let v = match self.ty {
            ValueType::Bit => parse_bool(s).map(Value::Bool),
            ValueType::Str => Some(Value::Str(s.to_string())),
            ValueType::F32 => s
                .parse::<f64>()
                .ok()
                .filter(|v| (*v as f32).is_finite())
                .map(Value::Float),
            _ => parse_int(s).map(Value::Int),
        };
        v.ok_or_else(|| self.bad_value(s))
    }

    /// Writes a typed value, with no text in between:
    /// - bits take `Bool` (or `Int` 0/1);
    /// - `i16`/`u16`/`i32`/`u32` and digit-specified devices take an `Int`
    ///   that fits the width as signed or unsigned (`-1` and `65535` both
    ///   write `FFFF` to a word), two words low word first;
    /// - `f32` takes a `Float` (or `Int`) rounded to the nearest `f32`, low word
    ///   first;
    /// - `str` takes a `Str`: its bytes two to a word, low byte first, then a
    ///   NUL (a whole NUL word when the length is even).
    ///
    /// Nothing is written when the value does not fit or a point is missing.
    pub fn write_value(&self, mem: &mut DeviceMemory, v: &Value) -> Result<(), AccessError> {
        let bad = || AccessError::Value {
            device: self.text.clone(),
            value: v.to_string(),
            ty: self.ty,
        };
        match self.target {
            Target::Bit(k, n) => {
                let b = as_bool(v).ok_or_else(bad)?;
                let s = self.span(mem, k, n, 1)?;
                mem.bits[s.start()] = b;
            }
            Target::WordBit(k, n, bit) => {
                let b = as_bool(v).ok_or_else(bad)?;
                let s = self.span(mem, k, n, 1)?;
                let w = &mut mem.words[s.start()];
                *w = if b { *w | 1 << bit } else { *w & !(1 << bit) };
            }
            Target::Digits(k, n, d) => {
                let raw = self.raw_of(v).ok_or_else(bad)?;
                let s = self.span(mem, k, n, 4 * d as u32)?;
                mem.unpack_bits(s.start(), 4 * d as usize, raw as u32);
            }
            Target::Word(k, n) if self.ty == ValueType::Str => {
                let Value::Str(text) = v else {
                    return Err(bad());
                };
                let mut bytes = text.as_bytes().to_vec();
                bytes.push(0);
                if bytes.len() % 2 == 1 {
                    bytes.push(0);
                }
                let s = self.span(mem, k, n, (bytes.len() / 2) as u32)?;
                for (w, pair) in mem.words[s.start()..].iter_mut().zip(bytes.chunks(2)) {
                    *w = u16::from_le_bytes([pair[0], pair[1]]);
                }
            }
            Target::Word(k, n) => {
                let s = self.span(mem, k, n, self.words())?;
                let raw = self.raw_of(v).ok_or_else(bad)?;
                for (i, w) in mem.words[s.start()..s.start() + s.len() as usize]
                    .iter_mut()
                    .enumerate()
                {
                    *w = (raw >> (16 * i)) as u16;
                }
            }
        }
        Ok(())
    }

    /// The raw bits of a numeric value in this spec's type and width.
    fn raw_of(&self, v: &Value) -> Option<u64> {
        if self.ty == ValueType::F32 {
            let x = match *v {
                Value::Float(x) => x as f32,
                Value::Int(i) => i as f32,
                _ => return None,
            };
            return Some(x.to_bits() as u64);
        }
        let Value::Int(v) = *v else {
            return None;
        };
        let bits = match self.target {
            Target::Digits(_, _, d) => 4 * d as u32,
            _ => 16 * self.words(),
        };
        let (min, max) = (-(1i64 << (bits - 1)), (1i64 << bits) - 1);
        (min..=max)
            .contains(&v)
            .then(|| (v as u64) & ((1u64 << bits) - 1))
    }
}

fn as_bool(v: &Value) -> Option<bool> {
    match *v {
        Value::Bool(b) => Some(b),
        Value::Int(0) => Some(false),
        Value::Int(1) => Some(true),
        _ => None,
    }
}

/// A decimal or `H1F`/`h1F`/`0x1F`/`0X1F` hex integer, optionally negative.
fn parse_int(s: &str) -> Option<i64> {
    let (neg, body) = match s.strip_prefix('-').filter(|b| !b.starts_with('-')) {
        Some(b) => (true, b),
        None => (false, s),
    };
    let mag = if let Some(h) = body
        .strip_prefix("0x")
        .or_else(|| body.strip_prefix("0X"))
        .or_else(|| body.strip_prefix('H'))
        .or_else(|| body.strip_prefix('h'))
    {
        i64::from_str_radix(h, 16).ok()?
    } else {
        body.parse::<i64>().ok()?
    };
    if neg {
        mag.checked_neg()
    } else {
        Some(mag)
    }
}

fn parse_bool(s: &str) -> Option<bool> {
    match s.to_ascii_lowercase().as_str() {
        "1" | "true" | "on" => Some(true),
        "0" | "false" | "off" => Some(false),
        _ => None,
    }
}
