//! Device names and values of the JSON API (contract §3.1): names are those
//! of `--show` (§2) in the program's dialect (`softplc_core::names`: MELSEC,
//! or the APLC's octal X/Y and high-word-first pairs), values JSON booleans,
//! numbers and strings. A multi-CPU system's names carry their CPU
//! (contract §6): `CPU2/D0` is CPU 2's D0, a name without a prefix CPU 1's
//! ([`Dev`]).

use serde_json::{json, Value as Json};
use softplc_core::access::{DeviceSpec, Value, ValueType};
use softplc_core::device::DeviceKind;
use softplc_core::engine::Cpu;
use softplc_core::names::{DevName, Names};
use softplc_core::profile;
use softplc_core::system::names::split;
use softplc_serve::ServeState;

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

/// A device name of one of the served CPUs: `CPU2/D0` is CPU 2's D0, a
/// name without a prefix (or `CPU1/`) CPU 1's. A suffix `@PROGRAM` names
/// the program file whose local devices it means (`D0@main`): the
/// monitor's chosen program (QCPU manual §10.13.1); without it a local
/// device is device memory's, the program's that ran last.
#[derive(Clone, Debug)]
pub struct Dev {
    /// The CPU, 0-based.
    pub cpu: usize,
    /// The name in that CPU's dialect, without the prefix.
    pub name: DevName,
    /// The program file after `@`, as given.
    program: Option<String>,
    /// The name as given: the key in answers.
    text: String,
}

impl Dev {
    pub fn text(&self) -> &str {
        &self.text
    }

    pub fn ty(&self) -> ValueType {
        self.name.ty()
    }

    pub fn read(&self, s: &mut ServeState) -> Result<Value, String> {
        self.on(s, |name, cpu| name.read(cpu))
    }

    pub fn write_value(&self, s: &mut ServeState, v: &Value) -> Result<(), String> {
        self.on(s, |name, cpu| name.write_value(cpu, v))
    }

    /// Runs `f` on this name's CPU, with its program's local devices in
    /// device memory when it names a program.
    fn on<R>(
        &self,
        s: &mut ServeState,
        f: impl FnOnce(&DevName, &mut Cpu) -> Result<R, String>,
    ) -> Result<R, String> {
        let cpu = s.cpu_mut_at(self.cpu);
        let Some(program) = &self.program else {
            return f(&self.name, cpu);
        };
        let Some(slot) = cpu.program_slot(program) else {
            let files: Vec<String> = (0..cpu.program_count())
                .map(|i| {
                    let file = &cpu.program_at(i).file;
                    std::path::Path::new(file)
                        .file_name()
                        .map_or(file.clone(), |f| f.to_string_lossy().into_owned())
                })
                .collect();
            return Err(format!(
                "`{}`: no program file `{program}` (the programs: {})",
                self.text,
                files.join(", ")
            ));
        };
        cpu.with_local_devices_of(slot, |cpu| f(&self.name, cpu))
    }

    /// A JSON value in the device's type ([`from_json`]), the error naming
    /// the device as given.
    pub fn value(&self, v: &Json) -> Result<Value, String> {
        from_json(&self.name, v).map_err(|e| {
            e.replacen(
                &format!("`{}`", self.name.text()),
                &format!("`{}`", self.text),
                1,
            )
        })
    }
}

/// Parses a device name of the served CPUs, whose names are `cpus` (CPU 1's
/// first), naming it in the error.
pub fn dev(text: &str, cpus: &[Names]) -> Result<Dev, String> {
    let text = text.trim();
    if text.is_empty() {
        return Err("empty device name".into());
    }
    let (cpu, rest) = split(text, cpus.len())?;
    let names = cpus
        .get(cpu)
        .ok_or_else(|| format!("`{text}`: no such CPU"))?;
    let (rest, program) = match rest.rsplit_once('@') {
        Some((_, p)) if p.trim().is_empty() => {
            return Err(format!("`{text}`: a program file name after `@`"))
        }
        Some((dev, p)) => (dev.trim_end(), Some(p.trim().to_string())),
        None => (rest, None),
    };
    let name = name(rest, names).map_err(|e| {
        if rest.len() == text.len() {
            e
        } else {
            format!("`{text}`: {e}")
        }
    })?;
    Ok(Dev {
        cpu,
        name,
        program,
        text: text.to_string(),
    })
}

