//! Time sources. The engine never reads the host clock for PLC time: it is given a
//! [`Clock`], so tests and `softplc run` are deterministic in virtual time.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Microseconds since an arbitrary origin, never going backwards.
pub trait Clock: Send {
    fn now_us(&self) -> u64;

    /// A reading that drives nothing in the CPU (a tool looking at the
    /// time: the calendar shown, a serial port's timeout). A recording
    /// clock does not record it, so a replay need not make it.
    fn peek_us(&self) -> u64 {
        self.now_us()
    }

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

    fn is_virtual(&self) -> bool {
        true
    }
}

/// Real time from the host's monotonic clock.
#[derive(Clone, Debug)]
pub struct MonotonicClock(Instant);

impl Default for MonotonicClock {
    fn default() -> Self {
        MonotonicClock(Instant::now())
    }
}

impl Clock for MonotonicClock {
    fn now_us(&self) -> u64 {
        self.0.elapsed().as_micros() as u64
    }
}
