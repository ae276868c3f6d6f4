//! What `softplc serve` runs (contract §3, §6): one CPU — a program file or
//! a project — or a multi-CPU system directory, each CPU with the
//! battery-backed memory of its state directory, and the doors' settings of
//! CPU 1's project.

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use softplc_core::engine::calendar::DateTime;
use softplc_core::engine::{Clock, Cpu, MonotonicClock, VirtualClock};
use softplc_core::persist::{Attach, Battery, OnDamage};
use softplc_core::system::System;
use softplc_serve::ServeState;

use crate::run::{load, power_on, sanitize, use_exec, Loaded};
use crate::run_system::use_tier;
use crate::serve::ServeArgs;

/// The loaded CPUs and CPU 1's settings for the doors.
pub struct Served {
    pub state: ServeState,
    /// A single CPU's battery-backed memory (a system's are in `state`).
    pub battery: Option<Battery>,
    /// The scan period of a CPU without a constant scan (a single CPU's
    /// period).
    pub period: Duration,
    /// CPU 1's project's `[modbus]`, `[http]`, `[opcua]`.
    pub modbus: Option<toml::Table>,
    pub http: Option<toml::Table>,
    pub opcua: Option<toml::Table>,
    /// APLC `[port1]`/`[port2]` of a single APLC-TCP project.
    pub ports: Vec<softplc_core::aplc::PortConfig>,
    /// One line per CPU of a system for the start message (empty for one CPU).
    pub cpus: Vec<String>,
    /// The clock the CPUs run on with --time-scale or --lockstep (else the
    /// monotonic clock).
    pub virtual_clock: Option<VirtualClock>,
}

/// The virtual clock of --time-scale and --lockstep.
fn virtual_clock(args: &ServeArgs) -> Option<VirtualClock> {
    (args.time_scale.is_some() || args.lockstep).then(VirtualClock::new)
}

/// A clock on `time` when given, else on the host's monotonic clock (all
/// CPUs of a system on one).
fn clock_on(time: &Option<VirtualClock>, monotonic: &MonotonicClock) -> Box<dyn Clock> {
    match time {
        Some(t) => Box::new(t.clone()),
        None => Box::new(monotonic.clone()),
    }
}

/// Loads what `args.program` names, powered on (`Err`: the exit code, the
/// diagnostics printed).
pub fn load_served(
    args: &ServeArgs,
    start: DateTime,
    restore_clock: bool,
) -> Result<Served, ExitCode> {
    if softplc_core::system::is_system(&args.program) {
        load_system(args, start, restore_clock)
    } else {
        load_one(args, start, restore_clock)
    }
}

/// A single program file or project.
fn load_one(args: &ServeArgs, start: DateTime, restore_clock: bool) -> Result<Served, ExitCode> {
    let time = virtual_clock(args);
    let mut loaded = load(
        &args.program,
        clock_on(&time, &MonotonicClock::default()),
        Some(start),
        args.model.as_deref(),
    )?;
    use_exec(&mut loaded, args.exec, args.stats)?;
    let Loaded {
        mut cpu,
        state,
        modbus,
        http,
        opcua,
        on_damage,
        ports,
        ..
    } = loaded;
    let period = args
        .scan_time
        .or(cpu.config().constant_scan)
        .unwrap_or(DEFAULT_PERIOD);
    let battery = match args.state.clone().or(state) {
        Some(dir) => Some(attach(&dir, &mut cpu, restore_clock, on_damage)?),
        None => None,
    };
    Ok(Served {
        state: ServeState::new(cpu),
        battery,
        period,
        modbus,
        http,
        opcua,
        ports,
        cpus: Vec::new(),
        virtual_clock: time,
    })
}

/// The scan period without `--scan-time` or a constant scan.
pub const DEFAULT_PERIOD: Duration = Duration::from_millis(10);

/// A multi-CPU system directory: every CPU on one monotonic time source,
/// each with its project's state directory.
fn load_system(args: &ServeArgs, start: DateTime, restore_clock: bool) -> Result<Served, ExitCode> {
    let usage = |flag: &str, why: &str| {
        eprintln!("softplc: {flag}: {why}");
        Err(ExitCode::from(2))
    };
    if args.model.is_some() {
        return usage("--model", "a system's projects set [cpu] model");
    }
    if args.state.is_some() {
        return usage(
            "--state",
            "each CPU of a system keeps its state in its project's [state] dir",
        );
    }
    let time = virtual_clock(args);
    let monotonic = MonotonicClock::default();
    let mut clock = || clock_on(&time, &monotonic);
    let mut system = System::load(&args.program, &mut clock).map_err(|d| {
        for x in &d.0 {
            eprintln!("{}", sanitize(&x.to_string()));
        }
        let n = d.0.len();
        eprintln!(
            "{n} error{} in {}",
            if n == 1 { "" } else { "s" },
            args.program.display()
        );
        ExitCode::from(1)
    })?;
    let period = args.scan_time.unwrap_or(DEFAULT_PERIOD);
    let mut batteries = Vec::new();
    let mut cpus = Vec::new();
    for i in 0..system.len() {
        system
            .cpu_mut(i)
            .set_calendar_unix_us(start.to_unix() * 1_000_000);
        let exec = use_tier(&mut system, i, args.exec)?;
        if args.stats {
            let t = exec.map_or("interp".to_string(), |s| s.tier.to_string());
            eprintln!("exec: CPU {}: {t}", i + 1);
        }
        let m = &mut system.members_mut()[i];
        let cpu = &mut m.cpu;
        batteries.push(Some(attach(
            &m.project.state_dir,
            cpu,
            restore_clock,
            m.project.state_on_damage,
        )?));
        cpus.push(format!(
            "CPU {}: {} ({}), scan {:?}",
            i + 1,
            m.project.dir.display(),
            cpu.profile().model,
            cpu.config().constant_scan.unwrap_or(period),
        ));
    }
    let p = system.project(0);
    let (modbus, http, opcua) = (p.modbus.clone(), p.http.clone(), p.opcua.clone());
    Ok(Served {
        state: ServeState::system(system, batteries),
        battery: None,
        period,
        modbus,
        http,
        opcua,
        ports: Vec::new(),
        cpus,
        virtual_clock: time,
    })
}

/// The battery-backed memory of `dir` for `cpu`.
fn attach(
    dir: &Path,
    cpu: &mut Cpu,
    restore_clock: bool,
    on_damage: OnDamage,
) -> Result<Battery, ExitCode> {
    let how = Attach {
        restore_clock,
        on_damage,
    };
    power_on(dir, cpu, how).map_err(|e| {
        eprintln!("softplc: {e}");
        ExitCode::from(2)
    })
}
