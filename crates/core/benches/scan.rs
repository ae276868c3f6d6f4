//! Scan throughput against the Q06HCPU (004 Table 3.1: LD 34 ns, MOV 102 ns).
//!
//! Each benchmark runs one whole scan (program + END processing) of a generated
//! program; criterion's throughput is instructions per second, and the
//! `ns/instruction` printed at the end is the scan time divided by the number of
//! instructions. Run: `cargo bench -p softplc-core --bench scan`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use softplc_core::device::DeviceConfig;
use softplc_core::engine::{Cpu, CpuConfig, VirtualClock};
use softplc_core::program::compile_il;

/// 50,000 contact/coil instructions: rungs of LD, AND, OR, ANI, OUT.
fn contacts_program() -> (String, u64) {
    let mut s = String::new();
    for i in 0..10_000u32 {
        let x = i % 4096;
        s += &format!(
            "LD X{x:X}\nAND M{}\nOR M{}\nANI X{:X}\nOUT M{}\n",
            (i * 7) % 8000,
            (i * 13) % 8000,
            (x + 1) % 4096,
            i % 8000
        );
    }
    s += "END\n";
    (s, 50_000)
}

/// 20,000 MOV instructions (half constant to word, half word to word) on one rung.
fn mov_program() -> (String, u64) {
    let mut s = String::from("LD SM400\n");
    for i in 0..20_000u32 {
        if i % 2 == 0 {
            s += &format!("MOV K{} D{}\n", i % 30000, i % 12000);
        } else {
            s += &format!("MOV D{} D{}\n", (i * 7) % 12000, i % 12000);
        }
    }
    s += "END\n";
    (s, 20_001)
}

/// A realistic mixed program: interlocks, timers, counters, comparisons, BIN,
/// BCD and real arithmetic, conversions and block moves, 1,000 rungs.
fn mixed_program() -> (String, u64) {
    let mut s = String::new();
    let mut n = 0u64;
    for i in 0..1000u32 {
        let (d, m) = (10 * (i % 1000), i % 4000);
        let rung = match i % 10 {
            0 => format!(
                "LD X{:X}\nOR M{m}\nANI X{:X}\nOUT M{m}\n",
                i % 256,
                (i + 1) % 256
            ),
            1 => format!("LD M{m}\nOUT T{} K50\n", i % 2000),
            2 => format!("LD X{:X}\nOUT C{} K100\n", i % 256, i % 1000),
            3 => format!("LD> D{d} K100\nAND M{m}\nMOV D{d} D{}\n", d + 1),
            4 => format!("LD SM400\n+ D{d} K1 D{}\n* D{d} K3 D{}\n", d + 2, d + 4),
            5 => format!("LD SM400\nBCD D{d} D{}\nBIN D{} D{}\n", d + 6, d + 6, d + 7),
            6 => format!("LD M{m}\nDMOV K100000 D{}\nINC D{d}\n", d + 8),
            7 => format!(
                "LD SM400\nE+ E1.5 E2.5 D{}\nINT D{} D{}\n",
                d + 2,
                d + 2,
                d + 4
            ),
            8 => format!("LDP X{:X}\nMOV K{} D{d}\n", i % 256, i),
            _ => format!(
                "LD SM400\nMPS\nAND M{m}\nOUT Y{:X}\nMPP\nANI M{m}\nOUT Y{:X}\n",
                i % 512,
                512 + i % 512
            ),
        };
        n += rung.lines().count() as u64;
        s += &rung;
    }
    s += "END\n";
    (s, n + 1)
}

fn cpu(src: &str) -> (Cpu, VirtualClock) {
    let prog = compile_il("bench.il", src, &DeviceConfig::default()).expect("bench program loads");
    let clock = VirtualClock::new();
    let cpu = Cpu::new(prog, CpuConfig::default(), Box::new(clock.clone()));
    (cpu, clock)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("scan");
    for (name, (src, n)) in [
        ("contacts_50k", contacts_program()),
        ("mov_20k", mov_program()),
        ("mixed_1000_rungs", mixed_program()),
    ] {
        let (mut cpu, clock) = cpu(&src);
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
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
