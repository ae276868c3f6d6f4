//! Values published at END (contract §3.2), changed points only.
//!
//! An END hook on the engine thread reads every point's raw bits
//! (`DevName::raw`: no parsing, no allocation) and compares them with the
//! latest values in [`Feed`], under one short lock per END, so the task never
//! sees half an END. An async task takes the changed ones out and sets the
//! nodes, which notifies the subscriptions. A slow task only coalesces ENDs
//! (the latest values win); it never holds up the scan. A write samples its
//! END the same way and replies once the task has published it, so a read
//! after a write's reply shows the written value.

use std::sync::{Arc, Mutex};
use std::time::SystemTime;

use opcua::server::node_manager::memory::InMemoryNodeManager;
use opcua::server::SubscriptionCache;
use opcua::types::{DataValue, DateTime, NodeId, StatusCode, Variant};
use softplc_serve::ServeState;

use crate::space::{variant, SoftplcNodes, Space};

/// `Objects/softplc/Diagnostics` at one END.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Diag {
    /// `RUN`, `STOP` or `PAUSE`.
    pub state: &'static str,
    /// Executed scans since power-on (as contract §3.1 `scan`).
    pub scan: u64,
    /// The last scan's execution time, µs (as §3.1 `scan_time_us.last`).
    pub scan_time_us: u32,
    /// The latest self-diagnostic error code (SD0), 0 for none.
    pub error_code: u16,
}

impl Diag {
    /// CPU 1's (the only CPU's).
    pub fn of(s: &ServeState) -> Diag {
        Diag::at(s, 0)
    }

    /// CPU `i`'s (0-based).
    pub fn at(s: &ServeState, i: usize) -> Diag {
        let cpu = s.cpu_at(i);
        let exec = match i {
            0 => s.stats.exec_us,
            _ => s.stats.cpus.get(i).map_or(0, |c| c.exec_us),
        };
        Diag {
            state: cpu.state().as_str(),
            scan: cpu.scans(),
            scan_time_us: exec.min(u32::MAX as u64) as u32,
            error_code: cpu.error().map_or(0, |e| e.code.0),
        }
    }

    /// The values of [`crate::space::DIAGNOSTICS`], in its order.
    pub fn variants(&self) -> [Variant; 4] {
        [
            Variant::from(self.state),
            Variant::UInt64(self.scan),
            Variant::UInt32(self.scan_time_us),
            Variant::UInt16(self.error_code),
        ]
    }
}

/// What the END hook hands the publishing task.
struct Pending {
    /// Latest raw bits of every point (what the nodes show once published).
    values: Vec<u64>,
    /// Points changed since the task last took them, each once.
    dirty: Vec<u32>,
    queued: Vec<bool>,
    /// Each CPU's diagnostics, CPU 1's first.
    diag: Vec<Diag>,
    diag_dirty: bool,
    /// When the latest END was.
    at: SystemTime,
    /// Counts the ENDs that changed something.
    seq: u64,
}

/// The hand-over between the engine thread (END hook, writes) and the
/// publishing task.
pub struct Feed {
    space: Arc<Space>,
    pending: Mutex<Pending>,
    wake: tokio::sync::Notify,
    /// The latest `seq` the task has set in the address space.
    applied: tokio::sync::watch::Sender<u64>,
}

impl Feed {
    /// A feed of the points of `space`, which start at `raw` with
    /// diagnostics `diag` (what the address space is built with).
    pub fn new(space: Arc<Space>, raw: Vec<u64>, diag: Diag) -> Arc<Feed> {
        Feed::with_diags(space, raw, vec![diag])
    }

    /// [`Feed::new`] with each CPU's diagnostics (a multi-CPU system's).
    pub fn with_diags(space: Arc<Space>, raw: Vec<u64>, diag: Vec<Diag>) -> Arc<Feed> {
        let n = raw.len();
        Arc::new(Feed {
            space,
            pending: Mutex::new(Pending {
                values: raw,
                dirty: Vec::with_capacity(n),
                queued: vec![false; n],
                diag,
                diag_dirty: false,
                at: SystemTime::now(),
                seq: 0,
            }),
            wake: tokio::sync::Notify::new(),
            applied: tokio::sync::watch::channel(0).0,
        })
    }

    /// The points fed.
    pub fn space(&self) -> &Arc<Space> {
        &self.space
    }

    /// The latest raw bits of every point and each CPU's diagnostics.
    pub fn latest(&self) -> (Vec<u64>, Vec<Diag>) {
        match self.pending.lock() {
            Ok(p) => (p.values.clone(), p.diag.clone()),
            Err(e) => (e.get_ref().values.clone(), e.get_ref().diag.clone()),
        }
    }

    /// Reads every point now (the engine thread, at END) and queues the
    /// changed ones; returns the `seq` that covers this END.
    pub fn sample(&self, s: &ServeState) -> u64 {
        let Ok(mut guard) = self.pending.lock() else {
            return 0;
        };
        let p = &mut *guard;
        let mut any = false;
        for (k, point) in self.space.points.iter().enumerate() {
            // A point that cannot be read (an index register moved out of
            // range) keeps its last value.
            let Ok(r) = point.name.raw(s.cpu_at(point.cpu).memory()) else {
                continue;
            };
            if r != p.values[k] {
                p.values[k] = r;
                if !p.queued[k] {
                    p.queued[k] = true;
                    p.dirty.push(k as u32);
                }
                any = true;
            }
        }
        for (i, d) in p.diag.iter_mut().enumerate() {
            let now = Diag::at(s, i);
            if now != *d {
                *d = now;
                p.diag_dirty = true;
                any = true;
            }
        }
        if any {
            p.seq += 1;
            p.at = SystemTime::now();
            self.wake.notify_one();
        }
        p.seq
    }

