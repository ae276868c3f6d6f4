//! Projects: a directory with `plc.toml` and its program files (contract §1, §4).
//!
//! [`load_project`] reads `plc.toml` into a [`CpuConfig`] and a list of
//! [`ProgramSpec`]s, checking every setting against the ranges of the Q CPU's
//! PLC parameters (004 ch. 9). Every error of the file is reported, each as a
//! [`Diagnostic`] at the offending key or value (`plc.toml:7:17: …`); unknown
//! keys are errors, so a typo never silently falls back to a default.
//! `docs/plc-toml.md` documents every key.
//!
//! The program files are only checked to exist here; compiling them is the
//! caller's job (they need [`CpuConfig::devices`]).

mod aplc;
mod ctx;
mod devices;
mod initial;
mod latch;
mod local;
pub mod multi_cpu;
mod ports;
mod programs;
mod rack;
mod rules;
pub(crate) use rules::{check_files, step_relays, Ruled};
mod settings;
mod system_block;
pub use settings::{check_capacity, known_model, program_capacity, FILE_HEADER_STEPS};
pub use tree::line_col;
mod tree;
mod units;

pub use units::parse_duration;

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::engine::{CpuConfig, ExecType};
use crate::program::{Diagnostic, Diagnostics};
use ctx::Ctx;
use tree::{Entry, Value};

/// The manifest file name of a project.
pub const MANIFEST: &str = "plc.toml";

/// One `[[program]]` of a project, in execution order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgramSpec {
    /// The program file, resolved relative to the project directory.
    pub file: PathBuf,
    pub exec: ExecType,
    /// The interval of a fixed-scan program (required there, `None` otherwise).
    pub interval: Option<Duration>,
    /// Simulated execution time of one run (`sim_time`, virtual time only).
    pub sim_time: Option<Duration>,
    /// `local_devices`: the program has its own local devices (default), or
    /// with `false` ("not used") runs on the previous program's.
    pub local_devices: bool,
}

/// A loaded project.
#[derive(Clone, Debug)]
pub struct Project {
    /// The project directory (`.` for a bare `plc.toml` path).
    pub dir: PathBuf,
    /// The `plc.toml` path, as shown in diagnostics.
    pub manifest: PathBuf,
    /// CPU parameters; every key absent from the file keeps its
    /// [`CpuConfig::default`] value.
    pub config: CpuConfig,
    pub programs: Vec<ProgramSpec>,
    /// `[state] dir` resolved relative to the project (default `state`).
    pub state_dir: PathBuf,
    /// `[state] on_damage`: stop or continue when the state directory is found
    /// damaged at power-on (default continue; BATTERY ERROR 1600 either way).
    pub state_on_damage: crate::persist::OnDamage,
    /// `[cpu] common_pointer`: pointers from this number to P4095 are common,
    /// callable from every program (004 §10.9.2); `None` (default): all local.
    pub common_pointer: Option<u32>,
    /// The `[modbus]` table as written (map and slave settings, interpreted by
    /// the Modbus server; see docs/plc-toml.md).
    pub modbus: Option<toml::Table>,
    /// The `[http]` table as written (`token`, read by `softplc serve --http`).
    pub http: Option<toml::Table>,
    /// The `[opcua]` table as written, read by `softplc serve --opcua`.
    pub opcua: Option<toml::Table>,
    /// `[process]`: the process CPU's decisions (default: the spec's choices).
    pub process: crate::program::ProcessSettings,
    /// `[port1]`/`[port2]` of an APLC-TCP project (contract §3.3).
    pub ports: Vec<softplc_aplc::comm::PortConfig>,
    /// `[cpu] exec`: the execution tier (`None`: not given, auto).
    pub exec: Option<crate::tier::Exec>,
    /// `[multi_cpu]`: the CPU's multi-CPU parameters (contract §6).
    pub multi_cpu: Option<multi_cpu::MultiCpuParams>,
}

