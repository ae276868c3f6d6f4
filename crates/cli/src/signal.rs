//! Ctrl-C and SIGTERM for `softplc run`: instead of killing the process they
//! set the CPU's abort flag, which stops it even in the middle of a scan stuck
//! in an endless loop, so latched data is committed before exit.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, OnceLock};

static ABORT: OnceLock<Vec<Arc<AtomicBool>>> = OnceLock::new();
/// The signal that arrived (0: none).
static SIGNAL: AtomicI32 = AtomicI32::new(0);

extern "C" fn on_signal(sig: libc::c_int) {
    // Only atomics here: async-signal-safe.
    SIGNAL.store(sig, Ordering::SeqCst);
    for a in ABORT.get().into_iter().flatten() {
        a.store(true, Ordering::SeqCst);
    }
}

/// Routes SIGINT and SIGTERM to `abort` (once per process).
pub fn stop_on_signals(abort: Arc<AtomicBool>) {
    stop_on_signals_all(vec![abort]);
}

/// Routes SIGINT and SIGTERM to every CPU's abort flag (a multi-CPU system).
pub fn stop_on_signals_all(aborts: Vec<Arc<AtomicBool>>) {
    if ABORT.set(aborts).is_err() {
        return;
    }
    for sig in [libc::SIGINT, libc::SIGTERM] {
        // SAFETY: `sigaction` is given a zeroed (valid) struct whose handler is
        // an `extern "C"` function that only touches atomics (async-signal-safe)
        // and an empty mask; the old action is not needed (null).
        unsafe {
            let mut sa: libc::sigaction = std::mem::zeroed();
            sa.sa_sigaction = on_signal as *const () as libc::sighandler_t;
            libc::sigemptyset(&mut sa.sa_mask);
            libc::sigaction(sig, &sa, std::ptr::null_mut());
        }
    }
}

/// The signal that stopped the run, if any (`SIGINT`, `SIGTERM`).
pub fn received() -> Option<i32> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s),
    }
}
