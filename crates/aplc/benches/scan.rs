//! APLC scan throughput against the APLC-TCP's 0.3 µs basic-instruction time
//! (002 L849-850; issue #13 asks for ≥ 100×, i.e. ≤ 3 ns an instruction).
//! Run: `cargo bench -p softplc-aplc --bench scan`; the `ns/instruction` line
//! is the scan time divided by the number of instructions.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use softplc_engine::{Cpu, CpuConfig, LoadedProgram, VirtualClock};

/// 50,000 contact/coil instructions: rungs of LD, AND, OR, ANI, OUT.
fn contacts_program() -> (String, u64) {
    let mut s = String::new();
    for i in 0..10_000u32 {
        let x = i % 128;
        s += &format!(
            "LD X{x:o}\nAND M{}\nOR M{}\nANI X{:o}\nOUT M{}\n",
            (i * 7) % 2048,
            (i * 13) % 2048,
            (x + 1) % 128,
            i % 2048
        );
    }
    (s, 50_000)
}

/// 20,000 MOV (half constant to word, half word to word) on one rung.
fn mov_program() -> (String, u64) {
    let mut s = String::from("LD SM0\n");
    for i in 0..20_000u32 {
        if i % 2 == 0 {
            s += &format!("MOV {} D{}\n", i % 30000, i % 8000);
        } else {
            s += &format!("MOV D{} D{}\n", (i * 7) % 8000, i % 8000);
        }
    }
    (s, 20_001)
}

fn cpu(src: &str) -> (Cpu, VirtualClock) {
    let program =
        softplc_aplc::load_bytes("bench.apl", src.as_bytes()).expect("bench program loads");
    let cfg = CpuConfig {
        devices: softplc_aplc::device_config(),
        latch: Vec::new(),
        system: softplc_aplc::system(),
        ..CpuConfig::new(&softplc_aplc::profile::PROFILE)
    };
    let clock = VirtualClock::new();
    let p = LoadedProgram {
        program,
        exec: Default::default(),
        interval: None,
        sim_time: None,
        local_devices: true,
    };
    let cpu = Cpu::with_programs(vec![p], cfg, Box::new(clock.clone())).expect("cpu");
    (cpu, clock)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("aplc_scan");
    for (name, (src, n)) in [
        ("contacts_50k", contacts_program()),
        ("mov_20k", mov_program()),
    ] {
        let (mut cpu, clock) = cpu(&src);
        g.throughput(Throughput::Elements(n));
        g.bench_function(name, |b| {
            b.iter(|| {
                clock.advance_us(10_000);
                cpu.scan();
            })
        });
        let t = std::time::Instant::now();
        let reps = 200;
        for _ in 0..reps {
            clock.advance_us(10_000);
            cpu.scan();
        }
        let ns = t.elapsed().as_nanos() as f64 / (reps as f64 * n as f64);
        eprintln!("{name}: {ns:.2} ns/instruction (APLC-TCP: 300 ns a basic instruction, L849)");
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
