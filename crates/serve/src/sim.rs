//! Virtual time for `softplc serve` (contract §7): `--time-scale F` runs the
//! CPUs' clock at F times real time, or as fast as the scans go, and
//! `--lockstep` holds the CPUs before scan 1 and after each END until a
//! client advances them ([`ServeState::advance`], the web monitor's
//! `POST /api/v1/sim/advance`).
//!
//! The CPUs read a [`VirtualClock`] that this loop moves to each scan's due
//! time, so a scan is instantaneous in virtual time and a CPU's scans are
//! exactly its period apart, as in `softplc run`: timers, SD412, the calendar
//! and the scan-time registers follow virtual time, and a multi-CPU system
//! keeps its order in virtual time ([`System::next_due`]). Between two scans
//! the engine serves requests at the END just made — while it waits for the
//! next scan's real time and, in lockstep, for as long as it is held — so
//! every door (MC, Modbus, OPC UA, HTTP) is answered from the held END and
//! its writes apply before the next scan.
//!
//! [`System::next_due`]: softplc_core::system::System::next_due

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use softplc_core::engine::{Clock, VirtualClock};
use softplc_core::system::Cpus;
use tokio::sync::oneshot;

use crate::engine::{
    account, log_stats, scan_cpu, serve_end, EngineConfig, Heartbeat, Job, ServeState,
};

/// How fast virtual time runs against real time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeScale {
    /// F times real time, [`TimeScale::SLOWEST`] ≤ F ≤ [`TimeScale::FASTEST`]:
    /// a 10 ms scan at F = 2 starts every 5 ms of real time.
    Factor(f64),
    /// As fast as the scans go.
    Max,
}

impl TimeScale {
    pub const SLOWEST: f64 = 0.01;
    pub const FASTEST: f64 = 1000.0;

    /// `F` (0.01-1000) or `max`.
    pub fn parse(s: &str) -> Result<TimeScale, String> {
        let t = s.trim();
        if t.eq_ignore_ascii_case("max") {
            return Ok(TimeScale::Max);
        }
        match t.parse::<f64>() {
            Ok(f) if (Self::SLOWEST..=Self::FASTEST).contains(&f) => Ok(TimeScale::Factor(f)),
            _ => Err(format!(
                "`{s}`: expected a factor from {} to {} (virtual time per real time) or `max`",
                Self::SLOWEST,
                Self::FASTEST
            )),
        }
    }
}

impl std::fmt::Display for TimeScale {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimeScale::Factor(x) => write!(f, "{x}x real time"),
            TimeScale::Max => f.write_str("as fast as possible"),
        }
    }
}

/// Virtual time for a served state ([`ServeState::set_virtual_time`]).
#[derive(Clone, Debug)]
pub struct VirtualTime {
    /// The clock every CPU of the state was built on (a multi-CPU system's
    /// CPUs share it); the engine moves it to each scan's time.
    pub clock: VirtualClock,
    /// How fast it runs; in lockstep, how fast an advance's scans go.
    pub scale: TimeScale,
    /// Hold the CPUs before scan 1 and after each END until advanced.
    pub lockstep: bool,
}

/// Most scans of CPU 1 one advance runs (a day of 10 ms scans fits).
pub const MAX_ADVANCE: u64 = 10_000_000;

/// What an advance runs: scans of CPU 1, or virtual time (µs) rounded up
/// to whole scans of CPU 1's period.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Advance {
    Scans(u64),
    Us(u64),
}

/// CPU 1 after the last END of an advance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Advanced {
    /// Its executed scans since power-on (as `Cpu::scans`).
    pub scan: u64,
    /// Its virtual time since power-on, µs.
    pub time_us: u64,
}

/// Why an advance was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AdvanceRefused {
    #[error("the CPU is not held: start serve with --lockstep to advance it")]
    NotLockstep,
    #[error("an advance is running; wait for its answer (one advance at a time)")]
    Running,
    #[error("an advance runs 1 to {MAX_ADVANCE} scans of CPU 1; this one would run {0}")]
    Scans(u64),
}