/// Largest `plc.toml` read.
pub const MAX_MANIFEST_BYTES: u64 = 4 << 20;

/// True when `path` is a directory containing `plc.toml`, or a file named
/// `plc.toml` (whether it exists or not, so that loading it reports the problem).
pub fn is_project(path: &Path) -> bool {
    if path.is_dir() {
        path.join(MANIFEST).is_file()
    } else {
        path.file_name().is_some_and(|n| n == MANIFEST)
    }
}

/// Loads a project; `path` is a project directory or its `plc.toml`.
///
/// On failure every diagnostic of the file is returned, in file order.
pub fn load_project(path: &Path) -> Result<Project, Diagnostics> {
    let (dir, manifest) = if path.is_dir() {
        (path.to_path_buf(), path.join(MANIFEST))
    } else {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        (dir, path.to_path_buf())
    };
    let name = manifest.display().to_string();
    let fail = |message: String| {
        Diagnostics(vec![Diagnostic {
            file: name.clone(),
            line: 0,
            col: 0,
            message,
        }])
    };
    if path.is_dir() && !manifest.is_file() {
        return Err(fail(format!(
            "not a project: no {MANIFEST} in {}",
            path.display()
        )));
    }
    let bytes =
        crate::program::read_limited(&manifest, MAX_MANIFEST_BYTES, "plc.toml").map_err(fail)?;
    let src = match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => {
            let ok = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let text = String::from_utf8_lossy(ok);
            let (line, col) = tree::line_col(&text, text.len());
            return Err(Diagnostics(vec![Diagnostic {
                file: name,
                line,
                col,
                message: "the file is not UTF-8 text".into(),
            }]));
        }
    };
    load_str(&name, &src, &dir).map(|mut p| {
        p.manifest = manifest;
        p
    })
}

