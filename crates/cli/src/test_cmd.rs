//! `softplc test`: scenario tests (issue 7). Runs scenario files in parallel,
//! prints a PASS/FAIL line per assertion (with the history around the first
//! failing scan) and ends with `N passed, M failed`. `--shard I/N` runs one
//! of N parts of the files, `--jsonl` prints one JSON line per file and
//! `--merge` sums such lines (issue 16).

mod jsonl;
mod junit;
mod shard;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use clap::Args;
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use softplc_sim::plot;
use softplc_sim::scenario::{Outcome, PlotSpec, Scenario};

use crate::run::parse_duration;
use crate::stdout::{out, outln};

#[derive(Args, Debug)]
pub struct TestArgs {
    /// Scenario files (TOML), see docs/scenarios.md.
    #[arg(required_unless_present = "merge", value_name = "SCENARIO")]
    pub scenarios: Vec<PathBuf>,
    /// Run only shard I of N (I from 0 to N-1, e.g. Kubernetes'
    /// JOB_COMPLETION_INDEX): the files ranked by path are dealt out
    /// round-robin, so N runs given the same files split them exactly.
    #[arg(long, value_name = "I/N", value_parser = shard::parse_shard)]
    pub shard: Option<shard::Shard>,
    /// Print one JSON line per scenario file (file, name, passed, assertion
    /// counts and results, wall and simulated seconds) instead of the report;
    /// the `N passed, M failed` summary goes to stderr.
    #[arg(long)]
    pub jsonl: bool,
    /// Sum up --jsonl files (e.g. of the shards): one line per scenario file
    /// sorted by file, the failed assertions, and `N passed, M failed`; with
    /// --jsonl the merged lines instead. Exits non-zero when any failed.
    #[arg(long, num_args = 1.., value_name = "FILE.jsonl", conflicts_with_all = ["scenarios", "shard"])]
    pub merge: Vec<PathBuf>,
    /// Also write the results as JUnit XML to this file (one testsuite per
    /// scenario file, one testcase per assertion), for CI systems; with
    /// --merge, the merged results.
    #[arg(long, value_name = "FILE.xml")]
    pub junit: Option<PathBuf>,
    /// Record these devices (comma-separated, e.g. D610,D611,D612 or
    /// D10:f32,Y0; CPU2/D0 of a multi-CPU system; line1/D0 of the PLC
    /// named line1 in a fleet) to CSV, instead of the scenario's [trace]
    /// devices.
    #[arg(long, value_name = "DEV,...", value_delimiter = ',')]
    pub trace: Vec<String>,
    /// CSV file for the trace (default: the scenario's [trace] file, else
    /// SCENARIO-STEM.trace.csv in the current directory). With several
    /// scenarios, each file name gets -STEM before its extension (-DIR-STEM
    /// when two scenarios have the same name); the files written are listed
    /// after the reports.
    #[arg(long, value_name = "FILE")]
    pub trace_file: Option<PathBuf>,
    /// Trace sample period, e.g. 1s (default: every scan, or fewer for long
    /// runs so that at most 10000 samples are kept).
    #[arg(long, value_name = "DUR", value_parser = parse_duration)]
    pub trace_interval: Option<Duration>,
    /// Draw the traced devices over time to this SVG file (the --trace
    /// devices, else the scenario's [plot]/[trace] devices, else the devices
    /// the assertions check). With several scenarios, each file name gets
    /// -STEM before its extension (-DIR-STEM when two scenarios have the same
    /// name): `--plot out.svg` writes out-conveyor.svg, out-sfc.svg …, listed
    /// after the reports.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Scenarios run at the same time (default: the number of CPUs).
    #[arg(long, short = 'j', value_name = "N")]
    pub jobs: Option<usize>,
    /// Print only failing assertions (and the summary).
    #[arg(long, short = 'q')]
    pub quiet: bool,
    /// No progress bar (it is shown only when stdout is a terminal anyway).
    #[arg(long)]
    pub no_progress: bool,
    /// Execution tier: auto, jit or interp (as `run --exec`).
    #[arg(long, value_name = "TIER", value_parser = softplc_core::tier::Exec::parse)]
    pub exec: Option<softplc_core::tier::Exec>,
}

/// What tells a scenario's files apart when several run: its file stem, or
/// `PARENT-STEM` when an earlier scenario given has the same stem
/// (`sim/conveyor.toml` then `aplc/conveyor.toml`: `conveyor`,
/// `aplc-conveyor`); `None` for a single one.
fn scenario_tag(scenario: &Path, all: &[PathBuf]) -> Option<String> {
    if all.len() <= 1 {
        return None;
    }
    let stem = |p: &Path| {
        p.file_stem()
            .map_or_else(|| "scenario".into(), |s| s.to_string_lossy().into_owned())
    };
    let own = stem(scenario);
    let shared = all
        .iter()
        .find(|p| stem(p) == own)
        .is_some_and(|first| first != scenario);
    let parent = scenario
        .parent()
        .and_then(|p| p.file_name())
        .map(|p| p.to_string_lossy().into_owned());
    Some(match parent {
        Some(dir) if shared => format!("{dir}-{own}"),
        _ => own,
    })
}

