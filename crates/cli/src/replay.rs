//! `softplc replay FILE` (docs/recording.md): a recording of `serve
//! --record` run again in virtual time, its program built from the files it
//! embeds; `--program` runs a changed program beside it and reports where
//! devices first differ.

use std::path::{Component, Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use serde_json::{json, Map, Value as Json};
use softplc_core::access::Value;
use softplc_core::engine::calendar::DateTime;
use softplc_core::engine::Cpu;
use softplc_core::names::{DevName, Names};
use softplc_record::{Header, Player};

use crate::run::{load, to_json, Loaded};
use crate::stdout::outln;

#[derive(Args, Debug)]
pub struct ReplayArgs {
    /// The recording (`softplc serve … --record FILE`).
    pub file: PathBuf,
    /// Report a device after the last replayed END: DEV or DEV:TYPE as
    /// `run --show` (repeatable).
    #[arg(long = "show", value_name = "DEV[:TYPE]")]
    pub show: Vec<String>,
    /// Print one JSON object on stdout (as `run --json`).
    #[arg(long)]
    pub json: bool,
    /// Stop at the first END whose scan count reaches N (the CPU's scans
    /// since power-on, as HTTP's `scan`).
    #[arg(long, value_name = "N")]
    pub until: Option<u64>,
    /// Run this program (a file or project directory) beside the recorded
    /// one, with the same changes from outside and clock, and report the
    /// first scan where each --diverge (or --show) device differs.
    #[arg(long, value_name = "PATH")]
    pub program: Option<PathBuf>,
    /// A device to compare between the recorded and the --program run
    /// (repeatable).
    #[arg(long = "diverge", value_name = "DEV[:TYPE]", requires = "program")]
    pub diverge: Vec<String>,
    /// Print every change from outside on stderr as it is replayed: the
    /// scan count of its END, the door it came through and what it did.
    #[arg(long)]
    pub log: bool,
    /// Write the recorded program's whole CPU state after the last replayed
    /// END as a state file (as `run --save-state`): `run --load-state` goes
    /// on from the incident, e.g. with other inputs (docs/snapshots.md).
    #[arg(long, value_name = "FILE")]
    pub save_state: Option<PathBuf>,
}

/// Where a compared device first differed.
struct Split {
    scan: u64,
    recorded: Value,
    new: Value,
}

pub fn replay(args: ReplayArgs) -> ExitCode {
    let fail = |msg: String| {
        eprintln!("softplc: {msg}");
        ExitCode::from(2)
    };
    let mut player = match Player::open(&args.file) {
        Ok(p) => p,
        Err(e) => return fail(e.to_string()),
    };
    let header = player.header().clone();
    let dir = match tempfile::Builder::new().prefix("softplc-replay").tempdir() {
        Ok(d) => d,
        Err(e) => {
            return fail(format!(
                "cannot make a directory for the recorded program: {e}"
            ))
        }
    };
    let program = match unpack(&header, dir.path()) {
        Ok(p) => p,
        Err(e) => return fail(format!("{}: {e}", args.file.display())),
    };
    let calendar = DateTime::from_unix(header.calendar_unix_s);
    let clock = Box::new(player.clock());
    let Ok(Loaded { cpu, .. }) = load(&program, clock, Some(calendar), header.model.as_deref())
    else {
        return fail(format!(
            "{}: the recorded program {} does not load in this softplc",
            args.file.display(),
            header.program
        ));
    };
    let mut cpus = vec![cpu];
    if let Some(p) = &args.program {
        let clock = Box::new(player.clock());
        match load(p, clock, Some(calendar), header.model.as_deref()) {
            Ok(l) => cpus.push(l.cpu),
            Err(code) => return code,
        }
    }
    let names = |list: &[String], cpu: &Cpu| -> Result<Vec<DevName>, String> {
        let n = Names::of(cpu);
        list.iter().map(|s| n.parse(s)).collect()
    };
    let shows = match names(&args.show, &cpus[0]) {
        Ok(s) => s,
        Err(e) => return fail(e),
    };
    // Compared: --diverge, else every --show device.
    let compared = if args.diverge.is_empty() {
        &args.show
    } else {
        &args.diverge
    };
    let pairs = match cpus.get(1) {
        Some(new) => match names(compared, &cpus[0]).and_then(|a| Ok((a, names(compared, new)?))) {
            Ok((a, b)) => a.into_iter().zip(b).collect(),
            Err(e) => return fail(e),
        },
        None => Vec::new(),
    };
    let mut splits: Vec<Option<Split>> = (0..pairs.len()).map(|_| None).collect();
    let result = (|| -> Result<(), String> {
        let mut refs: Vec<&mut Cpu> = cpus.iter_mut().collect();
        player.start(&mut refs)?;
        if args.log {
            log(0, &player.start_events());
        }
        loop {
            let Some(end) = player.step(&mut refs)? else {
                return Ok(());
            };
            if args.log {
                log(end.scans, &end.events);
            }
            for ((a, b), split) in pairs.iter().zip(splits.iter_mut()) {
                if split.is_some() {
                    continue;
                }
                let (va, vb) = (a.read(refs[0])?, b.read(refs[1])?);
                if va != vb {
                    *split = Some(Split {
                        scan: end.scans,
                        recorded: va,
                        new: vb,
                    });
                }
            }
            if end.scanned && args.until.is_some_and(|n| end.scans >= n) {
                return Ok(());
            }
        }
    })();
    if let Err(e) = result {
        return fail(e);
    }
    if let Some(path) = &args.save_state {
        let bytes = softplc_core::snapshot::save(&mut cpus[0]);
        if let Err(e) = crate::state_file::save(path, &bytes) {
            return fail(e);
        }
    }
    if let Some(ending) = player.ending() {
        if !args.json {
            eprintln!(
                "softplc: replayed {} ENDs; {}",
                player.ends(),
                ending.describe()
            );
        }
    }
    report(&args, &header, &player, &cpus[0], &shows, &pairs, &splits)
}

/// `--log`: the changes of an END whose scan count is `scans`.
fn log(scans: u64, events: &[softplc_record::Event]) {
    for e in events {
        eprintln!("scan {scans} {}: {}", e.source.name(), e.change);
    }
}

/// Writes the recorded files under `dir`; the program path to load.
fn unpack(header: &Header, dir: &Path) -> Result<PathBuf, String> {
    for f in &header.files {
        let rel = Path::new(&f.path);
        if rel.components().any(|c| !matches!(c, Component::Normal(_))) {
            return Err(format!(
                "a recorded file has the path `{}`, outside the program",
                f.path
            ));
        }
        let path = dir.join(rel);
        if let Some(p) = path.parent() {
            std::fs::create_dir_all(p).map_err(|e| format!("{}: {e}", p.display()))?;
        }
        std::fs::write(&path, &f.bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if header.project {
        return Ok(dir.to_path_buf());
    }
    match header.files.first() {
        Some(f) => Ok(dir.join(&f.path)),
        None => Err("the recording holds no program file".into()),
    }
}

fn report(
    args: &ReplayArgs,
    header: &Header,
    player: &Player<std::io::BufReader<std::fs::File>>,
    cpu: &Cpu,
    shows: &[DevName],
    pairs: &[(DevName, DevName)],
    splits: &[Option<Split>],
) -> ExitCode {
    let mut devices = Map::new();
    let mut text = Vec::new();
    for d in shows {
        match d.read(cpu) {
            Ok(v) => {
                text.push(format!("{} = {v}", d.text()));
                devices.insert(d.text().to_string(), to_json(&v));
            }
            Err(e) => {
                eprintln!("softplc: {e}");
                return ExitCode::from(2);
            }
        }
    }
    let time_ms = player.clock_elapsed_us() as f64 / 1e3;
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
    let mut diverge = Map::new();
    for ((a, _), s) in pairs.iter().zip(splits) {
        let v = match s {
            Some(s) => {
                json!({"scan": s.scan, "recorded": to_json(&s.recorded), "new": to_json(&s.new)})
            }
            None => Json::Null,
        };
        diverge.insert(a.text().to_string(), v);
    }
    if args.json {
        let mut out = json!({
            "scans": cpu.scans(),
            "time_ms": time_ms,
            "state": cpu.state().as_str(),
            "error": error,
            "devices": devices,
            "recording": {
                "program": header.program,
                "identity": header.identity,
                "model": header.cpu_model,
                "ends": player.ends(),
                "ending": player.ending().map(|e| e.name()),
            },
        });
        if args.program.is_some() {
            out["diverge"] = Json::Object(diverge);
        }
        outln!("{out}");
    } else {
        outln!(
            "scans: {}  time: {time_ms} ms  state: {}",
            cpu.scans(),
            cpu.state().as_str()
        );
        match cpu.error() {
            None => outln!("error: none"),
            Some(e) => outln!("error: {} {}", e.code.0, cpu.error_message(e.code)),
        }
        for line in text {
            outln!("{line}");
        }
        for ((a, _), s) in pairs.iter().zip(splits) {
            match s {
                Some(s) => outln!(
                    "{} differs first at scan {}: recorded {}, new {}",
                    a.text(),
                    s.scan,
                    s.recorded,
                    s.new
                ),
                None => outln!("{} never differs", a.text()),
            }
        }
    }
    ExitCode::SUCCESS
}