    /// Waits until the nodes show `seq` (at most one second: a stopped
    /// task must not hang a client).
    pub async fn published(&self, seq: u64) {
        let mut rx = self.applied.subscribe();
        let _ = tokio::time::timeout(
            std::time::Duration::from_secs(1),
            rx.wait_for(|&a| a >= seq),
        )
        .await;
    }
}

/// Installs the END hook that feeds `feed`.
pub fn install(s: &mut ServeState, feed: Arc<Feed>) {
    s.add_hook(Box::new(move |s| {
        feed.sample(s);
    }));
}

/// OPC UA time (100 ns ticks since 1601) of `t`.
fn ua_time(t: SystemTime) -> DateTime {
    const UNIX_EPOCH_TICKS: i64 = 116_444_736_000_000_000;
    let ticks = match t.duration_since(SystemTime::UNIX_EPOCH) {
        Ok(d) => UNIX_EPOCH_TICKS + (d.as_nanos() / 100) as i64,
        Err(_) => UNIX_EPOCH_TICKS,
    };
    DateTime::from(ticks)
}

/// The publishing task: sets the nodes from `feed` as ENDs change them.
pub async fn run(
    feed: Arc<Feed>,
    nodes: Arc<InMemoryNodeManager<SoftplcNodes>>,
    subscriptions: Arc<SubscriptionCache>,
    ns: u16,
) {
    let space = feed.space.clone();
    let ids: Vec<NodeId> = space
        .points
        .iter()
        .map(|p| NodeId::new(ns, p.id.clone()))
        .collect();
    // Each CPU's diagnostics variables, in the order of `DIAGNOSTICS`.
    let diag_ids: Vec<NodeId> = (0..space.cpus())
        .flat_map(|cpu| {
            let space = &space;
            crate::space::DIAGNOSTICS
                .iter()
                .map(move |(name, _)| NodeId::new(ns, space.diagnostic(cpu, name)))
        })
        .collect();
    let mut taken: Vec<u32> = Vec::new();
    let mut values: Vec<(usize, Variant)> = Vec::new();
    loop {
        feed.wake.notified().await;
        let (at, diag, seq) = {
            let Ok(mut p) = feed.pending.lock() else {
                return;
            };
            std::mem::swap(&mut taken, &mut p.dirty);
            values.clear();
            for &k in &taken {
                let k = k as usize;
                p.queued[k] = false;
                values.push((k, variant(space.points[k].kind, p.values[k])));
            }
            taken.clear();
            let diag = std::mem::take(&mut p.diag_dirty).then(|| p.diag.clone());
            (p.at, diag, p.seq)
        };
        let stamp = ua_time(at);
        let now = DateTime::now();
        let dv = |v: Variant| DataValue {
            value: Some(v),
            status: Some(StatusCode::Good),
            source_timestamp: Some(stamp),
            server_timestamp: Some(now),
            ..Default::default()
        };
        let points = values.drain(..).map(|(k, v)| (&ids[k], None, dv(v)));
        let diags = diag
            .into_iter()
            .flatten()
            .flat_map(|d| d.variants())
            .zip(&diag_ids)
            .map(|(v, id)| (id, None, dv(v)));
        // Every id is a node of this manager: set_values cannot miss one.
        let _ = nodes.set_values(&subscriptions, points.chain(diags));
        feed.applied.send_replace(seq);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn end_times_are_opc_ua_ticks() {
        // 1601-01-01 to 1970-01-01 is 11 644 473 600 s.
        assert_eq!(
            i64::from(ua_time(SystemTime::UNIX_EPOCH)),
            116_444_736_000_000_000
        );
        let t = SystemTime::UNIX_EPOCH + std::time::Duration::from_micros(1_500_001);
        assert_eq!(i64::from(ua_time(t)), 116_444_736_000_000_000 + 15_000_010);
    }

    #[test]
    fn only_changed_points_are_queued_each_once() {
        use softplc_core::access::Value;
        use softplc_core::device::DeviceConfig;
        use softplc_core::engine::{Cpu, VirtualClock};
        let p = softplc_core::program::compile_il(
            "t.il",
            "LD X0\nOUT Y0\nMOV D0 D1\nEND\n",
            &DeviceConfig::default(),
        )
        .unwrap();
        let cpu = Cpu::new(
            p,
            softplc_core::profile::default_config(),
            Box::new(VirtualClock::new()),
        );
        let devices = crate::points::devices(&cpu, &[]).unwrap();
        let names: Vec<&str> = devices.iter().map(|p| p.id.as_str()).collect();
        assert_eq!(names, ["D0", "D1", "X0", "Y0"]);
        let d0 = devices[0].name.clone();
        let space = Arc::new(Space::new(devices, Vec::new()));
        let mut s = ServeState::new(cpu);
        let feed = Feed::new(space, vec![0; 4], Diag::of(&s));
        assert_eq!(feed.sample(&s), 0, "nothing changed");
        d0.write_value(s.cpu_mut(), &Value::Int(-7)).unwrap();
        assert_eq!(feed.sample(&s), 1);
        d0.write_value(s.cpu_mut(), &Value::Int(8)).unwrap();
        assert_eq!(feed.sample(&s), 2);
        let p = feed.pending.lock().unwrap();
        // D0 queued once with its latest value.
        assert_eq!(p.dirty, [0]);
        assert_eq!(p.values, [8, 0, 0, 0]);
        assert!(!p.diag_dirty);
    }
}
