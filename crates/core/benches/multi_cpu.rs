//! A two-CPU system against its two CPUs alone (issue: "a two-CPU system
//! scans at no more than ~2× the cost of its two CPUs alone"): one
//! iteration is one scan of each CPU, alone (two independent CPUs) or in the
//! system (both scans and both ENDs' exchange: own information, 2 auto
//! refresh settings of 2 + 64 words a CPU, the shared-memory mirrors).
//! Run: `cargo bench -p softplc-core --bench multi_cpu`.

use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use softplc_core::engine::{Clock, Cpu, VirtualClock};
use softplc_core::system::System;
use softplc_core::tier::{apply, Exec};

mod programs;

const PARAMS: &str = "[[program]]\nfile = \"main.il\"\n\
    [multi_cpu]\ncpus = 2\n\
    [[multi_cpu.refresh]]\ndevice = \"B1000\"\nwords = [2, 2]\n\
    [[multi_cpu.refresh]]\ndevice = \"D5000\"\nwords = [64, 64]\n";

/// A system directory with the same program in both CPUs.
fn write_system(dir: &Path, program: &str) {
    std::fs::write(
        dir.join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    for d in ["cpu1", "cpu2"] {
        let p = dir.join(d);
        std::fs::create_dir_all(&p).unwrap();
        std::fs::write(p.join("plc.toml"), PARAMS).unwrap();
        std::fs::write(p.join("main.il"), program).unwrap();
    }
}

fn alone(dir: &Path, exec: Exec, clock: &VirtualClock) -> Vec<Cpu> {
    ["cpu1", "cpu2"]
        .iter()
        .map(|d| {
            let p = softplc_core::project::load_project(&dir.join(d)).unwrap();
            let mut cpu = p.build_cpu(Box::new(clock.clone())).unwrap();
            apply(&mut cpu, exec).unwrap();
            cpu
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("multi_cpu");
    let tiny = ("LD SM400\nINC D0\nEND\n".to_string(), 3);
    for (name, (src, _)) in [("one_rung", tiny), ("mixed_1000_rungs", programs::mixed())] {
        let dir = tempfile::tempdir().unwrap();
        write_system(dir.path(), &src);
        for (tier, exec) in [("interp", Exec::Interp), ("jit", Exec::Jit)] {
            let clock = VirtualClock::new();
            let mut cpus = alone(dir.path(), exec, &clock);
            g.bench_function(format!("{name}/{tier}/two_alone"), |b| {
                b.iter(|| {
                    clock.advance_us(10_000);
                    for cpu in &mut cpus {
                        cpu.scan();
                    }
                })
            });
            let clock = VirtualClock::new();
            let c2 = clock.clone();
            let mut sys =
                System::load(dir.path(), &mut || Box::new(c2.clone()) as Box<dyn Clock>).unwrap();
            for i in 0..2 {
                apply(sys.cpu_mut(i), exec).unwrap();
            }
            sys.schedule(Duration::from_millis(10), 0);
            let mut t = 0;
            g.bench_function(format!("{name}/{tier}/system"), |b| {
                b.iter(|| {
                    t += 10_000;
                    sys.run_until(t, &clock);
                })
            });
            assert!(sys.cpu(0).error().is_none() && sys.cpu(1).error().is_none());
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
