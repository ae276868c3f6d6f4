//! The PLC inside an FMU: what `resources/` holds (the program files and
//! [`Config`]), the CPU or multi-CPU system loaded from it, its variables,
//! and the scans a communication step runs. No FMI and no C here.

use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use softplc_core::access::{Value, ValueType};
use softplc_core::engine::{Clock, CpuState, VirtualClock};
use softplc_core::names::DevName;
use softplc_core::system::{self, Cpus, System};
use softplc_core::{project, single, tier};

use crate::state;

/// The file in `resources/` that says what to load.
pub const CONFIG_FILE: &str = "softplc-fmu.toml";

/// What the FMU runs: written by `softplc fmu`, read at instantiation.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// The program file, project directory or system directory, relative
    /// to `resources/`.
    pub program: String,
    /// The CPU model of a single program file (`--model`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// The scan time the FMU starts with, µs (the `scan_time` parameter).
    pub scan_time_us: u64,
    /// Devices the master writes, as `--set` names them.
    #[serde(default)]
    pub inputs: Vec<String>,
    /// Devices the master reads, as `--show` names them.
    #[serde(default)]
    pub outputs: Vec<String>,
}

impl Config {
    /// Reads `dir/softplc-fmu.toml`.
    pub fn read(dir: &Path) -> Result<Config, String> {
        let path = dir.join(CONFIG_FILE);
        let text = std::fs::read_to_string(&path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The text written to `resources/softplc-fmu.toml`.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }
}

/// FMI 3.0's type of a variable (§2.4.7), from the name's `:TYPE`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiType {
    Boolean,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Float32,
    /// Only the `scan_time` parameter.
    Float64,
}

impl FmiType {
    /// The element name in modelDescription.xml and the type in fmi3Get/Set.
    pub fn name(self) -> &'static str {
        match self {
            FmiType::Boolean => "Boolean",
            FmiType::Int16 => "Int16",
            FmiType::UInt16 => "UInt16",
            FmiType::Int32 => "Int32",
            FmiType::UInt32 => "UInt32",
            FmiType::Float32 => "Float32",
            FmiType::Float64 => "Float64",
        }
    }

    fn of(name: &DevName) -> Result<FmiType, String> {
        Ok(match name.ty() {
            ValueType::Bit => FmiType::Boolean,
            ValueType::I16 => FmiType::Int16,
            ValueType::U16 => FmiType::UInt16,
            ValueType::I32 => FmiType::Int32,
            ValueType::U32 => FmiType::UInt32,
            ValueType::F32 => FmiType::Float32,
            ValueType::Str => {
                return Err(format!(
                    "`{}`: a string has no FMU variable type; give :i16, :u16, :i32, :u32 or :f32",
                    name.text()
                ))
            }
        })
    }
}

/// Causality of a device variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Input,
    Output,
}

/// A device the master reads or writes.
pub struct Var {
    /// As given (`D40:i32`, `CPU2/M0`): the variable's name.
    pub name: String,
    pub causality: Causality,
    pub ty: FmiType,
    /// The CPU (0-based) the name is in.
    cpu: usize,
    dev: DevName,
    /// An input's value as the master last set it (its start value before).
    value: Value,
    /// Set since the last scan: written before the next one.
    pending: bool,
}

impl Var {
    /// An input's value as last set (outputs read the CPU).
    pub fn input_value(&self) -> &Value {
        &self.value
    }
}

/// The loaded PLC and its variables, stepping in virtual time.
pub struct Plc {
    cpus: Cpus,
    clock: VirtualClock,
    pub vars: Vec<Var>,
    scan_us: u64,
    /// Scans of a single CPU so far (a system keeps its own schedule).
    scans: u64,
}

/// A duration in whole µs, at least 1.
pub fn micros(d: Duration) -> u64 {
    (d.as_micros() as u64).max(1)
}

