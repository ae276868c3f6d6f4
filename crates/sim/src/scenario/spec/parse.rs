//! The scenario file as TOML deserializes it, and its translation into a
//! [`Scenario`]: source, times, models and the timeline.

use softplc_core::names::Names;
use softplc_core::profile::{self, Profile, SourceFormat};
use softplc_core::single;
use softplc_core::system;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::expect::{expect_label, expect_spec};
use super::fleet::{self, PlcSpec};
use super::values::{binding, device, scan_at, time_us, write_text, Layout, Space};
use super::{
    EventSpec, ExpectKind, InputBinding, ModelSpec, OutputBinding, PlotSpec, Scenario, Setpoint,
    Source, TraceSpec,
};
use crate::model;
use crate::scenario::fmt::fmt_time;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Doc {
    name: Option<String>,
    #[allow(dead_code)]
    description: Option<String>,
    program: Option<String>,
    project: Option<String>,
    cpu: Option<String>,
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
    port1: Option<toml::Table>,
    port2: Option<toml::Table>,
    #[serde(default)]
    peer: Vec<toml::Table>,
    #[serde(default)]
    plc: Vec<fleet::PlcDoc>,
    #[serde(default)]
    link: Vec<fleet::LinkDoc>,
    #[serde(default)]
    client: Vec<fleet::ClientDoc>,
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
        let mut doc: Doc = toml::from_str(text).map_err(|e| {
            let (line, col) =
                softplc_core::project::line_col(text, e.span().map_or(0, |s| s.start));
            format!("{line}:{col}: {}", one_line(e.message()))
        })?;
        let base = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        // One PLC: its source first (errors in the order they always came).
        let single = if doc.plc.is_empty() {
            let source = fleet::source_of(&doc.program, &doc.project, &base)?;
            let cpu = single_cpu(&doc.cpu, &source)?;
            Some((source, cpu))
        } else {
            None
        };
        let scan_us = time_us(&doc.scan_time, "scan_time")?;
        if scan_us == 0 {
            return Err("scan_time: must be at least 1us".into());
        }
        let plcs = if doc.plc.is_empty() {
            Vec::new()
        } else {
            fleet_plcs(&mut doc, &base, text, scan_us)?
        };
        let (source, cpu, cpu_profile, dev_names) = match plcs.first() {
            Some(first) => {
                let mut names = Vec::new();
                let mut layout = Vec::new();
                for p in &plcs {
                    let (_, n) = names_of(&p.source, p.cpu);
                    layout.push((p.name.clone(), n.len()));
                    names.extend(n);
                }
                let space = Space {
                    names,
                    layout: Layout::Fleet(layout),
                };
                (first.source.clone(), first.cpu, first.profile, space)
            }
            None => {
                let (source, cpu) = single.expect("one PLC without [[plc]] tables");
                let (profile, names) = names_of(&source, cpu);
                let layout = Layout::One(names.len());
                (source, cpu, profile, Space { names, layout })
            }
        };
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
            models.push(model_spec(m, i, &base, &dev_names)?);
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
            timeline_entry(e, i, scan_us, scans, &dev_names, &mut timeline)?;
        }
        if timeline.len() as u64 > MAX_EVENTS {
            return Err(format!("timeline: more than {MAX_EVENTS} writes"));
        }
        timeline.sort_by_key(|e: &EventSpec| e.scan);

        let mut expects = Vec::new();
        for (i, t) in doc.expect.iter().enumerate() {
            expects.push(
                expect_spec(t, scan_us, scans, &dev_names)
                    .map_err(|e| format!("expect #{} ({}): {e}", i + 1, expect_label(t)))?,
            );
        }

        let mut trace = TraceSpec::default();
        if let Some(t) = doc.trace {
            for d in &t.devices {
                device(d, "trace", &dev_names)?;
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
                    device(d, "plot", &dev_names)?;
                }
                Some(PlotSpec {
                    file: base.join(p.file),
                    devices: p.devices,
                    title: p.title,
                })
            }
            None => None,
        };
        let mut ports = Vec::new();
        for (n, t) in [(1u8, &doc.port1), (2, &doc.port2)] {
            let Some(t) = t else { continue };
            if !matches!(source, Source::Program(_)) || cpu_profile.doors.serial_ports == 0 {
                return Err(format!(
                    "[port{n}]: only for an APLC program file (a project sets its ports in plc.toml)"
                ));
            }
            ports.push(super::peer::port_config(n, t)?);
        }
        let mut peers = Vec::new();
        for (i, t) in doc.peer.iter().enumerate() {
            let mut t = t.clone();
            let plc = match (t.remove("plc"), plcs.is_empty()) {
                (None, true) => None,
                (Some(_), true) => {
                    return Err(format!(
                        "peer #{}: `plc` names a PLC of [[plc]] tables; this scenario runs one PLC",
                        i + 1
                    ))
                }
                (None, false) => {
                    return Err(format!(
                    "peer #{}: `plc` is required with [[plc]] tables: the PLC whose port it is on",
                    i + 1
                ))
                }
                (Some(v), false) => {
                    let name = v.as_str().unwrap_or_default();
                    Some(
                        fleet::find_plc(&plcs, name)
                            .map_err(|e| format!("peer #{} plc: {e}", i + 1))?,
                    )
                }
            };
            let profile = plc.map_or(cpu_profile, |p| plcs[p].profile);
            if profile.doors.serial_ports == 0 {
                return Err(format!(
                    "peer #{}: serial peers need an APLC-TCP program (its PORT1/PORT2)",
                    i + 1
                ));
            }
            let mut spec = super::peer::peer(&t, i)?;
            spec.plc = plc.unwrap_or(0);
            peers.push(spec);
        }
        if plcs.is_empty() && !(doc.link.is_empty() && doc.client.is_empty()) {
            return Err("[[link]] and [[client]] connect the PLCs of [[plc]] tables".into());
        }
        let links = fleet::links(&doc.link, &plcs, text)?;
        let check = |d: &str, what: &str| device(d, what, &dev_names).map(|_| ());
        let clients = fleet::clients(
            std::mem::take(&mut doc.client),
            &plcs,
            &dev_names.layout,
            text,
            &check,
        )?;
        Ok(Scenario {
            file: path.to_path_buf(),
            name,
            source,
            cpu,
            profile: cpu_profile,
            names: dev_names.names.clone(),
            layout: dev_names.layout.clone(),
            scan_us,
            scans,
            models,
            timeline,
            expects,
            trace,
            plot,
            ports,
            peers,
            plcs,
            links,
            clients,
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

/// The `cpu` key of a scenario (or a `[[plc]]`) whose source is `source`.
fn single_cpu(cpu: &Option<String>, source: &Source) -> Result<Option<&'static Profile>, String> {
    match (cpu, source) {
        (None, _) => Ok(None),
        (Some(_), Source::Project(_)) => {
            Err("cpu: a project sets its CPU model with [cpu] model in plc.toml".into())
        }
        (Some(_), Source::System(_)) => Err(
            "cpu: each CPU of a multi-CPU system sets its model with [cpu] model in its plc.toml"
                .into(),
        ),
        (Some(m), Source::Program(p)) => Ok(Some(program_model(m, p)?)),
    }
}

/// The `[[plc]]` tables of a fleet; the single-PLC keys may not be mixed
/// with them.
fn fleet_plcs(
    doc: &mut Doc,
    base: &Path,
    text: &str,
    scan_us: u64,
) -> Result<Vec<PlcSpec>, String> {
    for (key, given) in [
        ("program", doc.program.is_some()),
        ("project", doc.project.is_some()),
        ("cpu", doc.cpu.is_some()),
        ("[port1]", doc.port1.is_some()),
        ("[port2]", doc.port2.is_some()),
    ] {
        if given {
            return Err(format!(
                "{key}: a key of a single-PLC scenario; with [[plc]] tables each PLC gives its own"
            ));
        }
    }
    let mut plcs: Vec<PlcSpec> = Vec::new();
    for (i, p) in std::mem::take(&mut doc.plc).into_iter().enumerate() {
        let name = p.name.get_ref().trim().to_string();
        let what = format!("{}: [[plc]] #{} `{name}`", fleet::at(text, &p.name), i + 1);
        fleet::check_name(&name).map_err(|e| format!("{what}: name: {e}"))?;
        if plcs.iter().any(|q| q.name == name) {
            return Err(format!("{what}: two PLCs are named `{name}`"));
        }
        let ctx = |e: String| format!("{what}: {e}");
        let source = fleet::source_of(&p.program, &p.project, base).map_err(ctx)?;
        let cpu = single_cpu(&p.cpu, &source).map_err(ctx)?;
        let (profile, _) = names_of(&source, cpu);
        let plc_scan = match &p.scan_time {
            Some(v) => time_us(v, "scan_time").map_err(ctx)?,
            None => scan_us,
        };
        if plc_scan == 0 {
            return Err(ctx("scan_time: must be at least 1us".into()));
        }
        let mut ports = Vec::new();
        for (n, t) in [(1u8, &p.port1), (2, &p.port2)] {
            let Some(t) = t else { continue };
            if !matches!(source, Source::Program(_)) || profile.doors.serial_ports == 0 {
                return Err(ctx(format!(
                    "[port{n}]: only for an APLC program file (a project sets its ports in plc.toml)"
                )));
            }
            ports.push(super::peer::port_config(n, t).map_err(ctx)?);
        }
        plcs.push(PlcSpec {
            name,
            source,
            cpu,
            profile,
            scan_us: plc_scan,
            ports,
        });
    }
    Ok(plcs)
}

/// The `cpu` of a scenario that runs one program file: a model that reads
/// the file's format (the APLC-TCP `.apl` files, a MELSEC model `.il`/`.csv`).
fn program_model(model: &str, program: &std::path::Path) -> Result<&'static Profile, String> {
    let model = profile::find(model).map_err(|e| format!("cpu: {e}"))?;
    single::profile_for(program, Some(model), None).map_err(|e| format!("cpu: {e}"))
}

