//! APLC device names outside programs (`--set`, `--show`; contract §2):
//! `X10` and `Y10` octal, `M100`, `D0`, `SM0`, `SD20`, `Z0`, `K4M0`, `D10Z1`,
//! `T5`/`C5` the contact, `TN5`/`CN5` the current value (`CN200`-`CN255`
//! 32-bit, `i32` by default), `LM`/`V` MAIN's locals (read only). `:i32`,
//! `:u32`, `:f32` read Dn as the HIGH word. Values may be `16#1F`, `8#17`,
//! `2#101`.
//!
//! A name resolves to a [`DeviceSpec`] of the shared door over the storage
//! the APLC device lives in, with the word order turned where two registers
//! hold one value.

use softplc_ir::access::{DeviceSpec, Value, ValueType};
use softplc_ir::device::DeviceKind;

use crate::devices::{counter_word, is_counter32, parse_device, Dev};

/// A parsed APLC `DEV[:TYPE]`.
#[derive(Clone, Debug)]
pub struct Name {
    /// The door's spec over the storage (two-register values as `u32`).
    pub spec: DeviceSpec,
    /// The type shown and written.
    pub ty: ValueType,
    /// Two registers holding one value, high word first: turned on the way.
    swap: bool,
    /// LM and V: MAIN's locals, not writable from outside.
    local: bool,
}

impl Name {
    /// Parses `DEV` or `DEV:TYPE`.
    pub fn parse(s: &str) -> Result<Name, String> {
        let (dev, ty) = match s.split_once(':') {
            Some((d, t)) => (d.trim(), Some(t.trim().to_ascii_lowercase())),
            None => (s.trim(), None),
        };
        let u = dev.to_ascii_uppercase();
        // TN5 / CN5: the current value.
        let value_of = ["TN", "CN"].iter().any(|p| {
            u.strip_prefix(*p)
                .is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit()))
        });
        let (melsec, bit, wide, local) = if value_of {
            let d = parse_device(&format!("{}{}", &u[..1], &u[2..]))?
                .filter(|d| d.group.is_none())
                .ok_or_else(|| format!("`{s}` is not a device"))?;
            let (kind, n) = d
                .dev
                .word_storage(d.n)
                .ok_or_else(|| format!("`{s}` is not a device"))?;
            let wide = d.dev == Dev::C && is_counter32(d.n);
            (with_index(kind.format(n), d.index), false, wide, false)
        } else {
            let d = parse_device(&u)?.ok_or_else(|| format!("`{s}` is not an APLC device"))?;
            let local = matches!(d.dev, Dev::LM | Dev::V);
            if let Some(k) = d.group {
                let (kind, n) = d
                    .dev
                    .bit_storage(d.n)
                    .ok_or_else(|| format!("`{s}` is not a bit group"))?;
                (
                    with_index(format!("K{k}{}", kind.format(n)), d.index),
                    false,
                    k > 4,
                    local,
                )
            } else if d.dev.is_bit() {
                let (kind, n) = d
                    .dev
                    .bit_storage(d.n)
                    .ok_or_else(|| format!("`{s}` is not a device"))?;
                (with_index(kind.format(n), d.index), true, false, local)
            } else {
                let (kind, n) = d
                    .dev
                    .word_storage(d.n)
                    .ok_or_else(|| format!("`{s}` is not a device"))?;
                (with_index(kind.format(n), d.index), false, false, local)
            }
        };
        let group = melsec.starts_with('K');
        let ty = match (ty.as_deref(), bit) {
            (None, true) => ValueType::Bit,
            (Some("bool" | "bit"), true) => ValueType::Bit,
            (Some(t), true) => return Err(format!("`{s}`: a bit device takes no type `{t}`")),
            (None, false) if wide => ValueType::I32,
            (None, false) => ValueType::I16,
            (Some("i16"), false) => ValueType::I16,
            (Some("u16"), false) => ValueType::U16,
            (Some("i32"), false) => ValueType::I32,
            (Some("u32"), false) => ValueType::U32,
            (Some("f32"), false) if !group => ValueType::F32,
            (Some(t), false) => {
                return Err(format!(
                    "`{s}`: unknown type `{t}` (i16, u16, i32, u32, f32)"
                ))
            }
        };
        let two = matches!(ty, ValueType::I32 | ValueType::U32 | ValueType::F32);
        if wide && !two {
            return Err(format!("`{s}`: C200-C255 are 32-bit (i32 or u32)"));
        }
        let swap = two && !group;
        let door_ty = match ty {
            _ if swap => "u32",
            ValueType::Bit => "bit",
            ValueType::U16 => "u16",
            ValueType::I32 => "i32",
            ValueType::U32 => "u32",
            _ => "i16",
        };
        let mut spec =
            DeviceSpec::parse(&format!("{melsec}:{door_ty}")).map_err(|e| format!("`{s}`: {e}"))?;
        spec.text = s.to_string();
        Ok(Name {
            spec,
            ty,
            swap,
            local,
        })
    }

    /// Two registers holding one value high word first: the door's `u32`
    /// is turned on the way.
    pub fn swaps(&self) -> bool {
        self.swap
    }

    /// LM or V: MAIN's locals, read only from outside.
    pub fn is_local(&self) -> bool {
        self.local
    }

    /// The value read through the door, in this name's type.
    pub fn present(&self, v: Value) -> Value {
        let Value::Int(raw) = v else {
            return v;
        };
        if !self.swap {
            return Value::Int(raw);
        }
        let w = (raw as u32).rotate_left(16);
        match self.ty {
            ValueType::I32 => Value::Int(w as i32 as i64),
            ValueType::F32 => Value::Float(f32::from_bits(w) as f64),
            _ => Value::Int(w as i64),
        }
    }

    /// The value to write through the door for `text` (decimal, `16#`, `8#`,
    /// `2#`, a float for `:f32`, `0`/`1`/`true`/`false` for bits).
    pub fn value(&self, text: &str) -> Result<Value, String> {
        if self.local {
            return Err(format!(
                "`{}`: LM and V are POU locals and cannot be set",
                self.spec.text
            ));
        }
        let bad = || format!("`{}`: bad value `{text}`", self.spec.text);
        let t = text.trim();
        if self.ty == ValueType::Bit {
            return match t.to_ascii_lowercase().as_str() {
                "1" | "true" | "on" => Ok(Value::Bool(true)),
                "0" | "false" | "off" => Ok(Value::Bool(false)),
                _ => Err(bad()),
            };
        }
        let raw: i64 = if self.ty == ValueType::F32 && !t.contains('#') {
            let f: f32 = t.parse().map_err(|_| bad())?;
            f.to_bits() as i64
        } else {
            parse_int(t).ok_or_else(bad)?
        };
        if !self.swap {
            return Ok(Value::Int(raw));
        }
        let bits = u32::try_from(raw)
            .or_else(|_| i32::try_from(raw).map(|v| v as u32))
            .map_err(|_| bad())?;
        Ok(Value::Int(bits.rotate_left(16) as i64))
    }
}

