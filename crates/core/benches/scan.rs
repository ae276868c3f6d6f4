//! Scan throughput against the Q06HCPU (004 Table 3.1: LD 34 ns, MOV 102 ns).
//!
//! Each benchmark runs one whole scan (program + END processing) of a generated
//! program; criterion's throughput is instructions per second, and the
//! `ns/instruction` printed at the end is the scan time divided by the number of
//! instructions. Every program runs on both tiers (`…/interp`, `…/jit`,
//! issue #17). Run: `cargo bench -p softplc-core --bench scan`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use softplc_core::device::DeviceConfig;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_core::tier::{apply, Exec};

mod programs;

fn cpu(src: &str, exec: Exec) -> (Cpu, VirtualClock) {
    let prog = compile_il("bench.il", src, &DeviceConfig::default()).expect("bench program loads");
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(clock.clone()),
    );
    if let Some(s) = apply(&mut cpu, exec).expect("tier") {
        eprintln!(
            "compile: {:.1} ms ({} native ops)",
            s.compile.as_secs_f64() * 1e3,
            s.native_ops
        );
    }
    (cpu, clock)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("scan");
    for (prog, (src, n)) in [
        ("contacts_50k", programs::contacts()),
        ("mov_20k", programs::movs()),
        (
            "timers_counters_compare",
            programs::timers_counters_compare(),
        ),
        ("mixed_1000_rungs", programs::mixed()),
        ("mov_chain_12k", programs::mov_chain()),
        ("tcc_groups", programs::timer_counter_compare_groups()),
    ] {
        for (tier, exec) in [("interp", Exec::Interp), ("jit", Exec::Jit)] {
            let name = &format!("{prog}/{tier}");
            let (mut cpu, clock) = cpu(&src, exec);
            g.throughput(Throughput::Elements(n));
            g.bench_function(name, |b| {
                b.iter(|| {
                    clock.advance_us(10_000);
                    cpu.scan();
                })
            });
            // A plain timing for the ns/instruction summary line.
            let t = std::time::Instant::now();
            let reps = 200;
            for _ in 0..reps {
                clock.advance_us(10_000);
                cpu.scan();
            }
            let ns = t.elapsed().as_nanos() as f64 / (reps as f64 * n as f64);
            eprintln!("{name}: {ns:.2} ns/instruction (Q06HCPU: LD 34 ns, MOV 102 ns)");
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