/// What the scenario's device names mean: those of the program file's model
/// (`cpu`, else by the file name) or the project's, with the programs'
/// global names (the APLC's); each CPU's of a multi-CPU system (CPU 1's
/// profile is returned). A program, project or system that does not load
/// gives plain names here (four CPUs' for a system) and its errors when the
/// scenario is built.
fn names_of(source: &Source, cpu: Option<&'static Profile>) -> (&'static Profile, Vec<Names>) {
    match source {
        Source::Program(p) => {
            let d = match cpu {
                Some(m) => m,
                None => SourceFormat::of_file(p).default_profile(),
            };
            (d, vec![Names::of_files(d, &[p.as_path()])])
        }
        Source::Project(p) => {
            let (profile, names) = project_names(p);
            (profile, vec![names])
        }
        Source::System(p) => {
            let names: Vec<_> = match system::manifest::read(p) {
                Ok((_, dirs)) => dirs.iter().map(|d| project_names(d)).collect(),
                Err(_) => {
                    let profile = profile::default_profile();
                    (0..4).map(|_| (profile, Names::plain(profile))).collect()
                }
            };
            (names[0].0, names.into_iter().map(|(_, n)| n).collect())
        }
    }
}

/// A project's CPU model and names (plain names of the default model when
/// it does not load).
fn project_names(dir: &Path) -> (&'static Profile, Names) {
    match softplc_core::project::load_project(dir) {
        Ok(proj) => {
            let files: Vec<&Path> = proj.programs.iter().map(|s| s.file.as_path()).collect();
            let profile = proj.config.profile;
            (profile, Names::of_files(profile, &files))
        }
        Err(_) => {
            let profile = profile::default_profile();
            (profile, Names::plain(profile))
        }
    }
}

fn model_spec(mut m: ModelDoc, i: usize, base: &Path, names: &Space) -> Result<ModelSpec, String> {
    let name = m.name.clone().unwrap_or_else(|| m.kind.clone());
    let what = format!("model #{} `{name}`", i + 1);
    // An FMU's file is relative to the scenario file.
    if m.kind == "fmu" {
        if let Some(toml::Value::String(f)) = m.params.get_mut("file") {
            *f = base.join(&*f).display().to_string();
        }
    }
    let (ins, outs) = model::ports(&m.kind, &m.params).map_err(|e| format!("{what}: {e}"))?;
    let port = |ports: &[model::Port], p: &str, dir: &str| {
        ports.iter().position(|q| q == p).ok_or_else(|| {
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
        let idx = port(&ins, p, "input")?;
        inputs.push((
            idx,
            binding(v, &format!("{what}: input `{p}`"), true, names)?,
        ));
    }
    let mut outputs = Vec::new();
    for (p, v) in &m.outputs {
        let idx = port(&outs, p, "output")?;
        match binding(v, &format!("{what}: output `{p}`"), false, names)? {
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
    names: &Space,
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
        device(dev, &what, names)?;
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

/// A TOML error message on one line (its parts joined with "; ").
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}
