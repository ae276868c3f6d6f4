//! `[initial]`: device initial values (004 §10.13.2, L7687-7748), written at
//! power-on and STOP→RUN.
//!
//! Keys are device specs as on the command line (`D0`, `D10:f32`, `W1F:u16`,
//! `D100:str`); values are TOML integers, floats (for `:f32`) or strings (text
//! for `:str`, or a number such as `"H1F"`). The manual allows T/ST/C current
//! values (`TN`, `STN`, `CN`), D, SD, W, SW and file registers R; ZR (the same
//! memory, serially numbered) is accepted too, and the buffer memory of the
//! rack's intelligent modules, `U<n>\\G<addr>` (004 ch. 8: device initial
//! values reach a module at power-on, RESET and STOP→RUN).

use super::ctx::Ctx;
use super::tree::{Entry, Value};
use crate::access::{DeviceSpec, ValueType};
use crate::device::{parse_operand, DeviceConfig, DeviceKind, DeviceMemory, Operand};
use crate::engine::InitialValue;

const ALLOWED: &[DeviceKind] = {
    use DeviceKind::*;
    &[TN, STN, CN, D, SD, W, SW, R, ZR, G]
};
const ALLOWED_TEXT: &str =
    "TN, STN, CN (current values), D, SD, W, SW, R, ZR and buffer memory U\\G";

fn describe(ty: ValueType) -> &'static str {
    match ty {
        ValueType::I16 | ValueType::U16 => "a 16-bit integer: -32768 to 65535, or H0-HFFFF",
        ValueType::I32 | ValueType::U32 => {
            "a 32-bit integer: -2147483648 to 4294967295, or H0-HFFFFFFFF"
        }
        ValueType::F32 => "a finite 32-bit real number",
        ValueType::Str => "text",
        ValueType::Bit => "a bit",
    }
}

/// Reads `[initial]`; `devices` gives the device points values must fit in.
pub(crate) fn initial(cx: &mut Ctx, t: &[Entry], devices: &DeviceConfig) -> Vec<InitialValue> {
    let mut out = Vec::new();
    if t.is_empty() {
        return out;
    }
    let mut mem = DeviceMemory::new(devices);
    // Words already given an initial value: (kind, first, count, key).
    let mut taken: Vec<(DeviceKind, u32, u32, &str)> = Vec::new();
    for e in t {
        let key = e.key.as_str();
        let strip = |m: String| {
            m.strip_prefix(&format!("`{key}`: "))
                .map(str::to_string)
                .unwrap_or(m)
        };
        let spec = match DeviceSpec::parse(key) {
            Ok(s) => s,
            Err(m) => {
                cx.error(&e.key_span, format!("\"{key}\": {}", strip(m)));
                continue;
            }
        };
        let dev_text = key.split(':').next().unwrap_or(key);
        let Ok(Operand::Device {
            dev,
            digits,
            bit,
            index,
        }) = parse_operand(dev_text)
        else {
            cx.error(&e.key_span, format!("\"{key}\" is not a device"));
            continue;
        };
        if index.is_some() {
            cx.error(
                &e.key_span,
                format!("\"{key}\": index modification is not allowed for initial values"),
            );
            continue;
        }
        if digits.is_some() || bit.is_some() {
            cx.error(
                &e.key_span,
                format!(
                    "\"{key}\" is a bit operand; initial values are set for word devices ({ALLOWED_TEXT})"
                ),
            );
            continue;
        }
        if dev.generic {
            let word = dev.word_kind().format(dev.number);
            cx.error(
                &e.key_span,
                format!("\"{key}\" is a contact; write {word} for the current value"),
            );
            continue;
        }
        if !ALLOWED.contains(&dev.kind) {
            cx.error(
                &e.key_span,
                format!(
                    "{} cannot have an initial value; initial values are for {ALLOWED_TEXT}",
                    dev.kind.name()
                ),
            );
            continue;
        }
        // The value as text DeviceSpec::write understands.
        let value = match (&e.item.value, spec.ty) {
            (Value::Str(s), _) => s.clone(),
            (Value::Int(_) | Value::Float(_), ValueType::Str) => {
                cx.error(
                    &e.item.span,
                    format!("the initial value of {key} must be text (a string)"),
                );
                continue;
            }
            (Value::Int(i), _) => i.to_string(),
            (Value::Float(f), ValueType::F32) => format!("{f}"),
            (Value::Float(f), ty) => {
                cx.error(
                    &e.item.span,
                    format!(
                        "initial value {f} is not valid for {key} ({}); write {dev_text}:f32 for a real number",
                        describe(ty)
                    ),
                );
                continue;
            }
            (v, _) => {
                cx.error(
                    &e.item.span,
                    format!(
                        "the initial value of {key} must be a number or a string, not {}",
                        v.type_name()
                    ),
                );
                continue;
            }
        };
        // The device range (value-independent), then the value.
        let probe = if spec.ty == ValueType::Str { "" } else { "0" };
        if let Err(m) = spec.write(&mut mem, probe) {
            cx.error(&e.key_span, format!("{key}: {}", strip(m)));
            continue;
        }
        if let Err(m) = spec.write(&mut mem, &value) {
            let msg = if spec.ty == ValueType::Str {
                format!("the text for {key} does not fit: {}", strip(m))
            } else {
                let shown = match &e.item.value {
                    Value::Str(s) => format!("\"{s}\""),
                    _ => value.clone(),
                };
                format!(
                    "initial value {shown} is not valid for {key} ({})",
                    describe(spec.ty)
                )
            };
            cx.error(&e.item.span, msg);
            continue;
        }
        // Two initial values for one word: the file would depend on key order.
        let words = match spec.ty {
            ValueType::I32 | ValueType::U32 | ValueType::F32 => 2,
            ValueType::Str => value.len() as u32 / 2 + 1,
            _ => 1,
        };
        let kind = if dev.kind == DeviceKind::R {
            DeviceKind::ZR
        } else {
            dev.kind
        };
        // Buffer memory: one number space per unit.
        let number = match dev.reach {
            crate::device::Reach::Unit(u) => u << 16 | dev.number,
            _ => dev.number,
        };
        let (first, last) = (number, number + words - 1);
        if let Some((_, _, _, other)) = taken
            .iter()
            .find(|(k, f, n, _)| *k == kind && *f <= last && first < f + n)
        {
            cx.error(
                &e.key_span,
                format!("{key} overlaps the initial value of {other}"),
            );
            continue;
        }
        taken.push((kind, first, words, key));
        out.push(InitialValue {
            device: spec,
            value,
        });
    }
    out
}
