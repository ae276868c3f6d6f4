//! Device names and values of the JSON API (contract §3.1): names are those
//! of `--show` (§2), values JSON booleans, numbers and strings.

use serde_json::{json, Value as Json};
use softplc_core::access::{DeviceSpec, Value, ValueType};
use softplc_core::device::DeviceKind;

/// Most names in one request.
pub const MAX_NAMES: usize = 1024;

/// Parses a device name, naming it in the error.
pub fn spec(name: &str) -> Result<DeviceSpec, String> {
    let name = name.trim();
    if name.is_empty() {
        return Err("empty device name".into());
    }
    DeviceSpec::parse(name).map_err(|e| format!("unknown device `{name}`: {e}"))
}

/// Parses `names=D0,Y0,D10:f32`.
pub fn spec_list(names: Option<&str>) -> Result<Vec<DeviceSpec>, String> {
    let names = names.ok_or("missing `names` (e.g. ?names=D0,Y0,D10:f32)")?;
    let list: Vec<&str> = names.split(',').filter(|n| !n.trim().is_empty()).collect();
    if list.is_empty() {
        return Err("`names` lists no device".into());
    }
    if list.len() > MAX_NAMES {
        return Err(format!("at most {MAX_NAMES} names in one request"));
    }
    list.into_iter().map(spec).collect()
}

/// A device value as JSON.
pub fn to_json(v: &Value) -> Json {
    match v {
        Value::Bool(b) => Json::Bool(*b),
        Value::Int(i) => json!(i),
        Value::Float(f) => json!(f),
        Value::Str(s) => Json::String(s.clone()),
    }
}

/// A JSON value for `spec`, or an error naming both.
pub fn from_json(spec: &DeviceSpec, v: &Json) -> Result<Value, String> {
    let bad = || format!("`{}`: `{v}` is not a valid {:?} value", spec.text, spec.ty);
    let value = match (spec.ty, v) {
        (ValueType::Bit, Json::Bool(b)) => Value::Bool(*b),
        (ValueType::Bit, Json::Number(n)) => match n.as_u64() {
            Some(0) => Value::Bool(false),
            Some(1) => Value::Bool(true),
            _ => return Err(bad()),
        },
        (ValueType::Str, Json::String(s)) => Value::Str(s.clone()),
        (ValueType::F32, Json::Number(n)) => {
            let f = n.as_f64().ok_or_else(bad)?;
            if !(f as f32).is_finite() {
                return Err(bad());
            }
            Value::Float(f)
        }
        (ValueType::Bit | ValueType::Str, _) => return Err(bad()),
        (_, Json::Number(n)) => Value::Int(n.as_i64().ok_or_else(bad)?),
        // "H1F", "0x1F", "-5" as text.
        (_, Json::String(s)) => spec.parse_value(s).map_err(|e| e.to_string())?,
        _ => return Err(bad()),
    };
    Ok(value)
}

/// X`n` or Y`n` named by a force request (contract §3.1: only X and Y).
pub fn io_point(name: &str) -> Result<(DeviceKind, u32), String> {
    let s = spec(name)?;
    match s.bit_span() {
        Some((k @ (DeviceKind::X | DeviceKind::Y), n, 1)) if s.ty == ValueType::Bit => Ok((k, n)),
        _ => Err(format!("`{}`: only X and Y points can be forced", s.text)),
    }
}

/// The `--show` name of X`n`/Y`n` (hexadecimal).
pub fn io_name(kind: DeviceKind, n: u32) -> String {
    format!("{kind:?}{n:X}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_values_follow_the_device_type() {
        let d = spec("D0").unwrap();
        assert_eq!(from_json(&d, &json!(5)).unwrap(), Value::Int(5));
        assert_eq!(from_json(&d, &json!("H1F")).unwrap(), Value::Int(31));
        assert!(from_json(&d, &json!(true)).is_err());
        assert!(from_json(&d, &json!(1.5)).is_err());
        let m = spec("M0").unwrap();
        assert_eq!(from_json(&m, &json!(true)).unwrap(), Value::Bool(true));
        assert!(from_json(&m, &json!(2)).is_err());
        let f = spec("D10:f32").unwrap();
        assert_eq!(from_json(&f, &json!(2.5)).unwrap(), Value::Float(2.5));
        assert!(from_json(&f, &json!(1e300)).is_err());
        assert!(spec("QQ9").unwrap_err().contains("QQ9"));
    }

    #[test]
    fn only_x_and_y_points_are_forced() {
        assert_eq!(io_point("X1F").unwrap(), (DeviceKind::X, 0x1F));
        assert_eq!(io_point("y0").unwrap(), (DeviceKind::Y, 0));
        assert!(io_point("M0").is_err());
        assert!(io_point("K4X0").is_err());
        assert_eq!(io_name(DeviceKind::X, 0x1F), "X1F");
    }
}
