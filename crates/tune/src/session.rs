//! A scenario run driven scan by scan through a loop tag, with the trend of
//! PV, SV and MV recorded for the plot.

use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::Cpu;
use softplc_sim::scenario::fmt::Kind;
use softplc_sim::scenario::{Run, Scenario, TraceData};

use crate::loop_tag::{offset, LoopTag};

/// Trend samples kept before the trend is thinned to every other sample.
const MAX_TREND: usize = 100_000;

/// Keeps the 1st, 3rd, 5th … element.
fn every_other<T>(v: &mut Vec<T>) {
    let mut i = 0;
    v.retain(|_| {
        i += 1;
        i % 2 == 1
    });
}

/// One scan's values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Virtual time after the scan, s.
    pub t: f64,
    pub pv: f64,
    pub sv: f64,
    pub mv: f64,
}

/// The running scenario.
pub struct Session {
    pub run: Run,
    pub tag: LoopTag,
    /// The loop's CPU (0-based; a multi-CPU system's by the `CPUn/` prefix
    /// of the loop's head).
    cpu: usize,
    /// Where PV is read (the loop tag's +10 unless `--pv` names a device),
    /// and its CPU.
    pv: Option<(usize, DeviceSpec)>,
    /// The `--pv` device holds PV in % of RH − RL (e.g. S.IN's BW).
    pv_percent: bool,
    /// Virtual time per scan, s.
    pub scan_s: f64,
    /// The scans of the scenario's timeline (played before tuning starts).
    pub timeline_scans: u64,
    trend: Trend,
    labels: [String; 3],
}

#[derive(Default)]
struct Trend {
    every: u64,
    count: u64,
    scans: Vec<u64>,
    samples: Vec<Sample>,
}

impl Session {
    /// Builds the scenario's run and resolves the loop tag (and PV device).
    /// In a multi-CPU system both names take `CPUn/` prefixes.
    pub fn start(
        sc: &Scenario,
        loop_head: &str,
        pv_device: Option<&str>,
        pv_percent: bool,
    ) -> Result<Session, String> {
        let run = sc.build()?;
        let (cpu, head) = run
            .split_name(loop_head)
            .map_err(|e| format!("--loop: {e}"))?;
        let given = loop_head.trim();
        let tag = LoopTag::on_cpu(&given[..given.len() - head.len()], head, run.cpu_at(cpu))?;
        let mut pv_name = tag.name_at(offset::PV);
        let pv = match pv_device {
            Some(d) => {
                let (pv_cpu, name) = run.split_name(d).map_err(|e| format!("--pv: {e}"))?;
                let spec = DeviceSpec::parse(name.trim()).map_err(|e| format!("--pv: {e}"))?;
                run.cpu_at(pv_cpu)
                    .read_device(&spec)
                    .map_err(|e| format!("--pv: {e}"))?;
                if matches!(spec.ty, softplc_core::access::ValueType::Str) {
                    return Err(format!("--pv {d}: a string cannot be a PV"));
                }
                let given = d.trim();
                pv_name = format!("{}{}", &given[..given.len() - name.len()], spec.text);
                Some((pv_cpu, spec))
            }
            None => None,
        };
        let labels = [
            format!("PV {pv_name}"),
            format!("SV {}", tag.name_at(offset::SV)),
            format!("MV {} [%]", tag.name_at(offset::MV)),
        ];
        Ok(Session {
            scan_s: run.scan_us() as f64 / 1e6,
            timeline_scans: sc.timeline.last().map_or(0, |e| e.scan),
            run,
            tag,
            cpu,
            pv,
            pv_percent,
            trend: Trend {
                every: 1,
                ..Trend::default()
            },
            labels,
        })
    }

    /// Virtual time after the last scan, s.
    pub fn now(&self) -> f64 {
        self.run.steps_done() as f64 * self.scan_s
    }

    /// The loop's CPU.
    pub fn cpu(&self) -> &Cpu {
        self.run.cpu_at(self.cpu)
    }

    /// PV now.
    pub fn pv(&self) -> Result<f64, String> {
        match &self.pv {
            None => self.tag.read(self.cpu(), offset::PV),
            Some((cpu, d)) => {
                let v = match self.run.cpu_at(*cpu).read_device(d)? {
                    Value::Float(x) => x,
                    Value::Int(i) => i as f64,
                    Value::Bool(b) => f64::from(u8::from(b)),
                    Value::Str(_) => return Err(format!("{}: a string", d.text)),
                };
                if !self.pv_percent {
                    return Ok(v);
                }
                let (rl, rh) = (self.read(offset::RL)?, self.read(offset::RH)?);
                Ok(rl + v * (rh - rl) / 100.0)
            }
        }
    }

    /// Reads a float of the loop tag.
    pub fn read(&self, off: u32) -> Result<f64, String> {
        self.tag.read(self.cpu(), off)
    }

    /// Writes a float of the loop tag (before the next scan).
    pub fn write(&mut self, off: u32, v: f64) -> Result<(), String> {
        self.tag.write(self.run.cpu_at_mut(self.cpu), off, v)
    }

    /// Sets the loop's operation mode (before the next scan).
    pub fn set_mode(&mut self, mode: u16) -> Result<(), String> {
        self.tag.set_mode(self.run.cpu_at_mut(self.cpu), mode)
    }

    /// One scan; returns its sample (and records it in the trend).
    pub fn scan(&mut self) -> Result<Sample, String> {
        self.run.step()?;
        let s = Sample {
            t: self.now(),
            pv: self.pv()?,
            sv: self.read(offset::SV)?,
            mv: self.read(offset::MV)?,
        };
        let tr = &mut self.trend;
        if tr.count.is_multiple_of(tr.every) {
            tr.scans.push(self.run.steps_done());
            tr.samples.push(s);
            if tr.samples.len() >= MAX_TREND {
                every_other(&mut tr.samples);
                every_other(&mut tr.scans);
                tr.every *= 2;
            }
        }
        tr.count += 1;
        Ok(s)
    }

    /// Scans for `seconds` of virtual time (at least one scan).
    pub fn scan_for(&mut self, seconds: f64) -> Result<Sample, String> {
        let n = (seconds / self.scan_s).ceil().max(1.0) as u64;
        let mut last = self.scan()?;
        for _ in 1..n {
            last = self.scan()?;
        }
        Ok(last)
    }

    /// The recorded trend as a trace for `softplc_sim::plot`.
    pub fn trace(&self) -> TraceData {
        let tr = &self.trend;
        let mut values = Vec::with_capacity(tr.samples.len() * 3);
        for s in &tr.samples {
            values.extend([s.pv, s.sv, s.mv]);
        }
        TraceData {
            devices: self
                .labels
                .iter()
                .map(|l| (l.clone(), Kind::Float))
                .collect(),
            scans: tr.scans.clone(),
            times_us: tr
                .samples
                .iter()
                .map(|s| (s.t * 1e6).round() as u64)
                .collect(),
            values,
        }
    }

    /// The trend's column names (PV, SV, MV).
    pub fn labels(&self) -> &[String; 3] {
        &self.labels
    }
}
