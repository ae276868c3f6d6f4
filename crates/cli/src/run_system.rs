//! `softplc run` and `softplc check` of a multi-CPU system (contract §6): a
//! directory with `system.toml`. All CPUs scan in one virtual time, each at
//! its constant scan (`--scan-time` for those without one); `--scans N`
//! counts CPU 1's scans and the run ends early only when every CPU has
//! stopped. Names take `CPUn/` prefixes.

use std::path::Path;
use std::process::ExitCode;

use serde_json::{json, Map, Value as Json};
use softplc_core::device::DeviceKind;
use softplc_core::engine::tier::TierStats;
use softplc_core::engine::{Clock, Cpu, VirtualClock};
use softplc_core::names::DevName;
use softplc_core::persist::{Attach, Battery};
use softplc_core::system::{names, System};
use softplc_core::tier::{self, Exec};

use crate::run::{power_on, RunArgs};
use crate::stdout::outln;

/// Loads a system on `clock` (every CPU reads it) and puts each CPU on its tier.
fn load(path: &Path, clock: &VirtualClock, exec: Option<Exec>) -> Result<System, ExitCode> {
    let mut sys =
        System::load(path, &mut || Box::new(clock.clone()) as Box<dyn Clock>).map_err(|d| {
            eprint!("{d}");
            if !d.to_string().ends_with('\n') {
                eprintln!();
            }
            ExitCode::from(1)
        })?;
    for i in 0..sys.len() {
        use_tier(&mut sys, i, exec)?;
    }
    Ok(sys)
}

/// Puts CPU `i` of `sys` on the tier `exec` (the command line's) or else its
/// project chooses; the error is printed with the CPU's number.
pub(crate) fn use_tier(
    sys: &mut System,
    i: usize,
    exec: Option<Exec>,
) -> Result<Option<TierStats>, ExitCode> {
    let own = sys.project(i).exec;
    Exec::choose(exec, own)
        .and_then(|e| tier::apply(sys.cpu_mut(i), e))
        .map_err(|e| {
            eprintln!("softplc: CPU {}: {e}", i + 1);
            ExitCode::from(2)
        })
}

/// `softplc check SYSTEM`: every CPU's programs compile and link.
pub fn check(path: &Path, exec: Option<Exec>) -> ExitCode {
    let sys = match load(path, &VirtualClock::new(), exec) {
        Ok(s) => s,
        Err(code) => return code,
    };
    outln!("{}: OK, {} CPUs", path.display(), sys.len());
    for i in 0..sys.len() {
        let cpu = sys.cpu(i);
        let n = cpu.program_count();
        let steps: u32 = (0..n).map(|k| cpu.program_at(k).steps).sum();
        outln!(
            "  CPU {}: {}, {n} program{}, {steps} steps",
            i + 1,
            cpu.profile().model,
            if n == 1 { "" } else { "s" },
        );
    }
    ExitCode::SUCCESS
}

/// A name with its CPU, and as the user wrote it.
struct Named {
    cpu: usize,
    name: DevName,
    text: String,
}

fn parse_name(text: &str, sys: &System) -> Result<Named, String> {
    let (cpu, rest) = names::split(text.trim(), sys.len())?;
    let name = DevName::parse_for(rest, sys.cpu(cpu))?;
    Ok(Named {
        cpu,
        name,
        text: text.trim().to_string(),
    })
}

/// A write before CPU 1's scan `scan`.
struct Write {
    scan: u64,
    to: Named,
    value: String,
}

fn writes(args: &RunArgs, sys: &System) -> Result<Vec<Write>, String> {
    let mut out = Vec::new();
    let mut add = |arg: &str, scan: u64| -> Result<(), String> {
        let (dev, value) = arg
            .split_once('=')
            .ok_or_else(|| format!("`{arg}`: expected DEV=VALUE"))?;
        out.push(Write {
            scan,
            to: parse_name(dev, sys)?,
            value: value.trim().to_string(),
        });
        Ok(())
    };
    for s in &args.set {
        add(s, 1)?;
    }
    for a in &args.at {
        let (n, rest) = a
            .split_once(':')
            .ok_or_else(|| format!("`{a}`: expected N:DEV=VALUE"))?;
        let n = n
            .trim()
            .parse::<u64>()
            .ok()
            .filter(|n| *n >= 1)
            .ok_or_else(|| format!("`{a}`: scan number must be 1 or more"))?;
        add(rest, n)?;
    }
    out.sort_by_key(|w| w.scan);
    Ok(out)
}

