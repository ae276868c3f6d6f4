//! The CPU's battery: binds a [`Store`] to a [`Cpu`]'s retained memory (latch
//! ranges, file registers, error history) and the calendar clock, kept as its
//! offset from the host clock (the battery keeps the clock running while off). Opening restores it — each process
//! start is a power-on — and `commit` is called right after a scan, i.e. at END
//! processing, so what is on disk is always the state of some END.

use std::path::Path;
use std::time::{Duration, Instant};

use super::{CommitStats, PersistError, Region, Store};
use crate::engine::Cpu;

/// What the CPU does when the state directory was found damaged at power-on
/// (`[state] on_damage` in plc.toml). Either way the loss is reported as
/// BATTERY ERROR 1600 in SD0 and the error history, and the intact regions
/// are restored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OnDamage {
    /// Keep running (a continuation error, as the CPU's BATTERY ERROR).
    #[default]
    Continue,
    /// Hold a stop error: the CPU stays in STOP until RESET.
    Stop,
}

/// How [`Battery::attach_with`] powers the CPU on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Attach {
    /// The calendar clock continues from the saved offset to the host clock
    /// (real time, `serve`); off, `run` keeps its reproducible `--clock` start.
    pub restore_clock: bool,
    pub on_damage: OnDamage,
}

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
    ///
    /// With `restore_clock` the calendar clock continues from the saved offset
    /// to the host clock (real time, `serve`); `run` keeps its reproducible
    /// `--clock` start instead.
    pub fn attach(dir: &Path, cpu: &mut Cpu, restore_clock: bool) -> Result<Battery, PersistError> {
        Battery::attach_with(
            dir,
            cpu,
            Attach {
                restore_clock,
                on_damage: OnDamage::Continue,
            },
        )
    }

    /// [`Battery::attach`] with the damage policy. Lost data
    /// ([`Store::lost`]) is reported as BATTERY ERROR 1600.
    pub fn attach_with(dir: &Path, cpu: &mut Cpu, opts: Attach) -> Result<Battery, PersistError> {
        let restore_clock = opts.restore_clock;
        let mut layout: Vec<Region> = cpu
            .retained_layout()
            .into_iter()
            .map(|(name, len)| Region::new(name, len))
            .collect();
        layout.push(Region::new("clock-offset", CLOCK_LEN));
        let (store, data) = Store::open(dir, &layout)?;
        cpu.restore_retained(&data[..data.len() - 1]);
        if let (true, Some(Some(c))) = (restore_clock, data.last()) {
            if c[0] == 1 {
                let offset = i64::from_le_bytes(c[1..9].try_into().unwrap_or([0; 8]));
                cpu.set_calendar_unix_us(host_unix_us() + offset);
            }
        }
        if !store.lost().is_empty() {
            cpu.report_battery_error(opts.on_damage == OnDamage::Stop);
        }
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

    /// Retained data found damaged at power-on (see [`Store::lost`]).
    pub fn lost(&self) -> &[String] {
        self.store.lost()
    }

    /// Commits the CPU's retained memory now (atomically; only changed chunks
    /// are written).
    pub fn commit(&mut self, cpu: &Cpu) -> Result<CommitStats, PersistError> {
        let n = self.bufs.len();
        cpu.save_retained(&mut self.bufs[..n - 1]);
        // The clock offset changes by a few µs per commit as host and engine
        // clocks drift; it is kept rounded to whole seconds so an unchanged clock
        // writes nothing.
        let offset =
            (cpu.calendar_unix_us() - host_unix_us() + 500_000).div_euclid(1_000_000) * 1_000_000;
        let c = &mut self.bufs[n - 1];
        c[0] = 1;
        c[1..9].copy_from_slice(&offset.to_le_bytes());
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

/// The saved clock: a flag byte and the offset (µs, i64 LE) of the PLC calendar
/// from the host's clock.
const CLOCK_LEN: usize = 9;

fn host_unix_us() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_micros() as i64)
}