/// `dir/name.ext` → `dir/name-TAG.ext` when several scenarios share a file.
fn per_scenario(path: &Path, tag: Option<&str>) -> PathBuf {
    let Some(tag) = tag else {
        return path.to_path_buf();
    };
    let name = match (path.file_stem(), path.extension()) {
        (Some(s), Some(e)) => format!("{}-{tag}.{}", s.to_string_lossy(), e.to_string_lossy()),
        (Some(s), None) => format!("{}-{tag}", s.to_string_lossy()),
        _ => tag.to_string(),
    };
    path.with_file_name(name)
}

/// The result of one scenario file: its report text, counts and JSON line.
struct Done {
    text: String,
    passed: usize,
    failed: usize,
    line: jsonl::Line,
    /// Trace and plot files written.
    written: Vec<PathBuf>,
}

/// Applies the command-line trace and plot options to a scenario.
fn configure(sc: &mut Scenario, args: &TestArgs, tag: Option<&str>) {
    if !args.trace.is_empty() {
        sc.trace.devices = args.trace.iter().map(|d| d.trim().to_string()).collect();
        if sc.trace.file.is_none() && args.trace_file.is_none() {
            let stem = sc
                .file
                .file_stem()
                .map_or_else(|| "scenario".into(), |s| s.to_string_lossy().into_owned());
            let name = tag.unwrap_or(&stem);
            sc.trace.file = Some(PathBuf::from(format!("{name}.trace.csv")));
        }
    }
    if let Some(f) = &args.trace_file {
        sc.trace.file = Some(per_scenario(f, tag));
    }
    if let Some(i) = args.trace_interval {
        sc.trace.interval_us = Some(i.as_micros() as u64);
    }
    if let Some(p) = &args.plot {
        let file = per_scenario(p, tag);
        let devices = if !args.trace.is_empty() {
            sc.trace.devices.clone()
        } else {
            sc.plot
                .as_ref()
                .map(|p| p.devices.clone())
                .unwrap_or_default()
        };
        let title = sc.plot.as_ref().and_then(|p| p.title.clone());
        sc.plot = Some(PlotSpec {
            file,
            devices,
            title,
        });
    }
}

/// Writes the trace CSV and the plot; returns lines for the report and
/// adds the files written to `written`.
fn artifacts(
    sc: &Scenario,
    outcome: &Outcome,
    written: &mut Vec<PathBuf>,
) -> Result<String, String> {
    let mut notes = String::new();
    let Some(trace) = &outcome.trace else {
        return Ok(notes);
    };
    if let Some(f) = &sc.trace.file {
        std::fs::write(f, trace.to_csv())
            .map_err(|e| format!("cannot write {}: {e}", f.display()))?;
        notes += &format!("  trace: {} ({} samples)\n", f.display(), trace.len());
        written.push(f.clone());
    }
    if let Some(p) = &sc.plot {
        let devices = if !p.devices.is_empty() {
            p.devices.clone()
        } else if !sc.trace.devices.is_empty() {
            sc.trace.devices.clone()
        } else {
            sc.expect_devices()
        };
        let title = p.title.clone().unwrap_or_else(|| sc.name.clone());
        plot::write_svg(&p.file, trace, &devices, &title)?;
        notes += &format!("  plot: {}\n", p.file.display());
        written.push(p.file.clone());
    }
    Ok(notes)
}

fn style() -> ProgressStyle {
    ProgressStyle::with_template("{prefix:24!} [{bar:30}] {percent:>3}% {msg}")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ")
}

