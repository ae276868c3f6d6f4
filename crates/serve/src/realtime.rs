//! The engine thread's real-time setup and its wait for a scan's deadline:
//! SCHED_FIFO, locked memory, CPU pinning, and a sleep on the monotonic
//! clock that ends a short busy-wait before the deadline.
//!
//! Every request is best effort: what is not permitted (no CAP_SYS_NICE, no
//! CAP_IPC_LOCK) is reported once in [`Applied::note`] and the loop goes on
//! at normal priority.

use std::time::{Duration, Instant};

/// What the engine thread asks of the operating system (`serve --realtime`,
/// `--no-realtime`, `--spin-us`, `--cpu`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RealTime {
    /// SCHED_FIFO at the middle priority.
    pub fifo: bool,
    /// `mlockall(MCL_CURRENT | MCL_FUTURE)`: no page fault stalls a scan.
    pub lock_memory: bool,
    /// The busy-wait before each deadline: the sleep ends this much early
    /// (the sleep's wake-up latency is hidden while it stays below it).
    /// Zero: sleep only.
    pub spin: Duration,
    /// Pin the engine thread to this CPU.
    pub cpu: Option<usize>,
}

impl RealTime {
    /// `--spin-us` by default: above the wake-up latency of an idle Linux
    /// machine, a fifth of a 1 ms period.
    pub const DEFAULT_SPIN: Duration = Duration::from_micros(200);

    /// Normal priority, memory not locked, not pinned (tests, benchmarks,
    /// `serve --no-realtime`); the default spin.
    pub fn none() -> RealTime {
        RealTime {
            fifo: false,
            ..RealTime::default()
        }
    }
}

/// `serve` without options: SCHED_FIFO when granted, the default spin.
impl Default for RealTime {
    fn default() -> RealTime {
        RealTime {
            fifo: true,
            lock_memory: false,
            spin: RealTime::DEFAULT_SPIN,
            cpu: None,
        }
    }
}

/// What the engine thread got.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Applied {
    /// SCHED_FIFO was granted.
    pub fifo: bool,
    /// mlockall succeeded.
    pub memory_locked: bool,
    /// The CPU the thread is pinned to.
    pub cpu: Option<usize>,
    /// For the log: "SCHED_FIFO priority 50; memory locked; pinned to CPU 1",
    /// or why a request was not granted.
    pub note: String,
}

/// Applies `rt` to the calling (engine) thread.
pub fn apply(rt: &RealTime) -> Applied {
    let mut a = Applied::default();
    let mut notes = Vec::new();
    if rt.fifo {
        let (granted, note) = set_fifo();
        a.fifo = granted;
        notes.push(note);
    } else {
        notes.push("not requested".to_string());
    }
    if rt.lock_memory {
        match lock_memory() {
            Ok(()) => {
                a.memory_locked = true;
                notes.push("memory locked".into());
            }
            Err(e) => notes.push(format!("memory not locked ({e})")),
        }
    }
    if let Some(cpu) = rt.cpu {
        match pin(cpu) {
            Ok(()) => {
                a.cpu = Some(cpu);
                notes.push(format!("pinned to CPU {cpu}"));
            }
            Err(e) => notes.push(format!("not pinned to CPU {cpu} ({e})")),
        }
    }
    fine_timer_slack();
    a.note = notes.join("; ");
    a
}

