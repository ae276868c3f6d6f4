//! TOML values of a scenario file: times, numbers, device names, model port
//! bindings, device writes and their conversion to scans.

use softplc_core::access::ValueType;
use softplc_core::names::{DevName, Names};
use softplc_core::system;

use super::{InputBinding, Scale};
use crate::model;

/// A time: seconds as a number, or a string with units ("1.5s", "2min").
pub(super) fn time_us(v: &toml::Value, what: &str) -> Result<u64, String> {
    let secs = match v {
        toml::Value::Integer(i) if *i >= 0 => *i as f64,
        toml::Value::Float(f) if *f >= 0.0 && f.is_finite() => *f,
        toml::Value::String(s) => model::parse_duration(s).map_err(|e| format!("{what}: {e}"))?,
        _ => {
            return Err(format!(
                "{what}: expected a time (seconds, or a string like \"1.5s\", \"500ms\", \"2min\")"
            ))
        }
    };
    let us = (secs * 1e6).round();
    if us > 1e15 {
        return Err(format!("{what}: too long"));
    }
    Ok(us as u64)
}

pub(super) fn number(v: &toml::Value, what: &str) -> Result<f64, String> {
    match v {
        toml::Value::Integer(i) => Ok(*i as f64),
        toml::Value::Float(f) if !f.is_nan() => Ok(*f),
        toml::Value::Boolean(b) => Ok(f64::from(u8::from(*b))),
        _ => Err(format!("{what}: expected a number")),
    }
}

fn pair_f64(v: &toml::Value, what: &str) -> Result<(f64, f64), String> {
    match v.as_array().map(|a| a.as_slice()) {
        Some([a, b]) => Ok((number(a, what)?, number(b, what)?)),
        _ => Err(format!("{what}: expected [low, high]")),
    }
}

fn pair_i32(v: &toml::Value, what: &str) -> Result<(i32, i32), String> {
    let bad = || format!("{what}: expected [low, high] raw integers");
    match v.as_array().map(|a| a.as_slice()) {
        Some([toml::Value::Integer(a), toml::Value::Integer(b)]) => Ok((
            i32::try_from(*a).map_err(|_| bad())?,
            i32::try_from(*b).map_err(|_| bad())?,
        )),
        _ => Err(bad()),
    }
}

/// A module channel `U<n>\CH<k>`: the unit `n` (hex, as in `U<n>\G<addr>`)
/// and the channel `k` (from 1, as the manuals' CH1). `None` when `text` is
/// not written as a channel.
pub(crate) fn channel(text: &str) -> Option<Result<(u32, u32), String>> {
    let t = text.trim();
    let (unit, ch) = t.split_once('\\')?;
    let unit = unit.strip_prefix(['U', 'u'])?;
    if ch.len() < 2 || !ch.is_char_boundary(2) || !ch[..2].eq_ignore_ascii_case("CH") {
        return None;
    }
    let parsed = u32::from_str_radix(unit, 16)
        .ok()
        .zip(ch[2..].parse::<u32>().ok().filter(|&k| k >= 1));
    Some(parsed.ok_or_else(|| {
        format!("`{t}`: a module channel is written U<unit>\\CH<channel>, e.g. U2\\CH1")
    }))
}

/// The CPU (0-based) a device name addresses and the name without its
/// `CPUn/` prefix, for `cpus` CPUs (contract §6: `CPU2/D0`; a name without
/// a prefix is CPU 1's). A single CPU takes `CPU1/` too; in it, a name
/// whose head is not `CPU<n>` passes whole to the CPU's own names.
pub(crate) fn split_cpu(text: &str, cpus: usize) -> Result<(usize, &str), String> {
    let text = text.trim();
    if cpus > 1 {
        return system::names::split(text, cpus);
    }
    match system::names::prefix(text) {
        None => Ok((0, text)),
        Some((1, rest)) => Ok((0, rest)),
        Some((n, _)) => Err(format!(
            "`{text}`: there is no CPU {n} (the scenario runs one CPU; a multi-CPU system is a directory with system.toml)"
        )),
    }
}

/// How a scenario's device names choose their CPU: by a `CPUn/` prefix
/// among the CPUs of one PLC, or in a fleet (`[[plc]]`) by the PLC's name
/// first (`line1/D0`, `line2/CPU2/D0`). CPUs are numbered flat: the first
/// PLC's CPUs first.
#[derive(Clone, Debug, PartialEq)]
pub enum Layout {
    /// One PLC of this many CPUs; names without a PLC name.
    One(usize),
    /// The PLCs of a fleet in `[[plc]]` order: name and number of CPUs.
    Fleet(Vec<(String, usize)>),
}

