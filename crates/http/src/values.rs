//! Device names and values of the JSON API (contract §3.1): names are those
//! of `--show` (§2) in the program's dialect (`softplc_core::names`: MELSEC,
//! or the APLC's octal X/Y and high-word-first pairs), values JSON booleans,
//! numbers and strings.

use serde_json::{json, Value as Json};
use softplc_core::access::{DeviceSpec, Value, ValueType};
use softplc_core::device::DeviceKind;
use softplc_core::names::{DevName, Names};
use softplc_core::profile;

/// Most names in one request.
pub const MAX_NAMES: usize = 1024;

/// Parses a device name (or an APLC global name) of `names`, naming it in
/// the error.
pub fn name(name: &str, names: &Names) -> Result<DevName, String> {
    let name = name.trim();
    if name.is_empty() {
        return Err("empty device name".into());
    }
    names
        .parse(name)
        .map_err(|e| format!("unknown device `{name}`: {e}"))
}

/// Parses `names=D0,Y0,D10:f32` with `names`.
pub fn name_list(list: Option<&str>, names: &Names) -> Result<Vec<DevName>, String> {
    split_names(list)?
        .into_iter()
        .map(|n| name(n, names))
        .collect()
}

/// Parses a MELSEC device name, naming it in the error.
pub fn spec(text: &str) -> Result<DeviceSpec, String> {
    name(text, &Names::plain(profile::default_profile())).map(|n| n.spec().clone())
}

/// Parses `names=D0,Y0,D10:f32` as MELSEC names.
pub fn spec_list(names: Option<&str>) -> Result<Vec<DeviceSpec>, String> {
    split_names(names)?.into_iter().map(spec).collect()
}

fn split_names(names: Option<&str>) -> Result<Vec<&str>, String> {
    let names = names.ok_or("missing `names` (e.g. ?names=D0,Y0,D10:f32)")?;
    let list: Vec<&str> = names.split(',').filter(|n| !n.trim().is_empty()).collect();
    if list.is_empty() {
        return Err("`names` lists no device".into());
    }
    if list.len() > MAX_NAMES {
        return Err(format!("at most {MAX_NAMES} names in one request"));
    }
    Ok(list)
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

/// A JSON value for `dev` in its type, or an error naming both.
pub fn from_json(dev: &DevName, v: &Json) -> Result<Value, String> {
    let bad = || {
        format!(
            "`{}`: `{v}` is not a valid {:?} value",
            dev.text(),
            dev.ty()
        )
    };
    let value = match (dev.ty(), v) {
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
        // "H1F", "0x1F" (MELSEC), "16#1F" (APLC), "-5" as text.
        (_, Json::String(s)) => dev.parse_value(s)?,
        _ => return Err(bad()),
    };
    Ok(value)
}

/// X`n` or Y`n` named by a force request (contract §3.1: only X and Y).
pub fn io_point(text: &str, names: &Names) -> Result<(DeviceKind, u32), String> {
    let d = name(text, names)?;
    match d.spec().bit_span() {
        Some((k @ (DeviceKind::X | DeviceKind::Y), n, 1)) if d.ty() == ValueType::Bit => Ok((k, n)),
        _ => Err(format!("`{}`: only X and Y points can be forced", d.text())),
    }
}

/// The `--show` name of X`n`/Y`n` in `names`' dialect.
pub fn io_name(kind: DeviceKind, n: u32, names: &Names) -> String {
    names.naming.io_name(kind, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_values_follow_the_device_type() {
        let mel = Names::plain(profile::default_profile());
        let spec = |s| name(s, &mel);
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
        // APLC: 16# values; LM/V are parsed but refused on write.
        let d = name("D0", &Names::plain(profile::aplc())).unwrap();
        assert_eq!(from_json(&d, &json!("16#1F")).unwrap(), Value::Int(31));
        assert!(name("X8", &Names::plain(profile::aplc()))
            .unwrap_err()
            .contains("X8"));
    }

    #[test]
    fn only_x_and_y_points_are_forced() {
        let m = &Names::plain(profile::default_profile());
        assert_eq!(io_point("X1F", m).unwrap(), (DeviceKind::X, 0x1F));
        assert_eq!(io_point("y0", m).unwrap(), (DeviceKind::Y, 0));
        assert!(io_point("M0", m).is_err());
        assert!(io_point("K4X0", m).is_err());
        assert_eq!(io_name(DeviceKind::X, 0x1F, m), "X1F");
        // APLC X/Y are octal: X10 is input 8.
        assert_eq!(
            io_point("X10", &Names::plain(profile::aplc())).unwrap(),
            (DeviceKind::X, 8)
        );
        assert_eq!(
            io_name(DeviceKind::Y, 8, &Names::plain(profile::aplc())),
            "Y10"
        );
    }
}
