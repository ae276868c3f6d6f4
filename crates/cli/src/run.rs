//! `softplc run` and `softplc check` (contract §2).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use clap::Args;
use serde_json::{json, Map, Value as Json};
use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::calendar::DateTime;
use softplc_core::engine::trace::{Trace, TraceConfig};
use softplc_core::engine::{Clock, Cpu, CpuState, VirtualClock};
use softplc_core::names::{DevName, Names};
use softplc_core::persist::{Attach, Battery, OnDamage, PersistError};
use softplc_core::profile::Profile;
use softplc_core::program::Diagnostics;
use softplc_core::project;
use softplc_core::single;
use softplc_core::snapshot;
use softplc_core::tier::{self, Exec};

use crate::stdout::{out, outln};

#[derive(Args, Debug)]
pub struct RunArgs {
    /// Program file (.il text list, GX Works2 .csv export or APLC-TCP .apl
    /// instruction list), or a project directory (or its plc.toml).
    pub program: PathBuf,
    /// CPU model a single program file runs on (default Q06HCPU; a process
    /// CPU, e.g. Q06PHCPU, has the process-control instructions). A project
    /// sets it with `[cpu] model`.
    #[arg(long, value_name = "MODEL")]
    pub model: Option<String>,
    /// State directory for latched devices, file registers and the error history
    /// (default for a project: its [state] dir; a single file keeps no state
    /// unless this is given). Each run is a power-on.
    #[arg(long, value_name = "DIR")]
    pub state: Option<PathBuf>,
    /// Calendar clock at power-on, e.g. 2024-05-01T08:00:00 (default
    /// 2000-01-01T00:00:00, or the project's [clock] start).
    #[arg(long, value_name = "DATETIME", value_parser = parse_datetime)]
    pub clock: Option<DateTime>,
    /// Number of scans to execute.
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub scans: u64,
    /// Virtual time each scan takes, e.g. 10ms, 500us, 1s.
    #[arg(long, default_value = "10ms", value_name = "DUR", value_parser = parse_duration)]
    pub scan_time: Duration,
    /// Write a device before scan 1, e.g. --set X0=1 --set D10:f32=1.5 (repeatable).
    #[arg(long = "set", value_name = "DEV=VALUE")]
    pub set: Vec<String>,
    /// Write a device before scan N (1-based), e.g. --at 50:X0=0 (repeatable).
    /// An input keeps its value until written again.
    #[arg(long = "at", value_name = "N:DEV=VALUE")]
    pub at: Vec<String>,
    /// Report a device after the last scan: DEV or DEV:TYPE with TYPE one of
    /// i16 (default for words), u16, i32, u32, f32, str (repeatable).
    #[arg(long = "show", value_name = "DEV[:TYPE]")]
    pub show: Vec<String>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Sampling trace: devices to sample at END, comma-separated, e.g.
    /// --trace D0,M0,D10:f32 (at most 50 bit and 50 word devices).
    #[arg(long, value_name = "DEV,...", value_delimiter = ',')]
    pub trace: Vec<String>,
    /// Where to write the trace as CSV (scan, time_ms, one column per device).
    #[arg(long, value_name = "FILE", requires = "trace")]
    pub trace_file: Option<PathBuf>,
    /// Sample every N-th scan.
    #[arg(long, value_name = "N", default_value_t = 1, requires = "trace")]
    pub trace_every: u32,
    /// Sample every DUR of virtual time instead (the "fixed time" trace point).
    #[arg(long, value_name = "DUR", value_parser = parse_duration, requires = "trace")]
    pub trace_interval: Option<Duration>,
    /// Samples kept (the latest ones), 1-8192.
    #[arg(long, value_name = "N", default_value_t = 8192, requires = "trace")]
    pub trace_size: usize,
    /// Wall-clock limit, e.g. 10s: the CPU is stopped when it is reached, even
    /// inside a scan that never ends (an endless loop with WDT), latched data is
    /// committed and the report shows "state": "STOP" and "stopped": "timeout".
    /// Ctrl-C and SIGTERM stop a run the same way (exit status 130/143).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub timeout: Option<Duration>,
    /// APLC PORT1 on a serial device or pty (the project's `[port1]`
    /// settings); with a serial line, virtual time keeps pace with the wall
    /// clock.
    #[arg(long, value_name = "PATH")]
    pub port1: Option<PathBuf>,
    /// APLC PORT2 on a serial device or pty (`[port2]`).
    #[arg(long, value_name = "PATH")]
    pub port2: Option<PathBuf>,
    /// How a single program file is read: melsec or aplc, or a family
    /// (MELSEC-Q, MELSEC-QnPH, APLC) (default by name: `.apl` is aplc). APLC
    /// device names: X10/Y10 octal, Dn the high word of :i32/:u32/:f32,
    /// TN5/CN5 current values.
    #[arg(long, value_name = "D", value_parser = crate::names::parse_family)]
    pub dialect: Option<&'static Profile>,
    /// Execution tier: auto (native code where the host has it), jit or
    /// interp; overrides SOFTPLC_EXEC and a project's `[cpu] exec`.
    #[arg(long, value_name = "TIER", value_parser = Exec::parse)]
    pub exec: Option<Exec>,
    /// Print the tier and its compile time at load, and the wall time of the
    /// scans at the end (on stderr).
    #[arg(long)]
    pub stats: bool,
    /// Write the whole CPU state (every CPU's for a multi-CPU system) after
    /// the last scan to FILE: device memory, timers, edges, scheduling,
    /// interrupts, errors, clock and virtual time (docs/snapshots.md).
    #[arg(long, value_name = "FILE")]
    pub save_state: Option<PathBuf>,
    /// Restore the state of a --save-state FILE before scan 1 instead of
    /// the power-on; refused for another program, model or a damaged file.
    /// `scans` then counts this run's scans, `time_ms` the virtual time
    /// since power-on.
    #[arg(long, value_name = "FILE")]
    pub load_state: Option<PathBuf>,
}

