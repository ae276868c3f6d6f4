//! Building a scenario against its program and running it scan by scan.

use std::time::{Duration, Instant};

use softplc_core::engine::{Clock, Cpu, CpuState, VirtualClock};
use softplc_core::names::Names;
use softplc_core::system::{Cpus, System};

use super::client::{self, Client};
use super::plcs::{Plc, Plcs};
use softplc_core::{project, single};

use super::bind::{Probe, Sink, Source};
use super::check::{Check, Failure, Ring, Verdict, HISTORY_BEFORE};
use super::fmt::{fmt_time, Kind};
use super::spec::{ExpectKind, Layout, PlcSpec, Scenario, Setpoint, DEFAULT_MAX_SAMPLES};
use super::trace::{Recorder, TraceData};
use crate::model::{self, Model};

/// A model with its bindings and pre-sized port buffers.
struct Bound {
    name: String,
    model: Box<dyn Model>,
    inputs: Vec<Source>,
    outputs: Vec<(usize, Sink)>,
    in_buf: Vec<f64>,
    out_buf: Vec<f64>,
}

impl Bound {
    fn write_outputs(&mut self, cpus: &mut Plcs) {
        for (i, sink) in &mut self.outputs {
            sink.write(cpus, self.out_buf[*i]);
        }
    }
}

/// A resolved timeline write: the value parsed once, written typed.
struct Write {
    scan: u64,
    /// The CPU (0-based).
    cpu: usize,
    spec: softplc_core::access::DeviceSpec,
    value: softplc_core::access::Value,
}

/// A scenario ready to run: CPU (or every CPU of a system) powered on,
/// every device resolved.
pub struct Run {
    name: String,
    file: std::path::PathBuf,
    cpus: Plcs,
    clock: VirtualClock,
    scan_us: u64,
    total: u64,
    models: Vec<Bound>,
    writes: Vec<Write>,
    probes: Vec<Probe>,
    names: Vec<(String, Kind)>,
    values: Vec<f64>,
    ring: Ring,
    checks: Vec<Check>,
    recorder: Option<Recorder>,
    /// Scans done and the next timeline write, for [`Run::step`].
    stepped: u64,
    next_step_write: usize,
    /// The slave registers following a model.
    follows: Vec<super::ports::Follow>,
}

/// The result of one assertion.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckResult {
    pub text: String,
    pub passed: bool,
    /// Evidence: the value seen, when it happened, why it failed.
    pub detail: String,
    /// The first failing scan and the device history around it.
    pub failure: Option<Failure>,
    /// Not an expectation but the run itself failing: a CPU stopped or a
    /// plant model failed (a test report's error rather than its failure).
    pub error: bool,
}

/// The result of a scenario run.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub name: String,
    pub file: std::path::PathBuf,
    /// Scans executed (fewer than planned when the CPU stopped); CPU 1's
    /// of a multi-CPU system.
    pub scans: u64,
    /// Steps of `scan_us` run: the virtual time (the scans of a single CPU).
    pub steps: u64,
    pub scan_us: u64,
    /// Wall-clock time of the scan loop.
    pub wall: Duration,
    /// One per expectation, in file order; a CPU stop error adds one more,
    /// failed (one per CPU that stopped in a system).
    pub results: Vec<CheckResult>,
    pub trace: Option<TraceData>,
}

impl Outcome {
    pub fn passed(&self) -> usize {
        self.results.iter().filter(|r| r.passed).count()
    }

    pub fn failed(&self) -> usize {
        self.results.len() - self.passed()
    }

    /// Virtual time run, µs.
    pub fn simulated_us(&self) -> u64 {
        self.steps * self.scan_us
    }

    /// Simulated time / wall-clock time.
    pub fn speed(&self) -> f64 {
        self.simulated_us() as f64 / 1e6 / self.wall.as_secs_f64().max(1e-9)
    }
}

/// How often (in scans) the progress callback is called.
pub const PROGRESS_EVERY: u64 = 1 << 14;

impl Scenario {
    /// Loads the program, project or multi-CPU system, powers on the CPUs
    /// (in virtual time, no retained state) and resolves every device of
    /// the scenario.
    pub fn build(&self) -> Result<Run, String> {
        self.build_on(None)
    }