impl Layout {
    /// The CPU (flat, 0-based) `text` addresses and the name after its
    /// prefixes.
    pub fn split<'a>(&self, text: &'a str) -> Result<(usize, &'a str), String> {
        let plcs = match self {
            Layout::One(cpus) => return split_cpu(text, *cpus),
            Layout::Fleet(plcs) => plcs,
        };
        let text = text.trim();
        let Some((head, rest)) = text.split_once('/') else {
            return Err(format!(
                "`{text}`: name the PLC it belongs to, as in `{}/{text}` (PLCs: {})",
                plcs[0].0,
                self.plc_names()
            ));
        };
        let mut first = 0;
        for (name, cpus) in plcs {
            if name == head.trim() {
                let (cpu, rest) =
                    split_cpu(rest, *cpus).map_err(|e| format!("PLC `{name}`: {e}"))?;
                return Ok((first + cpu, rest));
            }
            first += cpus;
        }
        Err(format!(
            "`{text}`: no PLC is named `{}` (PLCs: {})",
            head.trim(),
            self.plc_names()
        ))
    }

    /// The PLC (0-based) and its own CPU (0-based) of flat CPU `cpu`.
    pub fn locate(&self, cpu: usize) -> (usize, usize) {
        let Layout::Fleet(plcs) = self else {
            return (0, cpu);
        };
        let mut first = 0;
        for (i, (_, n)) in plcs.iter().enumerate() {
            if cpu < first + n {
                return (i, cpu - first);
            }
            first += n;
        }
        (plcs.len().saturating_sub(1), 0)
    }

    /// The CPUs of every PLC together.
    pub fn cpus(&self) -> usize {
        match self {
            Layout::One(n) => *n,
            Layout::Fleet(plcs) => plcs.iter().map(|(_, n)| n).sum(),
        }
    }

    fn plc_names(&self) -> String {
        match self {
            Layout::One(_) => String::new(),
            Layout::Fleet(plcs) => plcs
                .iter()
                .map(|(n, _)| n.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        }
    }
}

/// The device names of a scenario: each CPU's dialect (flat, as
/// [`Layout`] numbers them) and how a name chooses its CPU.
#[derive(Clone, Debug)]
pub struct Space {
    pub names: Vec<Names>,
    pub layout: Layout,
}

/// A device name in the scenario's dialect, `names` per CPU (checked
/// against the CPU at build).
pub(super) fn device(text: &str, what: &str, names: &Space) -> Result<DevName, String> {
    let (cpu, text) = names
        .layout
        .split(text)
        .map_err(|e| format!("{what}: {e}"))?;
    if channel(text).is_some() {
        return Err(format!(
            "{what}: `{}` is a module channel: it binds a model port (check or trace the module's U\\G words)",
            text.trim()
        ));
    }
    let spec = names.names[cpu]
        .parse(text.trim())
        .map_err(|e| format!("{what}: {e}"))?;
    if spec.ty() == ValueType::Str {
        return Err(format!(
            "{what}: `{text}`: strings cannot be bound or checked"
        ));
    }
    Ok(spec)
}