/// Why ops run in the interpreter on a tier: `; interpreted: A in runs
/// shorter than N …, B with no native form …`, empty when every op is native.
fn why_interpreted(s: &softplc_core::engine::tier::TierStats) -> String {
    let other = s.ops.saturating_sub(s.native_ops + s.short_run_ops);
    let mut why = Vec::new();
    if s.short_run_ops > 0 {
        why.push(format!(
            "{} in runs shorter than {} native ops in a row (too short to pay for entering native code)",
            s.short_run_ops, s.min_run
        ));
    }
    if other > 0 {
        why.push(format!(
            "{other} with no native form (only contacts and their edge forms, coils, PLS/PLF, MEP/MEF, comparisons, timers, counters, MC/MCR, MOV/DMOV, +, -, INC, DEC, WAND, WOR, WXOR, BSET and BRST on plain devices and constants have one; native code calls the others, and skips those that act only while their condition is ON when it is OFF)"
        ));
    }
    if why.is_empty() {
        String::new()
    } else {
        format!("; interpreted: {}", why.join(", "))
    }
}

/// Puts the loaded CPU on its tier (`--exec` > SOFTPLC_EXEC > `[cpu] exec` >
/// auto); with `stats`, says which on stderr with the compile time.
pub(crate) fn use_exec(l: &mut Loaded, flag: Option<Exec>, stats: bool) -> Result<(), ExitCode> {
    let applied = Exec::choose(flag, l.exec).and_then(|e| tier::apply(&mut l.cpu, e));
    match applied {
        Ok(s) if stats => {
            match s {
                Some(s) => eprintln!(
                    "exec: {}, {} of {} ops native, compiled in {:.1} ms{}",
                    s.tier,
                    s.native_ops,
                    s.ops,
                    s.compile.as_secs_f64() * 1e3,
                    why_interpreted(&s),
                ),
                None => eprintln!("exec: interp"),
            }
            Ok(())
        }
        Ok(_) => Ok(()),
        Err(e) => {
            eprintln!("softplc: {e}");
            Err(ExitCode::from(2))
        }
    }
}