    /// [`Scenario::build`] on the execution tier `exec` (`--exec`), else
    /// `SOFTPLC_EXEC`, else the project's `[cpu] exec`, else auto.
    pub fn build_on(&self, exec: Option<softplc_core::tier::Exec>) -> Result<Run, String> {
        let clock = VirtualClock::new();
        let ctx = |e: String| format!("{}: {e}", self.file.display());
        if !self.plcs.is_empty() {
            return self.build_fleet(clock, exec).map_err(ctx);
        }
        let one = PlcSpec {
            name: String::new(),
            source: self.source.clone(),
            cpu: self.cpu,
            profile: self.profile,
            scan_us: self.scan_us,
            ports: self.ports.clone(),
        };
        let loaded = self.load_plc(&one, &clock, exec)?;
        self.build_with_ports(loaded.cpus, clock, &loaded.ports)
            .map_err(ctx)
    }

    /// Loads one PLC's program, project or system on `clock`: its CPUs on
    /// their execution tier, its APLC port settings and its project's
    /// `[modbus]` table.
    fn load_plc(
        &self,
        plc: &PlcSpec,
        clock: &VirtualClock,
        exec: Option<softplc_core::tier::Exec>,
    ) -> Result<Loaded, String> {
        let PlcSpec {
            source,
            cpu,
            profile,
            scan_us,
            ..
        } = plc;
        let mut ports = plc.ports.clone();
        let mut project_exec = None;
        let mut modbus = None;
        let mut cpu = match source {
            super::Source::Program(p) => {
                let options = single::Options {
                    ports: ports.clone(),
                    explicit_model: cpu.is_some(),
                    ..Default::default()
                };
                single::load(p, profile, options, Box::new(clock.clone()))
                    .map_err(|e| e.to_string())?
            }
            super::Source::Project(p) => {
                let proj = project::load_project(p).map_err(|d| format!("{d}"))?;
                ports = proj.ports.clone();
                project_exec = proj.exec;
                modbus = proj.modbus.clone();
                proj.build_cpu(Box::new(clock.clone()))
                    .map_err(|d| format!("{d}"))?
            }
            super::Source::System(p) => {
                let sys = self.load_system(p, clock, exec, *scan_us)?;
                return Ok(Loaded {
                    cpus: Cpus::System(sys),
                    ports: Vec::new(),
                    modbus: None,
                });
            }
        };
        let exec = softplc_core::tier::Exec::choose(exec, project_exec)?;
        softplc_core::tier::apply(&mut cpu, exec)?;
        Ok(Loaded {
            cpus: Cpus::One(cpu),
            ports,
            modbus,
        })
    }

    /// Loads every PLC of a fleet on one clock, links their ports and
    /// builds the run.
    fn build_fleet(
        &self,
        clock: VirtualClock,
        exec: Option<softplc_core::tier::Exec>,
    ) -> Result<Run, String> {
        let mut units = Vec::new();
        let mut configs = Vec::new();
        let mut modbus = Vec::new();
        let mut layout = Vec::new();
        for p in &self.plcs {
            let loaded = self
                .load_plc(p, &clock, exec)
                .map_err(|e| format!("PLC `{}`: {e}", p.name))?;
            layout.push((p.name.clone(), loaded.cpus.len()));
            units.push(Plc {
                cpus: loaded.cpus,
                ports: softplc_ports::Ports::new(),
                period_us: p.scan_us,
                next_due_us: clock.now_us() + p.scan_us,
            });
            configs.push(loaded.ports);
            modbus.push(loaded.modbus);
        }
        let plcs = Plcs::new(units, Layout::Fleet(layout));
        self.finish_build(plcs, clock, configs, modbus)
    }

    /// Loads a multi-CPU system on `clock`, puts each CPU on its execution
    /// tier and schedules the CPUs from time 0: each at its constant scan,
    /// else at the scenario's scan time.
    fn load_system(
        &self,
        path: &std::path::Path,
        clock: &VirtualClock,
        exec: Option<softplc_core::tier::Exec>,
        scan_us: u64,
    ) -> Result<System, String> {
        let mut sys = System::load(path, &mut || Box::new(clock.clone()) as Box<dyn Clock>)
            .map_err(|d| format!("{d}"))?;
        for i in 0..sys.len() {
            let tier = softplc_core::tier::Exec::choose(exec, sys.project(i).exec)
                .and_then(|e| softplc_core::tier::apply(sys.cpu_mut(i), e));
            tier.map_err(|e| format!("CPU {}: {e}", i + 1))?;
        }
        sys.schedule(Duration::from_micros(scan_us), 0);
        Ok(sys)
    }

