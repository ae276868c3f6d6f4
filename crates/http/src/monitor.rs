//! The web monitor's part of END processing (contract §3.1), one hook on the
//! engine thread after every scan:
//!
//! - **step**: `cpu/step?scans=N` puts a paused CPU in RUN; after exactly N
//!   executed scans the hook pauses it again and answers the request;
//! - **breakpoint**: "pause at END when a condition becomes true" (an
//!   extension, docs/web-monitor.md): the condition is read at every END of a
//!   running CPU; on its rising edge the CPU pauses (in a multi-CPU system,
//!   the CPU of the condition's device, at its own END);
//! - **snapshots**: the names SSE clients subscribed to are read at most every
//!   [`SAMPLE`] and published on a `watch` channel, so every event is one END
//!   and nothing is read while no one watches. A subscription belongs to its
//!   stream ([`Owner`]): the hook drops the names of every stream that has
//!   ended, however it ended, so no message has to reach the engine for it.
//!
//! All state lives in [`Monitor`], kept in `ServeState::ext` and touched only
//! on the engine thread (requests change it with `at_end` jobs): no locks.

use std::collections::HashMap;
use std::sync::{Arc, Weak};
use std::time::{Duration, Instant};

use serde_json::Value as Json;
use softplc_core::access::Value;
use softplc_core::engine::CpuState;
use softplc_core::names::Names;
use softplc_serve::ServeState;
use tokio::sync::{oneshot, watch};

use crate::values::{to_json, Dev};

/// Snapshots are published at most this often (10 a second, contract §3.1).
pub const SAMPLE: Duration = Duration::from_millis(100);

/// Device values of one END.
#[derive(Debug, Default)]
pub struct Snapshot {
    /// `scan` of that END (contract §3.1).
    pub scan: u64,
    /// Serial number of the snapshot (0: none yet).
    pub seq: u64,
    pub values: HashMap<String, Json>,
}

/// A running step request.
struct Step {
    /// The CPU stepping (0-based).
    cpu: usize,
    until: u64,
    done: Option<oneshot::Sender<StepDone>>,
}

/// How a step ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepDone {
    pub state: CpuState,
    pub scan: u64,
}

/// A comparison of a breakpoint condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl Cmp {
    pub fn as_str(self) -> &'static str {
        match self {
            Cmp::Eq => "==",
            Cmp::Ne => "!=",
            Cmp::Lt => "<",
            Cmp::Le => "<=",
            Cmp::Gt => ">",
            Cmp::Ge => ">=",
        }
    }
}

/// "Pause at END when `device op value` becomes true".
#[derive(Clone, Debug)]
pub struct Breakpoint {
    pub device: Dev,
    pub cmp: Cmp,
    pub value: Value,
    /// The condition at the previous END (it pauses on the rising edge).
    pub prev: bool,
    /// `scan` of the END at which it paused the CPU, if it did.
    pub hit: Option<u64>,
}

impl Breakpoint {
    /// Parses `M0` (ON), `D0 >= 100`, `D10:f32 < 1.5`, `Y0 == false` with
    /// the served CPU's device `names`.
    pub fn parse(text: &str, names: &Names) -> Result<Breakpoint, String> {
        Breakpoint::parse_in(text, std::slice::from_ref(names))
    }

    /// [`Breakpoint::parse`] with the names of every served CPU (CPU 1's
    /// first): `CPU2/D0 >= 100` watches CPU 2.
    pub fn parse_in(text: &str, cpus: &[Names]) -> Result<Breakpoint, String> {
        let t = text.trim();
        let ops = [
            ("==", Cmp::Eq),
            ("!=", Cmp::Ne),
            ("<>", Cmp::Ne),
            (">=", Cmp::Ge),
            ("<=", Cmp::Le),
            ("=", Cmp::Eq),
            ("<", Cmp::Lt),
            (">", Cmp::Gt),
        ];
        let found = ops
            .iter()
            .filter_map(|(s, c)| t.find(s).map(|i| (i, *s, *c)))
            .min_by_key(|(i, s, _)| (*i, std::cmp::Reverse(s.len())));
        let (name, cmp, value) = match found {
            Some((i, s, c)) => (&t[..i], c, Some(t[i + s.len()..].trim())),
            None => (t, Cmp::Eq, None),
        };
        let device = crate::values::dev(name, cpus)?;
        let value = match value {
            None if device.ty() == softplc_core::access::ValueType::Bit => Value::Bool(true),
            None => {
                return Err(format!(
                    "`{t}`: a word device needs a comparison, e.g. `D0 >= 100`"
                ))
            }
            Some(v) => device
                .name
                .parse_value(v)
                .map_err(|e| format!("breakpoint `{t}`: {e}"))?,
        };
        Ok(Breakpoint {
            device,
            cmp,
            value,
            prev: false,
            hit: None,
        })
    }

