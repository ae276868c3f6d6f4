//! The `.apl` loader must never panic, and a program that loads must run
//! without panicking (any bytes: UTF-8 or GB18030 text).
#![no_main]
use libfuzzer_sys::fuzz_target;
use softplc_core::engine::{Cpu, LoadedProgram, VirtualClock};

fuzz_target!(|data: &[u8]| {
    let Ok(program) = softplc_core::aplc::load_bytes("fuzz.apl", data) else {
        return;
    };
    let clock = VirtualClock::new();
    let p = LoadedProgram { program, exec: Default::default(), interval: None, sim_time: None, local_devices: true };
    if let Ok(mut cpu) = Cpu::with_programs(vec![p], softplc_core::aplc::cpu_config(), Box::new(clock.clone())) {
        for _ in 0..3 {
            clock.advance_us(10_000);
            cpu.scan();
        }
    }
});