    /// [`Scenario::build`] with a CPU built by the caller (it must use `clock`).
    pub fn build_with(&self, cpu: Cpu, clock: VirtualClock) -> Result<Run, String> {
        self.build_with_ports(Cpus::One(cpu), clock, &self.ports)
    }

    /// [`Scenario::build_with`] with the APLC ports the CPU was configured with.
    fn build_with_ports(
        &self,
        cpus: Cpus,
        clock: VirtualClock,
        port_configs: &[softplc_ports::PortConfig],
    ) -> Result<Run, String> {
        let n = cpus.len();
        let unit = Plc {
            cpus,
            ports: softplc_ports::Ports::new(),
            period_us: self.scan_us,
            next_due_us: clock.now_us() + self.scan_us,
        };
        let plcs = Plcs::new(vec![unit], Layout::One(n));
        self.finish_build(plcs, clock, vec![port_configs.to_vec()], vec![None])
    }

    /// Resolves every device of the scenario against the PLCs and builds
    /// their ports (`configs` per PLC), links and clients (`modbus`: each
    /// PLC's `[modbus]` table of plc.toml).
    fn finish_build(
        &self,
        mut cpus: Plcs,
        clock: VirtualClock,
        configs: Vec<Vec<softplc_ports::PortConfig>>,
        modbus: Vec<Option<toml::Table>>,
    ) -> Result<Run, String> {
        // Models.
        let mut models = Vec::new();
        for m in &self.models {
            let what = |e: String| format!("model `{}`: {e}", m.name);
            let model = model::build(&m.kind, &m.params).map_err(what)?;
            let mut inputs = vec![Source::Const(0.0); model.inputs().len()];
            for (i, b) in &m.inputs {
                inputs[*i] = match b {
                    super::InputBinding::Const(v) => Source::Const(*v),
                    super::InputBinding::Device { device, scale } => {
                        Source::new(device, *scale, &cpus).map_err(what)?
                    }
                };
            }
            let mut outputs = Vec::new();
            for (i, b) in &m.outputs {
                outputs.push((*i, Sink::new(&b.device, b.scale, &mut cpus).map_err(what)?));
            }
            let mut bound = Bound {
                name: m.name.clone(),
                in_buf: vec![0.0; model.inputs().len()],
                out_buf: vec![0.0; model.outputs().len()],
                model,
                inputs,
                outputs,
            };
            // The sensors read their initial state at power-on.
            bound.model.outputs_now(&mut bound.out_buf);
            bound.write_outputs(&mut cpus);
            models.push(bound);
        }

        // Timeline: check every value on a scratch copy of each memory.
        let mut scratch: Vec<_> = (0..cpus.len())
            .map(|i| cpus.get(i).memory().clone())
            .collect();
        let mut writes = Vec::new();
        let names: Vec<Names> = (0..cpus.len()).map(|i| Names::of(cpus.get(i))).collect();
        for e in &self.timeline {
            for (dev, value) in &e.set {
                let at = |err: String| format!("timeline at scan {}: {err}", e.scan);
                let (cpu, dev) = cpus.layout.split(dev).map_err(at)?;
                let name = names[cpu].parse(dev.trim()).map_err(at)?;
                let value = name
                    .parse_value(value)
                    .and_then(|v| name.door_value(&v))
                    .map_err(at)?;
                let spec = name.spec().clone();
                let cpu = cpus.write_owner(cpu, &spec);
                spec.write_value(&mut scratch[cpu], &value)
                    .map_err(|e| at(e.to_string()))?;
                writes.push(Write {
                    scan: e.scan,
                    cpu,
                    spec,
                    value,
                });
            }
        }
        drop(scratch);

        // Watched devices and checks.
        let mut probes: Vec<Probe> = Vec::new();
        let mut watch = |text: &str, cpus: &Plcs| -> Result<usize, String> {
            let p = Probe::new(text, cpus)?;
            if let Some(i) = probes.iter().position(|q| q.same(&p)) {
                return Ok(i);
            }
            probes.push(p);
            Ok(probes.len() - 1)
        };
        let mut checks = Vec::new();
        for e in &self.expects {
            let probe = watch(&e.device, &cpus)?;
            let (mut sv_probe, mut sv_value) = (None, 0.0);
            if let ExpectKind::Settle { setpoint, .. } = &e.kind {
                match setpoint {
                    Setpoint::Device(d) => sv_probe = Some(watch(d, &cpus)?),
                    Setpoint::Value(v) => sv_value = *v,
                }
            }
            let mut columns = vec![probe];
            columns.extend(sv_probe);
            for s in &e.show {
                let i = watch(s, &cpus)?;
                if !columns.contains(&i) {
                    columns.push(i);
                }
            }
            checks.push((e, probe, sv_probe, sv_value, columns));
        }
        let names: Vec<(String, Kind)> = probes
            .iter()
            .map(|p| (p.name().to_string(), p.kind()))
            .collect();
        let checks = checks
            .into_iter()
            .map(|(e, probe, sv_probe, sv_value, columns)| {
                Check::new(
                    e.text.clone(),
                    probe,
                    sv_probe,
                    sv_value,
                    columns,
                    e.kind.clone(),
                    names[probe].1,
                )
            })
            .collect();

        // Trace: the trace devices, plus the plot's.
        let mut trace_devs: Vec<String> = self.trace.devices.clone();
        if let Some(p) = &self.plot {
            let plot_devs = if p.devices.is_empty() && self.trace.devices.is_empty() {
                self.expect_devices()
            } else {
                p.devices.clone()
            };
            for d in plot_devs {
                if !trace_devs.iter().any(|t| t.eq_ignore_ascii_case(&d)) {
                    trace_devs.push(d);
                }
            }
        }
        let recorder = if trace_devs.is_empty() {
            None
        } else {
            let tp = trace_devs
                .iter()
                .map(|d| Probe::new(d, &cpus).map_err(|e| format!("trace: {e}")))
                .collect::<Result<Vec<_>, _>>()?;
            let every = match self.trace.interval_us {
                Some(us) => (us / self.scan_us).max(1),
                None => self.scans.div_ceil(DEFAULT_MAX_SAMPLES).max(1),
            };
            Some(Recorder::new(tp, every, self.scans))
        };

        let built: Vec<(&super::ModelSpec, &dyn Model)> = self
            .models
            .iter()
            .zip(&models)
            .map(|(s, b)| (s, b.model.as_ref()))
            .collect();
        let mut linked = super::ports::links(&self.links, &configs, &self.plcs)?;
        let mut follows = Vec::new();
        for (u, cfgs) in configs.iter().enumerate() {
            let peers: Vec<(usize, &super::PeerSpec)> = self
                .peers
                .iter()
                .enumerate()
                .filter(|(_, p)| p.plc == u)
                .collect();
            let ends = std::mem::take(&mut linked[u]);
            let (ports, f) = super::ports::build(cfgs, &peers, ends, &built)?;
            cpus.units[u].ports = ports;
            follows.extend(f);
        }
        for c in &self.clients {
            let profile = cpus.units[c.plc].cpus.get(0).profile();
            let client = Client::new(c, &cpus, profile, modbus[c.plc].as_ref())?;
            cpus.clients.push(client);
        }
        let width = probes.len();
        Ok(Run {
            name: self.name.clone(),
            file: self.file.clone(),
            cpus,
            clock,
            scan_us: self.scan_us,
            total: self.scans,
            models,
            writes,
            values: vec![0.0; width],
            ring: Ring::new(width, HISTORY_BEFORE + 1),
            probes,
            names,
            checks,
            recorder,
            stepped: 0,
            next_step_write: 0,
            follows,
        })
    }
}

