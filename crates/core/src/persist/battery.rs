//! The CPU's battery: binds a [`Store`] to a [`Cpu`]'s retained memory (latch
//! ranges, file registers, error history). Opening restores it — each process
//! start is a power-on — and `commit` is called right after a scan, i.e. at END
//! processing, so what is on disk is always the state of some END.

use std::path::Path;
use std::time::{Duration, Instant};

use super::{CommitStats, PersistError, Region, Store};
use crate::engine::Cpu;

/// A CPU's battery-backed memory in a state directory.
pub struct Battery {
    store: Store,
    bufs: Vec<Vec<u8>>,
    last: Instant,
    /// Minimum wall-clock time between two commits (0: every END).
    pub interval: Duration,
}

impl Battery {
    /// Opens (or creates) the state directory and restores the CPU's retained
    /// memory from it. Warnings (discarded regions, a torn journal tail) are in
    /// [`Battery::warnings`].
    pub fn attach(dir: &Path, cpu: &mut Cpu) -> Result<Battery, PersistError> {
        let layout: Vec<Region> = cpu
            .retained_layout()
            .into_iter()
            .map(|(name, len)| Region::new(name, len))
            .collect();
        let (store, data) = Store::open(dir, &layout)?;
        cpu.restore_retained(&data);
        let bufs = layout.iter().map(|r| vec![0; r.len]).collect();
        Ok(Battery {
            store,
            bufs,
            last: Instant::now(),
            interval: Duration::from_millis(10),
        })
    }

    pub fn warnings(&self) -> &[String] {
        self.store.warnings()
    }

    /// Commits the CPU's retained memory now (atomically; only changed chunks
    /// are written).
    pub fn commit(&mut self, cpu: &Cpu) -> Result<CommitStats, PersistError> {
        cpu.save_retained(&mut self.bufs);
        let regions: Vec<&[u8]> = self.bufs.iter().map(|b| b.as_slice()).collect();
        self.last = Instant::now();
        self.store.commit(&regions)
    }

    /// Commits if `interval` has passed since the last commit.
    pub fn commit_due(&mut self, cpu: &Cpu) -> Result<Option<CommitStats>, PersistError> {
        if self.last.elapsed() >= self.interval {
            self.commit(cpu).map(Some)
        } else {
            Ok(None)
        }
    }
}