/// `softplc run SYSTEM`.
pub fn run(args: &RunArgs) -> ExitCode {
    for (given, what) in [
        (args.model.is_some(), "--model"),
        (args.dialect.is_some(), "--dialect"),
        (
            args.state.is_some(),
            "--state (each CPU keeps its project's [state] dir)",
        ),
        (!args.trace.is_empty(), "--trace"),
        (
            args.port1.is_some() || args.port2.is_some(),
            "--port1/--port2",
        ),
    ] {
        if given {
            eprintln!("softplc: {what} does not apply to a multi-CPU system");
            return ExitCode::from(2);
        }
    }
    let clock = VirtualClock::new();
    let mut sys = match load(&args.program, &clock, args.exec) {
        Ok(s) => s,
        Err(code) => return code,
    };
    let (writes, shows) = match writes(args, &sys).and_then(|w| {
        let s = args
            .show
            .iter()
            .map(|s| parse_name(s, &sys))
            .collect::<Result<Vec<_>, _>>()?;
        Ok((w, s))
    }) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    };
    // Power-on: each CPU's latched devices come back from its state directory.
    let mut batteries: Vec<Option<Battery>> = Vec::new();
    for i in 0..sys.len() {
        let p = sys.project(i);
        let (dir, on_damage) = (p.state_dir.clone(), p.state_on_damage);
        let attach = Attach {
            restore_clock: false,
            on_damage,
        };
        match power_on(&dir, sys.cpu_mut(i), attach) {
            Ok(b) => batteries.push(Some(b)),
            Err(e) => {
                eprintln!("softplc: CPU {}: {e}", i + 1);
                return ExitCode::from(2);
            }
        }
    }
    let aborts: Vec<_> = (0..sys.len()).map(|i| sys.cpu(i).abort_handle()).collect();
    crate::signal::stop_on_signals_all(aborts);
    sys.schedule(args.scan_time, clock.now_us());
    // A state file instead of the power-on: every CPU's state, the time and
    // each CPU's scan period and next scan come back from it.
    if let Some(path) = &args.load_state {
        if let Err(e) = crate::state_file::load(path, |b| sys.load_state(b)) {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    }
    // `scans` counts this run's scans (contract §7).
    let before: Vec<u64> = (0..sys.len()).map(|i| sys.cpu(i).scans()).collect();
    let started = std::time::Instant::now();
    let mut pending = writes.iter().peekable();
    let mut scans = 0;
    while scans < args.scans {
        let n = sys.cpu(0).scans().saturating_sub(before[0]) + 1;
        while let Some(w) = pending.next_if(|w| w.scan <= n) {
            // An input of a module goes to its control CPU's input image.
            let cpu = match w.to.name.spec().bit_span() {
                Some((DeviceKind::X, x, _)) => sys.input_owner(w.to.cpu, x),
                _ => w.to.cpu,
            };
            if let Err(e) = w.to.name.write(sys.cpu_mut(cpu), &w.value) {
                eprintln!("softplc: {e}");
                return ExitCode::from(2);
            }
        }
        // Up to and including CPU 1's next scan, and every CPU due with it.
        let t = sys.next_due_of(0);
        while let Some(i) = sys.scan_due(t, &clock) {
            if let Some(b) = &mut batteries[i] {
                if let Err(e) = b.commit_due(sys.cpu(i)) {
                    eprintln!("softplc: CPU {}: cannot save state: {e}", i + 1);
                    return ExitCode::from(2);
                }
            }
        }
        scans += 1;
        if sys.all_stopped() || (0..sys.len()).any(|i| sys.cpu(i).aborted()) {
            break;
        }
    }
    if args.stats {
        eprintln!(
            "run: {scans} scans of CPU 1 in {:.1} ms of wall time",
            started.elapsed().as_secs_f64() * 1e3
        );
    }
    let signal = crate::signal::received();
    for (i, b) in batteries.iter_mut().enumerate() {
        if signal.is_some() {
            sys.cpu_mut(i).set_stop();
        }
        if let Some(b) = b {
            if let Err(e) = b.commit(sys.cpu(i)) {
                eprintln!("softplc: CPU {}: cannot save state: {e}", i + 1);
                return ExitCode::from(2);
            }
        }
    }
    if let Some(path) = &args.save_state {
        if let Err(e) = crate::state_file::save(path, &sys.save_state()) {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    }
    report(args, &sys, &shows, &before, clock.now_us(), signal)
}

/// The report: CPU 1's state, error and scans at the top, every CPU in `cpus`.
fn report(
    args: &RunArgs,
    sys: &System,
    shows: &[Named],
    before: &[u64],
    now_us: u64,
    signal: Option<i32>,
) -> ExitCode {
    let mut devices = Map::new();
    let mut text = Vec::new();
    for s in shows {
        match s.name.read(sys.cpu(s.cpu)) {
            Ok(v) => {
                text.push(format!("{} = {v}", s.text));
                devices.insert(s.text.clone(), crate::run::to_json(&v));
            }
            Err(e) => {
                eprintln!("softplc: {e}");
                return ExitCode::from(2);
            }
        }
    }
    let error_json = |cpu: &Cpu| {
        cpu.error().map(|e| {
            json!({
                "code": e.code.0,
                "message": cpu.error_message(e.code),
                "step": e.step,
                "file": e.file,
                "line": e.line,
            })
        })
    };
    let time_ms = now_us as f64 / 1000.0;
    let first = sys.cpu(0);
    if args.json {
        let cpus: Vec<Json> = (0..sys.len())
            .map(|i| {
                let c = sys.cpu(i);
                json!({
                    "cpu": i + 1,
                    "state": c.state().as_str(),
                    "error": error_json(c),
                    "scans": c.scans().saturating_sub(before[i]),
                })
            })
            .collect();
        let mut o = json!({
            "scans": first.scans().saturating_sub(before[0]),
            "time_ms": time_ms,
            "state": first.state().as_str(),
            "error": error_json(first),
            "cpus": cpus,
            "devices": devices,
        });
        if signal.is_some() {
            o["stopped"] = json!("signal");
        }
        outln!("{o}");
    } else {
        outln!(
            "scans: {}  time: {time_ms} ms  state: {}",
            first.scans().saturating_sub(before[0]),
            first.state().as_str()
        );
        for (i, base) in before.iter().enumerate() {
            let c = sys.cpu(i);
            let err = match c.error() {
                None => "none".to_string(),
                Some(e) => format!("{} {}", e.code.0, c.error_message(e.code)),
            };
            outln!(
                "CPU {}: {} scans, state {}, error: {err}",
                i + 1,
                c.scans().saturating_sub(*base),
                c.state().as_str()
            );
        }
        for line in text {
            outln!("{line}");
        }
    }
    match signal {
        Some(s) => ExitCode::from((128 + s).clamp(0, 255) as u8),
        None => ExitCode::SUCCESS,
    }
}