impl Run {
    /// One step: the models' input refresh, the due timeline writes and the
    /// scan (every CPU of a system whose scan ends by the step's end). A
    /// model that fails (an FMU call) stops the run before the scan: its
    /// index is returned.
    fn advance(&mut self, n: u64, dt: f64, next_write: &mut usize) -> Result<(), usize> {
        // Input refresh: the plant advances over the scan and the sensors
        // are sampled.
        for (i, m) in self.models.iter_mut().enumerate() {
            for (buf, src) in m.in_buf.iter_mut().zip(&m.inputs) {
                *buf = src.read(&self.cpus);
            }
            m.model.step(dt, &m.in_buf, &mut m.out_buf);
            if m.model.fault().is_some() {
                return Err(i);
            }
            m.write_outputs(&mut self.cpus);
        }
        for f in &self.follows {
            f.apply(&self.models[f.model()].out_buf);
        }
        while let Some(w) = self.writes.get(*next_write).filter(|w| w.scan == n) {
            // Checked on a scratch memory at build: cannot fail.
            let _ = self.cpus.get_mut(w.cpu).write_value(&w.spec, &w.value);
            *next_write += 1;
        }
        self.cpus.run_until(n * self.scan_us, &self.clock);
        Ok(())
    }

    /// Why model `i` failed, with its name.
    fn fault_detail(&self, i: usize) -> String {
        let m = &self.models[i];
        format!(
            "model `{}`: {}",
            m.name,
            m.model.fault().unwrap_or("failed")
        )
    }

