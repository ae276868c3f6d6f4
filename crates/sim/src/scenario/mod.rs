//! Scenario tests: a PLC program run in virtual time against plant models
//! bound to its devices, with a timeline of input changes and assertions on
//! device values (issue 7). The file format is documented in
//! `docs/scenarios.md`; `softplc test` is the command line.
//!
//! ```no_run
//! use softplc_sim::scenario::Scenario;
//!
//! let sc = Scenario::load("examples/sim/heated_tank.toml".as_ref()).unwrap();
//! let outcome = sc.build().unwrap().run(&mut |_scans| {});
//! print!("{}", outcome.report(false));
//! assert_eq!(outcome.failed(), 0);
//! ```
//!
//! # The scan loop
//!
//! Scan `n` (1-based) runs at virtual time `n · scan_time`. Before it, in this
//! order:
//!
//! 1. every model, in file order, reads its inputs from the devices (as the
//!    last scan left them; a model sees what an earlier model wrote in this
//!    step), advances by one scan time and writes its outputs: X bits through
//!    the input image (as an input module), other devices directly;
//! 2. the timeline writes due at this scan (so a timeline write to a device a
//!    model also drives wins for that scan);
//! 3. the clock advances by the scan time and the CPU scans;
//! 4. the communication phase of the APLC ports (`[[peer]]` devices on
//!    virtual lines, registers that follow a model written after step 1).
//!
//! A model that reports a fault in step 1 (an FMU call failed) ends the run
//! there, before the scan, with one more failed result naming it.
//!
//! A multi-CPU system (a directory with `system.toml`, contract §6) runs in
//! the same loop with the scan time as its step: in step 3 every CPU whose
//! scan ends by the step's end scans (each at its constant scan, else once
//! per step; equal times in CPU-number order, each followed by its END's
//! exchange). Names take `CPUn/` prefixes, resolved against their CPU at
//! build time; each binding keeps its CPU's index.
//!
//! A fleet (`[[plc]]` tables) runs its PLCs in the same loop: in step 3
//! every PLC whose scan ends by the step's end scans, earliest END first
//! and `[[plc]]` order on ties (`plcs.rs`), each scan followed by its APLC
//! ports (`[[link]]`s to other PLCs' ports among them) and the
//! `[[client]]`s polling it. Names take `NAME/` prefixes (`Layout`); the
//! CPUs of all PLCs are numbered flat, the first PLC's first.
//!
//! After the scan every watched device is sampled once: the expectations are
//! evaluated online (O(1) per expectation per scan) and the trace takes its
//! sample when due. Nothing in the loop parses, and apart from the ports'
//! frames and a client's poll nothing allocates: devices are resolved at
//! build time, the failure history is a fixed ring buffer and the trace is
//! pre-sized.

mod bind;
mod check;
mod client;
pub mod fmt;
mod plcs;
mod ports;
mod run;
mod spec;
mod trace;

pub use check::{Failure, HISTORY_AFTER, HISTORY_BEFORE};
pub use run::{CheckResult, Outcome, Run, PROGRESS_EVERY};
pub use spec::{
    Band, BlockSpec, ClientProtocol, ClientSpec, Cond, EventSpec, ExpectKind, ExpectSpec,
    InputBinding, Layout, LinkSpec, ModelSpec, OutputBinding, PeerKind, PeerSpec, PlcSpec,
    PlotSpec, PortRef, Remote, Scale, Scenario, ScriptStep, Setpoint, Source, TraceSpec,
    DEFAULT_MAX_SAMPLES,
};
pub use trace::TraceData;

use self::fmt::{fmt_secs, fmt_time, fmt_value};

impl Outcome {
    /// The header line: file, name, scans, simulated and wall time.
    pub fn header(&self) -> String {
        format!(
            "{} — {}: {} scans, {} simulated in {:.2} s ({:.0}× real time)",
            self.file.display(),
            self.name,
            self.scans,
            fmt_time(self.simulated_us()),
            self.wall.as_secs_f64(),
            self.speed()
        )
    }

    /// The report: the header, one `PASS`/`FAIL` line per assertion, and for
    /// each failure the first failing scan with the history of its devices.
    /// With `failures_only`, passing lines are left out.
    pub fn report(&self, failures_only: bool) -> String {
        let mut s = self.header();
        s.push('\n');
        for r in &self.results {
            if r.passed && failures_only {
                continue;
            }
            s += &format!(
                "  {} {}: {}\n",
                if r.passed { "PASS" } else { "FAIL" },
                r.text,
                r.detail
            );
            if let Some(f) = &r.failure {
                s += &render_history(f);
            }
        }
        s
    }
}

/// The history table of a failure.
fn render_history(f: &Failure) -> String {
    let mut s = format!(
        "       first failing scan {} (t = {} s):\n",
        f.scan,
        fmt_secs(f.time_us)
    );
    let scan_us = f.time_us.checked_div(f.scan).unwrap_or(0);
    let mut table: Vec<Vec<String>> = vec![std::iter::once("scan".to_string())
        .chain(std::iter::once("t/s".to_string()))
        .chain(f.columns.iter().map(|(n, _)| n.clone()))
        .collect()];
    for (scan, vals) in &f.rows {
        let mut row = vec![
            format!("{}{}", if *scan == f.scan { "> " } else { "" }, scan),
            fmt_secs(scan * scan_us),
        ];
        row.extend(
            vals.iter()
                .zip(&f.columns)
                .map(|(v, (_, k))| fmt_value(*v, *k)),
        );
        table.push(row);
    }
    let cols = table[0].len();
    let widths: Vec<usize> = (0..cols)
        .map(|c| {
            table
                .iter()
                .map(|r| r[c].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    for row in &table {
        s += "        ";
        for (c, cell) in row.iter().enumerate() {
            let pad = widths[c] - cell.chars().count();
            s += &" ".repeat(pad + 2);
            s += cell;
        }
        s.push('\n');
    }
    s
}