    pub fn text(&self) -> String {
        format!(
            "{} {} {}",
            self.device.text(),
            self.cmp.as_str(),
            self.value
        )
    }

    /// The condition against device memory now (false when unreadable).
    pub(crate) fn holds(&self, s: &mut ServeState) -> bool {
        let Ok(v) = self.device.read(s) else {
            return false;
        };
        let ord = match (&v, &self.value) {
            (Value::Bool(a), Value::Bool(b)) => a.partial_cmp(b),
            (Value::Int(a), Value::Int(b)) => a.partial_cmp(b),
            (Value::Float(a), Value::Float(b)) => a.partial_cmp(b),
            (Value::Int(a), Value::Float(b)) => (*a as f64).partial_cmp(b),
            (Value::Float(a), Value::Int(b)) => a.partial_cmp(&(*b as f64)),
            (Value::Str(a), Value::Str(b)) => a.partial_cmp(b),
            _ => None,
        };
        let Some(o) = ord else { return false };
        use std::cmp::Ordering::*;
        match self.cmp {
            Cmp::Eq => o == Equal,
            Cmp::Ne => o != Equal,
            Cmp::Lt => o == Less,
            Cmp::Le => o != Greater,
            Cmp::Gt => o == Greater,
            Cmp::Ge => o != Less,
        }
    }
}

/// What an event stream holds while it lives: its subscription is read at
/// END as long as the stream keeps its `Owner`, and released at the first
/// END after the stream is dropped (client gone, server stopping, or the
/// request abandoned before its subscription was even made).
#[derive(Debug, Default)]
pub struct Owner(Arc<()>);

impl Owner {
    /// What the engine keeps of the stream: it can tell whether it ended.
    pub fn watcher(&self) -> Watcher {
        Watcher(Arc::downgrade(&self.0))
    }
}

/// The engine's side of an [`Owner`].
#[derive(Debug, Clone)]
pub struct Watcher(Weak<()>);

impl Watcher {
    fn ended(&self) -> bool {
        self.0.strong_count() == 0
    }
}

/// One stream's subscribed names, kept while its [`Owner`] lives.
struct Stream {
    owner: Watcher,
    names: Vec<Dev>,
}

/// The monitor's state on the engine thread.
#[derive(Default)]
pub struct Monitor {
    step: Option<Step>,
    pub breakpoint: Option<Breakpoint>,
    /// Subscribed names with their subscriber counts (over `streams`).
    subs: Vec<(Dev, usize)>,
    /// The open event streams' subscriptions.
    streams: Vec<Stream>,
    publish: Option<watch::Sender<Arc<Snapshot>>>,
    last: Option<Instant>,
    seq: u64,
}

impl Monitor {
    /// Devices SSE clients watch now (read at each published END).
    pub fn watched(&self) -> usize {
        self.subs.len()
    }

    /// Drops the subscriptions of the streams that ended.
    fn release_ended(&mut self) {
        let mut i = 0;
        while i < self.streams.len() {
            if !self.streams[i].owner.ended() {
                i += 1;
                continue;
            }
            let gone = self.streams.swap_remove(i);
            for d in &gone.names {
                if let Some(k) = self.subs.iter().position(|(e, _)| e.text() == d.text()) {
                    self.subs[k].1 -= 1;
                    if self.subs[k].1 == 0 {
                        self.subs.swap_remove(k);
                    }
                }
            }
        }
    }
}

/// Installs the END hook (once, from the server's first request).
pub fn install(s: &mut ServeState, tx: watch::Sender<Arc<Snapshot>>) {
    let m = s.ext::<Monitor>();
    if m.publish.is_some() {
        m.publish = Some(tx);
        return;
    }
    m.publish = Some(tx);
    s.add_hook(Box::new(end_hook));
}