/// Loads `plc.toml` text; `name` is the file name for diagnostics and `dir` the
/// project directory program files and the state directory are relative to.
pub fn load_str(name: &str, src: &str, dir: &Path) -> Result<Project, Diagnostics> {
    let mut cx = Ctx::new(name, src);
    let root = match tree::parse(src) {
        Ok(root) => root,
        Err(e) => {
            cx.error(&e.span, format!("TOML syntax error: {}", e.message));
            return Err(cx.finish());
        }
    };
    let Value::Table(top) = &root.value else {
        unreachable!("a TOML document is a table")
    };
    let mut config = crate::profile::default_config();
    let mut state_dir = dir.join("state");

    const SECTIONS: &[&str] = &[
        "cpu",
        "devices",
        "timers",
        "ras",
        "latch",
        "interrupts",
        "program",
        "initial",
        "clock",
        "state",
        // The Modbus slave's map and settings, read by `softplc serve`.
        "modbus",
        "process",
        // The web monitor's settings (`token`), read by `softplc serve --http`.
        "http",
        // APLC-TCP serial ports (contract §3.3).
        "port1",
        "port2",
        // The APLC-TCP system block's run settings.
        "system_block",
        // The OPC UA server's settings, read by `softplc serve --opcua`.
        "opcua",
        // The rack: I/O assignment and modules (contract §5).
        "io",
        "slot",
        // Multi-CPU parameters (contract §6).
        "multi_cpu",
    ];
    cx.unknown_keys(top, None, SECTIONS);
    let section = |name: &str| top.iter().find(|e| e.key == name);
    let table = |cx: &mut Ctx, name: &str| -> Option<&[Entry]> {
        section(name).and_then(|e| cx.table(e, &format!("[{name}]")))
    };

    let mut common_pointer = None;
    let mut exec = None;
    let mut melsec = softplc_melsec::system::Params::default();
    if let Some(t) = table(&mut cx, "cpu") {
        common_pointer = settings::cpu(&mut cx, t, &mut config, &mut melsec);
        exec = settings::exec(&mut cx, t);
    }
    let devices_at = section("devices").map(|e| e.item.span.clone());
    if let Some(t) = table(&mut cx, "devices") {
        let at = devices_at.unwrap_or(0..0);
        let name = &mut melsec.file_register.name;
        devices::devices(&mut cx, t, at, &mut config.devices, name);
    }
    let empty_points = match table(&mut cx, "io") {
        Some(t) => rack::io(&mut cx, t),
        None => rack::EMPTY_POINTS,
    };
    let slots = rack::slots(&mut cx, section("slot"), empty_points, &config.devices);
    if !slots.is_empty() && crate::profile::is_aplc(config.profile) {
        if let Some(e) = section("slot") {
            cx.error(
                &e.key_span,
                format!(
                    "a {} has no base units: [[slot]] is for MELSEC-Q CPUs",
                    config.profile.model
                ),
            );
        }
    }
    let units: Vec<(u32, u32)> = slots
        .intelligent()
        .map(|s| (s.unit(), s.buffer_words))
        .collect();
    config.devices.set_units(&units);
    melsec.bases = softplc_melsec::system::bases::Bases::of(&slots);
    config.rack = std::sync::Arc::new(slots);
    if let Some(t) = table(&mut cx, "timers") {
        settings::timers(&mut cx, t, &mut config);
    }
    if let Some(t) = table(&mut cx, "ras") {
        settings::ras(&mut cx, t, &mut config);
    }
    if let Some(t) = table(&mut cx, "interrupts") {
        settings::interrupts(&mut cx, t, &mut config);
    }
    let aplc_model = crate::profile::is_aplc(config.profile);
    if !aplc_model {
        melsec.file_register.standard_ram = softplc_melsec::profiles::standard_ram(config.profile);
        config.system = softplc_melsec::system::system_from(melsec);
    } else if let Some(Value::Table(t)) = section("devices").map(|e| &e.item.value) {
        if let Some(e) = t.iter().find(|e| e.key == devices::FILE_REGISTER_NAME) {
            cx.error(
                &e.key_span,
                format!(
                    "file_register_name is a MELSEC-Q parameter (SD641-SD646); the {} has none",
                    config.profile.model
                ),
            );
        }
    }
    let ports = ports::ports(&mut cx, top, aplc_model, dir);
    if aplc_model {
        aplc::configure(&mut cx, top, &mut config, &ports);
    } else if let Some(e) = section("system_block") {
        cx.error(
            &e.key_span,
            "[system_block] is an APLC-TCP setting (set [cpu] model = \"APLC-TCP\")",
        );
    }
    if let Some(t) = table(&mut cx, "clock") {
        settings::clock(&mut cx, t, &mut config);
    }
    let mut state_on_damage = crate::persist::OnDamage::default();
    if let Some(t) = table(&mut cx, "state") {
        if let Some(d) = settings::state(&mut cx, t, &mut state_on_damage) {
            state_dir = dir.join(d);
        }
    }
    if let Some(e) = section("devices") {
        if let Value::Table(t) = &e.item.value {
            config.local_devices = local::local(&mut cx, t, &config.devices);
        }
    }
    let latch_table = table(&mut cx, "latch");
    config.latch = latch::latch(&mut cx, latch_table, &config.devices);
    if let Some(t) = table(&mut cx, "initial") {
        config.initial_values = initial::initial(&mut cx, t, &config.devices);
    }
    let mut process = crate::program::ProcessSettings::default();
    if let Some(e) = section("process") {
        if let Some(t) = cx.table(e, "[process]") {
            settings::process(&mut cx, e, t, config.profile, &mut process);
        }
    }
    let mut multi_cpu = None;
    if let Some(e) = section("multi_cpu") {
        if crate::profile::is_aplc(config.profile) {
            cx.error(
                &e.key_span,
                format!(
                    "an {} is never part of a multi-CPU system: [multi_cpu] is for MELSEC-Q CPUs",
                    config.profile.model
                ),
            );
        } else if let Some(t) = cx.table(e, "[multi_cpu]") {
            multi_cpu = multi_cpu::multi_cpu(&mut cx, e, t, &config.devices);
        }
    }
    let programs = programs::programs(&mut cx, section("program"), dir, &config);

    if cx.has_errors() {
        return Err(cx.finish());
    }
    let whole = toml::from_str::<toml::Table>(src).ok();
    let modbus = whole
        .as_ref()
        .and_then(|t| t.get("modbus").and_then(|m| m.as_table()).cloned());
    let http = whole
        .as_ref()
        .and_then(|t| t.get("http").and_then(|m| m.as_table()).cloned());
    let opcua = whole.and_then(|t| t.get("opcua").and_then(|m| m.as_table()).cloned());
    Ok(Project {
        dir: dir.to_path_buf(),
        manifest: PathBuf::from(name),
        config,
        programs,
        state_dir,
        state_on_damage,
        common_pointer,
        modbus,
        http,
        opcua,
        process,
        ports,
        exec,
        multi_cpu,
    })
}

