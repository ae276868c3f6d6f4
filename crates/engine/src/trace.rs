//! Sampling trace (004 §7.12, qcpu.md §4.10): device values stored at END every
//! scan (or every n-th scan), up to 50 bit and 50 word devices and 8192 samples,
//! with an optional trigger after which a set number of samples completes the
//! trace. Samples go into a ring buffer allocated once, so tracing does not
//! allocate while scanning. The family's relays ([`TraceRelays`]: MELSEC's
//! SM800-SM805 and SM826) show its state: ready, executing, trigger, after
//! trigger, complete, error (a device that could not be read); turning the
//! trigger relay ON triggers it, turning the start relay OFF aborts it (the
//! samples are cleared and the relays but ready turn OFF) and ON again
//! starts it anew (004 §7.12 (1) (d), (f)).

use softplc_ir::access::{DeviceSpec, Value, ValueType};
use softplc_ir::device::DeviceMemory;
use softplc_ir::system::TraceRelays;

/// Limits of the Q CPU's sampling trace.
pub const MAX_BIT_DEVICES: usize = 50;
pub const MAX_WORD_DEVICES: usize = 50;
pub const MAX_SAMPLES: usize = 8192;

/// What to trace.
#[derive(Clone, Debug)]
pub struct TraceConfig {
    pub devices: Vec<DeviceSpec>,
    /// Sample at every n-th END (1 = every scan).
    pub every_scans: u32,
    /// Or sample at the first END after each interval of engine time (µs), the
    /// "fixed time" trace point; overrides `every_scans` when set.
    pub interval_us: Option<u64>,
    /// Ring-buffer size in samples (1..=8192).
    pub capacity: usize,
    /// Trigger: when this bit device turns ON (a rising edge: a condition already
    /// true at the start is not recognised, L4762), or the trigger relay turns
    /// ON, or TRACE executes, `after_trigger` more samples are taken and the
    /// trace completes. `None`: only the trigger relay and TRACE trigger it.
    pub trigger: Option<DeviceSpec>,
    pub after_trigger: usize,
}

impl TraceConfig {
    /// Checks the manual's limits; strings cannot be traced.
    pub fn validate(&self) -> Result<(), String> {
        let bits = self
            .devices
            .iter()
            .filter(|d| d.ty == ValueType::Bit)
            .count();
        let words = self.devices.len() - bits;
        if bits > MAX_BIT_DEVICES || words > MAX_WORD_DEVICES {
            return Err(format!(
                "a sampling trace takes at most {MAX_BIT_DEVICES} bit and {MAX_WORD_DEVICES} word devices ({bits} bit, {words} word given)"
            ));
        }
        if let Some(d) = self.devices.iter().find(|d| d.ty == ValueType::Str) {
            return Err(format!("`{}`: strings cannot be traced", d.text));
        }
        if !(1..=MAX_SAMPLES).contains(&self.capacity) {
            return Err(format!("trace size must be 1 to {MAX_SAMPLES} samples"));
        }
        if self.every_scans == 0 {
            return Err("trace interval must be at least 1 scan".into());
        }
        Ok(())
    }
}

/// A running sampling trace.
#[derive(Clone, Debug)]
pub struct Trace {
    cfg: TraceConfig,
    /// `capacity × devices` raw values, sample-major.
    values: Vec<u64>,
    /// Per sample: (scan number, engine time µs).
    stamps: Vec<(u64, u64)>,
    /// Next slot to write and samples held.
    next: usize,
    len: usize,
    countdown: u32,
    /// Engine time of the last sample (interval trace point).
    last_sample_us: Option<u64>,
    /// Trigger device and trigger relay at the previous END (edges).
    trigger_before: bool,
    relay_before: bool,
    /// Aborted by the start relay: no samples until it is ON again.
    aborted: bool,
    /// The relays showing the trace's state (set by the CPU).
    relays: Option<TraceRelays>,
    /// Samples still to take after the trigger; `None` before the trigger.
    remaining: Option<usize>,
    complete: bool,
}

impl Trace {
    pub fn new(cfg: TraceConfig) -> Result<Trace, String> {
        cfg.validate()?;
        let n = cfg.devices.len();
        Ok(Trace {
            values: vec![0; cfg.capacity * n],
            stamps: vec![(0, 0); cfg.capacity],
            next: 0,
            len: 0,
            countdown: 0,
            last_sample_us: None,
            trigger_before: true,
            relay_before: true,
            aborted: false,
            relays: None,
            remaining: None,
            complete: false,
            cfg,
        })
    }

    /// What the trace is of, for a state file: its settings.
    pub(crate) fn key(&self) -> String {
        format!("{:?}", self.cfg)
    }

    /// The samples and the trace's progress, in a state file.
    pub(crate) fn snapshot(&mut self, s: &mut softplc_ir::snapshot::Snap) {
        let cap = self.cfg.capacity;
        s.u64s(&mut self.values);
        if s.same_len(self.stamps.len()) {
            for (scan, us) in &mut self.stamps {
                s.u64(scan);
                s.u64(us);
            }
        }
        s.index(&mut self.next, cap.max(1));
        s.index(&mut self.len, cap + 1);
        s.u32(&mut self.countdown);
        s.option(&mut self.last_sample_us, |s, v| s.u64(v));
        s.bool(&mut self.trigger_before);
        s.bool(&mut self.relay_before);
        s.bool(&mut self.aborted);
        s.option(&mut self.remaining, |s, v| s.index(v, cap + 1));
        s.bool(&mut self.complete);
    }

