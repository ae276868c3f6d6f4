//! Scan information registers (004 App. 2 (4), L10443-10478; §4.2.3): SD500
//! the program running, SD540-SD549 where the scan time went. Expected
//! values are worked out by hand in the comments.

mod common;
use std::time::Duration;

use common::Plc;
use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::{Cpu, CpuConfig, ExecType, LoadedProgram, VirtualClock};
use softplc_core::program::compile_il;

fn int(cpu: &Cpu, d: &str) -> i64 {
    match cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap() {
        Value::Int(v) => v,
        v => panic!("{d}: {v:?}"),
    }
}

/// The registers SD540-SD549 as (ms, 100 µs part) pairs: END processing,
/// constant-scan wait, low-speed cycle so far, low-speed in this scan, scan
/// programs.
fn split(cpu: &Cpu) -> [(i64, i64); 5] {
    [540, 542, 544, 546, 548].map(|r| {
        (
            int(cpu, &format!("SD{r}")),
            int(cpu, &format!("SD{}", r + 1)),
        )
    })
}

#[test]
fn sd500_is_the_number_of_the_program_running() {
    // Each program reads SD500 as it runs: its place in the program list,
    // from 1 (App. 2 L10443).
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(10)),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_programs(
        &[
            ("LD SM400\nMOV SD500 D0\nEND\n", ExecType::Scan, None),
            ("LD SM400\nMOV SD500 D1\nEND\n", ExecType::Standby, None),
            ("LD SM400\nMOV SD500 D2\nEND\n", ExecType::Scan, None),
            ("LD SM400\nMOV SD500 D3\nEND\n", ExecType::LowSpeed, None),
        ],
        cfg,
    );
    p.scan();
    assert_eq!(
        (p.int("D0"), p.int("D1"), p.int("D2"), p.int("D3")),
        (1, 0, 3, 4)
    );
    assert_eq!(p.int("SD500"), 4);
}

#[test]
fn the_scan_time_split_without_execution_times() {
    // Programs without a simulated execution time take none: a 10 ms scan
    // is all END processing (SD540 = 10 ms).
    let mut p = Plc::new("LD SM400\nINC D0\nEND\n");
    p.scans(2);
    assert_eq!(split(&p.cpu), [(10, 0), (0, 0), (0, 0), (0, 0), (0, 0)]);
    // Constant scan 20 ms, scans of 20 ms: all of it is the wait (SD542).
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(20)),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("LD SM400\nINC D0\nEND\n", cfg);
    p.scan_time_us(20_000).scans(2);
    assert_eq!(split(&p.cpu), [(0, 0), (20, 0), (0, 0), (0, 0), (0, 0)]);
}

#[test]
fn the_scan_time_split_with_low_speed_programs() {
    // The worked schedule of 004 §4.2.3 (1)(1) (L1630-1650): constant scan
    // 8 ms, scan programs 4 ms, low-speed A 1 ms and B 3 ms, END 0 ms; 3.5 ms
    // usable a scan (0.5 ms before the next scan, *1).
    // Scan 1: A (1), B 2.5 of 3: low-speed 3.5 ms in the scan and in the
    // cycle so far; wait 8 - 7.5 = 0.5 ms; END 0.
    // Scan 2: B ends (0.5) → low-speed END (the cycle restarts), A (1), B 2
    // of 3: 3.5 ms in the scan, 3 ms in the new cycle.
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(8)),
        ..softplc_core::profile::default_config()
    };
    let progs = [
        ("main.il", "LD SM400\nINC D2\nEND\n", ExecType::Scan, 4),
        ("a.il", "LD SM400\nINC D0\nEND\n", ExecType::LowSpeed, 1),
        ("b.il", "LD SM400\nINC D1\nEND\n", ExecType::LowSpeed, 3),
    ];
    let loaded = progs
        .iter()
        .map(|(name, src, exec, ms)| LoadedProgram {
            program: compile_il(name, src, &cfg.devices).unwrap(),
            exec: *exec,
            interval: None,
            sim_time: Some(Duration::from_millis(*ms)),
            local_devices: true,
        })
        .collect();
    let clock = VirtualClock::new();
    let mut cpu = Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
    softplc_core::tier::apply_env(&mut cpu);
    clock.advance_us(8_000);
    cpu.scan();
    assert_eq!(split(&cpu), [(0, 0), (0, 500), (3, 500), (3, 500), (4, 0)]);
    clock.advance_us(8_000);
    cpu.scan();
    assert_eq!(split(&cpu), [(0, 0), (0, 500), (3, 0), (3, 500), (4, 0)]);
}
