//! Programs that load must run without panicking: faults become MELSEC errors.
#![no_main]
use std::time::Duration;

use libfuzzer_sys::fuzz_target;
use softplc_core::engine::{Cpu, CpuConfig, VirtualClock};
use softplc_core::program::load_bytes;

fuzz_target!(|data: &[u8]| {
    let cfg = CpuConfig {
        watchdog: Duration::from_millis(20),
        ..CpuConfig::default()
    };
    if let Ok(prog) = load_bytes("fuzz.il", data, &cfg.devices) {
        let clock = VirtualClock::new();
        let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
        for _ in 0..4 {
            clock.advance_us(10_000);
            cpu.scan();
        }
    }
});