impl Plc {
    /// Loads what `config` names from `dir` (the unpacked `resources/`),
    /// powered on at time 0 with the scan time `scan_us`, and resolves the
    /// variables. The error names the file or the device.
    pub fn load(dir: &Path, config: &Config, scan_us: u64) -> Result<Plc, String> {
        let path = dir.join(&config.program);
        let clock = VirtualClock::new();
        let cpus = load_cpus(&path, config.model.as_deref(), &clock)?;
        let mut vars: Vec<Var> = Vec::new();
        let named = config
            .inputs
            .iter()
            .map(|n| (n, Causality::Input))
            .chain(config.outputs.iter().map(|n| (n, Causality::Output)));
        for (text, causality) in named {
            let text = text.trim();
            if text == SCAN_TIME || text == "time" {
                return Err(format!(
                    "`{text}`: the name of the FMU's own variable, not a device"
                ));
            }
            if vars.iter().any(|v| v.name == text) {
                return Err(format!("`{text}`: named twice among the variables"));
            }
            let (cpu, rest) = match &cpus {
                Cpus::One(_) => (0, text),
                Cpus::System(s) => system::names::split(text, s.len())?,
            };
            let dev = DevName::parse_for(rest, cpus.get(cpu))?;
            let ty = FmiType::of(&dev)?;
            if causality == Causality::Input && dev.is_read_only() {
                return Err(format!("`{text}`: cannot be an input: it cannot be set"));
            }
            let value = dev.read(cpus.get(cpu))?;
            vars.push(Var {
                name: text.to_string(),
                causality,
                ty,
                cpu,
                dev,
                value,
                pending: false,
            });
        }
        Ok(Plc {
            cpus,
            clock,
            vars,
            scan_us: scan_us.max(1),
            scans: 0,
        })
    }

    /// The scan time, µs.
    pub fn scan_us(&self) -> u64 {
        self.scan_us
    }

    /// Changes the scan time before the first step.
    pub fn set_scan_us(&mut self, us: u64) {
        self.scan_us = us.max(1);
    }

    /// Schedules the CPUs from time 0 (a system: each at its constant scan,
    /// else at the scan time). Called once, at the end of initialization.
    pub fn start(&mut self) {
        if let Cpus::System(s) = &mut self.cpus {
            s.schedule(Duration::from_micros(self.scan_us), 0);
        }
    }

    /// The value of variable `i` in its type: an input as last set, an
    /// output as the CPU holds it now.
    pub fn get(&self, i: usize) -> Result<Value, String> {
        let v = &self.vars[i];
        match v.causality {
            Causality::Input => Ok(v.value.clone()),
            Causality::Output => v.dev.read(self.cpus.get(v.cpu)),
        }
    }

    /// Whether `value` may be set to variable `i`: an input, and a value
    /// that fits its type.
    pub fn check(&self, i: usize, value: &Value) -> Result<(), String> {
        let v = &self.vars[i];
        if v.causality != Causality::Input {
            return Err(format!("`{}` is an output and cannot be set", v.name));
        }
        v.dev.door_value(value).map(|_| ())
    }

    /// Sets input `i`, written before the next scan. The value is checked
    /// against the type now (nothing is kept when it does not fit).
    pub fn set(&mut self, i: usize, value: Value) -> Result<(), String> {
        self.check(i, &value)?;
        let v = &mut self.vars[i];
        v.value = value;
        v.pending = true;
        Ok(())
    }

    /// Writes the inputs set since the last scan (as `run --at` before a scan).
    fn write_pending(&mut self) -> Result<(), String> {
        for v in self.vars.iter_mut().filter(|v| v.pending) {
            let cpu = self.cpus.write_owner(v.cpu, v.dev.spec());
            v.dev.write_value(self.cpus.get_mut(cpu), &v.value)?;
            v.pending = false;
        }
        Ok(())
    }

    /// Runs every scan that ends at or before `until_us` (µs from power-on),
    /// as `softplc run` does: a single CPU's scan `k` ends at `k` scan
    /// times and none runs once it is in STOP; a system's CPUs scan at
    /// their periods until all are in STOP. Returns the scans run.
    pub fn run_until(&mut self, until_us: u64) -> Result<u64, String> {
        let mut ran = 0;
        loop {
            let due = match &self.cpus {
                Cpus::One(c) if c.state() == CpuState::Stop => break,
                Cpus::One(_) => (self.scans + 1).saturating_mul(self.scan_us),
                Cpus::System(s) if s.all_stopped() => break,
                Cpus::System(s) => s.next_due().1,
            };
            if due > until_us {
                break;
            }
            self.write_pending()?;
            match &mut self.cpus {
                Cpus::One(cpu) => {
                    self.clock.advance_us(due - self.clock.now_us());
                    cpu.scan();
                    self.scans += 1;
                }
                Cpus::System(s) => {
                    s.scan_due(until_us, &self.clock);
                }
            }
            ran += 1;
        }
        Ok(ran)
    }

    /// The PLC's state between scans (FMU state, [`crate::state`]): the
    /// CPUs' state file, the variables, the scan count and scan time.
    pub fn save_state(&mut self, start: f64, now: f64) -> Vec<u8> {
        let cpus = self.cpus.save_state();
        let vars: Vec<(bool, &Value)> = self.vars.iter().map(|v| (v.pending, &v.value)).collect();
        let times = state::Times {
            start,
            now,
            scans: self.scans,
            scan_us: self.scan_us,
        };
        state::encode(times, &vars, &cpus)
    }

