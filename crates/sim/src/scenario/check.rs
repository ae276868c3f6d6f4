//! Expectations evaluated online, one sample per scan, O(1) per scan each.

use super::fmt::{fmt_num, fmt_time, fmt_value, Kind};
use super::spec::{Band, Cond, ExpectKind};

/// Samples shown before (and including) the first failing scan.
pub const HISTORY_BEFORE: usize = 5;
/// Samples shown after it.
pub const HISTORY_AFTER: u32 = 3;

impl Cond {
    #[inline]
    pub fn holds(&self, v: f64) -> bool {
        match *self {
            Cond::Eq { value, tol } => (v - value).abs() <= tol,
            Cond::Gt(x) => v > x,
            Cond::Lt(x) => v < x,
            Cond::Ge(x) => v >= x,
            Cond::Le(x) => v <= x,
        }
    }
}

/// The last few samples of every watched device: a fixed ring buffer.
#[derive(Debug)]
pub struct Ring {
    width: usize,
    cap: usize,
    scans: Vec<u64>,
    values: Vec<f64>,
    next: usize,
    len: usize,
}

impl Ring {
    pub fn new(width: usize, cap: usize) -> Ring {
        Ring {
            width,
            cap,
            scans: vec![0; cap],
            values: vec![0.0; cap * width],
            next: 0,
            len: 0,
        }
    }

    #[inline]
    pub fn push(&mut self, scan: u64, values: &[f64]) {
        self.scans[self.next] = scan;
        self.values[self.next * self.width..(self.next + 1) * self.width].copy_from_slice(values);
        // No division on the per-scan path.
        self.next += 1;
        if self.next == self.cap {
            self.next = 0;
        }
        if self.len < self.cap {
            self.len += 1;
        }
    }