/// The engine's virtual time ([`ServeState::sim`]).
pub(crate) struct Sim {
    clock: VirtualClock,
    scale: TimeScale,
    /// A single CPU's period, µs (a system's CPUs keep theirs), set when the
    /// engine starts.
    period_us: u64,
    /// Lockstep: how far the CPUs may run.
    hold: Option<Hold>,
}

struct Hold {
    /// Scans due at or before this virtual time may run (the last END of
    /// the running advance, or the held END).
    until_us: u64,
    /// The advance answered at the END that reaches `until_us`.
    pending: Option<oneshot::Sender<Advanced>>,
}

impl Sim {
    /// The CPU that scans next and when (virtual µs): a single CPU one
    /// period after its last scan, a system's earliest due.
    fn next_scan(&self, cpus: &Cpus) -> (usize, u64) {
        match cpus {
            Cpus::One(_) => (0, self.clock.now_us() + self.period_us),
            Cpus::System(s) => s.next_due(),
        }
    }

    /// When CPU `i` scans next (virtual µs).
    fn due_of(&self, cpus: &Cpus, i: usize) -> u64 {
        match cpus {
            Cpus::One(_) => self.clock.now_us() + self.period_us,
            Cpus::System(s) => s.next_due_of(i),
        }
    }

    fn period_of(&self, cpus: &Cpus, i: usize) -> u64 {
        match cpus {
            Cpus::One(_) => self.period_us,
            Cpus::System(s) => s.period_us(i),
        }
    }
}

impl ServeState {
    /// Runs the CPUs in virtual time on `t.clock`, which they must have
    /// been built on.
    pub fn set_virtual_time(&mut self, t: VirtualTime) {
        self.sim = Some(Sim {
            clock: t.clock,
            scale: t.scale,
            period_us: 1,
            hold: t.lockstep.then_some(Hold {
                until_us: 0,
                pending: None,
            }),
        });
    }

    /// How fast virtual time runs (`None`: the CPUs run in real time).
    pub fn time_scale(&self) -> Option<TimeScale> {
        self.sim.as_ref().map(|s| s.scale)
    }

    /// The CPUs run only when advanced.
    pub fn is_lockstep(&self) -> bool {
        self.sim.as_ref().is_some_and(|s| s.hold.is_some())
    }

    /// Lockstep: lets the CPUs run `a` from the held END — the scans of
    /// CPU 1 it counts, with every scan of the other CPUs of a system due
    /// up to CPU 1's last — and answers CPU 1's scan count and time after
    /// the last of those ENDs (sent after that END's commit). In STOP or
    /// PAUSE a "scan" is a period of END processing. One advance runs at a
    /// time: another meanwhile is refused.
    pub fn advance(&mut self, a: Advance) -> Result<oneshot::Receiver<Advanced>, AdvanceRefused> {
        let Some(sim) = &mut self.sim else {
            return Err(AdvanceRefused::NotLockstep);
        };
        let period = sim.period_of(&self.cpus, 0);
        let next = sim.due_of(&self.cpus, 0);
        let Some(hold) = &mut sim.hold else {
            return Err(AdvanceRefused::NotLockstep);
        };
        if hold.pending.is_some() {
            return Err(AdvanceRefused::Running);
        }
        let n = match a {
            Advance::Scans(n) => n,
            Advance::Us(us) => us.div_ceil(period),
        };
        if !(1..=MAX_ADVANCE).contains(&n) {
            return Err(AdvanceRefused::Scans(n));
        }
        let (tx, rx) = oneshot::channel();
        hold.until_us = next + (n - 1) * period;
        hold.pending = Some(tx);
        Ok(rx)
    }