    /// The same trace shown by `relays`.
    pub(crate) fn with_relays(mut self, relays: Option<TraceRelays>) -> Trace {
        self.relays = relays;
        self
    }

    /// Sets the relay `pick` chooses, if the trace has relays.
    fn show(&self, mem: &mut DeviceMemory, pick: fn(&TraceRelays) -> u32, v: bool) {
        if let Some(r) = &self.relays {
            mem.bits[pick(r) as usize] = v;
        }
    }

    /// END processing: takes a sample when due.
    pub(crate) fn sample(&mut self, mem: &mut DeviceMemory, scan: u64, now_us: u64) {
        self.show(mem, |r| r.ready, true);
        let started = self.relays.is_none_or(|r| mem.bits[r.start as usize]);
        match (started, self.aborted) {
            (false, false) => {
                // Aborted: the trace count is cleared (§7.12 (1) (d) 1)).
                self.aborted = true;
                self.reset(mem);
                self.show(mem, |r| r.executing, false);
                return;
            }
            (false, true) => return,
            (true, true) => {
                // Started again (§7.12 (1) (d) 2)).
                self.aborted = false;
                self.show(mem, |r| r.error, false);
            }
            (true, false) => {}
        }
        if self.complete {
            return;
        }
        self.show(mem, |r| r.executing, true);
        // Trigger on a rising edge of the trigger device or of the trigger relay.
        let dev = self
            .cfg
            .trigger
            .as_ref()
            .is_some_and(|t| matches!(t.read(mem), Ok(Value::Bool(true))));
        let relay = self.relays.is_some_and(|r| mem.bits[r.trigger as usize]);
        let fired = dev && !self.trigger_before || relay && !self.relay_before;
        (self.trigger_before, self.relay_before) = (dev, relay);
        if fired {
            self.trigger();
            self.show(mem, |r| r.trigger, true);
        }
        if self.remaining.is_some() {
            self.show(mem, |r| r.after_trigger, true);
        }
        let due = match self.cfg.interval_us {
            Some(iv) => {
                let due = self.last_sample_us.is_none_or(|t| now_us >= t + iv);
                if due {
                    self.last_sample_us = Some(now_us);
                }
                due
            }
            None if self.countdown > 0 => {
                self.countdown -= 1;
                false
            }
            None => {
                self.countdown = self.cfg.every_scans - 1;
                true
            }
        };
        if !due {
            return;
        }
        let n = self.cfg.devices.len();
        let row = &mut self.values[self.next * n..(self.next + 1) * n];
        let mut unreadable = false;
        for (v, d) in row.iter_mut().zip(&self.cfg.devices) {
            *v = d.read_raw(mem).unwrap_or_else(|_| {
                unreadable = true;
                0
            });
        }
        if unreadable {
            // A device outside the CPU's points: the trace error (SM826),
            // the sample keeps 0 for it.
            self.show(mem, |r| r.error, true);
        }
        self.stamps[self.next] = (scan, now_us);
        self.next = (self.next + 1) % self.cfg.capacity;
        self.len = (self.len + 1).min(self.cfg.capacity);
        if let Some(r) = &mut self.remaining {
            *r = r.saturating_sub(1);
        }
        if self.remaining == Some(0) {
            self.complete = true;
            self.show(mem, |r| r.executing, false);
            self.show(mem, |r| r.complete, true);
        }
    }

    /// TRACER: clears the samples and the trigger; the trace starts again.
    pub fn reset(&mut self, mem: &mut DeviceMemory) {
        self.next = 0;
        self.len = 0;
        self.countdown = 0;
        self.last_sample_us = None;
        self.remaining = None;
        self.complete = false;
        self.show(mem, |r| r.trigger, false);
        self.show(mem, |r| r.after_trigger, false);
        self.show(mem, |r| r.complete, false);
    }

    /// The TRACE instruction or a trigger operation: starts the after-trigger count.
    pub fn trigger(&mut self) {
        if self.remaining.is_none() && !self.complete {
            self.remaining = Some(self.cfg.after_trigger);
            self.complete = self.cfg.after_trigger == 0;
        }
    }

    pub fn devices(&self) -> &[DeviceSpec] {
        &self.cfg.devices
    }

    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// The samples held, oldest first: (scan, time µs, values).
    pub fn samples(&self) -> impl Iterator<Item = (u64, u64, Vec<Value>)> + '_ {
        let n = self.cfg.devices.len();
        let cap = self.cfg.capacity;
        let first = (self.next + cap - self.len) % cap;
        (0..self.len).map(move |k| {
            let i = (first + k) % cap;
            let (scan, t) = self.stamps[i];
            let vals = self.values[i * n..(i + 1) * n]
                .iter()
                .zip(&self.cfg.devices)
                .map(|(raw, d)| d.present_raw(*raw))
                .collect();
            (scan, t, vals)
        })
    }

    /// The trace as CSV: `scan,time_ms,DEV,…` then one row per sample.
    pub fn to_csv(&self) -> String {
        let mut out = String::from("scan,time_ms");
        for d in &self.cfg.devices {
            out.push(',');
            out.push_str(&d.text);
        }
        out.push('\n');
        for (scan, t, vals) in self.samples() {
            out.push_str(&format!("{scan},{}", t as f64 / 1000.0));
            for v in vals {
                out.push(',');
                out.push_str(&match v {
                    Value::Bool(b) => (b as u8).to_string(),
                    v => v.to_string(),
                });
            }
            out.push('\n');
        }
        out
    }
}