/// Loads, runs and reports one scenario file.
fn run_one(path: &Path, args: &TestArgs, tag: Option<&str>, mp: &MultiProgress) -> Done {
    let began = Instant::now();
    let fail = |msg: String| Done {
        text: format!("{}\n  FAIL {msg}\n", path.display()),
        passed: 0,
        failed: 1,
        line: jsonl::Line::of_error(path, &msg, began.elapsed().as_secs_f64()),
        written: Vec::new(),
    };
    let mut sc = match Scenario::load(path) {
        Ok(s) => s,
        Err(e) => return fail(e),
    };
    configure(&mut sc, args, tag);
    let run = match sc.build_on(args.exec) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    let total = run.total_scans();
    let bar = mp.add(ProgressBar::new(total));
    bar.set_style(style());
    bar.set_prefix(
        path.file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
    );
    let sim_s = sc.scan_us as f64 / 1e6;
    let start = Instant::now();
    let outcome = run.run(&mut |n| {
        bar.set_position(n);
        let wall = start.elapsed().as_secs_f64().max(1e-9);
        bar.set_message(format!(
            "{:.0} s simulated, {:.0}× real time",
            n as f64 * sim_s,
            n as f64 * sim_s / wall
        ));
    });
    bar.finish_and_clear();
    mp.remove(&bar);
    let mut text = outcome.report(args.quiet);
    let mut failed = outcome.failed();
    let mut extra = Vec::new();
    let mut written = Vec::new();
    match artifacts(&sc, &outcome, &mut written) {
        Ok(notes) => text += &notes,
        Err(e) => {
            text += &format!("  FAIL {e}\n");
            failed += 1;
            extra.push(e);
        }
    }
    let line = jsonl::Line::of_outcome(path, &outcome, &extra, began.elapsed().as_secs_f64());
    Done {
        text,
        passed: outcome.passed(),
        failed,
        line,
        written,
    }
}

/// `--merge`: sums up JSON-lines files.
fn merge(args: &TestArgs) -> ExitCode {
    let lines = match jsonl::merge(&args.merge) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let (text, total) = jsonl::summary(&lines);
    if let Some(f) = &args.junit {
        if let Err(e) = junit::write(f, &lines) {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
    if args.jsonl {
        for l in &lines {
            outln!("{}", l.to_json());
        }
        eprint!(
            "{}",
            text.lines()
                .last()
                .map_or(String::new(), |l| format!("{l}\n"))
        );
    } else {
        out!("{text}");
    }
    if total.failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

pub fn run(args: TestArgs) -> ExitCode {
    if !args.merge.is_empty() {
        return merge(&args);
    }
    let shard_files;
    let files = match args.shard {
        Some(s) => {
            shard_files = s.select(&args.scenarios);
            &shard_files
        }
        None => &args.scenarios,
    };
    // Per-file trace names are the same whichever shard a file lands in.
    let tags: Vec<Option<String>> = files
        .iter()
        .map(|f| scenario_tag(f, &args.scenarios))
        .collect();
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, files.len().max(1));
    let mp = MultiProgress::new();
    if args.no_progress || !std::io::stdout().is_terminal() {
        mp.set_draw_target(ProgressDrawTarget::hidden());
    }
    // Reports are printed in file order as soon as they and all earlier ones
    // are done.
    let slots: Mutex<(usize, Vec<Option<Done>>)> =
        Mutex::new((0, (0..files.len()).map(|_| None).collect()));
    let totals = Mutex::new((0usize, 0usize));
    let written: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
    let lines: Mutex<Vec<jsonl::Line>> = Mutex::new(Vec::new());
    let next = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= files.len() {
                    break;
                }
                let done = run_one(&files[i], &args, tags[i].as_deref(), &mp);
                let mut g = slots.lock().unwrap_or_else(|e| e.into_inner());
                g.1[i] = Some(done);
                while g.0 < files.len() {
                    let k = g.0;
                    let Some(d) = g.1[k].take() else { break };
                    if args.jsonl {
                        mp.suspend(|| outln!("{}", d.line.to_json()));
                    } else {
                        mp.suspend(|| out!("{}", d.text));
                    }
                    if args.junit.is_some() {
                        lines.lock().unwrap_or_else(|e| e.into_inner()).push(d.line);
                    }
                    let mut t = totals.lock().unwrap_or_else(|e| e.into_inner());
                    t.0 += d.passed;
                    t.1 += d.failed;
                    written
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .extend(d.written);
                    g.0 += 1;
                }
            });
        }
    });
    let (passed, failed) = *totals.lock().unwrap_or_else(|e| e.into_inner());
    let written = written.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut junit_failed = false;
    if let Some(f) = &args.junit {
        let lines = lines.into_inner().unwrap_or_else(|e| e.into_inner());
        if let Err(e) = junit::write(f, &lines) {
            eprintln!("error: {e}");
            junit_failed = true;
        }
    }
    if files.len() > 1 && !written.is_empty() {
        // One file per scenario: say which, in one place.
        let list: String = written
            .iter()
            .map(|f| format!("  {}\n", f.display()))
            .collect();
        let text = format!("files written ({}):\n{list}", written.len());
        if args.jsonl {
            eprint!("{text}");
        } else {
            out!("{text}");
        }
    }
    if args.jsonl {
        eprintln!("{passed} passed, {failed} failed");
    } else {
        outln!("{passed} passed, {failed} failed");
    }
    if junit_failed {
        ExitCode::from(2)
    } else if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