    /// Lockstep: the next scan is beyond what the advances allow.
    fn held(&self) -> bool {
        self.sim.as_ref().is_some_and(|sim| {
            sim.hold
                .as_ref()
                .is_some_and(|h| sim.next_scan(&self.cpus).1 > h.until_us)
        })
    }

    /// Lockstep without a running advance: held at virtual time `now_us`.
    fn hold_at(&mut self, now_us: u64) {
        let hold = self.sim.as_mut().and_then(|s| s.hold.as_mut());
        if let Some(h) = hold.filter(|h| h.pending.is_none()) {
            h.until_us = now_us;
        }
    }

    /// At the END that completes an advance: its answer goes out with this
    /// END's replies.
    fn complete_advance(&mut self) {
        if !self.held() {
            return;
        }
        let pending = self.sim.as_mut().and_then(|s| s.hold.as_mut());
        let Some(tx) = pending.and_then(|h| h.pending.take()) else {
            return;
        };
        let done = Advanced {
            scan: self.cpu().scans(),
            time_us: self.cpu().since_power_on_us(),
        };
        self.replies.push(Box::new(move || {
            let _ = tx.send(done);
        }));
    }
}

/// A scan that starts more than this late in real time gives up the lost
/// time (a suspended process, a long stall) instead of catching up on it
/// with scans back to back.
const MAX_LAG: Duration = Duration::from_secs(1);

/// Real time of virtual time at a scale: `origin` is `origin_us`.
struct Pace {
    factor: Option<f64>,
    origin: Instant,
    origin_us: u64,
}

impl Pace {
    fn new(scale: TimeScale, now_us: u64) -> Pace {
        Pace {
            factor: match scale {
                TimeScale::Factor(f) => Some(f),
                TimeScale::Max => None,
            },
            origin: Instant::now(),
            origin_us: now_us,
        }
    }

    /// Virtual time `v_us` is now.
    fn restart(&mut self, v_us: u64) {
        self.origin = Instant::now();
        self.origin_us = v_us;
    }

    /// When virtual time `v_us` is due in real time (`None`: at once).
    /// The factor is at least 0.01, so the duration is finite.
    fn real(&self, v_us: u64) -> Option<Instant> {
        let f = self.factor?;
        let us = v_us.saturating_sub(self.origin_us) as f64 / f;
        self.origin.checked_add(Duration::from_secs_f64(us / 1e6))
    }
}

/// The engine loop in virtual time: each scan at its due time on the
/// virtual clock, paced by the time scale, held in lockstep.
pub(crate) fn run(
    mut s: ServeState,
    cfg: &EngineConfig,
    rx: &Receiver<Job>,
    stop: &AtomicBool,
    beat: &Heartbeat,
) -> ServeState {
    let Some(sim) = s.sim.as_mut() else {
        return s;
    };
    sim.period_us = (cfg.period.as_micros() as u64).max(1);
    let (clock, scale) = (sim.clock.clone(), sim.scale);
    if let Some(h) = &mut sim.hold {
        // Held before scan 1.
        h.until_us = clock.now_us();
    }
    if let Cpus::System(sys) = &mut s.cpus {
        sys.schedule(cfg.period, clock.now_us());
    }
    let mut pace = Pace::new(scale, clock.now_us());
    // The time this loop last set (or found) on the clock.
    let mut set_us = clock.now_us();
    let mut jitter_sum = 0f64;
    let mut logged = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        let now = clock.now_us();
        if now != set_us {
            // A request set the clock (a restored state): pace, and hold,
            // from the time it set.
            pace.restart(now);
            s.hold_at(now);
            set_us = now;
        }
        if s.held() {
            between_scans(&mut s, rx, cfg, stop, None);
            // An advance's scans are paced from its start.
            pace.restart(clock.now_us());
            continue;
        }
        let Some(sim) = &s.sim else { break };
        let (i, due) = sim.next_scan(&s.cpus);
        let real = pace.real(due);
        if let Some(t) = real {
            between_scans(&mut s, rx, cfg, stop, Some(t));
            let changed = s.sim.as_ref().map(|sim| sim.next_scan(&s.cpus)) != Some((i, due));
            if changed || stop.load(Ordering::Relaxed) {
                // A request moved the schedule (or the clock): start over.
                continue;
            }
        }
        let start = Instant::now();
        let jitter = real.map_or(0, |t| start.saturating_duration_since(t).as_micros() as u64);
        if let Some(t) = real {
            s.timing.started(t, start);
        }
        clock.advance_us(due.saturating_sub(clock.now_us()));
        set_us = clock.now_us();
        scan_cpu(&mut s, i, start, beat);
        s.run_hooks();
        s.complete_advance();
        serve_end(&mut s, rx, cfg);
        account(&mut s.stats, start, jitter, &mut jitter_sum);
        log_stats(&s.stats, cfg, &mut logged);
        // Overrun: this CPU's next scan is due already in real time.
        let Some(sim) = &s.sim else { break };
        if let Some(t) = pace.real(sim.due_of(&s.cpus, i)) {
            let now = Instant::now();
            if now > t {
                s.stats.overruns += 1;
                s.stats.cpus[i].overruns += 1;
                s.timing.overran();
                if now - t > MAX_LAG {
                    pace.restart(sim.next_scan(&s.cpus).1);
                }
            }
        }
    }
    s
}

