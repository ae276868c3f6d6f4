//! The hand-over from the engine thread to the MQTT task: an END hook reads
//! the published devices and marks the changed ones under one short lock;
//! the task takes them out when it can send. A slow or absent broker only
//! coalesces ENDs (the latest value wins); it never holds up the scan.

use std::sync::{Arc, Mutex};

use softplc_core::access::Value;
use softplc_http::values::Dev;
use softplc_serve::ServeState;

/// A device's latest value and the scan count of the END it was read at.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    pub value: Value,
    pub scan: u64,
}

struct Pending {
    latest: Vec<Option<Sample>>,
    dirty: Vec<bool>,
}

/// The published devices and their latest values.
pub struct Feed {
    pub points: Vec<Dev>,
    pending: Mutex<Pending>,
    pub wake: tokio::sync::Notify,
}

impl Feed {
    pub fn new(points: Vec<Dev>) -> Arc<Feed> {
        let n = points.len();
        Arc::new(Feed {
            points,
            pending: Mutex::new(Pending {
                latest: vec![None; n],
                dirty: vec![false; n],
            }),
            wake: tokio::sync::Notify::new(),
        })
    }

    /// Reads every point at this END; marks the changed ones (all of them
    /// the first time). `seen` is the hook's own copy of the last values,
    /// so the lock is taken only when something changed.
    pub fn sample(&self, s: &mut ServeState, seen: &mut [Option<Value>]) {
        let mut changed = false;
        for (k, p) in self.points.iter().enumerate() {
            // A point that cannot be read now (an index register out of
            // range) keeps its last value.
            let Ok(v) = p.read(s) else { continue };
            if seen[k].as_ref() != Some(&v) {
                seen[k] = Some(v);
                changed = true;
            }
        }
        if !changed {
            return;
        }
        let Ok(mut g) = self.pending.lock() else {
            return;
        };
        let p = &mut *g;
        for (k, v) in seen.iter().enumerate() {
            let Some(v) = v else { continue };
            let scan = s.cpu_at(self.points[k].cpu).scans();
            if p.latest[k].as_ref().map(|x| &x.value) != Some(v) {
                p.latest[k] = Some(Sample {
                    value: v.clone(),
                    scan,
                });
                p.dirty[k] = true;
            }
        }
        drop(g);
        self.wake.notify_one();
    }

    /// Marks every point with a value for sending (after a connect).
    pub fn mark_all(&self) {
        if let Ok(mut p) = self.pending.lock() {
            let p = &mut *p;
            for (d, l) in p.dirty.iter_mut().zip(&p.latest) {
                *d = l.is_some();
            }
        }
    }

    /// Takes the marked points out: (index, sample).
    pub fn take(&self, out: &mut Vec<(usize, Sample)>) {
        out.clear();
        let Ok(mut p) = self.pending.lock() else {
            return;
        };
        let p = &mut *p;
        for (k, d) in p.dirty.iter_mut().enumerate() {
            if *d {
                *d = false;
                if let Some(s) = &p.latest[k] {
                    out.push((k, s.clone()));
                }
            }
        }
    }

    /// Marks point `k` again (its send did not go out), unless a newer
    /// value is already marked.
    pub fn retry(&self, k: usize) {
        if let Ok(mut p) = self.pending.lock() {
            p.dirty[k] = true;
        }
    }
}

/// Installs the END hook that feeds `feed`.
pub fn install(s: &mut ServeState, feed: Arc<Feed>) {
    let mut seen: Vec<Option<Value>> = vec![None; feed.points.len()];
    s.add_hook(Box::new(move |s| feed.sample(s, &mut seen)));
}
