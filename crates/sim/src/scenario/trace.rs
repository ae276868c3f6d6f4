//! Per-scan trend recording for CSV and plots (pre-allocated; decimated by a
//! fixed sample period).

use std::fmt::Write as _;

use super::bind::Probe;
use super::fmt::{fmt_secs, fmt_value, Kind};
use super::plcs::Plcs;

/// Recorded samples of some devices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TraceData {
    /// Device names and kinds (columns).
    pub devices: Vec<(String, Kind)>,
    /// Scan number of each sample.
    pub scans: Vec<u64>,
    /// Virtual time of each sample, µs.
    pub times_us: Vec<u64>,
    /// Sample-major values: `values[i * devices.len() + j]`.
    pub values: Vec<f64>,
}

impl TraceData {
    pub fn len(&self) -> usize {
        self.scans.len()
    }

    pub fn is_empty(&self) -> bool {
        self.scans.is_empty()
    }

    /// Index of a device column.
    pub fn column_of(&self, name: &str) -> Option<usize> {
        self.devices
            .iter()
            .position(|(d, _)| d.eq_ignore_ascii_case(name))
    }

    /// (time in s, value) of column `j`.
    pub fn series(&self, j: usize) -> impl Iterator<Item = (f64, f64)> + '_ {
        let w = self.devices.len();
        self.times_us
            .iter()
            .enumerate()
            .map(move |(i, t)| (*t as f64 / 1e6, self.values[i * w + j]))
    }

    /// CSV: `scan,time_s,DEV,...`, bits as 0/1.
    pub fn to_csv(&self) -> String {
        let w = self.devices.len();
        let mut s = String::with_capacity(32 + self.len() * (12 + 8 * w));
        s.push_str("scan,time_s");
        for (d, _) in &self.devices {
            s.push(',');
            s.push_str(d);
        }
        s.push('\n');
        for i in 0..self.len() {
            let _ = write!(s, "{},{}", self.scans[i], fmt_secs(self.times_us[i]));
            for (j, (_, k)) in self.devices.iter().enumerate() {
                let v = self.values[i * w + j];
                s.push(',');
                match k {
                    Kind::Bit => s.push(if v > 0.5 { '1' } else { '0' }),
                    _ => s.push_str(&fmt_value(v, *k)),
                }
            }
            s.push('\n');
        }
        s
    }
}

/// Takes a sample at scan 1, every `every` scans, and at the last scan.
#[derive(Debug)]
pub struct Recorder {
    probes: Vec<Probe>,
    every: u64,
    /// The next multiple of `every` (no division per scan).
    due: u64,
    last: u64,
    pub data: TraceData,
}

impl Recorder {
    pub fn new(probes: Vec<Probe>, every: u64, total: u64) -> Recorder {
        let every = every.max(1);
        let samples = (total / every + 2) as usize;
        let w = probes.len();
        Recorder {
            data: TraceData {
                devices: probes
                    .iter()
                    .map(|p| (p.name().to_string(), p.kind()))
                    .collect(),
                scans: Vec::with_capacity(samples),
                times_us: Vec::with_capacity(samples),
                values: Vec::with_capacity(samples * w),
            },
            probes,
            every,
            due: every,
            last: total,
        }
    }

    #[inline]
    pub(super) fn sample(&mut self, n: u64, time_us: u64, cpus: &Plcs) {
        if n == self.due {
            self.due += self.every;
            self.take(n, time_us, cpus);
        } else if n == 1 || n == self.last {
            self.take(n, time_us, cpus);
        }
    }

    /// Takes a sample now (e.g. the scan where the CPU stopped).
    pub(super) fn take(&mut self, n: u64, time_us: u64, cpus: &Plcs) {
        if self.data.scans.last() == Some(&n) {
            return;
        }
        self.data.scans.push(n);
        self.data.times_us.push(time_us);
        for p in &self.probes {
            self.data.values.push(p.read(cpus));
        }
    }
}