/// Parses `10ms`, `500us`, `1.5s`, `250ns` (the plc.toml duration syntax).
pub fn parse_duration(s: &str) -> Result<Duration, String> {
    let s = s.trim();
    if !s.contains(|c: char| c.is_ascii_alphabetic() || c == 'µ') {
        return Err(format!("`{s}`: give a unit, e.g. 10ms, 500us, 1s"));
    }
    let d = project::parse_duration(s)
        .ok_or_else(|| format!("`{s}` is not a duration (a number and ns, us, ms or s)"))?;
    if d < Duration::from_micros(1) {
        return Err(format!("`{s}`: must be at least 1us"));
    }
    Ok(d)
}

/// Parses `2024-05-01T08:00:00` (or with a space instead of `T`).
pub fn parse_datetime(s: &str) -> Result<DateTime, String> {
    let dt = DateTime::parse(s).ok_or_else(|| format!("`{s}`: expected YYYY-MM-DDTHH:MM:SS"))?;
    if !dt.is_valid() {
        return Err(format!("`{s}`: not a valid date and time in 1980-2079"));
    }
    Ok(dt)
}

/// Longest echoed token in a diagnostic (characters between backquotes).
const MAX_TOKEN: usize = 64;

/// A diagnostic made safe for a terminal: control characters escaped (`\u{1b}`),
/// quoted tokens longer than [`MAX_TOKEN`] characters cut with their length.
pub(crate) fn sanitize(line: &str) -> String {
    let mut out = String::with_capacity(line.len().min(1024));
    let mut parts = line.split('`');
    let mut quoted = false;
    while let Some(part) = parts.next() {
        let n = part.chars().count();
        let shown: String = if quoted && n > MAX_TOKEN {
            let head: String = part.chars().take(MAX_TOKEN).collect();
            format!("{head}…({n} characters)")
        } else {
            part.to_string()
        };
        for c in shown.chars() {
            if c.is_control() && c != '\t' {
                out.push_str(&c.escape_unicode().to_string());
            } else {
                out.push(c);
            }
        }
        if parts.clone().next().is_some() {
            out.push('`');
        }
        quoted = !quoted;
    }
    out
}

fn report(diags: &Diagnostics, what: &Path) -> ExitCode {
    for d in &diags.0 {
        eprintln!("{}", sanitize(&d.to_string()));
    }
    let n = diags.0.len();
    eprintln!(
        "{n} error{} in {}",
        if n == 1 { "" } else { "s" },
        what.display()
    );
    ExitCode::from(1)
}

/// Why a directory without plc.toml does not load, and what to give instead:
/// a program file in it, when it has one.
fn not_a_project(dir: &Path) -> String {
    let mut programs: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.is_file()
                        && p.extension().is_some_and(|x| {
                            ["il", "csv", "apl"]
                                .iter()
                                .any(|k| x.eq_ignore_ascii_case(k))
                        })
                })
                .collect()
        })
        .unwrap_or_default();
    programs.sort();
    let hint = programs.first().map_or(String::new(), |p| {
        format!(", or give one program file, e.g. {}", p.display())
    });
    format!(
        "{}: no plc.toml in this directory: a project directory needs a plc.toml \
         naming its CPU model and program files (see docs/plc-toml.md){hint}",
        dir.display()
    )
}

/// A loaded CPU and where its battery-backed memory lives.
pub(crate) struct Loaded {
    pub cpu: Cpu,
    pub state: Option<PathBuf>,
    /// A project's `[modbus]` table.
    pub modbus: Option<toml::Table>,
    /// A project's `[http]` table.
    pub http: Option<toml::Table>,
    /// A project's `[opcua]` table.
    pub opcua: Option<toml::Table>,
    /// A project's `[state] on_damage`.
    pub on_damage: OnDamage,
    /// An APLC-TCP project's `[port1]`/`[port2]`.
    pub ports: Vec<softplc_core::aplc::PortConfig>,
    /// A project's `[cpu] exec`.
    pub exec: Option<Exec>,
}

