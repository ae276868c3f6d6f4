//! The real-time engine thread: one scan per constant-scan period on the
//! monotonic clock, and END processing that serves the protocol requests queued
//! since the previous END (004 §4.3: communication is processed at END), so a
//! reply never shows a half-written scan.
//!
//! Requests arrive on a bounded queue; at most [`EngineConfig::end_budget`] of
//! each END is spent serving them, so a flood of clients delays replies, never
//! the scan.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender, TrySendError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use softplc_core::engine::Cpu;
use softplc_core::persist::Battery;

/// Scan statistics of the real-time loop (what the CPU's SD520-SD527 show, plus
/// the period's jitter).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScanStats {
    pub scans: u64,
    /// Execution time of the last scan (program + END processing), µs.
    pub current_us: u64,
    /// The CPU's own execution time of the last scan, from input refresh to
    /// END, without serving requests, commit or the constant-scan wait (what
    /// contract §3.1 `scan_time_us` reports), and its minimum and maximum, µs.
    pub exec_us: u64,
    pub exec_min_us: u64,
    pub exec_max_us: u64,
    pub min_us: u64,
    pub max_us: u64,
    /// Scans that did not finish within the period.
    pub overruns: u64,
    /// Largest and mean deviation of a scan's start from its due time, µs.
    pub jitter_max_us: u64,
    pub jitter_mean_us: f64,
    /// Requests served at END processing.
    pub requests: u64,
    /// The engine thread got real-time scheduling (SCHED_FIFO).
    pub realtime: bool,
    /// How the real-time request went, for the log ("SCHED_FIFO priority 50",
    /// "not granted: Operation not permitted …", "not requested").
    pub realtime_note: String,
}

/// Everything a request may touch, owned by the engine thread.
pub struct ServeState {
    pub cpu: Cpu,
    pub stats: ScanStats,
    /// Protocol state shared by all connections of one protocol (e.g. Modbus
    /// diagnostic counters), set up by the server that needs it.
    pub ext: Vec<Box<dyn std::any::Any + Send>>,
    /// Set by a request that may have changed device memory (a write, a
    /// remote operation): this END is committed to the state directory before
    /// any reply goes out (acknowledged writes are never lost).
    pub wrote: bool,
    /// Replies of this END, sent after its commit.
    replies: Vec<Box<dyn FnOnce() + Send>>,
    /// Called on the engine thread after every scan, before the requests of
    /// its END (the web monitor's step, breakpoints and snapshots). Add one
    /// from a request with [`ServeState::add_hook`].
    hooks: Vec<Hook>,
}

/// An END hook ([`ServeState::add_hook`]).
pub type Hook = Box<dyn FnMut(&mut ServeState) + Send>;

impl ServeState {
    pub fn new(cpu: Cpu) -> Self {
        ServeState {
            cpu,
            stats: ScanStats::default(),
            ext: Vec::new(),
            wrote: false,
            replies: Vec::new(),
            hooks: Vec::new(),
        }
    }

    /// Runs `hook` after every scan from the next one on, before the requests
    /// of that END are served.
    pub fn add_hook(&mut self, hook: Hook) {
        self.hooks.push(hook);
    }

    /// Runs the END hooks (the engine thread, after each scan).
    fn run_hooks(&mut self) {
        if self.hooks.is_empty() {
            return;
        }
        let mut hooks = std::mem::take(&mut self.hooks);
        for h in &mut hooks {
            h(self);
        }
        // Hooks added by a hook run from the next END.
        hooks.append(&mut self.hooks);
        self.hooks = hooks;
    }

    /// The shared protocol state of type `T`, created with `T::default()` on first use.
    pub fn ext<T: Default + Send + 'static>(&mut self) -> &mut T {
        let i = match self.ext.iter().position(|e| e.is::<T>()) {
            Some(i) => i,
            None => {
                self.ext.push(Box::new(T::default()));
                self.ext.len() - 1
            }
        };
        self.ext[i].downcast_mut().expect("checked by position")
    }
}

type Job = Box<dyn FnOnce(&mut ServeState) + Send>;

/// The queue is full: the engine is not keeping up (reply "busy").
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the PLC is busy: request queue full or engine stopped")]
pub struct Busy;

/// Sends work to the engine thread; cheap to clone.
#[derive(Clone)]
pub struct EngineHandle {
    tx: SyncSender<Job>,
}

impl EngineHandle {
    /// Runs `f` at the next END processing and returns its result.
    pub async fn at_end<R, F>(&self, f: F) -> Result<R, Busy>
    where
        R: Send + 'static,
        F: FnOnce(&mut ServeState) -> R + Send + 'static,
    {
        let (otx, orx) = tokio::sync::oneshot::channel();
        let job: Job = Box::new(move |s| {
            let r = f(s);
            s.replies.push(Box::new(move || {
                let _ = otx.send(r);
            }));
        });
        match self.tx.try_send(job) {
            Ok(()) => orx.await.map_err(|_| Busy),
            Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => Err(Busy),
        }
    }
}