/// Real-time priority for the calling thread: SCHED_FIFO at the middle of
/// the range, so the kernel's own real-time threads stay above it. Needs
/// CAP_SYS_NICE (or an RLIMIT_RTPRIO); without it the thread keeps the
/// normal policy and the reason is reported.
#[cfg(target_os = "linux")]
fn set_fifo() -> (bool, String) {
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
fn set_fifo() -> (bool, String) {
    (false, "not available on this system".into())
}

#[cfg(target_os = "linux")]
fn lock_memory() -> Result<(), String> {
    use nix::sys::mman::{mlockall, MlockAllFlags};
    mlockall(MlockAllFlags::MCL_CURRENT | MlockAllFlags::MCL_FUTURE)
        .map_err(|e| format!("{}; needs CAP_IPC_LOCK or a large RLIMIT_MEMLOCK", e.desc()))
}

#[cfg(not(target_os = "linux"))]
fn lock_memory() -> Result<(), String> {
    Err("not available on this system".into())
}

#[cfg(target_os = "linux")]
fn pin(cpu: usize) -> Result<(), String> {
    use nix::sched::{sched_setaffinity, CpuSet};
    use nix::unistd::Pid;
    let mut set = CpuSet::new();
    set.set(cpu).map_err(|e| e.desc().to_string())?;
    // Pid 0: the calling thread.
    sched_setaffinity(Pid::from_raw(0), &set).map_err(|e| e.desc().to_string())
}

#[cfg(not(target_os = "linux"))]
fn pin(_cpu: usize) -> Result<(), String> {
    Err("not available on this system".into())
}

/// Checks `--cpu N` before anything starts: `Err` names the CPUs this
/// process may run on.
pub fn check_cpu(cpu: usize) -> Result<(), String> {
    #[cfg(target_os = "linux")]
    {
        use nix::sched::{sched_getaffinity, CpuSet};
        use nix::unistd::Pid;
        let Ok(set) = sched_getaffinity(Pid::from_raw(0)) else {
            return Ok(());
        };
        let allowed: Vec<usize> = (0..CpuSet::count())
            .filter(|&c| set.is_set(c).unwrap_or(false))
            .collect();
        if allowed.contains(&cpu) {
            return Ok(());
        }
        Err(format!(
            "CPU {cpu} is not one this process may run on ({})",
            ranges(&allowed)
        ))
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = cpu;
        Err("pinning is not available on this system".into())
    }
}

/// "0-3, 6" for a sorted list of CPU numbers.
fn ranges(cpus: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < cpus.len() {
        let mut j = i;
        while j + 1 < cpus.len() && cpus[j + 1] == cpus[j] + 1 {
            j += 1;
        }
        out.push(if i == j {
            cpus[i].to_string()
        } else {
            format!("{}-{}", cpus[i], cpus[j])
        });
        i = j + 1;
    }
    if out.is_empty() {
        "none".into()
    } else {
        format!("CPUs {}", out.join(", "))
    }
}

/// A normal-priority thread's sleeps end up to 50 µs late by default (the
/// kernel's timer slack, which lets it merge wake-ups); the engine thread's
/// deadline is exact. SCHED_FIFO threads have no slack anyway.
fn fine_timer_slack() {
    #[cfg(target_os = "linux")]
    let _ = nix::sys::prctl::set_timerslack(1);
}

/// Sleeps until `spin` before `t`, then busy-waits until `t`: the scan
/// starts on time whenever the sleep's wake-up latency stays below `spin`.
pub fn wait_until(t: Instant, spin: Duration) {
    if let Some(sleep_to) = t.checked_sub(spin) {
        sleep_until(sleep_to);
    }
    while Instant::now() < t {
        std::hint::spin_loop();
    }
}

/// Sleeps until `t` (if it is ahead) on CLOCK_MONOTONIC, the clock of
/// `Instant`, with an absolute deadline: a signal or a preemption between
/// reading the clock and sleeping does not move the wake-up.
#[cfg(target_os = "linux")]
fn sleep_until(t: Instant) {
    use nix::sys::time::TimeSpec;
    use nix::time::{clock_gettime, clock_nanosleep, ClockId, ClockNanosleepFlags};
    let ahead = t.saturating_duration_since(Instant::now());
    if ahead.is_zero() {
        return;
    }
    let clock = ClockId::CLOCK_MONOTONIC;
    let Ok(now) = clock_gettime(clock) else {
        std::thread::sleep(ahead);
        return;
    };
    let deadline = now + TimeSpec::from_duration(ahead);
    while let Err(nix::errno::Errno::EINTR) =
        clock_nanosleep(clock, ClockNanosleepFlags::TIMER_ABSTIME, &deadline)
    {}
}

#[cfg(not(target_os = "linux"))]
fn sleep_until(t: Instant) {
    let ahead = t.saturating_duration_since(Instant::now());
    if !ahead.is_zero() {
        std::thread::sleep(ahead);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_lists_read_as_ranges() {
        assert_eq!(ranges(&[0, 1, 2, 3, 6]), "CPUs 0-3, 6");
        assert_eq!(ranges(&[1]), "CPUs 1");
        assert_eq!(ranges(&[0, 2, 4, 5]), "CPUs 0, 2, 4-5");
        assert_eq!(ranges(&[]), "none");
    }

    #[test]
    fn a_cpu_beyond_any_set_is_refused() {
        let e = check_cpu(100_000).unwrap_err();
        assert!(e.starts_with("CPU 100000 is not one"), "{e}");
    }

    #[test]
    fn the_wait_never_ends_before_its_deadline() {
        for spin in [Duration::ZERO, Duration::from_micros(200)] {
            let t = Instant::now() + Duration::from_millis(2);
            wait_until(t, spin);
            assert!(Instant::now() >= t);
        }
        // A deadline in the past returns at once (nothing to wait for).
        wait_until(
            Instant::now() - Duration::from_millis(1),
            RealTime::DEFAULT_SPIN,
        );
    }
}
