//! Time sources. The engine never reads the host clock for PLC time: it is given a
//! [`Clock`], so tests and `softplc run` are deterministic in virtual time.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Microseconds since an arbitrary origin, never going backwards.
pub trait Clock: Send {
    fn now_us(&self) -> u64;

    /// Sets the time to `now_us` (a state file restores the time of its
    /// END, contract §7); the clock goes on from there.
    fn restore_us(&mut self, now_us: u64);

    /// Virtual time: instructions take none of it, so the engine's wall-clock
    /// watchdog only guards against endless scans (see
    /// `softplc_engine::VIRTUAL_WATCHDOG_FLOOR`).
    fn is_virtual(&self) -> bool {
        false
    }
}

/// Virtual time, advanced explicitly by its owner (cloneable handle).
#[derive(Clone, Debug, Default)]
pub struct VirtualClock(Arc<AtomicU64>);

impl VirtualClock {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn advance_us(&self, us: u64) {
        self.0.fetch_add(us, Ordering::Relaxed);
    }
}

impl Clock for VirtualClock {
    fn now_us(&self) -> u64 {
        self.0.load(Ordering::Relaxed)
    }

    /// Every handle of this clock sees the time restored.
    fn restore_us(&mut self, now_us: u64) {
        self.0.store(now_us, Ordering::Relaxed);
    }

    fn is_virtual(&self) -> bool {
        true
    }
}

/// Real time from the host's monotonic clock: the time at `origin` plus
/// the host time since.
#[derive(Clone, Debug)]
pub struct MonotonicClock {
    origin: Instant,
    at_origin_us: u64,
}

impl Default for MonotonicClock {
    fn default() -> Self {
        MonotonicClock {
            origin: Instant::now(),
            at_origin_us: 0,
        }
    }
}

impl Clock for MonotonicClock {
    fn now_us(&self) -> u64 {
        self.at_origin_us + self.origin.elapsed().as_micros() as u64
    }

    fn restore_us(&mut self, now_us: u64) {
        self.origin = Instant::now();
        self.at_origin_us = now_us;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_restored_clock_goes_on_from_the_time_restored() {
        let v = VirtualClock::new();
        let mut c: Box<dyn Clock> = Box::new(v.clone());
        c.restore_us(5_000);
        v.advance_us(10);
        assert_eq!(c.now_us(), 5_010);
        let mut m = MonotonicClock::default();
        m.restore_us(7_000_000);
        assert!(m.now_us() >= 7_000_000);
    }
}
