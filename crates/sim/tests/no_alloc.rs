//! The scenario loop allocates nothing per scan (docs/scenarios.md,
//! "Speed"): with a counting global allocator, a run of 2,000 scans makes
//! exactly as many allocations as a run of 200 of the same scenario — the
//! CPU's scan and END processing, three plant models stepped and bound to
//! devices, timeline writes, assertions evaluated every scan and a trace
//! sampled every scan. What a run allocates at all (its first and last
//! scan's bookkeeping, the verdicts' texts) does not grow with its length.

use std::path::PathBuf;
use std::sync::atomic::Ordering;

use softplc_sim::scenario::Scenario;

#[path = "../../core/tests/counting_alloc/mod.rs"]
mod counting_alloc;

use counting_alloc::{ALLOCS, COUNTING};

/// The fill/drain sequence of examples/sim (two valves chained into a tank:
/// three models) for `duration`, with a timeline, assertions of every kind
/// decided within the first 2 s or at the end, and a trace of every scan.
fn scenario(duration: &str) -> Scenario {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/sim");
    let text = format!(
        r#"
program = "fill_drain.il"
scan_time = "10ms"
duration = "{duration}"

[[model]]
name = "fill_valve"
type = "valve"
params = {{ travel_time = "2s" }}
inputs.open = "Y0"
outputs.position = "D100:f32"

[[model]]
name = "drain_valve"
type = "valve"
params = {{ travel_time = "3s" }}
inputs.open = "Y1"
outputs.position = "D102:f32"

[[model]]
type = "tank"
params = {{ area = 1.0, height = 2.0, cv = 0.04, qmax = 0.02 }}
inputs.q_in = "D100:f32"
inputs.valve = "D102:f32"
outputs.level = {{ device = "D0", eng = [0.0, 2.0], raw = [0, 4000] }}
outputs.overflow = "X10"
outputs.q_out = "D104:f32"

[[timeline]]
at = 0
set = {{ X1 = 1 }}

[[timeline]]
at = "1s"
set = {{ X0 = 1 }}

[[timeline]]
at = "1.5s"
set = {{ X0 = 0 }}

[[expect]]
device = "Y0"
equals = true
within = "20ms"
after = "1s"

[[expect]]
device = "D0"
never_exceeds = 3300

[[expect]]
device = "X10"
never = true
equals = true

[[expect]]
device = "K4Y0"
never = true
equals = 3

[[expect]]
device = "D100:f32"
at_least = 1
at = "2s"

[trace]
devices = ["D0", "Y0", "D100:f32", "D104:f32"]
interval = "10ms"
"#
    );
    Scenario::parse(&text, &dir.join("no_alloc.toml")).expect("the scenario parses")
}

/// Allocations made while `duration` of the scenario runs (building it
/// not counted), and its outcome's failures.
fn allocations(duration: &str) -> (usize, usize, u64) {
    let run = scenario(duration).build().expect("the scenario builds");
    ALLOCS.store(0, Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    let out = run.run(&mut |_| {});
    COUNTING.with(|c| c.set(false));
    (ALLOCS.load(Ordering::Relaxed), out.failed(), out.scans)
}

#[test]
fn a_scenario_scan_allocates_nothing() {
    let (short, failed, scans) = allocations("2s");
    assert_eq!((failed, scans), (0, 200));
    let (long, failed, scans) = allocations("20s");
    assert_eq!((failed, scans), (0, 2000));
    // 1,800 more scans, each with the CPU's scan, three model steps, their
    // device writes, five assertions and a trace sample: not one more
    // allocation.
    assert_eq!(
        long, short,
        "allocations per run: {short} in 2 s, {long} in 20 s"
    );
}