/// `PORT = "DEV"`, `PORT = { device = "DEV", raw = [..], eng = [..] }` (and
/// for inputs a constant number); a module channel in place of DEV
/// (`"U2\\CH1"`, `{ device = "U2\\CH1", signal = [4, 20], eng = [..] }`).
pub(super) fn binding(
    v: &toml::Value,
    what: &str,
    input: bool,
    names: &Space,
) -> Result<InputBinding, String> {
    let target = match v {
        toml::Value::String(s) => Some(s.as_str()),
        toml::Value::Table(t) => t.get("device").and_then(|d| d.as_str()),
        _ => None,
    };
    let target = target
        .map(|t| names.layout.split(t).map_err(|e| format!("{what}: {e}")))
        .transpose()?;
    if let Some(ch) = target.and_then(|(_, t)| channel(t)) {
        ch.map_err(|e| format!("{what}: {e}"))?;
        return channel_binding(v, what);
    }
    let (dev, scale) = match v {
        toml::Value::String(s) => (s.clone(), Scale::None),
        toml::Value::Integer(_) | toml::Value::Float(_) if input => {
            return Ok(InputBinding::Const(number(v, what)?))
        }
        toml::Value::Table(t) => {
            for k in t.keys() {
                if k == "signal" {
                    return Err(format!(
                        "{what}: `signal` is for a module channel (U<n>\\CH<k>); a device takes raw = [..]"
                    ));
                }
                if !["device", "raw", "eng"].contains(&k.as_str()) {
                    return Err(format!(
                        "{what}: unknown key `{k}` (keys: device, raw, eng)"
                    ));
                }
            }
            let dev = t
                .get("device")
                .and_then(|d| d.as_str())
                .ok_or_else(|| format!("{what}: `device` (a string) is required"))?
                .to_string();
            let spec = device(&dev, what, names)?;
            let eng = t
                .get("eng")
                .map(|e| pair_f64(e, &format!("{what}: eng")))
                .transpose()?;
            let raw = t
                .get("raw")
                .map(|r| pair_i32(r, &format!("{what}: raw")))
                .transpose()?;
            let scale = match (raw, eng, spec.ty() == ValueType::Bit) {
                (None, None, _) => Scale::None,
                (None, Some((off, on)), true) if input => Scale::Bit { off, on },
                (Some(raw), Some(eng), false) => {
                    if raw.0 == raw.1 || eng.0 == eng.1 {
                        return Err(format!("{what}: raw and eng ranges must not be empty"));
                    }
                    Scale::Analog { raw, eng }
                }
                (_, _, true) => {
                    return Err(format!(
                        "{what}: a bit device takes no `raw` range{}",
                        if input {
                            " (give eng = [off, on] to map OFF/ON to values)"
                        } else {
                            ""
                        }
                    ))
                }
                _ => {
                    return Err(format!(
                        "{what}: give both `raw` and `eng` ranges, or neither"
                    ))
                }
            };
            (dev, scale)
        }
        _ => {
            return Err(format!(
                "{what}: expected a device name, {{ device = .., raw = [..], eng = [..] }}{}",
                if input { ", or a constant number" } else { "" }
            ))
        }
    };
    device(&dev, what, names)?;
    Ok(InputBinding::Device { device: dev, scale })
}

/// A binding to a module channel: its physical value as is, or scaled from
/// `eng` to `signal`.
fn channel_binding(v: &toml::Value, what: &str) -> Result<InputBinding, String> {
    let (dev, scale) = match v {
        toml::Value::Table(t) => {
            for k in t.keys() {
                if k == "raw" {
                    return Err(format!(
                        "{what}: a module channel carries mA or V, not digital values: give signal = [..] and eng = [..]"
                    ));
                }
                if !["device", "signal", "eng"].contains(&k.as_str()) {
                    return Err(format!(
                        "{what}: unknown key `{k}` (keys: device, signal, eng)"
                    ));
                }
            }
            let signal = t
                .get("signal")
                .map(|e| pair_f64(e, &format!("{what}: signal")))
                .transpose()?;
            let eng = t
                .get("eng")
                .map(|e| pair_f64(e, &format!("{what}: eng")))
                .transpose()?;
            let scale = match (signal, eng) {
                (None, None) => Scale::None,
                (Some(signal), Some(eng)) => {
                    if signal.0 == signal.1 || eng.0 == eng.1 {
                        return Err(format!("{what}: signal and eng ranges must not be empty"));
                    }
                    Scale::Signal { signal, eng }
                }
                _ => {
                    return Err(format!(
                        "{what}: give both `signal` and `eng` ranges, or neither"
                    ))
                }
            };
            let dev = t.get("device").and_then(|d| d.as_str()).unwrap_or_default();
            (dev.trim().to_string(), scale)
        }
        toml::Value::String(s) => (s.trim().to_string(), Scale::None),
        _ => {
            return Err(format!(
                "{what}: expected a module channel such as \"U2\\CH1\""
            ))
        }
    };
    Ok(InputBinding::Device { device: dev, scale })
}

/// A value for `Cpu::write_device`.
pub(super) fn write_text(v: &toml::Value, what: &str) -> Result<String, String> {
    Ok(match v {
        toml::Value::Boolean(b) => if *b { "1" } else { "0" }.to_string(),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => format!("{f:?}"),
        toml::Value::String(s) => s.clone(),
        _ => return Err(format!("{what}: expected a number, true/false or a string")),
    })
}

/// The first scan at or after time `us` (scan n runs at n·scan_us), at least 1.
pub(super) fn scan_at(us: u64, scan_us: u64) -> u64 {
    us.div_ceil(scan_us).max(1)
}

/// The last scan at or before time `us`.
pub(super) fn scan_before(us: u64, scan_us: u64) -> u64 {
    us / scan_us
}