fn end_hook(s: &mut ServeState) {
    let scanned = s.scanned();
    let scan = s.cpu().scans();
    let mut m = std::mem::take(s.ext::<Monitor>());
    m.release_ended();
    if let Some(st) = m.step.as_mut().filter(|st| st.cpu == scanned) {
        let cpu = s.cpu_mut_at(st.cpu);
        let (state, at) = (cpu.state(), cpu.scans());
        if state != CpuState::Run || at >= st.until {
            if state == CpuState::Run {
                let _ = cpu.set_pause();
            }
            if let Some(done) = st.done.take() {
                let _ = done.send(StepDone {
                    state: cpu.state(),
                    scan: at,
                });
            }
            m.step = None;
        }
    }
    if let Some(bp) = m.breakpoint.as_mut().filter(|b| b.device.cpu == scanned) {
        if s.cpu_at(scanned).state() == CpuState::Run {
            let now = bp.holds(s);
            if now && !bp.prev {
                let cpu = s.cpu_mut_at(scanned);
                let _ = cpu.set_pause();
                bp.hit = Some(cpu.scans());
            }
            bp.prev = now;
        }
    }
    if !m.subs.is_empty() && m.last.is_none_or(|t| t.elapsed() >= SAMPLE) {
        m.last = Some(Instant::now());
        m.seq += 1;
        let values = m
            .subs
            .iter()
            .map(|(d, _)| {
                let v = d.read(s).map_or(Json::Null, |v| to_json(&v));
                (d.text().to_string(), v)
            })
            .collect();
        if let Some(tx) = &m.publish {
            let _ = tx.send(Arc::new(Snapshot {
                scan,
                seq: m.seq,
                values,
            }));
        }
    }
    *s.ext::<Monitor>() = m;
}

/// Starts a step of `n` scans of CPU `cpu` (0-based) from PAUSE; the
/// receiver gets the state after it.
pub fn start_step(
    s: &mut ServeState,
    cpu: usize,
    n: u64,
) -> Result<oneshot::Receiver<StepDone>, String> {
    let c = s.cpu_mut_at(cpu);
    if c.state() != CpuState::Pause {
        return Err(format!(
            "step runs from PAUSE; the CPU is in {}",
            c.state().as_str()
        ));
    }
    c.set_run()?;
    let (tx, rx) = oneshot::channel();
    let until = c.scans() + n;
    s.ext::<Monitor>().step = Some(Step {
        cpu,
        until,
        done: Some(tx),
    });
    Ok(rx)
}

/// Most distinct devices all SSE clients together watch (bounds the work
/// of one published END).
pub const MAX_WATCHED: usize = 4096;

/// Subscribes the stream of `owner` to `specs` (each must be readable now).
/// A stream that ended before this runs subscribes nothing.
pub fn subscribe(s: &mut ServeState, specs: &[Dev], owner: Watcher) -> Result<(), String> {
    for d in specs {
        d.read(s)?;
    }
    let m = s.ext::<Monitor>();
    m.release_ended();
    if owner.ended() {
        return Ok(());
    }
    let fresh = specs
        .iter()
        .filter(|d| !m.subs.iter().any(|(e, _)| e.text() == d.text()))
        .count();
    if m.subs.len() + fresh > MAX_WATCHED {
        return Err(format!(
            "the monitor watches {} devices already; at most {MAX_WATCHED}",
            m.subs.len()
        ));
    }
    for d in specs {
        match m.subs.iter_mut().find(|(e, _)| e.text() == d.text()) {
            Some((_, n)) => *n += 1,
            None => m.subs.push((d.clone(), 1)),
        }
    }
    m.streams.push(Stream {
        owner,
        names: specs.to_vec(),
    });
    // The next END publishes the new names.
    m.last = None;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn breakpoint_conditions_parse() {
        let b = Breakpoint::parse(
            "D0 >= 100",
            &Names::plain(softplc_core::profile::default_profile()),
        )
        .unwrap();
        assert_eq!((b.device.text(), b.cmp), ("D0", Cmp::Ge));
        assert_eq!(b.value, Value::Int(100));
        let b = Breakpoint::parse(
            "M5",
            &Names::plain(softplc_core::profile::default_profile()),
        )
        .unwrap();
        assert_eq!((b.cmp, b.value.clone()), (Cmp::Eq, Value::Bool(true)));
        let b = Breakpoint::parse(
            "D10:f32<1.5",
            &Names::plain(softplc_core::profile::default_profile()),
        )
        .unwrap();
        assert_eq!((b.cmp, b.value.clone()), (Cmp::Lt, Value::Float(1.5)));
        assert_eq!(
            Breakpoint::parse(
                "Y0 == false",
                &Names::plain(softplc_core::profile::default_profile())
            )
            .unwrap()
            .value,
            Value::Bool(false)
        );
        assert_eq!(
            Breakpoint::parse(
                "D1 <> 3",
                &Names::plain(softplc_core::profile::default_profile())
            )
            .unwrap()
            .cmp,
            Cmp::Ne
        );
        assert!(Breakpoint::parse(
            "D0",
            &Names::plain(softplc_core::profile::default_profile())
        )
        .unwrap_err()
        .contains("comparison"));
        assert!(Breakpoint::parse(
            "D0 > x",
            &Names::plain(softplc_core::profile::default_profile())
        )
        .is_err());
        assert!(Breakpoint::parse(
            "QQ >= 1",
            &Names::plain(softplc_core::profile::default_profile())
        )
        .unwrap_err()
        .contains("QQ"));
    }
}
