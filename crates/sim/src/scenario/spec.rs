//! Scenario files: TOML parsing and validation. Everything that does not need
//! the CPU is checked here (syntax of device names, times inside the run,
//! model types and parameters); device ranges are checked when the scenario is
//! built against the loaded program.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use softplc_core::access::{DeviceSpec, ValueType};

use super::fmt::{fmt_num, fmt_time};
use crate::model;

/// What the scenario runs: a program file or a project.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A program file (`.il` or GX Works2 `.csv`).
    Program(PathBuf),
    /// A project directory or its `plc.toml`.
    Project(PathBuf),
}

/// Scaling of a model port bound to a device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// Values pass unchanged (bits are 0/1; word values are rounded and clamped
    /// to the device type; `:f32` devices hold the value as is).
    None,
    /// A/D (model output → device) or D/A (device → model input) conversion
    /// between the engineering range and the raw digital range.
    Analog { raw: (i32, i32), eng: (f64, f64) },
    /// A bit device read as a model input: `off` when OFF, `on` when ON.
    Bit { off: f64, on: f64 },
}

/// Where a model input comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum InputBinding {
    /// A constant value.
    Const(f64),
    /// A device read before every step.
    Device { device: String, scale: Scale },
}

/// Where a model output goes.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputBinding {
    pub device: String,
    pub scale: Scale,
}

/// A plant model bound to devices.
#[derive(Clone, Debug)]
pub struct ModelSpec {
    pub name: String,
    pub kind: String,
    pub params: toml::Table,
    /// (port index, binding), in port order.
    pub inputs: Vec<(usize, InputBinding)>,
    pub outputs: Vec<(usize, OutputBinding)>,
}

/// A write before a scan (timeline entries with `every` are expanded).
#[derive(Clone, Debug, PartialEq)]
pub struct EventSpec {
    /// 1-based scan before which the writes happen.
    pub scan: u64,
    /// (device, value as text for `Cpu::write_device`).
    pub set: Vec<(String, String)>,
}

/// A condition on one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cond {
    /// `|v − value| ≤ tol` (for `:f32` devices with `tol = 0`, `value` is
    /// compared after rounding to f32).
    Eq {
        value: f64,
        tol: f64,
    },
    Gt(f64),
    Lt(f64),
    Ge(f64),
    Le(f64),
}

/// The setpoint of a settle/overshoot check.
#[derive(Clone, Debug, PartialEq)]
pub enum Setpoint {
    Value(f64),
    Device(String),
}

/// The settling band.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Band {
    /// Percent of the setpoint step (SV − PV at the start of the window); of
    /// |SV| when there is no step.
    Percent(f64),
    /// Absolute, in device units.
    Abs(f64),
}

/// When an expectation is checked, resolved to scans.
#[derive(Clone, Debug, PartialEq)]
pub enum ExpectKind {
    /// The condition holds at this scan.
    At { scan: u64, cond: Cond },
    /// The condition holds at some scan in `first..=last`.
    Within { first: u64, last: u64, cond: Cond },
    /// The condition holds at every scan in `first..=last`.
    Always { first: u64, last: u64, cond: Cond },
    /// The condition holds at no scan in `first..=last`.
    Never { first: u64, last: u64, cond: Cond },
    /// Loop performance over `first..=last`: settled (inside the band from
    /// `deadline` on) and overshoot at most `max_overshoot` % of the step.
    Settle {
        first: u64,
        last: u64,
        setpoint: Setpoint,
        band: Band,
        deadline: Option<u64>,
        max_overshoot: Option<f64>,
    },
}

/// One `[[expect]]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct ExpectSpec {
    /// The pass/fail line's text.
    pub text: String,
    pub device: String,
    /// More devices shown in the history of a failure.
    pub show: Vec<String>,
    pub kind: ExpectKind,
}

/// `[trace]`: devices recorded for CSV and plots.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TraceSpec {
    pub devices: Vec<String>,
    /// CSV file to write (relative paths are relative to the scenario file).
    pub file: Option<PathBuf>,
    /// Sample period; default: every scan, or fewer so that a run keeps at
    /// most [`DEFAULT_MAX_SAMPLES`] samples.
    pub interval_us: Option<u64>,
}

