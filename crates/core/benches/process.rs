//! Process-control instructions (seed 000) against the manual's processing
//! times (000 Appendix 3, L25671-26258: S.IN 69 µs, S.PID 94 µs, S.OUT1 44 µs
//! per instruction on a QnPHCPU): 32 loops of S.IN → S.PID → S.OUT1 per scan,
//! each loop running in AUT with P, I and D active and CT = ΔT (every
//! execution computes), and each instruction alone ×32. An empty scan is the
//! baseline. Per instruction = (scan − empty scan) / 32 (/ 3 for the loop).
//! Run: `cargo bench -p softplc-core --bench process`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use softplc_core::device::{DeviceConfig, DeviceKind};
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::instructions::process::tag;
use softplc_core::program::{compile_il_in, dialect_for, ProcessSettings};

const LOOPS: u32 = 32;
/// Loop tags D4096 + 128·i.
const TAG: u32 = 4096;

fn tag_of(i: u32) -> u32 {
    TAG + 128 * i
}

/// One loop's instructions: S.IN reads its raw input at D100 + 8i; S.PID reads
/// S.IN's BW, S.OUT1 S.PID's BW (ΔMV); block memories at D400 + 10i.
fn lines(i: u32, which: &[&str]) -> String {
    let (e, b, t) = (100 + 8 * i, 400 + 10 * i, tag_of(i));
    let mut s = String::new();
    for w in which {
        s += &match *w {
            "S.IN" => format!("S.IN D{e} D{b} D800 D{t}\n"),
            "S.PID" => format!("S.PID D{b} D{} D820 D{t} SD1506\n", b + 3),
            "S.OUT1" => format!("S.OUT1 D{} D{} D830 D{t}\n", b + 3, b + 6),
            _ => unreachable!(),
        };
    }
    s
}

fn program(which: &[&str]) -> String {
    if which.is_empty() {
        return "END\n".into();
    }
    let mut s = String::from("LD SM400\n");
    for i in 0..LOOPS {
        s += &lines(i, which);
    }
    s + "END\n"
}

fn cpu(src: &str) -> (Cpu, VirtualClock) {
    let cfg = softplc_core::profile::config(
        softplc_core::profile::find("Q06PHCPU").expect("a process CPU"),
    );
    let dialect = dialect_for(cfg.profile, ProcessSettings::default());
    let prog = compile_il_in("bench.il", src, &DeviceConfig::default(), &dialect)
        .unwrap_or_else(|d| panic!("bench program loads: {d}"));
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    let mem = &mut cpu;
    let mut put = |n: u32, v: u16| mem.set_word(DeviceKind::D, n as i64, v).unwrap();
    let putf = |put: &mut dyn FnMut(u32, u16), n: u32, v: f32| {
        put(n, v.to_bits() as u16);
        put(n + 1, (v.to_bits() >> 16) as u16);
    };
    for (k, v) in [100.0, 0.0, 100.0, 0.0, 110.0, 100.0, 0.0, -10.0]
        .iter()
        .enumerate()
    {
        putf(&mut put, 800 + 2 * k as u32, *v); // S.IN EMAX EMIN NMAX NMIN HH H L LL
    }
    putf(&mut put, 820, 8.0); // S.PID MTD
    putf(&mut put, 822, 2.0); // DVLS
    put(824, 0); // PN reverse
    put(825, 0); // TRK
    put(826, 3); // SVPTN: no cascade
    putf(&mut put, 830, 100.0); // S.OUT1 NMAX
    putf(&mut put, 832, 0.0); // NMIN
    let defaults = tag::defaults();
    for i in 0..LOOPS {
        let t = tag_of(i);
        for (k, w) in defaults.iter().enumerate() {
            put(t + k as u32, *w);
        }
        put(t + 1, 0x10); // AUT
        put(t + 3, 0); // ALM: running
        put(t + 4, 0); // INH: nothing inhibited, no tracking
        putf(&mut put, t + 14, 50.0); // SV
        putf(&mut put, t + 46, 0.1); // CT = ΔT
        putf(&mut put, t + 56, 1.0); // TD 1 s
        putf(&mut put, t + 38, 0.2); // α
        putf(&mut put, 100 + 8 * i, 40.0 + i as f32 / 8.0); // raw input
    }
    let dt = 0.1f32.to_bits();
    cpu.set_word(DeviceKind::SD, 1500, dt as u16).unwrap();
    cpu.set_word(DeviceKind::SD, 1501, (dt >> 16) as u16)
        .unwrap();
    (cpu, clock)
}

fn bench(c: &mut Criterion) {
    let setups: [(&str, &[&str], &str); 5] = [
        ("empty_scan", &[], "-"),
        ("S.IN_x32", &["S.IN"], "69 µs each"),
        ("S.PID_x32", &["S.PID"], "94 µs each"),
        ("S.OUT1_x32", &["S.OUT1"], "44 µs each"),
        (
            "loop_x32 (S.IN+S.PID+S.OUT1)",
            &["S.IN", "S.PID", "S.OUT1"],
            "207 µs a loop",
        ),
    ];
    let mut g = c.benchmark_group("process");
    g.throughput(Throughput::Elements(1));
    for (name, which, manual) in setups {
        let (mut cpu, clock) = cpu(&program(which));
        cpu.scan();
        assert_eq!(cpu.error(), None, "{name}: {:?}", cpu.error());
        eprintln!("{name}: manual {manual}");
        g.bench_function(name, |b| {
            b.iter(|| {
                clock.advance_us(100_000);
                cpu.scan();
            })
        });
        assert_eq!(cpu.error(), None, "{name} after the runs");
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