impl EngineHandle {
    /// Runs `f` at the next END processing, blocking this (non-async) thread.
    pub fn call<R, F>(&self, f: F) -> Result<R, Busy>
    where
        R: Send + 'static,
        F: FnOnce(&mut ServeState) -> R + Send + 'static,
    {
        let (otx, orx) = std::sync::mpsc::sync_channel(1);
        let job: Job = Box::new(move |s| {
            let r = f(s);
            s.replies.push(Box::new(move || {
                let _ = otx.send(r);
            }));
        });
        self.tx.send(job).map_err(|_| Busy)?;
        orx.recv().map_err(|_| Busy)
    }
}

/// Real-time loop parameters.
pub struct EngineConfig {
    /// Constant-scan period.
    pub period: Duration,
    /// Time per END processing for serving requests.
    pub end_budget: Duration,
    /// Requests that may wait in the queue.
    pub queue: usize,
    /// Battery-backed memory, committed after END processing.
    pub battery: Option<Battery>,
    /// Print the scan statistics to stderr this often.
    pub log_every: Option<Duration>,
    /// Try to run the engine thread with real-time priority (SCHED_FIFO).
    pub realtime: bool,
    /// Replies to requests that wrote go out only after the END's commit (on
    /// by default; off only to measure what it costs).
    pub ack_after_commit: bool,
}

/// Starts the engine thread. It runs until `stop` is set, then commits the
/// latched data one last time and returns the state.
pub fn spawn(
    state: ServeState,
    cfg: EngineConfig,
    stop: Arc<AtomicBool>,
) -> (EngineHandle, JoinHandle<ServeState>) {
    let (tx, rx) = sync_channel::<Job>(cfg.queue.max(1));
    let beat = Arc::new(Heartbeat::default());
    let (b, st) = (beat.clone(), stop.clone());
    let stall_after = (cfg.period * 10).max(Duration::from_secs(1));
    let _ = std::thread::Builder::new()
        .name("softplc-stall-watch".into())
        .spawn(move || watch_stalls(&b, &st, stall_after));
    let join = std::thread::Builder::new()
        .name("softplc-engine".into())
        .spawn(move || run(state, cfg, rx, stop, &beat))
        .expect("spawn the engine thread");
    (EngineHandle { tx }, join)
}

/// What the engine thread is doing, for the stall watch.
#[derive(Default)]
struct Heartbeat {
    /// Scans started.
    started: std::sync::atomic::AtomicU64,
    /// Scans finished (END processing done).
    finished: std::sync::atomic::AtomicU64,
}

/// Reports a scan that does not end (an endless loop that resets the watchdog
/// with WDT never faults): once after `after`, then every 10 s while it lasts.
/// Ctrl-C/SIGTERM still stop it (the abort flag is checked on backward jumps).
fn watch_stalls(beat: &Heartbeat, stop: &AtomicBool, after: Duration) {
    let tick = Duration::from_millis(100);
    // (scan, since when it runs, when it was last reported)
    let mut current: Option<(u64, Instant, Option<Instant>)> = None;
    while !stop.load(Ordering::Relaxed) {
        std::thread::sleep(tick);
        let s = beat.started.load(Ordering::Relaxed);
        if s == beat.finished.load(Ordering::Relaxed) {
            current = None;
            continue;
        }
        let (scan, since, told) = match current {
            Some(c) if c.0 == s => c,
            _ => (s, Instant::now(), None),
        };
        let long = since.elapsed();
        let due = long >= after && told.is_none_or(|t| t.elapsed() >= Duration::from_secs(10));
        if due {
            eprintln!(
                "softplc: scan {scan} has not reached END for {:.1} s (an endless loop? WDT \
                 resets the watchdog); requests wait; Ctrl-C/SIGTERM stops the CPU",
                long.as_secs_f64()
            );
        }
        current = Some((scan, since, if due { Some(Instant::now()) } else { told }));
    }
}