/// `[plot]`: an SVG of traced devices over time.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotSpec {
    pub file: PathBuf,
    /// Devices to draw (default: the trace devices, else the expectation
    /// devices).
    pub devices: Vec<String>,
    pub title: Option<String>,
}

/// Samples a trace keeps by default (the sample period grows for long runs).
pub const DEFAULT_MAX_SAMPLES: u64 = 10_000;

/// A parsed scenario.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// The scenario file (for reports).
    pub file: PathBuf,
    pub name: String,
    pub source: Source,
    /// Virtual time per scan, µs.
    pub scan_us: u64,
    /// Scans to run (the duration rounded up to whole scans).
    pub scans: u64,
    pub models: Vec<ModelSpec>,
    /// Sorted by scan (file order within a scan).
    pub timeline: Vec<EventSpec>,
    pub expects: Vec<ExpectSpec>,
    pub trace: TraceSpec,
    pub plot: Option<PlotSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Doc {
    name: Option<String>,
    #[allow(dead_code)]
    description: Option<String>,
    program: Option<String>,
    project: Option<String>,
    scan_time: toml::Value,
    duration: toml::Value,
    #[serde(default)]
    model: Vec<ModelDoc>,
    #[serde(default)]
    timeline: Vec<EventDoc>,
    #[serde(default)]
    expect: Vec<toml::Table>,
    trace: Option<TraceDoc>,
    plot: Option<PlotDoc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelDoc {
    name: Option<String>,
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    params: toml::Table,
    #[serde(default)]
    inputs: toml::Table,
    #[serde(default)]
    outputs: toml::Table,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EventDoc {
    at: Option<toml::Value>,
    scan: Option<u64>,
    every: Option<toml::Value>,
    count: Option<u64>,
    set: toml::Table,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TraceDoc {
    #[serde(default)]
    devices: Vec<String>,
    file: Option<String>,
    interval: Option<toml::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlotDoc {
    file: String,
    #[serde(default)]
    devices: Vec<String>,
    title: Option<String>,
}

/// Events a timeline may expand to (`every` × `count`).
const MAX_EVENTS: u64 = 1_000_000;

/// A time: seconds as a number, or a string with units ("1.5s", "2min").
fn time_us(v: &toml::Value, what: &str) -> Result<u64, String> {
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

fn number(v: &toml::Value, what: &str) -> Result<f64, String> {
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

fn device(text: &str, what: &str) -> Result<DeviceSpec, String> {
    let spec = DeviceSpec::parse(text.trim()).map_err(|e| format!("{what}: {e}"))?;
    if spec.ty == ValueType::Str {
        return Err(format!(
            "{what}: `{text}`: strings cannot be bound or checked"
        ));
    }
    Ok(spec)
}

/// `PORT = "DEV"`, `PORT = { device = "DEV", raw = [..], eng = [..] }` (and
/// for inputs a constant number).
fn binding(v: &toml::Value, what: &str, input: bool) -> Result<InputBinding, String> {
    let (dev, scale) = match v {
        toml::Value::String(s) => (s.clone(), Scale::None),
        toml::Value::Integer(_) | toml::Value::Float(_) if input => {
            return Ok(InputBinding::Const(number(v, what)?))
        }
        toml::Value::Table(t) => {
            for k in t.keys() {
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
            let spec = device(&dev, what)?;
            let eng = t
                .get("eng")
                .map(|e| pair_f64(e, &format!("{what}: eng")))
                .transpose()?;
            let raw = t
                .get("raw")
                .map(|r| pair_i32(r, &format!("{what}: raw")))
                .transpose()?;
            let scale = match (raw, eng, spec.ty == ValueType::Bit) {
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
    device(&dev, what)?;
    Ok(InputBinding::Device { device: dev, scale })
}

/// A value for `Cpu::write_device`.
fn write_text(v: &toml::Value, what: &str) -> Result<String, String> {
    Ok(match v {
        toml::Value::Boolean(b) => if *b { "1" } else { "0" }.to_string(),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => format!("{f:?}"),
        toml::Value::String(s) => s.clone(),
        _ => return Err(format!("{what}: expected a number, true/false or a string")),
    })
}

/// The first scan at or after time `us` (scan n runs at n·scan_us), at least 1.
fn scan_at(us: u64, scan_us: u64) -> u64 {
    us.div_ceil(scan_us).max(1)
}

/// The last scan at or before time `us`.
fn scan_before(us: u64, scan_us: u64) -> u64 {
    us / scan_us
}

impl Scenario {
    /// Reads and parses a scenario file.
    pub fn load(path: &Path) -> Result<Scenario, String> {
        const MAX_SCENARIO_BYTES: u64 = 4 << 20;
        let bytes =
            softplc_core::program::read_limited(path, MAX_SCENARIO_BYTES, "a scenario file")
                .map_err(|e| format!("{}: {e}", path.display()))?;
        let text = String::from_utf8(bytes)
            .map_err(|e| format!("{}: not UTF-8 text: {e}", path.display()))?;
        Scenario::parse(&text, path)
    }

    /// Parses scenario text; relative paths in it are relative to `path`'s
    /// directory. Errors start with the file name.
    pub fn parse(text: &str, path: &Path) -> Result<Scenario, String> {
        Scenario::parse_inner(text, path).map_err(|e| format!("{}: {e}", path.display()))
    }

    fn parse_inner(text: &str, path: &Path) -> Result<Scenario, String> {
        let doc: Doc = toml::from_str(text).map_err(|e| e.to_string().trim_end().to_string())?;
        let base = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let source = match (&doc.program, &doc.project) {
            (Some(p), None) => Source::Program(base.join(p)),
            (None, Some(p)) => Source::Project(base.join(p)),
            _ => {
                return Err(
                    "give exactly one of `program` (a file) or `project` (a directory)".into(),
                )
            }
        };
        let scan_us = time_us(&doc.scan_time, "scan_time")?;
        if scan_us == 0 {
            return Err("scan_time: must be at least 1us".into());
        }
        let duration_us = time_us(&doc.duration, "duration")?;
        let scans = duration_us.div_ceil(scan_us);
        if scans == 0 {
            return Err("duration: must be at least one scan".into());
        }
        let name = doc.name.clone().unwrap_or_else(|| {
            path.file_stem()
                .map_or_else(|| "scenario".into(), |s| s.to_string_lossy().into_owned())
        });

        let mut models = Vec::new();
        for (i, m) in doc.model.into_iter().enumerate() {
            models.push(model_spec(m, i)?);
        }
        let mut names: Vec<&str> = models.iter().map(|m| m.name.as_str()).collect();
        names.sort_unstable();
        if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
            return Err(format!(
                "two models are named `{}` (give each a `name`)",
                w[0]
            ));
        }

        let mut timeline = Vec::new();
        for (i, e) in doc.timeline.into_iter().enumerate() {
            timeline_entry(e, i, scan_us, scans, &mut timeline)?;
        }
        if timeline.len() as u64 > MAX_EVENTS {
            return Err(format!("timeline: more than {MAX_EVENTS} writes"));
        }
        timeline.sort_by_key(|e: &EventSpec| e.scan);

        let mut expects = Vec::new();
        for (i, t) in doc.expect.iter().enumerate() {
            expects.push(
                expect_spec(t, scan_us, scans)
                    .map_err(|e| format!("expect #{} ({}): {e}", i + 1, expect_label(t)))?,
            );
        }

        let mut trace = TraceSpec::default();
        if let Some(t) = doc.trace {
            for d in &t.devices {
                device(d, "trace")?;
            }
            trace.devices = t.devices;
            trace.file = t.file.map(|f| base.join(f));
            trace.interval_us = t
                .interval
                .map(|v| time_us(&v, "trace: interval"))
                .transpose()?;
        }
        let plot = match doc.plot {
            Some(p) => {
                for d in &p.devices {
                    device(d, "plot")?;
                }
                Some(PlotSpec {
                    file: base.join(p.file),
                    devices: p.devices,
                    title: p.title,
                })
            }
            None => None,
        };
        Ok(Scenario {
            file: path.to_path_buf(),
            name,
            source,
            scan_us,
            scans,
            models,
            timeline,
            expects,
            trace,
            plot,
        })
    }

    /// Virtual time of the whole run, µs.
    pub fn duration_us(&self) -> u64 {
        self.scans * self.scan_us
    }

    /// The devices the expectations check (each once, in order): the default
    /// for plots.
    pub fn expect_devices(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for e in &self.expects {
            let mut add = |d: &str| {
                if !out.iter().any(|o| o == d) {
                    out.push(d.to_string());
                }
            };
            add(&e.device);
            if let ExpectKind::Settle {
                setpoint: Setpoint::Device(d),
                ..
            } = &e.kind
            {
                add(d);
            }
        }
        out
    }
}

fn model_spec(m: ModelDoc, i: usize) -> Result<ModelSpec, String> {
    let name = m.name.clone().unwrap_or_else(|| m.kind.clone());
    let what = format!("model #{} `{name}`", i + 1);
    let built = model::build(&m.kind, &m.params).map_err(|e| format!("{what}: {e}"))?;
    let port = |ports: &[&'static str], p: &str, dir: &str| {
        ports.iter().position(|q| *q == p).ok_or_else(|| {
            format!(
                "{what}: `{}` has no {dir} `{p}` ({dir}s: {})",
                m.kind,
                if ports.is_empty() {
                    "none".to_string()
                } else {
                    ports.join(", ")
                }
            )
        })
    };
    let mut inputs = Vec::new();
    for (p, v) in &m.inputs {
        let idx = port(built.inputs(), p, "input")?;
        inputs.push((idx, binding(v, &format!("{what}: input `{p}`"), true)?));
    }
    let mut outputs = Vec::new();
    for (p, v) in &m.outputs {
        let idx = port(built.outputs(), p, "output")?;
        match binding(v, &format!("{what}: output `{p}`"), false)? {
            InputBinding::Device { device, scale } => {
                outputs.push((idx, OutputBinding { device, scale }))
            }
            InputBinding::Const(_) => unreachable!("outputs take no constants"),
        }
    }
    inputs.sort_by_key(|(i, _)| *i);
    outputs.sort_by_key(|(i, _)| *i);
    Ok(ModelSpec {
        name,
        kind: m.kind,
        params: m.params,
        inputs,
        outputs,
    })
}

fn timeline_entry(
    e: EventDoc,
    i: usize,
    scan_us: u64,
    scans: u64,
    out: &mut Vec<EventSpec>,
) -> Result<(), String> {
    let what = format!("timeline #{}", i + 1);
    let first = match (&e.at, e.scan) {
        (Some(t), None) => scan_at(time_us(t, &format!("{what}: at"))?, scan_us),
        (None, Some(n)) if n >= 1 => n,
        (None, Some(_)) => return Err(format!("{what}: scan numbers start at 1")),
        _ => {
            return Err(format!(
                "{what}: give exactly one of `at` (a time) or `scan`"
            ))
        }
    };
    if e.set.is_empty() {
        return Err(format!("{what}: `set` is empty"));
    }
    if first > scans {
        return Err(format!(
            "{what}: scan {first} is after the end of the run ({scans} scans)"
        ));
    }
    let mut set = Vec::new();
    for (dev, v) in &e.set {
        device(dev, &what)?;
        set.push((dev.clone(), write_text(v, &format!("{what}: `{dev}`"))?));
    }
    let (every, count) = match (&e.every, e.count) {
        (None, None) => (0, 1),
        (Some(ev), c) => {
            let us = time_us(ev, &format!("{what}: every"))?;
            let n = us.div_ceil(scan_us);
            if us == 0 || us % scan_us != 0 {
                return Err(format!(
                    "{what}: every must be a whole number of scans ({} per scan)",
                    fmt_time(scan_us)
                ));
            }
            // Without a count, repeat to the end of the run.
            let c = c.unwrap_or_else(|| scans.saturating_sub(first) / n + 1);
            (n, c)
        }
        (None, Some(_)) => return Err(format!("{what}: `count` needs `every`")),
    };
    if count > MAX_EVENTS {
        return Err(format!("{what}: more than {MAX_EVENTS} repetitions"));
    }
    for k in 0..count {
        let scan = first + k * every;
        if scan > scans {
            break;
        }
        out.push(EventSpec {
            scan,
            set: set.clone(),
        });
    }
    Ok(())
}

fn expect_label(t: &toml::Table) -> String {
    match (t.get("name"), t.get("device")) {
        (Some(toml::Value::String(n)), _) => n.clone(),
        (_, Some(toml::Value::String(d))) => d.clone(),
        _ => "?".into(),
    }
}

const EXPECT_KEYS: &[&str] = &[
    "name",
    "device",
    "show",
    "at",
    "within",
    "after",
    "always",
    "never",
    "from",
    "to",
    "equals",
    "tolerance",
    "above",
    "below",
    "at_least",
    "at_most",
    "never_exceeds",
    "never_below",
    "setpoint",
    "band",
    "band_abs",
    "settle_within",
    "max_overshoot",
];

fn expect_spec(t: &toml::Table, scan_us: u64, scans: u64) -> Result<ExpectSpec, String> {
    for k in t.keys() {
        if !EXPECT_KEYS.contains(&k.as_str()) {
            return Err(format!(
                "unknown key `{k}` (keys: {})",
                EXPECT_KEYS.join(", ")
            ));
        }
    }
    let dev = t
        .get("device")
        .and_then(|v| v.as_str())
        .ok_or("`device` (a string) is required")?
        .to_string();
    let spec = device(&dev, "device")?;
    let is_bit = spec.ty == ValueType::Bit;
    let show = match t.get("show") {
        None => Vec::new(),
        Some(toml::Value::Array(a)) => a
            .iter()
            .map(|v| {
                let s = v.as_str().ok_or("show: expected device names")?;
                device(s, "show")?;
                Ok(s.to_string())
            })
            .collect::<Result<Vec<_>, String>>()?,
        Some(_) => return Err("show: expected a list of device names".into()),
    };
    let end_us = scans * scan_us;
    let get_time = |k: &str| t.get(k).map(|v| time_us(v, k)).transpose();
    let check_end = |us: u64, what: &str| {
        if us > end_us {
            Err(format!(
                "{what} {} is after the end of the run ({})",
                fmt_time(us),
                fmt_time(end_us)
            ))
        } else {
            Ok(())
        }
    };
    // The window of always/never/settle.
    let window = || -> Result<(u64, u64, u64, u64), String> {
        let from = get_time("from")?.unwrap_or(0);
        let to = get_time("to")?.unwrap_or(end_us);
        check_end(to, "to")?;
        // `to` itself is excluded (a timeline change at `to` starts a new
        // phase); without `to` the window runs to the last scan.
        let last = if t.contains_key("to") {
            scan_before(to.saturating_sub(1), scan_us)
        } else {
            scans
        };
        let first = scan_at(from, scan_us);
        if first > last {
            return Err(format!(
                "the window {}–{} holds no scan",
                fmt_time(from),
                fmt_time(to)
            ));
        }
        Ok((first, last, from, to))
    };
    let fmt_v = |v: f64| {
        if is_bit {
            (if v > 0.5 { "true" } else { "false" }).to_string()
        } else {
            fmt_num(v)
        }
    };
    let name_prefix = match t.get("name") {
        Some(toml::Value::String(n)) => format!("{n}: "),
        Some(_) => return Err("name: expected a string".into()),
        None => String::new(),
    };
    let finish = |text: String, kind: ExpectKind| {
        Ok(ExpectSpec {
            text: format!("{name_prefix}{text}"),
            device: dev.clone(),
            show: show.clone(),
            kind,
        })
    };

    // Loop performance.
    if let Some(sp) = t.get("setpoint") {
        if is_bit {
            return Err("a settle check needs a word device".into());
        }
        for k in [
            "at",
            "within",
            "after",
            "always",
            "never",
            "equals",
            "tolerance",
            "above",
            "below",
            "at_least",
            "at_most",
            "never_exceeds",
            "never_below",
        ] {
            if t.contains_key(k) {
                return Err(format!("`{k}` does not go with `setpoint`"));
            }
        }
        let setpoint = match sp {
            toml::Value::String(s) => {
                device(s, "setpoint")?;
                Setpoint::Device(s.clone())
            }
            v => Setpoint::Value(number(v, "setpoint")?),
        };
        let band = match (t.get("band"), t.get("band_abs")) {
            (Some(b), None) => Band::Percent(number(b, "band")?),
            (None, Some(b)) => Band::Abs(number(b, "band_abs")?),
            _ => return Err("give one of `band` (% of the step) or `band_abs`".into()),
        };
        if matches!(band, Band::Percent(b) | Band::Abs(b) if !(b >= 0.0 && b.is_finite())) {
            return Err("the band must be ≥ 0".into());
        }
        let settle = get_time("settle_within")?;
        let max_overshoot = t
            .get("max_overshoot")
            .map(|v| number(v, "max_overshoot"))
            .transpose()?;
        if settle.is_none() && max_overshoot.is_none() {
            return Err("give `settle_within` and/or `max_overshoot`".into());
        }
        let (first, last, from, to) = window()?;
        let deadline = match settle {
            Some(s) => {
                check_end(from + s, "from + settle_within =")?;
                Some(scan_at(from + s, scan_us))
            }
            None => None,
        };
        let sp_text = match &setpoint {
            Setpoint::Value(v) => fmt_num(*v),
            Setpoint::Device(d) => d.clone(),
        };
        let band_text = match band {
            Band::Percent(b) => format!("±{} %", fmt_num(b)),
            Band::Abs(b) => format!("±{}", fmt_num(b)),
        };
        let mut text = format!("{dev} settles to {sp_text} {band_text}");
        if let Some(s) = settle {
            text += &format!(" within {}", fmt_time(s));
        }
        if from > 0 {
            text += &format!(" after {}", fmt_time(from));
        }
        if let Some(o) = max_overshoot {
            text += &format!(", overshoot ≤ {} %", fmt_num(o));
        }
        if to != end_us {
            text += &format!(" (until {})", fmt_time(to));
        }
        return finish(
            text,
            ExpectKind::Settle {
                first,
                last,
                setpoint,
                band,
                deadline,
                max_overshoot,
            },
        );
    }

    // Sugar: never_exceeds / never_below.
    for (k, gt) in [("never_exceeds", true), ("never_below", false)] {
        if let Some(v) = t.get(k) {
            for other in [
                "at",
                "within",
                "after",
                "always",
                "never",
                "equals",
                "above",
                "below",
                "at_least",
                "at_most",
                "tolerance",
            ] {
                if t.contains_key(other) {
                    return Err(format!("`{other}` does not go with `{k}`"));
                }
            }
            if t.contains_key(if gt { "never_below" } else { "never_exceeds" }) {
                return Err("give one of `never_exceeds` or `never_below`".into());
            }
            let v = number(v, k)?;
            let (first, last, from, to) = window()?;
            let cond = if gt { Cond::Gt(v) } else { Cond::Lt(v) };
            let text = format!(
                "{dev} never {} {}{}",
                if gt { "exceeds" } else { "falls below" },
                fmt_num(v),
                window_text(from, to, end_us)
            );
            return finish(text, ExpectKind::Never { first, last, cond });
        }
    }

    // The condition.
    let mut conds = Vec::new();
    if let Some(v) = t.get("equals") {
        let value = number(v, "equals")?;
        let tol = t
            .get("tolerance")
            .map(|v| number(v, "tolerance"))
            .transpose()?
            .unwrap_or(0.0);
        if tol.is_nan() || tol < 0.0 {
            return Err("tolerance must be ≥ 0".into());
        }
        let value = if spec.ty == ValueType::F32 && tol == 0.0 {
            value as f32 as f64
        } else {
            value
        };
        conds.push(Cond::Eq { value, tol });
    } else if t.contains_key("tolerance") {
        return Err("`tolerance` goes with `equals`".into());
    }
    for (k, mk) in [
        ("above", Cond::Gt as fn(f64) -> Cond),
        ("below", Cond::Lt),
        ("at_least", Cond::Ge),
        ("at_most", Cond::Le),
    ] {
        if let Some(v) = t.get(k) {
            if is_bit {
                return Err(format!("`{k}`: a bit device takes `equals = true/false`"));
            }
            conds.push(mk(number(v, k)?));
        }
    }
    let cond = match conds.as_slice() {
        [c] => *c,
        [] => {
            return Err(
                "give a condition: equals (with tolerance), above, below, at_least or at_most"
                    .into(),
            )
        }
        _ => return Err("give only one of equals, above, below, at_least, at_most".into()),
    };
    let cond_text = match cond {
        Cond::Eq { value, tol } if tol > 0.0 => format!("= {} ±{}", fmt_v(value), fmt_num(tol)),
        Cond::Eq { value, .. } => format!("= {}", fmt_v(value)),
        Cond::Gt(v) => format!("> {}", fmt_num(v)),
        Cond::Lt(v) => format!("< {}", fmt_num(v)),
        Cond::Ge(v) => format!("≥ {}", fmt_num(v)),
        Cond::Le(v) => format!("≤ {}", fmt_num(v)),
    };

    // When.
    let always = match t.get("always") {
        None => false,
        Some(toml::Value::Boolean(true)) => true,
        Some(_) => return Err("always: write `always = true`".into()),
    };
    let never = match t.get("never") {
        None => false,
        Some(toml::Value::Boolean(true)) => true,
        Some(_) => return Err("never: write `never = true`".into()),
    };
    let whens = [
        t.contains_key("at"),
        t.contains_key("within"),
        always,
        never,
    ];
    if whens.iter().filter(|w| **w).count() != 1 {
        return Err("give exactly one of `at`, `within`, `always = true`, `never = true`".into());
    }
    if (t.contains_key("from") || t.contains_key("to")) && !(always || never) {
        return Err("`from`/`to` go with `always`, `never` and `setpoint`".into());
    }
    if t.contains_key("after") && !t.contains_key("within") {
        return Err("`after` goes with `within`".into());
    }
    if let Some(at) = get_time("at")? {
        check_end(at, "at")?;
        return finish(
            format!("{dev} {cond_text} at {}", fmt_time(at)),
            ExpectKind::At {
                scan: scan_at(at, scan_us),
                cond,
            },
        );
    }
    if let Some(w) = get_time("within")? {
        let after = get_time("after")?.unwrap_or(0);
        check_end(after + w, "after + within =")?;
        let (first, last) = (scan_at(after, scan_us), scan_before(after + w, scan_us));
        if first > last {
            return Err(format!(
                "the window {}–{} holds no scan",
                fmt_time(after),
                fmt_time(after + w)
            ));
        }
        let verb = if matches!(cond, Cond::Eq { .. }) {
            format!("becomes {}", cond_text.trim_start_matches("= "))
        } else {
            format!("becomes {cond_text}")
        };
        let mut text = format!("{dev} {verb} within {}", fmt_time(w));
        if after > 0 {
            text += &format!(" after {}", fmt_time(after));
        }
        return finish(text, ExpectKind::Within { first, last, cond });
    }
    let (first, last, from, to) = window()?;
    let wt = window_text(from, to, end_us);
    // "Y1 never true" rather than "Y1 never = true".
    let cond_text = match cond {
        Cond::Eq { .. } if is_bit => cond_text.trim_start_matches("= ").to_string(),
        _ => cond_text,
    };
    if always {
        finish(
            format!("{dev} always {cond_text}{wt}"),
            ExpectKind::Always { first, last, cond },
        )
    } else {
        finish(
            format!("{dev} never {cond_text}{wt}"),
            ExpectKind::Never { first, last, cond },
        )
    }
}

fn window_text(from: u64, to: u64, end: u64) -> String {
    match (from, to == end) {
        (0, true) => String::new(),
        (f, true) => format!(" from {}", fmt_time(f)),
        (f, false) => format!(" from {} to {}", fmt_time(f), fmt_time(to)),
    }
}