/// Serves requests at the END just made until the real time `until`
/// (spinning the last `cfg.realtime.spin` for a steady period) or, without one, while
/// the CPUs are held. Returns soon after `stop`.
fn between_scans(
    s: &mut ServeState,
    rx: &Receiver<Job>,
    cfg: &EngineConfig,
    stop: &AtomicBool,
    until: Option<Instant>,
) {
    // How often a wait looks at `stop`.
    const TICK: Duration = Duration::from_millis(20);
    let spin = cfg.realtime.spin;
    loop {
        if stop.load(Ordering::Relaxed) {
            return;
        }
        let wait = match until {
            Some(t) => {
                let now = Instant::now();
                if t <= now + spin {
                    while Instant::now() < t {
                        std::hint::spin_loop();
                    }
                    return;
                }
                (t - now - spin).min(TICK)
            }
            None if s.held() => TICK,
            None => return,
        };
        match rx.recv_timeout(wait) {
            Ok(job) => {
                job(s);
                s.stats.requests += 1;
                // The others queued with it, then the commit and the replies.
                serve_end(s, rx, cfg);
            }
            Err(RecvTimeoutError::Timeout) => {}
            // Every door has gone (shutting down): only `stop` is left.
            Err(RecvTimeoutError::Disconnected) => std::thread::sleep(wait),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_scales() {
        assert_eq!(TimeScale::parse("max"), Ok(TimeScale::Max));
        assert_eq!(TimeScale::parse(" MAX "), Ok(TimeScale::Max));
        assert_eq!(TimeScale::parse("0.01"), Ok(TimeScale::Factor(0.01)));
        assert_eq!(TimeScale::parse("4"), Ok(TimeScale::Factor(4.0)));
        assert_eq!(TimeScale::parse("1000"), Ok(TimeScale::Factor(1000.0)));
        for bad in ["0.0099", "1000.5", "0", "-2", "NaN", "inf", "", "fast"] {
            assert!(TimeScale::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn virtual_time_is_due_at_its_share_of_real_time() {
        let mut p = Pace::new(TimeScale::Factor(4.0), 1_000);
        p.restart(1_000);
        // 10 ms of virtual time after the origin is 2.5 ms of real time.
        assert_eq!(
            p.real(11_000).unwrap() - p.origin,
            Duration::from_micros(2_500)
        );
        // Before the origin: at once, at the origin.
        assert_eq!(p.real(0), Some(p.origin));
        assert_eq!(Pace::new(TimeScale::Max, 0).real(10_000), None);
    }
}