fn run(
    mut s: ServeState,
    mut cfg: EngineConfig,
    rx: Receiver<Job>,
    stop: Arc<AtomicBool>,
    beat: &Heartbeat,
) -> ServeState {
    let (granted, note) = if cfg.realtime {
        set_realtime()
    } else {
        (false, "not requested".to_string())
    };
    s.stats.realtime = granted;
    s.stats.realtime_note = note;
    if cfg.log_every.is_some() {
        eprintln!(
            "softplc: engine thread real-time: {}",
            s.stats.realtime_note
        );
    }
    let period = cfg.period;
    let mut due = Instant::now();
    let mut jitter_sum = 0f64;
    let mut logged = Instant::now();
    let mut timed = false;
    while !stop.load(Ordering::Relaxed) {
        let start = Instant::now();
        let jitter = start.saturating_duration_since(due).as_micros() as u64;
        beat.started.fetch_add(1, Ordering::Relaxed);
        let executed = s.cpu.scans();
        s.cpu.scan();
        beat.finished.fetch_add(1, Ordering::Relaxed);
        if s.cpu.scans() != executed {
            // Only scans that executed (not STOP/PAUSE) count, as SD520.
            let exec = start.elapsed().as_micros() as u64;
            let st = &mut s.stats;
            st.exec_min_us = if timed {
                st.exec_min_us.min(exec)
            } else {
                exec
            };
            timed = true;
            st.exec_us = exec;
            st.exec_max_us = st.exec_max_us.max(exec);
        }
        s.run_hooks();
        // END processing: communication requests, within the budget.
        let end = Instant::now();
        while end.elapsed() < cfg.end_budget {
            match rx.try_recv() {
                Ok(job) => {
                    job(&mut s);
                    s.stats.requests += 1;
                }
                Err(_) => break,
            }
        }
        // Group commit: an END at which a request wrote is committed before any
        // reply of this END goes out, so an acknowledged write survives kill -9.
        let wrote = std::mem::take(&mut s.wrote) && cfg.ack_after_commit;
        let committed = match &mut cfg.battery {
            Some(b) if wrote => b.commit(&s.cpu).map(|_| ()),
            Some(b) => b.commit_due(&s.cpu).map(|_| ()),
            None => Ok(()),
        };
        match committed {
            Ok(()) => s.replies.drain(..).for_each(|reply| reply()),
            Err(e) => {
                eprintln!("softplc: cannot save state: {e}");
                // Not durable: no acknowledgement (the clients see "busy").
                if wrote {
                    s.replies.clear();
                } else {
                    s.replies.drain(..).for_each(|reply| reply());
                }
            }
        }
        let busy = start.elapsed();
        let st = &mut s.stats;
        st.scans += 1;
        st.current_us = busy.as_micros() as u64;
        st.min_us = if st.scans == 1 {
            st.current_us
        } else {
            st.min_us.min(st.current_us)
        };
        st.max_us = st.max_us.max(st.current_us);
        st.jitter_max_us = st.jitter_max_us.max(jitter);
        jitter_sum += jitter as f64;
        st.jitter_mean_us = jitter_sum / st.scans as f64;
        if cfg.log_every.is_some_and(|d| logged.elapsed() >= d) {
            logged = Instant::now();
            eprintln!(
                "softplc: {} scans, scan {} us (min {}, max {}), {} overruns, jitter max {} us mean {:.0} us, {} requests; real-time: {}",
                st.scans, st.current_us, st.min_us, st.max_us, st.overruns, st.jitter_max_us, st.jitter_mean_us, st.requests,
                if st.realtime { "SCHED_FIFO" } else { "no" }
            );
        }
        due += period;
        let now = Instant::now();
        if now > due {
            // Overrun: the next scan starts at once and the schedule restarts.
            st.overruns += 1;
            due = now;
            continue;
        }
        wait_until(due);
    }
    if let Some(b) = &mut cfg.battery {
        if let Err(e) = b.commit(&s.cpu) {
            eprintln!("softplc: cannot save state: {e}");
        }
    }
    s.replies.drain(..).for_each(|reply| reply());
    s
}

/// Real-time priority for the calling (engine) thread: SCHED_FIFO at the middle
/// of the range, so the kernel's own real-time threads stay above it. Needs
/// CAP_SYS_NICE (or an RLIMIT_RTPRIO); without it the thread keeps the normal
/// policy and the reason is reported.
#[cfg(target_os = "linux")]
fn set_realtime() -> (bool, String) {
    // SAFETY: plain libc calls on the current thread with a fully initialised
    // `sched_param`; no pointers are kept.
    unsafe {
        let min = libc::sched_get_priority_min(libc::SCHED_FIFO);
        let max = libc::sched_get_priority_max(libc::SCHED_FIFO);
        if min < 0 || max < min {
            return (false, "not granted: SCHED_FIFO unavailable".into());
        }
        let prio = (min + max) / 2;
        let param = libc::sched_param {
            sched_priority: prio,
        };
        match libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param) {
            0 => (true, format!("SCHED_FIFO priority {prio}")),
            e => (
                false,
                format!(
                    "not granted ({}); normal priority (needs CAP_SYS_NICE or RLIMIT_RTPRIO)",
                    std::io::Error::from_raw_os_error(e)
                ),
            ),
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn set_realtime() -> (bool, String) {
    (false, "not available on this system".into())
}

/// Sleeps until `t`, spinning for the last 200 µs for a steady period.
fn wait_until(t: Instant) {
    const SPIN: Duration = Duration::from_micros(200);
    let now = Instant::now();
    if t > now + SPIN {
        std::thread::sleep(t - now - SPIN);
    }
    while Instant::now() < t {
        std::hint::spin_loop();
    }
}