fn with_index(mut s: String, z: Option<u8>) -> String {
    if let Some(z) = z {
        s += &format!("Z{z}");
    }
    s
}

fn parse_int(t: &str) -> Option<i64> {
    for (p, r) in [("16#", 16), ("8#", 8), ("2#", 2)] {
        if let Some(d) = t.strip_prefix(p) {
            return i64::from_str_radix(d, r).ok();
        }
    }
    t.strip_prefix('+').unwrap_or(t).parse().ok()
}

/// The storage of counter value `n` (for tools that address counters).
pub fn counter_value(n: u32) -> (DeviceKind, u32) {
    (DeviceKind::CN, counter_word(n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_map_to_storage() {
        let n = Name::parse("X10").unwrap();
        assert_eq!(n.spec.text, "X10");
        assert_eq!(n.ty, ValueType::Bit);
        assert!(Name::parse("X8").is_err());
        assert_eq!(Name::parse("CN200").unwrap().ty, ValueType::I32);
        assert!(Name::parse("CN200:i16").is_err());
        assert_eq!(
            Name::parse("D0:f32").unwrap().value("1.5").unwrap(),
            Value::Int(1.5f32.to_bits().rotate_left(16) as i64)
        );
        assert!(Name::parse("V0").unwrap().value("1").is_err());
        assert_eq!(
            Name::parse("D0").unwrap().value("16#1F").unwrap(),
            Value::Int(31)
        );
        let n = Name::parse("D0:i32").unwrap();
        assert_eq!(n.present(Value::Int(0x0002_0001)), Value::Int(0x0001_0002));
    }
}
