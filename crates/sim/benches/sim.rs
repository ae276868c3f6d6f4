//! Scenario-runner throughput (issue 7 §5): the heated-tank PIDCONT loop of
//! examples/sim/heated_tank.il against the `heater` model with a 10 ms scan,
//! with the per-scan work of a real scenario (model step and device binding,
//! two expectations evaluated every scan, a decimated trace).
//!
//! - `scenario/heated_tank_10min`: 60 000 scans per iteration (criterion,
//!   throughput in scans/s).
//! - Then one run of 1 h of plant time (360 000 scans) prints the
//!   simulated/wall ratio and the extrapolated wall time of 24 h (8.64 million
//!   scans). The full 24 h run is `examples/sim/soak/heated_tank_24h.toml`:
//!   `cargo run --release -p softplc -- test examples/sim/soak/heated_tank_24h.toml`.
//!
//! Run: `cargo bench -p softplc-sim --bench sim`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use softplc_sim::scenario::Scenario;

fn scenario(duration: &str) -> Scenario {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/sim");
    let text = format!(
        r#"
program = "heated_tank.il"
scan_time = "10ms"
duration = "{duration}"

[[model]]
type = "heater"
params = {{ capacity = 12000, power = 6000, resistance = 0.02, ambient = 20 }}
inputs.u = {{ device = "D820", raw = [0, 2000], eng = [0, 100] }}
outputs.temperature = {{ device = "D800", eng = [0, 200], raw = [0, 2000] }}

[[timeline]]
at = "1s"
set = {{ X0 = 1 }}

[[expect]]
device = "D611"
never_exceeds = 780

[[expect]]
device = "Y1"
never = true
equals = true

[trace]
devices = ["D610", "D611", "D820"]
"#
    );
    Scenario::parse(&text, &dir.join("bench.toml")).expect("bench scenario parses")
}

fn bench(c: &mut Criterion) {
    let sc = scenario("10min");
    let mut g = c.benchmark_group("scenario");
    g.throughput(Throughput::Elements(sc.scans));
    g.sample_size(20);
    g.bench_function("heated_tank_10min", |b| {
        b.iter_batched(
            || sc.build().expect("bench scenario builds"),
            |run| black_box(run.run(&mut |_| {})),
            BatchSize::PerIteration,
        )
    });
    g.finish();
}

/// One hour of plant time: the simulated/wall ratio and the 24 h estimate.
fn ratio() {
    let sc = scenario("1h");
    let run = sc.build().expect("bench scenario builds");
    let start = Instant::now();
    let out = run.run(&mut |_| {});
    let wall = start.elapsed().as_secs_f64();
    assert_eq!(out.failed(), 0, "{}", out.report(false));
    let sim = out.scans as f64 * out.scan_us as f64 / 1e6;
    println!(
        "1 h of plant time, 10 ms scan ({} scans): {wall:.3} s wall, {:.0}x real time, {:.2} M scans/s; 24 h (8.64 M scans) ≈ {:.1} s",
        out.scans,
        sim / wall,
        out.scans as f64 / wall / 1e6,
        wall * 24.0
    );
}

fn all(c: &mut Criterion) {
    bench(c);
    ratio();
}

criterion_group!(benches, all);
criterion_main!(benches);
