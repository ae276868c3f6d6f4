//! Programs that load must run without panicking: faults become MELSEC errors.
//! Each program runs on both tiers (issue #17), which must agree after every
//! scan on device memory, state and error; a watchdog error (wall-clock time)
//! ends the comparison, as the iterations before it differ from run to run.
#![no_main]
use std::time::Duration;

use libfuzzer_sys::fuzz_target;
use softplc_core::engine::{Cpu, CpuConfig, ErrorCode, VirtualClock};
use softplc_core::program::load_bytes;
use softplc_core::tier::{apply, Exec, Jit};

/// `exec` Jit: native code for every op that can have it, however short its
/// run, so the most crossings between native code and the interpreter.
fn cpu(data: &[u8], exec: Exec) -> Option<(Cpu, VirtualClock)> {
    let cfg = CpuConfig {
        watchdog: Duration::from_millis(20),
        ..softplc_core::profile::default_config()
    };
    let prog = load_bytes("fuzz.il", data, &cfg.devices).ok()?;
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    match exec {
        Exec::Jit => {
            cpu.use_tier(&Jit::with_min_run(1))
                .expect("the tier compiles every program that loads");
        }
        _ => {
            apply(&mut cpu, exec).expect("the tier compiles every program that loads");
        }
    }
    Some((cpu, clock))
}

fuzz_target!(|data: &[u8]| {
    let Some((mut a, ca)) = cpu(data, Exec::Interp) else {
        return;
    };
    let (mut b, cb) = cpu(data, Exec::Jit).expect("loads on both tiers");
    for _ in 0..4 {
        ca.advance_us(10_000);
        cb.advance_us(10_000);
        a.scan();
        b.scan();
        let err = |c: &Cpu| c.error().map(|e| (e.code, e.step));
        if [&a, &b].iter().any(|c| c.error().is_some_and(|e| e.code == ErrorCode(5000))) {
            return;
        }
        assert_eq!(a.state(), b.state());
        assert_eq!(err(&a), err(&b));
        assert!(a.memory().bits == b.memory().bits, "bit memory differs");
        assert!(a.memory().words == b.memory().words, "word memory differs");
    }
});