/// The APLC ports of a loaded program: `[port1]`/`[port2]` with
/// `--port1`/`--port2` binding them to a serial device or pty (contract §3.3).
pub(crate) fn open_ports(
    ports: &[softplc_core::aplc::PortConfig],
    port1: Option<&Path>,
    port2: Option<&Path>,
) -> Result<softplc_ports::Ports, String> {
    let p1 = port1.map(|p| p.display().to_string());
    let p2 = port2.map(|p| p.display().to_string());
    softplc_ports::Ports::open(ports, [p1.as_deref(), p2.as_deref()])
}

/// Loads a program file or a project into a powered-on CPU.
pub(crate) fn load(
    path: &Path,
    clock: Box<dyn Clock>,
    start: Option<DateTime>,
    model: Option<&str>,
) -> Result<Loaded, ExitCode> {
    load_with(path, clock, start, None, model)
}

/// [`load`] with the `--dialect` of a single program file.
pub(crate) fn load_with(
    path: &Path,
    clock: Box<dyn Clock>,
    start: Option<DateTime>,
    dialect: Option<&'static Profile>,
    model: Option<&str>,
) -> Result<Loaded, ExitCode> {
    if project::is_project(path) {
        if model.is_some() {
            eprintln!(
                "{}: --model applies to a single program file; a project sets [cpu] model",
                path.display()
            );
            return Err(ExitCode::from(2));
        }
        let mut p = project::load_project(path).map_err(|d| report(&d, path))?;
        if let Some(t) = start {
            p.config.clock_start = t;
        }
        let cpu = p.build_cpu(clock).map_err(|d| report(&d, path))?;
        return Ok(Loaded {
            cpu,
            state: Some(p.state_dir),
            modbus: p.modbus,
            http: p.http,
            opcua: p.opcua,
            on_damage: p.state_on_damage,
            ports: p.ports,
            exec: p.exec,
        });
    }
    if path.is_dir() {
        eprintln!("{}", not_a_project(path));
        return Err(ExitCode::from(1));
    }
    let model = match model.map(project::known_model).transpose() {
        Ok(m) => m,
        Err(e) => {
            eprintln!("--model: {e}");
            return Err(ExitCode::from(2));
        }
    };
    let profile = single::profile_for(path, model, dialect).map_err(|e| {
        eprintln!("--model: {e}");
        ExitCode::from(2)
    })?;
    let options = single::Options {
        clock_start: start,
        explicit_model: model.is_some(),
        ..Default::default()
    };
    let cpu = single::load(path, profile, options, clock).map_err(|e| match e {
        single::LoadError::Program(d) => report(&d, path),
        single::LoadError::Cpu(e) => {
            eprintln!("softplc: {e}");
            ExitCode::from(1)
        }
    })?;
    Ok(Loaded {
        cpu,
        state: None,
        modbus: None,
        http: None,
        opcua: None,
        on_damage: OnDamage::default(),
        ports: Vec::new(),
        exec: None,
    })
}

/// `softplc check`; `exec`/`stats` compile the program on its tier too
/// (`--stats` reports the compile time).
pub fn check(
    path: &Path,
    model: Option<&str>,
    dialect: Option<&'static Profile>,
    exec: Option<Exec>,
    stats: bool,
) -> ExitCode {
    if softplc_core::system::is_system(path) {
        if model.is_some() || dialect.is_some() {
            eprintln!("softplc: --model and --dialect do not apply to a multi-CPU system");
            return ExitCode::from(2);
        }
        return crate::run_system::check(path, exec);
    }
    match load_with(path, Box::new(VirtualClock::new()), None, dialect, model) {
        Ok(mut l) => {
            if exec.is_some() || stats {
                if let Err(code) = use_exec(&mut l, exec, stats) {
                    return code;
                }
            }
            let n = l.cpu.program_count();
            let steps: u32 = (0..n).map(|i| l.cpu.program_at(i).steps).sum();
            outln!(
                "{}: OK, {n} program{}, {steps} steps",
                path.display(),
                if n == 1 { "" } else { "s" },
            );
            ExitCode::SUCCESS
        }
        Err(code) => code,
    }
}

/// A write scheduled before a scan.
struct Write {
    scan: u64,
    spec: DevName,
    value: String,
}

