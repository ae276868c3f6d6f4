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
use softplc_core::system::System;

use softplc_core::system::Cpus;

use crate::realtime::{self, Applied, RealTime};
use crate::timing::Timing;

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
    /// How the real-time request went, for the log ("SCHED_FIFO priority 50;
    /// memory locked; pinned to CPU 1", "not granted (Operation not
    /// permitted …)…", "not requested").
    pub realtime_note: String,
    /// `mlockall` succeeded (`serve --realtime`).
    pub memory_locked: bool,
    /// The CPU the engine thread is pinned to (`serve --cpu`).
    pub pinned: Option<usize>,
    /// Each CPU's own scans, CPU 1 first (the fields above are the whole
    /// loop's, their execution times CPU 1's).
    pub cpus: Vec<CpuStats>,
}

/// One CPU's execution times and overruns (a multi-CPU system's CPUs scan
/// at their own periods in one loop).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CpuStats {
    /// Execution time of its last executed scan, and the least and most, µs
    /// (as [`ScanStats::exec_us`]).
    pub exec_us: u64,
    pub exec_min_us: u64,
    pub exec_max_us: u64,
    /// Its scans whose next one was due before it ended.
    pub overruns: u64,
    timed: bool,
}

impl CpuStats {
    fn record(&mut self, exec: u64) {
        self.exec_min_us = if self.timed {
            self.exec_min_us.min(exec)
        } else {
            exec
        };
        self.timed = true;
        self.exec_us = exec;
        self.exec_max_us = self.exec_max_us.max(exec);
    }
}

