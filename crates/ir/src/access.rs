//! Reading and writing devices by name and type, as `softplc run --set/--show`
//! (contract §2) and the protocol servers do: `D10:f32`, `K4M0`, `D0.F`, `TN0`.

use std::fmt;

use crate::device::{parse_operand, DeviceKind, DeviceMemory, Operand};

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
    target: Target,
    index: Option<u8>,
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
        Ok(DeviceSpec {
            text: s.to_string(),
            target,
            index,
            ty,
        })
    }

    /// The device kind and first number written, for bit devices without index.
    pub fn bit_span(&self) -> Option<(DeviceKind, u32, u32)> {
        match (self.target, self.index) {
            (Target::Bit(k, n), None) => Some((k, n, 1)),
            (Target::Digits(k, n, d), None) => Some((k, n, 4 * d as u32)),
            _ => None,
        }
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

    /// Reads the device.
    pub fn read(&self, mem: &DeviceMemory) -> Result<Value, String> {
        if let (Target::Word(k, n), ValueType::Str) = (self.target, self.ty) {
            let first = self.number(mem, n);
            let mut bytes = Vec::new();
            'words: for i in 0..(MAX_STR / 2) as i64 {
                let Ok(w) = mem.get_word(k, first + i) else {
                    break;
                };
                for b in w.to_le_bytes() {
                    if b == 0 {
                        break 'words;
                    }
                    bytes.push(b);
                }
            }
            return Ok(Value::Str(String::from_utf8_lossy(&bytes).into_owned()));
        }
        Ok(self.present_raw(self.read_raw(mem)?))
    }

    /// Reads the device's raw bits (not for `:str`): bits as 0/1, words and
    /// digit-specified devices low word first. Allocates only on error.
    pub fn read_raw(&self, mem: &DeviceMemory) -> Result<u64, String> {
        let e = |e: crate::device::OutOfRange| format!("`{}`: {e}", self.text);
        match self.target {
            Target::Bit(k, n) => Ok(mem.get_bit(k, self.number(mem, n)).map_err(e)? as u64),
            Target::WordBit(k, n, b) => {
                let w = mem.get_word(k, self.number(mem, n)).map_err(e)?;
                Ok((w >> b & 1) as u64)
            }
            Target::Digits(k, n, d) => {
                let first = self.number(mem, n);
                let mut v: u64 = 0;
                for i in 0..4 * d as i64 {
                    v |= (mem.get_bit(k, first + i).map_err(e)? as u64) << i;
                }
                Ok(v)
            }
            Target::Word(k, n) => {
                let first = self.number(mem, n);
                let mut v: u64 = 0;
                for i in 0..self.words() as i64 {
                    v |= (mem.get_word(k, first + i).map_err(e)? as u64) << (16 * i);
                }
                Ok(v)
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
        let e = |e: crate::device::OutOfRange| format!("`{}`: {e}", self.text);
        let bad = || {
            format!(
                "`{}`: `{value}` is not a valid {:?} value",
                self.text, self.ty
            )
        };
        match self.target {
            Target::Bit(k, n) => {
                let v = parse_bool(value).ok_or_else(bad)?;
                mem.set_bit(k, self.number(mem, n), v).map_err(e)
            }
            Target::WordBit(k, n, b) => {
                let v = parse_bool(value).ok_or_else(bad)?;
                let i = self.number(mem, n);
                let w = mem.get_word(k, i).map_err(e)?;
                let w = if v { w | 1 << b } else { w & !(1 << b) };
                mem.set_word(k, i, w).map_err(e)
            }
            Target::Digits(k, n, d) => {
                let v = self.parse_raw(value).ok_or_else(bad)?;
                let first = self.number(mem, n);
                mem.get_bit(k, first).map_err(e)?;
                mem.get_bit(k, first + 4 * d as i64 - 1).map_err(e)?;
                for i in 0..4 * d as i64 {
                    mem.set_bit(k, first + i, v >> i & 1 != 0).map_err(e)?;
                }
                Ok(())
            }
            Target::Word(k, n) => {
                let first = self.number(mem, n);
                let span = if self.ty == ValueType::Str {
                    value.len() as i64 / 2 + 1
                } else {
                    self.words() as i64
                };
                // Check the whole span first: a rejected write changes nothing.
                mem.get_word(k, first).map_err(e)?;
                mem.get_word(k, first + span - 1).map_err(e)?;
                if self.ty == ValueType::Str {
                    let mut bytes = value.as_bytes().to_vec();
                    bytes.push(0);
                    if bytes.len() % 2 == 1 {
                        bytes.push(0);
                    }
                    for (i, pair) in bytes.chunks(2).enumerate() {
                        mem.set_word(k, first + i as i64, u16::from_le_bytes([pair[0], pair[1]]))
                            .map_err(e)?;
                    }
                    return Ok(());
                }
                let v = self.parse_raw(value).ok_or_else(bad)?;
                for i in 0..self.words() as i64 {
                    mem.set_word(k, first + i, (v >> (16 * i)) as u16)
                        .map_err(e)?;
                }
                Ok(())
            }
        }
    }

    /// Parses a number into the raw bits of the type; a value fitting the width as
    /// signed or unsigned is accepted (`H8000` and `-32768` for a 16-bit word).
    fn parse_raw(&self, s: &str) -> Option<u64> {
        if self.ty == ValueType::F32 {
            let v: f64 = s.parse().ok()?;
            let f = v as f32;
            return f.is_finite().then_some(f.to_bits() as u64);
        }
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
        let v = if neg { mag.checked_neg()? } else { mag };
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

fn parse_bool(s: &str) -> Option<bool> {
    match s.to_ascii_lowercase().as_str() {
        "1" | "true" | "on" => Some(true),
        "0" | "false" | "off" => Some(false),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::DeviceConfig;

    #[test]
    fn round_trips() {
        let mut mem = DeviceMemory::new(&DeviceConfig::default());
        let w = |m: &mut DeviceMemory, d: &str, v: &str| {
            DeviceSpec::parse(d).unwrap().write(m, v).unwrap()
        };
        let r = |m: &DeviceMemory, d: &str| DeviceSpec::parse(d).unwrap().read(m).unwrap();
        w(&mut mem, "D0", "-5");
        assert_eq!(r(&mem, "D0"), Value::Int(-5));
        assert_eq!(r(&mem, "D0:u16"), Value::Int(65531));
        w(&mut mem, "D10:f32", "1.5");
        assert_eq!(mem.get_word(DeviceKind::D, 11).unwrap(), 0x3FC0);
        assert_eq!(r(&mem, "D10:f32"), Value::Float(1.5));
        w(&mut mem, "D20:i32", "H12345678");
        assert_eq!(mem.get_word(DeviceKind::D, 20).unwrap(), 0x5678);
        assert_eq!(r(&mem, "D20:u32"), Value::Int(0x1234_5678));
        w(&mut mem, "K2Y10", "0xA5");
        assert_eq!(r(&mem, "Y10"), Value::Bool(true));
        assert_eq!(r(&mem, "Y11"), Value::Bool(false));
        assert_eq!(r(&mem, "Y17"), Value::Bool(true));
        assert_eq!(r(&mem, "K2Y10"), Value::Int(0xA5));
        w(&mut mem, "D30:str", "ABC");
        assert_eq!(mem.get_word(DeviceKind::D, 30).unwrap(), 0x4241);
        assert_eq!(mem.get_word(DeviceKind::D, 31).unwrap(), 0x0043);
        assert_eq!(r(&mem, "D30:str"), Value::Str("ABC".into()));
        w(&mut mem, "D0.F", "1");
        assert_eq!(r(&mem, "D0.F"), Value::Bool(true));
        w(&mut mem, "Z0", "3");
        w(&mut mem, "D200Z0", "77");
        assert_eq!(mem.get_word(DeviceKind::D, 203).unwrap(), 77);
        assert!(DeviceSpec::parse("D0:f64").is_err());
        assert!(DeviceSpec::parse("D0")
            .unwrap()
            .write(&mut mem, "70000")
            .is_err());
        assert!(DeviceSpec::parse("D99999").unwrap().read(&mem).is_err());
    }
}