    /// Runs one scan as [`Run::run`] does (models, due timeline writes, the
    /// scan) but without expectations or trace, for drivers that act on the
    /// CPU between scans (`softplc tune`). Scans go on past the scenario's
    /// duration; the timeline simply has no more writes. Returns the virtual
    /// time after the scan in µs, or why the CPU (any CPU of a system)
    /// stopped.
    pub fn step(&mut self) -> Result<u64, String> {
        if let Some(i) = self.cpus.first_stopped() {
            return Err(format!(
                "{} is stopped: {}",
                label(&self.cpus, i),
                stop_detail(self.cpus.get(i))
            ));
        }
        let n = self.stepped + 1;
        let mut next = self.next_step_write;
        if let Err(i) = self.advance(n, self.scan_us as f64 / 1e6, &mut next) {
            return Err(format!(
                "before scan {n} ({}): {}",
                fmt_time(n * self.scan_us),
                self.fault_detail(i)
            ));
        }
        self.next_step_write = next;
        self.stepped = n;
        if let Some(i) = self.cpus.first_stopped() {
            return Err(format!(
                "{} stopped at scan {n} ({}): {}",
                label(&self.cpus, i),
                fmt_time(n * self.scan_us),
                stop_detail(self.cpus.get(i))
            ));
        }
        Ok(n * self.scan_us)
    }

    /// Scans done by [`Run::step`].
    pub fn steps_done(&self) -> u64 {
        self.stepped
    }

    /// Virtual time per scan, µs.
    pub fn scan_us(&self) -> u64 {
        self.scan_us
    }

    /// The CPU (CPU 1 of a system), to write devices between
    /// [`Run::step`]s (through its door).
    pub fn cpu_mut(&mut self) -> &mut Cpu {
        self.cpus.get_mut(0)
    }

    /// Scans the run will execute.
    pub fn total_scans(&self) -> u64 {
        self.total
    }

    /// The CPU (CPU 1 of a system; e.g. to inspect devices before or after
    /// [`Run::run`]).
    pub fn cpu(&self) -> &Cpu {
        self.cpus.get(0)
    }

    /// Number of CPUs: 1, or those of a multi-CPU system.
    pub fn cpu_count(&self) -> usize {
        self.cpus.len()
    }

    /// CPU `i` (0-based: CPU 1 is 0).
    ///
    /// # Panics
    /// When `i` is not below [`Run::cpu_count`].
    pub fn cpu_at(&self, i: usize) -> &Cpu {
        self.cpus.get(i)
    }

    /// CPU `i` (0-based), to write devices between [`Run::step`]s.
    ///
    /// # Panics
    /// When `i` is not below [`Run::cpu_count`].
    pub fn cpu_at_mut(&mut self, i: usize) -> &mut Cpu {
        self.cpus.get_mut(i)
    }