    /// Restores a state of [`Plc::save_state`] (of this FMU: the CPUs'
    /// state file checks the programs); on an error nothing changed.
    /// Returns the start time and time of the state.
    pub fn load_state(&mut self, bytes: &[u8]) -> Result<(f64, f64), String> {
        let d = state::decode(bytes, self.vars.len())?;
        for (v, (_, value)) in self.vars.iter().zip(&d.vars) {
            if v.causality == Causality::Input {
                v.dev.door_value(value)?;
            }
        }
        self.cpus.load_state(d.cpus).map_err(|e| e.to_string())?;
        for (v, (pending, value)) in self.vars.iter_mut().zip(d.vars) {
            v.pending = pending;
            v.value = value;
        }
        self.scans = d.times.scans;
        self.scan_us = d.times.scan_us;
        Ok((d.times.start, d.times.now))
    }

    /// Scans of CPU 1 so far.
    pub fn scans(&self) -> u64 {
        self.cpus.get(0).scans()
    }

    /// Every CPU (for tests and reports).
    pub fn cpus(&self) -> &Cpus {
        &self.cpus
    }
}

/// The name of the scan-time parameter.
pub const SCAN_TIME: &str = "scan_time";

/// Loads a program file, project or multi-CPU system on `clock` and puts
/// each CPU on its execution tier (`SOFTPLC_EXEC`, else the project's
/// `[cpu] exec`, else auto), as `softplc run` does without options.
fn load_cpus(path: &Path, model: Option<&str>, clock: &VirtualClock) -> Result<Cpus, String> {
    let shown = path.file_name().map_or(PathBuf::new(), PathBuf::from);
    let diag = |d: &dyn std::fmt::Display| {
        let text = d.to_string();
        text.trim_end().to_string()
    };
    if system::is_system(path) {
        let mut sys = System::load(path, &mut || Box::new(clock.clone()) as Box<dyn Clock>)
            .map_err(|d| diag(&d))?;
        for i in 0..sys.len() {
            let own = sys.project(i).exec;
            tier::Exec::choose(None, own)
                .and_then(|e| tier::apply(sys.cpu_mut(i), e))
                .map_err(|e| format!("CPU {}: {e}", i + 1))?;
        }
        return Ok(Cpus::System(sys));
    }
    let (mut cpu, exec) = if project::is_project(path) {
        if model.is_some() {
            return Err(format!(
                "{}: a model applies to a single program file; a project sets [cpu] model",
                shown.display()
            ));
        }
        let p = project::load_project(path).map_err(|d| diag(&d))?;
        let cpu = p.build_cpu(Box::new(clock.clone())).map_err(|d| diag(&d))?;
        (cpu, p.exec)
    } else {
        let model = model.map(project::known_model).transpose()?;
        let profile = single::profile_for(path, model, None)?;
        let options = single::Options {
            explicit_model: model.is_some(),
            ..Default::default()
        };
        let cpu =
            single::load(path, profile, options, Box::new(clock.clone())).map_err(|e| diag(&e))?;
        (cpu, None)
    };
    tier::Exec::choose(None, exec).and_then(|e| tier::apply(&mut cpu, e))?;
    Ok(Cpus::One(cpu))
}

/// The instantiation token of the resources in `dir`: SHA-256 over every
/// file's relative path and content, in path order, so that an FMU whose
/// resources were changed after export is refused.
pub fn token(dir: &Path) -> Result<String, String> {
    let mut files = Vec::new();
    collect(dir, Path::new(""), &mut files)?;
    files.sort();
    let mut h = Sha256::new();
    for rel in &files {
        let bytes = std::fs::read(dir.join(rel))
            .map_err(|e| format!("cannot read {}: {e}", dir.join(rel).display()))?;
        let name = rel.to_string_lossy().replace('\\', "/");
        h.update((name.len() as u64).to_le_bytes());
        h.update(name.as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(&bytes);
    }
    let digest = h.finalize();
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    Ok(format!("{{softplc-{hex}}}"))
}

/// Every regular file under `dir/rel`, relative to `dir`.
pub(crate) fn collect(dir: &Path, rel: &Path, out: &mut Vec<PathBuf>) -> Result<(), String> {
    let here = dir.join(rel);
    let entries =
        std::fs::read_dir(&here).map_err(|e| format!("cannot read {}: {e}", here.display()))?;
    for e in entries {
        let e = e.map_err(|e| format!("cannot read {}: {e}", here.display()))?;
        let ty = e
            .file_type()
            .map_err(|err| format!("{}: {err}", e.path().display()))?;
        let r = rel.join(e.file_name());
        if ty.is_dir() {
            collect(dir, &r, out)?;
        } else if ty.is_file() {
            out.push(r);
        }
    }
    Ok(())
}