fn parse_write(arg: &str, scan: u64, names: &Names) -> Result<Write, String> {
    let (dev, value) = arg
        .split_once('=')
        .ok_or_else(|| format!("`{arg}`: expected DEV=VALUE"))?;
    Ok(Write {
        scan,
        spec: names.parse(dev.trim())?,
        value: value.trim().to_string(),
    })
}

/// The `--trace` devices in the CPU's dialect and the engine's trace over
/// their storage.
fn parse_trace(args: &RunArgs, names: &Names) -> Result<Option<(Trace, Vec<DevName>)>, String> {
    if args.trace.is_empty() {
        return Ok(None);
    }
    let traced = args
        .trace
        .iter()
        .map(|d| names.parse(d.trim()))
        .collect::<Result<Vec<_>, _>>()?;
    let devices: Vec<DeviceSpec> = traced.iter().map(|n| n.spec().clone()).collect();
    Trace::new(TraceConfig {
        devices,
        every_scans: args.trace_every,
        interval_us: args.trace_interval.map(|d| d.as_micros() as u64),
        capacity: args.trace_size,
        trigger: None,
        after_trigger: 0,
    })
    .map(|t| Some((t, traced)))
}

/// The trace as CSV, `scan,time_ms,DEV,…`, values in each name's type (an
/// APLC pair high word first).
fn trace_csv(t: &Trace, names: &[DevName]) -> String {
    let mut out = String::from("scan,time_ms");
    for n in names {
        out.push(',');
        out.push_str(n.text());
    }
    out.push('\n');
    for (scan, us, vals) in t.samples() {
        out.push_str(&format!("{scan},{}", us as f64 / 1000.0));
        for (v, n) in vals.iter().zip(names) {
            out.push(',');
            out.push_str(&match n.present(v) {
                Value::Bool(b) => (b as u8).to_string(),
                v => v.to_string(),
            });
        }
        out.push('\n');
    }
    out
}

fn parse_options(args: &RunArgs, names: &Names) -> Result<(Vec<Write>, Vec<DevName>), String> {
    let mut writes = Vec::new();
    for s in &args.set {
        writes.push(parse_write(s, 1, names)?);
    }
    for a in &args.at {
        let (n, rest) = a
            .split_once(':')
            .ok_or_else(|| format!("`{a}`: expected N:DEV=VALUE"))?;
        let n: u64 = n
            .trim()
            .parse()
            .ok()
            .filter(|n| *n >= 1)
            .ok_or_else(|| format!("`{a}`: scan number must be 1 or more"))?;
        writes.push(parse_write(rest, n, names)?);
    }
    writes.sort_by_key(|w| w.scan);
    let shows = args
        .show
        .iter()
        .map(|s| names.parse(s))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((writes, shows))
}