    /// The CPU (0-based) a device name addresses and the name without its
    /// `CPUn/` prefix (a name without one is CPU 1's).
    pub fn split_name<'a>(&self, name: &'a str) -> Result<(usize, &'a str), String> {
        self.cpus.layout.split(name)
    }

    /// Runs every scan: before each, the due timeline writes and one step of
    /// every model (inputs read from the devices the last scan left, outputs
    /// written to the input image / word devices); then the scan in virtual
    /// time (every CPU of a system whose scan is due); then the expectations
    /// and the trace sample. `progress` is called with the scans done every
    /// [`PROGRESS_EVERY`] scans and at the end. The run ends early when the
    /// CPU (every CPU of a system) has stopped.
    pub fn run(mut self, progress: &mut dyn FnMut(u64)) -> Outcome {
        let dt = self.scan_us as f64 / 1e6;
        let start = Instant::now();
        let mut next_write = 0;
        let mut done = 0;
        // The scan at which each CPU was first seen stopped.
        let mut stopped: Vec<Option<u64>> = vec![None; self.cpus.len()];
        let mut running = stopped.len();
        let mut all_stopped = false;
        let mut fault = None;
        for n in 1..=self.total {
            if let Err(i) = self.advance(n, dt, &mut next_write) {
                fault = Some((n, i));
                break;
            }
            done = n;
            let time_us = n * self.scan_us;
            for (v, p) in self.values.iter_mut().zip(&self.probes) {
                *v = p.read(&self.cpus);
            }
            self.ring.push(n, &self.values);
            for c in &mut self.checks {
                c.update(n, self.scan_us, &self.values, &self.ring, &self.names);
            }
            if let Some(r) = &mut self.recorder {
                r.sample(n, time_us, &self.cpus);
            }
            for (i, s) in stopped.iter_mut().enumerate() {
                if s.is_none() && self.cpus.get(i).state() == CpuState::Stop {
                    *s = Some(n);
                    running -= 1;
                }
            }
            if running == 0 {
                all_stopped = true;
                if let Some(r) = &mut self.recorder {
                    r.take(n, time_us, &self.cpus);
                }
                break;
            }
            if n % PROGRESS_EVERY == 0 {
                progress(n);
            }
        }
        progress(done);
        let wall = start.elapsed();

        let mut results = Vec::new();
        let why = match (all_stopped, fault) {
            (true, _) if self.cpus.len() > 1 => "every CPU stopped",
            (true, _) => "the CPU stopped",
            (_, Some(_)) => "a model failed",
            _ => "the run ended",
        };
        for c in &mut self.checks {
            c.unfinished(done, self.scan_us, why);
            results.push(CheckResult {
                text: c.text.clone(),
                passed: c.verdict == Verdict::Pass,
                detail: std::mem::take(&mut c.detail),
                failure: c.failure.take(),
                error: false,
            });
        }
        for (i, s) in stopped.iter().enumerate() {
            let Some(n) = *s else { continue };
            results.push(CheckResult {
                text: format!(
                    "{} keeps running (stopped at {}, scan {n})",
                    label(&self.cpus, i),
                    fmt_time(n * self.scan_us)
                ),
                passed: false,
                detail: stop_detail(self.cpus.get(i)),
                failure: None,
                error: true,
            });
        }
        if let Some((n, i)) = fault {
            results.push(CheckResult {
                text: format!(
                    "the plant models keep running (model `{}` failed before scan {n}, at {})",
                    self.models[i].name,
                    fmt_time((n - 1) * self.scan_us)
                ),
                passed: false,
                detail: self.fault_detail(i),
                failure: None,
                error: true,
            });
        }
        for c in &self.cpus.clients {
            if let Some((text, detail)) = client::result(c) {
                results.push(CheckResult {
                    text,
                    passed: false,
                    detail,
                    failure: None,
                    error: false,
                });
            }
        }
        let scans = match (&self.cpus.layout, &self.cpus.units[0].cpus) {
            (Layout::One(_), Cpus::One(_)) => done,
            _ => self.cpus.get(0).scans(),
        };
        Outcome {
            name: self.name,
            file: self.file,
            scans,
            steps: done,
            scan_us: self.scan_us,
            wall,
            results,
            trace: self.recorder.map(|r| r.data),
        }
    }
}

/// How reports name CPU `i`: "the CPU", "CPU n" in a system, "PLC
/// `line1`" (and its CPU n) in a fleet.
fn label(cpus: &Plcs, i: usize) -> String {
    match &cpus.layout {
        Layout::One(1) => "the CPU".into(),
        Layout::One(_) => format!("CPU {}", i + 1),
        Layout::Fleet(plcs) => {
            let (u, c) = cpus.layout.locate(i);
            match cpus.in_system(i) {
                true => format!("PLC `{}` CPU {}", plcs[u].0, c + 1),
                false => format!("PLC `{}`", plcs[u].0),
            }
        }
    }
}

/// What [`Scenario::load_plc`] loaded.
struct Loaded {
    cpus: Cpus,
    ports: Vec<softplc_ports::PortConfig>,
    modbus: Option<toml::Table>,
}

/// Why a CPU stopped: the error code, message and step (the APLC has no
/// step numbers: its file and line, contract §2).
fn stop_detail(cpu: &Cpu) -> String {
    match cpu.error() {
        Some(e) => {
            let place = match (&e.file, e.line, e.step) {
                (Some(f), Some(l), _) if !cpu.profile().step_numbers => {
                    format!(" at {f}:{l}")
                }
                (Some(f), Some(l), Some(s)) => format!(" at step {s} ({f}:{l})"),
                _ => String::new(),
            };
            format!("error {} {}{place}", e.code.0, cpu.error_message(e.code))
        }
        None => "no error recorded".into(),
    }
}
