//! Compile time of the native-code tier, in process (docs/performance.md,
//! "Tiers"): each `.il` file compiled for the default CPU on the JIT, then
//! `SCANS` scans of 10 ms (default 2,000) timed.
//!
//! ```sh
//! cargo run --release -p softplc-core --example jit_compile -- FILE.il... [SCANS=N]
//! ```

use std::process::ExitCode;
use std::time::Instant;

use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::load_file;
use softplc_core::tier::Jit;

fn main() -> ExitCode {
    let cfg = softplc_core::profile::default_config();
    let scans: u32 = std::env::var("SCANS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000);
    for path in std::env::args().skip(1) {
        let prog = match load_file(path.as_ref(), &cfg.devices) {
            Ok(p) => p,
            Err(d) => {
                eprintln!("{path}: {d}");
                return ExitCode::from(1);
            }
        };
        let ops = prog.ops.len();
        let clock = VirtualClock::new();
        let mut cpu = Cpu::new(prog, cfg.clone(), Box::new(clock.clone()));
        let t = Instant::now();
        if let Err(e) = cpu.use_tier(&Jit::default()) {
            eprintln!("{path}: {e}");
            return ExitCode::from(1);
        }
        let us = t.elapsed().as_secs_f64() * 1e6;
        let t = Instant::now();
        for _ in 0..scans {
            clock.advance_us(10_000);
            cpu.scan();
        }
        let scan_ns = t.elapsed().as_secs_f64() * 1e9 / f64::from(scans.max(1));
        println!(
            "{path}: {ops} ops, compiled in {:.1} ms ({:.2} us per op), {:.2} us per scan ({:.3} ns per op)",
            us / 1e3,
            us / ops as f64,
            scan_ns / 1e3,
            scan_ns / ops as f64
        );
    }
    ExitCode::SUCCESS
}