    /// The last `n` samples, oldest first.
    pub fn last(&self, n: usize) -> impl Iterator<Item = (u64, &[f64])> {
        let n = n.min(self.len);
        (0..n).map(move |i| {
            let slot = (self.next + self.cap - n + i) % self.cap;
            (
                self.scans[slot],
                &self.values[slot * self.width..(slot + 1) * self.width],
            )
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Pending,
    Pass,
    Fail,
}

/// The device history around a failure.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The first failing scan and its time (µs).
    pub scan: u64,
    pub time_us: u64,
    /// Column names and kinds.
    pub columns: Vec<(String, Kind)>,
    /// (scan, value per column), a few before and after `scan`.
    pub rows: Vec<(u64, Vec<f64>)>,
}

/// Settle/overshoot state.
#[derive(Debug, Default)]
struct Loop {
    started: bool,
    step: f64,
    dir: f64,
    half: f64,
    last_out: Option<u64>,
    peak: f64,
    peak_scan: u64,
}

#[derive(Debug)]
pub struct Check {
    pub text: String,
    /// Index of the checked device among the watched probes.
    pub probe: usize,
    /// The setpoint device of a settle check.
    pub sv_probe: Option<usize>,
    pub sv_value: f64,
    /// Watched probes shown in the history.
    pub columns: Vec<usize>,
    pub kind: ExpectKind,
    pub dev_kind: Kind,
    pub verdict: Verdict,
    pub detail: String,
    pub failure: Option<Failure>,
    after_left: u32,
    /// The first scan that needs this check: the start of its window,
    /// every scan while it runs or collects history, never once decided.
    wake: u64,
    min: f64,
    max: f64,
    lp: Loop,
}

impl Check {
    pub fn new(
        text: String,
        probe: usize,
        sv_probe: Option<usize>,
        sv_value: f64,
        columns: Vec<usize>,
        kind: ExpectKind,
        dev_kind: Kind,
    ) -> Check {
        let wake = match kind {
            ExpectKind::At { scan, .. } => scan,
            ExpectKind::Within { first, .. }
            | ExpectKind::Always { first, .. }
            | ExpectKind::Never { first, .. }
            | ExpectKind::Settle { first, .. } => first,
        };
        Check {
            text,
            probe,
            sv_probe,
            sv_value,
            columns,
            kind,
            dev_kind,
            verdict: Verdict::Pending,
            detail: String::new(),
            failure: None,
            after_left: 0,
            wake,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            lp: Loop::default(),
        }
    }

    fn v(&self, v: f64) -> String {
        fmt_value(v, self.dev_kind)
    }

    fn pass(&mut self, detail: String) {
        self.wake = u64::MAX;
        self.verdict = Verdict::Pass;
        self.detail = detail;
    }

    fn fail(
        &mut self,
        scan: u64,
        scan_us: u64,
        detail: String,
        ring: &Ring,
        names: &[(String, Kind)],
    ) {
        self.verdict = Verdict::Fail;
        self.detail = detail;
        let rows = ring
            .last(HISTORY_BEFORE)
            .map(|(s, vals)| (s, self.columns.iter().map(|&c| vals[c]).collect()))
            .collect();
        self.failure = Some(Failure {
            scan,
            time_us: scan * scan_us,
            columns: self.columns.iter().map(|&c| names[c].clone()).collect(),
            rows,
        });
        self.after_left = HISTORY_AFTER;
    }

    /// Evaluates the sample of scan `n` (`values`: every watched probe, also
    /// already pushed into `ring`). Scans before its window and after its
    /// verdict (and history) cost one comparison.
    #[inline]
    pub fn update(
        &mut self,
        n: u64,
        scan_us: u64,
        values: &[f64],
        ring: &Ring,
        names: &[(String, Kind)],
    ) {
        if n >= self.wake {
            self.evaluate(n, scan_us, values, ring, names);
        }
    }

    fn evaluate(
        &mut self,
        n: u64,
        scan_us: u64,
        values: &[f64],
        ring: &Ring,
        names: &[(String, Kind)],
    ) {
        if self.verdict != Verdict::Pending {
            if self.after_left > 0 {
                self.after_left -= 1;
                let row = (n, self.columns.iter().map(|&c| values[c]).collect());
                if let Some(f) = &mut self.failure {
                    f.rows.push(row);
                }
            }
            if self.after_left == 0 {
                self.wake = u64::MAX;
            }
            return;
        }
        let v = values[self.probe];
        let t = |s: u64| fmt_time(s * scan_us);
        match self.kind {
            ExpectKind::At { scan, cond } => {
                if n == scan {
                    if cond.holds(v) {
                        self.pass(format!("got {}", self.v(v)));
                    } else {
                        let d = format!("got {} at {} (scan {n})", self.v(v), t(n));
                        self.fail(n, scan_us, d, ring, names);
                    }
                }
            }
            ExpectKind::Within { first, last, cond } => {
                if n >= first && n <= last {
                    if cond.holds(v) {
                        self.pass(format!("at {} (scan {n})", t(n)));
                    } else if n == last {
                        let d = format!("still {} at {} (scan {n})", self.v(v), t(n));
                        self.fail(n, scan_us, d, ring, names);
                    }
                }
            }
            ExpectKind::Always { first, last, cond } | ExpectKind::Never { first, last, cond } => {
                if n >= first && n <= last {
                    self.min = self.min.min(v);
                    self.max = self.max.max(v);
                    let always = matches!(self.kind, ExpectKind::Always { .. });
                    if cond.holds(v) != always || v.is_nan() {
                        let d = format!("{} at {} (scan {n})", self.v(v), t(n));
                        self.fail(n, scan_us, d, ring, names);
                    } else if n == last {
                        let d = if self.dev_kind == Kind::Bit {
                            format!("{} scans checked", last - first + 1)
                        } else {
                            format!("min {}, max {}", self.v(self.min), self.v(self.max))
                        };
                        self.pass(d);
                    }
                }
            }
            ExpectKind::Settle {
                first,
                last,
                band,
                deadline,
                max_overshoot,
                ..
            } => {
                if n < first || n > last {
                    return;
                }
                let sv = match self.sv_probe {
                    Some(p) => values[p],
                    None => self.sv_value,
                };
                if !self.lp.started {
                    self.lp.started = true;
                    self.lp.step = sv - v;
                    self.lp.dir = if self.lp.step < 0.0 { -1.0 } else { 1.0 };
                    self.lp.half = match band {
                        Band::Abs(b) => b,
                        Band::Percent(p) if self.lp.step != 0.0 => p / 100.0 * self.lp.step.abs(),
                        Band::Percent(p) => p / 100.0 * sv.abs(),
                    };
                }
                let err = v - sv;
                // NaN counts as outside.
                let out = err.abs() > self.lp.half || err.is_nan();
                if out {
                    self.lp.last_out = Some(n);
                }
                let os = self.lp.dir * err;
                if os > self.lp.peak {
                    self.lp.peak = os;
                    self.lp.peak_scan = n;
                }
                let os_pct = self.overshoot_pct();
                if let (Some(max), Some(p)) = (max_overshoot, os_pct) {
                    if p > max {
                        let d = format!(
                            "overshoot {:.1} % > {} % at {} (scan {n}): {} vs setpoint {}",
                            p,
                            fmt_num(max),
                            t(n),
                            self.v(v),
                            fmt_num(sv)
                        );
                        self.fail(n, scan_us, d, ring, names);
                        return;
                    }
                }
                if let Some(dl) = deadline {
                    if out && n >= dl {
                        let when = if n > dl {
                            format!("at {} (scan {n}), {} after the deadline", t(n), t(n - dl))
                        } else {
                            format!("at the deadline, {} (scan {n})", t(n))
                        };
                        let d = format!(
                            "{} is outside the band {}…{} {when}",
                            self.v(v),
                            fmt_num(sv - self.lp.half),
                            fmt_num(sv + self.lp.half),
                        );
                        self.fail(n, scan_us, d, ring, names);
                        return;
                    }
                }
                if n == last {
                    let settle = match self.lp.last_out {
                        None => "inside the band throughout".to_string(),
                        Some(s) if s == last => "not settled at the end".to_string(),
                        Some(s) => format!("settled after {}", t(s + 1 - first)),
                    };
                    let os = match os_pct {
                        Some(p) => format!("overshoot {:.1} %", p),
                        None => "no step".to_string(),
                    };
                    self.pass(format!("{settle}, {os}"));
                }
            }
        }
    }

    fn overshoot_pct(&self) -> Option<f64> {
        (self.lp.step != 0.0).then(|| self.lp.peak / self.lp.step.abs() * 100.0)
    }

    /// The run ended (at scan `n`) with this check still pending.
    pub fn unfinished(&mut self, n: u64, scan_us: u64, why: &str) {
        if self.verdict == Verdict::Pending {
            self.verdict = Verdict::Fail;
            self.detail = format!("not decided: {why} at {} (scan {n})", fmt_time(n * scan_us));
        }
    }
}
