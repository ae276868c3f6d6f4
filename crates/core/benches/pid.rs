//! PID operation with 32 loops in one scan against the manual's processing
//! times (seed 001 Appendix 1, Q04UDH-class CPU): S.PIDCONT 32 loops 728–744 µs
//! (first processing 927–931 µs), PIDCONT 32 loops 622–645 µs (first 776–785 µs).
//!
//! Each iteration is one whole scan (`LD SM400`, the PID instruction, END
//! processing) with every one of the 32 loops due (Ts = 10 ms, 10 ms scans,
//! loops per scan 32), in auto mode with P, I and D (and KD for S.PIDCONT)
//! active. "first" clears the I/O work words before each scan so all 32 loops
//! run their first processing. An empty scan is measured as the baseline.
//! Run: `cargo bench -p softplc-core --bench pid`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use softplc_core::device::{DeviceConfig, DeviceKind};
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;

const LOOPS: u32 = 32;
const DATA: u32 = 500;
const IO: u32 = 2000;

struct Setup {
    name: &'static str,
    src: String,
    params: u32,
    io: u32,
    manual_us: &'static str,
}

fn setups() -> Vec<Setup> {
    vec![
        Setup {
            name: "S.PIDCONT_32_loops",
            src: format!("LD SM400\nSP.PIDINIT D{DATA}\nS.PIDCONT D{IO}\nEND\n"),
            params: 14,
            io: 23,
            manual_us: "728-744 µs (first 927-931 µs)",
        },
        Setup {
            name: "PIDCONT_32_loops",
            src: format!("LD SM400\nPIDINITP D{DATA}\nPIDCONT D{IO}\nEND\n"),
            params: 10,
            io: 18,
            manual_us: "622-645 µs (first 776-785 µs)",
        },
        Setup {
            name: "empty_scan",
            src: "END\n".into(),
            params: 0,
            io: 0,
            manual_us: "-",
        },
    ]
}

fn cpu(s: &Setup) -> (Cpu, VirtualClock) {
    let prog =
        compile_il("bench.il", &s.src, &DeviceConfig::default()).expect("bench program loads");
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(clock.clone()),
    );
    if s.params > 0 {
        let mem = &mut cpu;
        let mut put = |n: u32, v: i32| mem.set_word(DeviceKind::D, n as i64, v as u16).unwrap();
        put(DATA, LOOPS as i32);
        put(DATA + 1, LOOPS as i32);
        for i in 0..LOOPS {
            let m = DATA + 2 + s.params * i;
            // select, Ts 10 ms, Kp 1.50, TI 10 s, TD 0.50 s, α 20 %, MV 0..2000,
            // ΔMVL 100, ΔPVL 100 (+ reserved 0, KD 8.00, 0, 0).
            for (j, v) in [
                (i % 2) as i32,
                1,
                150,
                100,
                50,
                20,
                0,
                2000,
                100,
                100,
                0,
                800,
                0,
                0,
            ]
            .iter()
            .take(s.params as usize)
            .enumerate()
            {
                put(m + j as u32, *v);
            }
            let b = IO + 10 + s.io * i;
            put(b, 1000); // SV
            put(b + 1, 900 + i as i32); // PV
            put(b + 5, 1); // auto
        }
    }
    (cpu, clock)
}

/// Clears the loops' MV and work words: the next scan is a first processing.
fn restart(cpu: &mut Cpu, s: &Setup) {
    for i in 0..LOOPS {
        let b = IO + 10 + s.io * i;
        for w in (b + 2..b + s.io).filter(|&w| w != b + 5) {
            cpu.set_word(DeviceKind::D, w as i64, 0).unwrap();
        }
    }
}

fn time_scans(cpu: &mut Cpu, clock: &VirtualClock, s: &Setup, first: bool) -> f64 {
    let reps = 2000;
    let mut total = std::time::Duration::ZERO;
    for _ in 0..reps {
        if first {
            restart(cpu, s);
        }
        clock.advance_us(10_000);
        let t = std::time::Instant::now();
        cpu.scan();
        total += t.elapsed();
    }
    total.as_nanos() as f64 / reps as f64
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("pid");
    g.throughput(Throughput::Elements(LOOPS as u64));
    let mut lines = vec![];
    for s in setups() {
        let (mut cpu, clock) = cpu(&s);
        for _ in 0..3 {
            clock.advance_us(10_000);
            cpu.scan();
        }
        assert!(cpu.error().is_none(), "{}: {:?}", s.name, cpu.error());
        g.bench_function(s.name, |b| {
            b.iter(|| {
                clock.advance_us(10_000);
                cpu.scan();
            })
        });
        let later = time_scans(&mut cpu, &clock, &s, false);
        let first = if s.params > 0 {
            time_scans(&mut cpu, &clock, &s, true)
        } else {
            0.0
        };
        assert!(cpu.error().is_none(), "{}: {:?}", s.name, cpu.error());
        lines.push(format!(
            "{}: {later:.0} ns/scan (first processing {first:.0} ns/scan); manual: {}",
            s.name, s.manual_us
        ));
    }
    g.finish();
    for l in lines {
        eprintln!("{l}");
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