/// Everything a request may touch, owned by the engine thread.
pub struct ServeState {
    /// The CPU, or a multi-CPU system's CPUs; requests address one of them.
    pub cpus: Cpus,
    pub stats: ScanStats,
    /// Distributions of scan start lateness, period jitter and execution
    /// time (`GET /api/v1/timing`).
    pub timing: Timing,
    /// Protocol state shared by all connections of one protocol (e.g. Modbus
    /// diagnostic counters), set up by the server that needs it.
    pub ext: Vec<Box<dyn std::any::Any + Send>>,
    /// The CPUs a request may have changed the device memory of (a write, a
    /// remote operation), one bit each ([`ServeState::mark_wrote`]): this
    /// END is committed to their state directories before any reply goes
    /// out (acknowledged writes are never lost).
    wrote: u8,
    /// Each CPU's battery-backed memory, committed after END processing.
    batteries: Vec<Option<Battery>>,
    /// Replies of this END, sent after its commit.
    pub(crate) replies: Vec<Box<dyn FnOnce() + Send>>,
    /// Called on the engine thread after every scan, before the requests of
    /// its END (the web monitor's step, breakpoints and snapshots). Add one
    /// from a request with [`ServeState::add_hook`].
    hooks: Vec<(&'static str, Hook)>,
    /// Called after the requests of every END, before its commit
    /// ([`ServeState::add_after_requests`]: a recording's frame).
    after_requests: Vec<Hook>,
    /// The door whose request or hook runs now ([`EngineHandle::for_door`]),
    /// and who is told when it changes ([`ServeState::watch_doors`]).
    door: &'static str,
    door_watch: Option<Box<dyn FnMut(&'static str) + Send>>,
    /// The CPU whose scan ended last.
    scanned: usize,
    /// Scans (ENDs) the engine has run, executed or not.
    ends: u64,
    /// Virtual time (`serve --time-scale`, `--lockstep`), when the CPUs run
    /// on it ([`ServeState::set_virtual_time`]).
    pub(crate) sim: Option<crate::sim::Sim>,
}

/// An END hook ([`ServeState::add_hook`]).
pub type Hook = Box<dyn FnMut(&mut ServeState) + Send>;

impl ServeState {
    /// One CPU (its battery is [`EngineConfig::battery`]).
    pub fn new(cpu: Cpu) -> Self {
        Self::with(Cpus::One(cpu), vec![None])
    }

    /// A multi-CPU system, each CPU with the battery-backed memory of its
    /// project's state directory (CPU 1's first).
    pub fn system(system: System, batteries: Vec<Option<Battery>>) -> Self {
        let mut batteries = batteries;
        batteries.resize_with(system.len(), || None);
        Self::with(Cpus::System(system), batteries)
    }

    fn with(cpus: Cpus, batteries: Vec<Option<Battery>>) -> Self {
        ServeState {
            stats: ScanStats {
                cpus: vec![CpuStats::default(); cpus.len()],
                ..ScanStats::default()
            },
            cpus,
            timing: Timing::default(),
            ext: Vec::new(),
            wrote: 0,
            batteries,
            replies: Vec::new(),
            hooks: Vec::new(),
            after_requests: Vec::new(),
            door: "",
            door_watch: None,
            scanned: 0,
            ends: 0,
            sim: None,
        }
    }

    /// CPU 1 (the only one of a single-CPU server).
    pub fn cpu(&self) -> &Cpu {
        self.cpus.get(0)
    }

    pub fn cpu_mut(&mut self) -> &mut Cpu {
        self.cpus.get_mut(0)
    }

    /// CPU `i`, 0-based (`i <` [`Self::cpu_count`]).
    pub fn cpu_at(&self, i: usize) -> &Cpu {
        self.cpus.get(i)
    }

    pub fn cpu_mut_at(&mut self, i: usize) -> &mut Cpu {
        self.cpus.get_mut(i)
    }

    /// Number of CPUs served (1-4).
    pub fn cpu_count(&self) -> usize {
        self.cpus.len()
    }

    /// Scans (ENDs) the engine has run since it started, STOP and PAUSE
    /// included: requests served again before the next scan (at a held or
    /// paced END) see the same count.
    pub fn ends(&self) -> u64 {
        self.ends
    }

    /// The CPU (0-based) whose scan ended last: the END hooks run after it.
    pub fn scanned(&self) -> usize {
        self.scanned
    }

    /// A request changed (or may have changed) CPU `i`'s device memory: this
    /// END is committed before its replies go out.
    pub fn mark_wrote(&mut self, i: usize) {
        self.wrote |= 1 << i.min(7);
    }

    /// Runs `hook` after every scan from the next one on, before the requests
    /// of that END are served.
    /// The hook belongs to the door whose request adds it.
    pub fn add_hook(&mut self, hook: Hook) {
        self.hooks.push((self.door, hook));
    }

    /// Runs `hook` after the requests of every END, before its commit and
    /// replies.
    pub fn add_after_requests(&mut self, hook: Hook) {
        self.after_requests.push(hook);
    }

    /// Calls `watch` with the door (`"MC protocol"`, `"HTTP"` …, empty for none)
    /// each time requests or hooks of another door start to run.
    pub fn watch_doors(&mut self, watch: Box<dyn FnMut(&'static str) + Send>) {
        self.door_watch = Some(watch);
    }

    fn enter_door(&mut self, door: &'static str) {
        if self.door != door {
            self.door = door;
            if let Some(w) = &mut self.door_watch {
                w(door);
            }
        }
    }

    /// Runs the END hooks (the engine thread, after each scan).
    pub(crate) fn run_hooks(&mut self) {
        if self.hooks.is_empty() {
            return;
        }
        let mut hooks = std::mem::take(&mut self.hooks);
        for (door, h) in &mut hooks {
            self.enter_door(door);
            h(self);
        }
        // Hooks added by a hook run from the next END.
        hooks.append(&mut self.hooks);
        self.hooks = hooks;
    }

    fn run_after_requests(&mut self) {
        if self.after_requests.is_empty() {
            return;
        }
        self.enter_door("");
        let mut hooks = std::mem::take(&mut self.after_requests);
        for h in &mut hooks {
            h(self);
        }
        hooks.append(&mut self.after_requests);
        self.after_requests = hooks;
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

pub(crate) type Job = Box<dyn FnOnce(&mut ServeState) + Send>;

/// The queue is full: the engine is not keeping up (reply "busy").
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the PLC is busy: request queue full or engine stopped")]
pub struct Busy;

/// Sends work to the engine thread; cheap to clone.
#[derive(Clone)]
pub struct EngineHandle {
    tx: SyncSender<Job>,
    /// The door whose requests this handle sends (empty: none named).
    door: &'static str,
}

impl EngineHandle {
    /// A handle whose requests are `door`'s (a recording names it).
    pub fn for_door(&self, door: &'static str) -> EngineHandle {
        EngineHandle {
            tx: self.tx.clone(),
            door,
        }
    }
}

impl EngineHandle {
    /// Runs `f` at the next END processing and returns its result.
    pub async fn at_end<R, F>(&self, f: F) -> Result<R, Busy>
    where
        R: Send + 'static,
        F: FnOnce(&mut ServeState) -> R + Send + 'static,
    {
        let (otx, orx) = tokio::sync::oneshot::channel();
        let door = self.door;
        let job: Job = Box::new(move |s| {
            s.enter_door(door);
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
        let door = self.door;
        let job: Job = Box::new(move |s| {
            s.enter_door(door);
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
    /// Battery-backed memory of a single CPU, committed after END
    /// processing (a system's are given to [`ServeState::system`]).
    pub battery: Option<Battery>,
    /// Print the scan statistics to stderr this often.
    pub log_every: Option<Duration>,
    /// SCHED_FIFO, locked memory, pinning and the spin before each deadline.
    pub realtime: RealTime,
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
    (EngineHandle { tx, door: "" }, join)
}

/// What the engine thread is doing, for the stall watch.
#[derive(Default)]
pub(crate) struct Heartbeat {
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
    // A loop that scans as fast as it can must not hold a CPU core at
    // real-time priority.
    let flat_out = s.time_scale() == Some(crate::TimeScale::Max);
    let applied = if flat_out {
        Applied {
            note: "not requested (virtual time as fast as possible)".to_string(),
            ..Applied::default()
        }
    } else {
        realtime::apply(&cfg.realtime)
    };
    s.stats.realtime = applied.fifo;
    s.stats.memory_locked = applied.memory_locked;
    s.stats.pinned = applied.cpu;
    s.stats.realtime_note = applied.note;
    let first_period = s.cpus.periods(cfg.period).first().copied();
    s.timing
        .configure(first_period.unwrap_or(cfg.period), cfg.realtime.spin);
    if cfg.log_every.is_some() {
        eprintln!(
            "softplc: engine thread real-time: {}",
            s.stats.realtime_note
        );
    }
    if let Some(b) = cfg.battery.take() {
        s.batteries[0] = Some(b);
    }
    let mut s = if s.sim.is_some() {
        // --time-scale / --lockstep: the CPUs' clock is virtual.
        crate::sim::run(s, &cfg, &rx, &stop, beat)
    } else {
        real_time(s, &cfg, &rx, &stop, beat)
    };
    commit(&mut s, u8::MAX);
    s.replies.drain(..).for_each(|reply| reply());
    s
}

/// The real-time loop: each CPU's scan at its period on the monotonic clock.
fn real_time(
    mut s: ServeState,
    cfg: &EngineConfig,
    rx: &Receiver<Job>,
    stop: &AtomicBool,
    beat: &Heartbeat,
) -> ServeState {
    let mut schedule = Schedule::new(&s.cpus, cfg.period);
    let mut jitter_sum = 0f64;
    let mut logged = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        let (i, due) = schedule.next();
        realtime::wait_until(due, cfg.realtime.spin);
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let start = Instant::now();
        let jitter = start.saturating_duration_since(due).as_micros() as u64;
        s.timing.started(due, start);
        if i == 0 {
            s.timing.first_cpu_started(start, schedule.period[0]);
        }
        scan_cpu(&mut s, i, start, beat);
        s.run_hooks();
        serve_end(&mut s, rx, cfg);
        account(&mut s.stats, start, jitter, &mut jitter_sum);
        log_stats(&s.stats, cfg, &mut logged);
        if schedule.done(i) {
            s.stats.overruns += 1;
            s.stats.cpus[i].overruns += 1;
            s.timing.overran();
        }
    }
    s
}

/// Scans CPU `i` (started at `start`); its execution time goes to the
/// statistics when it executed (not STOP/PAUSE, as SD520).
#[inline]
pub(crate) fn scan_cpu(s: &mut ServeState, i: usize, start: Instant, beat: &Heartbeat) {
    beat.started.fetch_add(1, Ordering::Relaxed);
    let executed = s.cpus.get(i).scans();
    match &mut s.cpus {
        Cpus::One(cpu) => cpu.scan(),
        Cpus::System(sys) => sys.scan(i),
    }
    s.scanned = i;
    s.ends += 1;
    beat.finished.fetch_add(1, Ordering::Relaxed);
    if s.cpus.get(i).scans() != executed {
        let took = start.elapsed();
        if i == 0 {
            s.timing.executed(took);
        }
        let exec = took.as_micros() as u64;
        let c = &mut s.stats.cpus[i];
        c.record(exec);
        if i == 0 {
            let st = &mut s.stats;
            let c = &st.cpus[0];
            (st.exec_us, st.exec_min_us, st.exec_max_us) =
                (c.exec_us, c.exec_min_us, c.exec_max_us);
        }
    }
}

/// END processing: the queued communication requests within the budget,
/// then the commit and the replies.
#[inline]
pub(crate) fn serve_end(s: &mut ServeState, rx: &Receiver<Job>, cfg: &EngineConfig) {
    let end = Instant::now();
    while end.elapsed() < cfg.end_budget {
        match rx.try_recv() {
            Ok(job) => {
                job(s);
                s.stats.requests += 1;
            }
            Err(_) => break,
        }
    }
    s.run_after_requests();
    reply_after_commit(s, cfg);
}

/// Group commit: an END at which a request wrote is committed before any
/// reply of this END goes out, so an acknowledged write survives kill -9.
#[inline]
pub(crate) fn reply_after_commit(s: &mut ServeState, cfg: &EngineConfig) {
    let wrote = if cfg.ack_after_commit {
        std::mem::take(&mut s.wrote)
    } else {
        s.wrote = 0;
        0
    };
    if commit(s, wrote) {
        s.replies.drain(..).for_each(|reply| reply());
    } else {
        // Not durable: no acknowledgement (the clients see "busy").
        s.replies.clear();
    }
}

/// The loop's statistics after a scan started at `start` `jitter` µs late
/// and its END processing.
#[inline]
pub(crate) fn account(st: &mut ScanStats, start: Instant, jitter: u64, jitter_sum: &mut f64) {
    let busy = start.elapsed();
    st.scans += 1;
    st.current_us = busy.as_micros() as u64;
    st.min_us = if st.scans == 1 {
        st.current_us
    } else {
        st.min_us.min(st.current_us)
    };
    st.max_us = st.max_us.max(st.current_us);
    st.jitter_max_us = st.jitter_max_us.max(jitter);
    *jitter_sum += jitter as f64;
    st.jitter_mean_us = *jitter_sum / st.scans as f64;
}

/// The `--stats-every` line, when due.
#[inline]
pub(crate) fn log_stats(st: &ScanStats, cfg: &EngineConfig, logged: &mut Instant) {
    if cfg.log_every.is_some_and(|d| logged.elapsed() >= d) {
        *logged = Instant::now();
        eprintln!(
            "softplc: {} scans, scan {} us (min {}, max {}), {} overruns, jitter max {} us mean {:.0} us, {} requests; real-time: {}",
            st.scans, st.current_us, st.min_us, st.max_us, st.overruns, st.jitter_max_us, st.jitter_mean_us, st.requests,
            if st.realtime { "SCHED_FIFO" } else { "no" }
        );
    }
}

/// Commits each CPU's battery-backed memory: now for the CPUs in `wrote`
/// (one bit each), else when its interval is due. False when a write could
/// not be made durable.
pub(crate) fn commit(s: &mut ServeState, wrote: u8) -> bool {
    let mut durable = true;
    for (i, b) in s.batteries.iter_mut().enumerate() {
        let Some(b) = b else { continue };
        let now = wrote & (1 << i.min(7)) != 0;
        let cpu = s.cpus.get(i);
        let r = if now {
            b.commit(cpu).map(|_| ())
        } else {
            b.commit_due(cpu).map(|_| ())
        };
        if let Err(e) = r {
            eprintln!("softplc: cannot save state: {e}");
            durable &= !now;
        }
    }
    durable
}

/// When each CPU scans next, on the monotonic clock: every CPU once per
/// period (its constant scan in a system, else the engine's period) from
/// the first scan, the earliest due first and CPU-number order among equals
/// (as [`System::next_due`] in virtual time). After an overrun a CPU's next
/// scan is due at once and its schedule restarts, so a slow CPU never holds
/// the others back more than one scan.
struct Schedule {
    due: Vec<Instant>,
    period: Vec<Duration>,
}

impl Schedule {
    fn new(cpus: &Cpus, period: Duration) -> Schedule {
        let now = Instant::now();
        let period = cpus.periods(period);
        Schedule {
            due: vec![now; period.len()],
            period,
        }
    }

    /// The CPU to scan next and when.
    fn next(&self) -> (usize, Instant) {
        self.due
            .iter()
            .copied()
            .enumerate()
            .min_by_key(|&(i, t)| (t, i))
            .unwrap_or((0, Instant::now()))
    }

    /// After CPU `i`'s scan: true when it overran (its next scan was due
    /// before this one ended).
    fn done(&mut self, i: usize) -> bool {
        self.due[i] += self.period[i];
        let now = Instant::now();
        if now > self.due[i] {
            self.due[i] = now;
            return true;
        }
        false
    }
}