/// Parses `names=D0,CPU2/Y0,D10:f32` for the served CPUs.
pub fn dev_list(list: Option<&str>, cpus: &[Names]) -> Result<Vec<Dev>, String> {
    split_names(list)?
        .into_iter()
        .map(|n| dev(n, cpus))
        .collect()
}

/// The prefix of CPU `cpu`'s (0-based) names in answers: none for CPU 1.
pub fn cpu_prefix(cpu: usize) -> String {
    if cpu == 0 {
        String::new()
    } else {
        format!("CPU{}/", cpu + 1)
    }
}

/// Parses a MELSEC device name, naming it in the error.
pub fn spec(text: &str) -> Result<DeviceSpec, String> {
    name(text, &Names::plain(profile::default_profile())).map(|n| n.spec().clone())
}

/// Parses `names=D0,Y0,D10:f32` as MELSEC names.
pub fn spec_list(names: Option<&str>) -> Result<Vec<DeviceSpec>, String> {
    split_names(names)?.into_iter().map(spec).collect()
}

/// Checks `names=D0,CPU2/Y0,D0@main` as MELSEC names, each with its CPU prefix
/// (up to CPU 4); the names as given.
pub fn prefixed_list(names: Option<&str>) -> Result<Vec<String>, String> {
    split_names(names)?
        .into_iter()
        .map(|n| {
            let (_, rest) = split(n.trim(), 4)?;
            // `D0@main`: a program's local device, checked when read.
            spec(
                rest.rsplit_once('@')
                    .map_or(rest, |(dev, _)| dev.trim_end()),
            )?;
            Ok(n.trim().to_string())
        })
        .collect()
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

/// X`n` or Y`n` of one of the served CPUs: (CPU, X or Y, n).
pub fn io_dev(text: &str, cpus: &[Names]) -> Result<(usize, DeviceKind, u32), String> {
    let d = dev(text, cpus)?;
    match d.name.spec().bit_span() {
        Some((k @ (DeviceKind::X | DeviceKind::Y), n, 1)) if d.ty() == ValueType::Bit => {
            Ok((d.cpu, k, n))
        }
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
    fn names_carry_their_cpu() {
        let mel = Names::plain(profile::default_profile());
        let two = [mel.clone(), mel.clone()];
        let d = dev(" CPU2/D10:f32", &two).unwrap();
        assert_eq!(
            (d.cpu, d.text(), d.name.text()),
            (1, "CPU2/D10:f32", "D10:f32")
        );
        assert_eq!(dev("D0", &two).unwrap().cpu, 0);
        assert_eq!(dev("cpu1/M0", &two).unwrap().cpu, 0);
        assert!(dev("CPU3/D0", &two).unwrap_err().contains("no CPU 3"));
        assert!(dev("CPU2/QQ9", &two).unwrap_err().contains("CPU2/QQ9"));
        // A single CPU takes CPU1/ only.
        assert!(dev("CPU2/D0", &two[..1]).is_err());
        let e = d.value(&json!(true)).unwrap_err();
        assert!(e.contains("`CPU2/D10:f32`"), "{e}");
        assert_eq!(io_dev("CPU2/Y1F", &two).unwrap(), (1, DeviceKind::Y, 0x1F));
        assert!(io_dev("CPU2/M0", &two).is_err());
        assert_eq!(cpu_prefix(0), "");
        assert_eq!(cpu_prefix(3), "CPU4/");
        assert_eq!(
            prefixed_list(Some("D0,CPU2/D1:f32")).unwrap(),
            ["D0", "CPU2/D1:f32"]
        );
        assert!(prefixed_list(Some("CPU5/D0")).is_err());
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
