//! State files (contract §7): save and load of a CPU with a 60k-step
//! program and 1 M words of file registers — the whole file each time,
//! identity hash and checksum included. Run:
//! `cargo bench -p softplc-core --bench snapshot`.

use criterion::{criterion_group, criterion_main, Criterion};
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_core::snapshot;

mod programs;

/// Words of file registers (ZR0-ZR1048575).
const ZR_WORDS: u32 = 1 << 20;

/// The contacts, the timers/counters and the mixed programs together:
/// over 60k steps, so a model with the program memory for them.
fn big_program() -> String {
    let (a, _) = programs::contacts();
    let (b, _) = programs::timers_counters_compare();
    let (c, _) = programs::mixed();
    [a, b, c]
        .iter()
        .map(|s| s.trim_end().trim_end_matches("END"))
        .collect::<String>()
        + "END\n"
}

fn cpu(src: &str) -> (Cpu, VirtualClock) {
    let profile = softplc_core::profile::find("Q25HCPU").expect("a known model");
    let mut cfg = softplc_core::profile::config(profile);
    cfg.devices.set_points(DeviceKind::ZR, ZR_WORDS);
    let prog = compile_il("bench.il", src, &cfg.devices).expect("bench program loads");
    eprintln!("program: {} steps, {} ops", prog.steps, prog.ops.len());
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    for _ in 0..10 {
        clock.advance_us(10_000);
        cpu.scan();
    }
    (cpu, clock)
}

/// Mean ms of a save and of a load of `cpu`'s state, `reps` each.
fn timed(cpu: &mut Cpu, reps: u32) -> (f64, f64) {
    let file = snapshot::save(cpu);
    let t = std::time::Instant::now();
    for _ in 0..reps {
        std::hint::black_box(snapshot::save(cpu));
    }
    let save = t.elapsed().as_secs_f64() * 1e3 / f64::from(reps);
    let t = std::time::Instant::now();
    for _ in 0..reps {
        snapshot::load(cpu, &file).expect("its own file loads");
    }
    let load = t.elapsed().as_secs_f64() * 1e3 / f64::from(reps);
    (save, load)
}

fn bench(c: &mut Criterion) {
    let (mut cpu, _clock) = cpu(&big_program());
    let file = snapshot::save(&mut cpu);
    eprintln!("state file: {:.1} MB", file.len() as f64 / 1e6);
    let mut g = c.benchmark_group("snapshot");
    g.sample_size(20);
    g.bench_function("save_60k_steps_1M_words", |b| {
        b.iter(|| snapshot::save(&mut cpu))
    });
    g.bench_function("load_60k_steps_1M_words", |b| {
        b.iter(|| snapshot::load(&mut cpu, &file).expect("its own file loads"))
    });
    g.finish();
    // Plain timings for the summary lines: the program's share is its
    // identity (a one-rung program with the same file registers).
    let (save, load) = timed(&mut cpu, 20);
    eprintln!("snapshot: save {save:.1} ms, load {load:.1} ms");
    let (mut small, _clock) = cpu_small();
    let (save, load) = timed(&mut small, 20);
    eprintln!("snapshot, one-rung program: save {save:.1} ms, load {load:.1} ms");
}

fn cpu_small() -> (Cpu, VirtualClock) {
    cpu("LD SM400\nINC D0\nEND\n")
}

criterion_group!(benches, bench);
criterion_main!(benches);