impl Project {
    /// The dialect the project's programs compile in (by `[cpu] model`),
    /// with the project's rack (the interrupt pointers its slots raise).
    pub fn dialect(&self) -> crate::program::Dialect {
        let d = crate::profile::dialect(self.config.profile, self.process);
        crate::program::Dialect {
            settings: d.settings.clone().with(self.config.rack.clone()),
            ..d
        }
    }

    /// Loads and compiles every program of the project (all diagnostics of all
    /// files on failure) and builds the CPU, linked and powered on.
    pub fn build_cpu(
        &self,
        clock: Box<dyn crate::engine::Clock>,
    ) -> Result<crate::engine::Cpu, Diagnostics> {
        let mut loaded = Vec::new();
        let mut diags = Vec::new();
        if crate::profile::is_aplc(self.config.profile) {
            let programs = aplc::load(&self.programs, &self.manifest.display().to_string())
                .map_err(Diagnostics)?;
            for program in programs {
                loaded.push(crate::engine::LoadedProgram {
                    program,
                    exec: crate::engine::ExecType::Scan,
                    interval: None,
                    sim_time: None,
                    local_devices: true,
                });
            }
            return crate::engine::Cpu::with_programs(loaded, self.config.clone(), clock).map_err(
                |e| {
                    Diagnostics(vec![crate::program::Diagnostic {
                        file: self.manifest.display().to_string(),
                        line: 1,
                        col: 1,
                        message: e,
                    }])
                },
            );
        }
        let dialect = self.dialect();
        for spec in &self.programs {
            match crate::program::load_file_in(
                &spec.file,
                &self.config.devices,
                &dialect,
                self.common_pointer,
            ) {
                Ok(program) => loaded.push(crate::engine::LoadedProgram {
                    program,
                    exec: spec.exec,
                    interval: spec.interval,
                    sim_time: spec.sim_time,
                    local_devices: spec.local_devices,
                }),
                Err(d) => diags.extend(d.0),
            }
        }
        if !diags.is_empty() {
            return Err(Diagnostics(diags));
        }
        let files: Vec<(&str, u32)> = loaded
            .iter()
            .map(|l| (l.program.file.as_str(), l.program.steps))
            .collect();
        settings::check_capacity(self.config.profile, &files).map_err(|d| Diagnostics(vec![d]))?;
        let broken = rules::check(&loaded, &self.config, self.common_pointer);
        if !broken.is_empty() {
            return Err(Diagnostics(broken));
        }
        crate::engine::Cpu::with_programs(loaded, self.config.clone(), clock).map_err(|e| {
            Diagnostics(vec![crate::program::Diagnostic {
                file: self.manifest.display().to_string(),
                line: 1,
                col: 1,
                message: e,
            }])
        })
    }
}