pub fn run(args: RunArgs) -> ExitCode {
    if softplc_core::system::is_system(&args.program) {
        return crate::run_system::run(&args);
    }
    let clock = VirtualClock::new();
    let mut loaded = match load_with(
        &args.program,
        Box::new(clock.clone()),
        args.clock,
        args.dialect,
        args.model.as_deref(),
    ) {
        Ok(l) => l,
        Err(code) => return code,
    };
    if let Err(code) = use_exec(&mut loaded, args.exec, args.stats) {
        return code;
    }
    let Loaded {
        mut cpu,
        state,
        on_damage,
        ports,
        ..
    } = loaded;
    let names = Names::of(&cpu);
    let (writes, shows, trace) = match parse_options(&args, &names)
        .and_then(|(w, s)| Ok((w, s, parse_trace(&args, &names)?)))
    {
        Ok(x) => x,
        Err(e) => {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    };
    let trace_names = match trace {
        Some((t, names)) => {
            cpu.set_trace(Some(t));
            names
        }
        None => Vec::new(),
    };
    // Power-on: latched devices, file registers and the error history come back.
    let mut battery = match args.state.clone().or(state) {
        Some(dir) => {
            let how = Attach {
                restore_clock: false,
                on_damage,
            };
            match power_on(&dir, &mut cpu, how) {
                Ok(b) => Some(b),
                Err(e) => {
                    eprintln!("softplc: {e}");
                    return ExitCode::from(2);
                }
            }
        }
        None => None,
    };
    // The state of a file instead of the power-on (after the battery's, so
    // the file wins); the virtual time goes on from its.
    if let Some(path) = &args.load_state {
        if let Err(e) = crate::state_file::load(path, |b| snapshot::load(&mut cpu, b)) {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    }
    let loaded_us = clock.now_us();
    // Ctrl-C/SIGTERM and --timeout stop the CPU, even mid-scan.
    let abort = cpu.abort_handle();
    crate::signal::stop_on_signals(abort.clone());
    let timed_out = Arc::new(AtomicBool::new(false));
    if let Some(limit) = args.timeout {
        let (abort, flag) = (abort.clone(), timed_out.clone());
        std::thread::spawn(move || {
            std::thread::sleep(limit);
            flag.store(true, Ordering::SeqCst);
            abort.store(true, Ordering::SeqCst);
        });
    }
    let mut ports = match open_ports(&ports, args.port1.as_deref(), args.port2.as_deref()) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    };
    // With a real serial line, virtual time keeps pace with the wall clock.
    let paced = ports.has_serial().then(std::time::Instant::now);
    let step_us = args.scan_time.as_micros() as u64;
    let mut pending = writes.iter().peekable();
    let mut scans = 0u64;
    // --stats: the wall time of the scans themselves (load and compile excluded).
    let started = std::time::Instant::now();
    for n in 1..=args.scans {
        while let Some(w) = pending.next_if(|w| w.scan == n) {
            if let Err(e) = w.spec.write(&mut cpu, &w.value) {
                eprintln!("softplc: {e}");
                return ExitCode::from(2);
            }
        }
        clock.advance_us(step_us);
        if let Some(t0) = paced {
            let due = t0 + Duration::from_micros(clock.now_us());
            std::thread::sleep(due.saturating_duration_since(std::time::Instant::now()));
        }
        cpu.scan();
        // The communication phase (L914-941).
        ports.after_end(&mut cpu);
        for e in ports.take_errors() {
            eprintln!("softplc: {e}");
        }
        scans = n;
        // END processing done: commit latched data (at most every 10 ms of wall time).
        if let Some(b) = &mut battery {
            if let Err(e) = b.commit_due(&cpu) {
                eprintln!("softplc: cannot save state: {e}");
                return ExitCode::from(2);
            }
        }
        if cpu.state() == CpuState::Stop || cpu.aborted() {
            break;
        }
    }
    if args.stats && scans > 0 {
        let secs = started.elapsed().as_secs_f64();
        eprintln!(
            "run: {scans} scans in {:.1} ms of wall time, {:.2} µs per scan",
            secs * 1e3,
            secs * 1e6 / scans as f64
        );
    }
    let signal = crate::signal::received();
    let stopped = if signal.is_some() {
        cpu.set_stop();
        Some("signal")
    } else if timed_out.load(Ordering::SeqCst) {
        cpu.set_stop();
        eprintln!(
            "softplc: --timeout {:?} reached after {scans} scans; the CPU was stopped",
            args.timeout.unwrap_or_default()
        );
        Some("timeout")
    } else {
        None
    };
    if let Some(b) = &mut battery {
        if let Err(e) = b.commit(&cpu) {
            eprintln!("softplc: cannot save state: {e}");
            return ExitCode::from(2);
        }
    }
    if let Some(path) = &args.save_state {
        if let Err(e) = crate::state_file::save(path, &snapshot::save(&mut cpu)) {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    }
    if let Some(t) = cpu.trace() {
        let csv = trace_csv(t, &trace_names);
        match &args.trace_file {
            Some(path) => {
                if let Err(e) = std::fs::write(path, csv) {
                    eprintln!("softplc: cannot write {}: {e}", path.display());
                    return ExitCode::from(2);
                }
            }
            None if !args.json => out!("{csv}"),
            None => {}
        }
    }
    let mut devices = Map::new();
    let mut text = Vec::new();
    for spec in &shows {
        match spec.read(&cpu) {
            Ok(v) => {
                text.push(format!("{} = {v}", spec.text()));
                devices.insert(spec.text().to_string(), to_json(&v));
            }
            Err(e) => {
                eprintln!("softplc: {e}");
                return ExitCode::from(2);
            }
        }
    }
    // Since power-on (a loaded state's time included), from whole
    // nanoseconds, so 510 scans of 10 ms print 5100, not 5100.000000000001.
    let ns = u128::from(loaded_us) * 1000 + u128::from(scans) * args.scan_time.as_nanos();
    let time_ms = ns as f64 / 1e6;
    // The APLC has no step numbers in its reports (contract §2).
    let steps = cpu.profile().step_numbers;
    let error = cpu.error().map(|e| {
        json!({
            "code": e.code.0,
            "message": cpu.error_message(e.code),
            "step": if steps { e.step } else { None },
            "file": e.file,
            "line": e.line,
        })
    });
    if args.json {
        let mut out = json!({
            "scans": scans,
            "time_ms": time_ms,
            "state": cpu.state().as_str(),
            "error": error,
            "devices": devices,
        });
        if let Some(why) = stopped {
            out["stopped"] = json!(why);
        }
        outln!("{out}");
    } else {
        outln!(
            "scans: {scans}  time: {time_ms} ms  state: {}",
            cpu.state().as_str()
        );
        match cpu.error() {
            None => outln!("error: none"),
            Some(e) => {
                let place = match (&e.file, e.line, e.step) {
                    (Some(f), Some(l), Some(s)) => format!(" at step {s} ({f}:{l})"),
                    _ => String::new(),
                };
                outln!("error: {} {}{place}", e.code.0, cpu.error_message(e.code));
            }
        }
        for line in text {
            outln!("{line}");
        }
    }
    match signal {
        // As a shell reports a process ended by the signal, after the commit.
        Some(s) => ExitCode::from((128 + s).clamp(0, 255) as u8),
        None => ExitCode::SUCCESS,
    }
}

/// Power-on of `cpu` from the state directory `dir`: its battery-backed
/// memory, the warnings printed ([`report_attach`]); the error names the
/// directory ([`state_error`]).
pub(crate) fn power_on(dir: &Path, cpu: &mut Cpu, how: Attach) -> Result<Battery, String> {
    let b = Battery::attach_with(dir, cpu, how).map_err(|e| state_error(dir, &e))?;
    report_attach(dir, &b);
    Ok(b)
}

/// Prints the warnings of a power-on from a state directory.
fn report_attach(dir: &Path, b: &Battery) {
    for w in b.warnings() {
        eprintln!("softplc: {}: {w}", dir.display());
    }
    if !b.lost().is_empty() {
        eprintln!(
            "softplc: {}: retained data lost ({}); BATTERY ERROR 1600 recorded in SD0",
            dir.display(),
            b.lost().join("; ")
        );
    }
}

/// A state-directory error, naming the directory once.
fn state_error(dir: &Path, e: &PersistError) -> String {
    match e {
        PersistError::Locked { .. } => e.to_string(),
        _ => format!("state directory {}: {e}", dir.display()),
    }
}

pub(crate) fn to_json(v: &Value) -> Json {
    match v {
        Value::Bool(b) => Json::Bool(*b),
        Value::Int(i) => json!(i),
        Value::Float(f) => json!(f),
        Value::Str(s) => Json::String(s.clone()),
    }
}

#[cfg(test)]
mod tests {
    use super::sanitize;

    #[test]
    fn diagnostics_escape_control_characters_and_cut_long_tokens() {
        assert_eq!(
            sanitize("a.il:1:1: `LD\x1b[2J` bad"),
            "a.il:1:1: `LD\\u{1b}[2J` bad"
        );
        let long = "X".repeat(100_000);
        let s = sanitize(&format!("a.il:1:1: unknown instruction `{long}`"));
        assert!(s.len() < 200, "{s}");
        assert!(s.ends_with("…(100000 characters)`"), "{s}");
        assert_eq!(sanitize("plain `LD` text"), "plain `LD` text");
    }
}
