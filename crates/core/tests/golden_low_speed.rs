//! Low-speed programs (004 §4.2.3, §10.6.1, §10.2.10 (f)): their own index
//! registers, the time their timers add, the low-speed execution monitor.
//! Expected values are worked out by hand in the comments.

mod common;
use std::time::Duration;

use common::Plc;
use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::{Cpu, CpuConfig, ExecType, LoadedProgram, VirtualClock};
use softplc_core::program::compile_il;

/// A CPU with (name, source, type, simulated execution time in µs) programs.
fn cpu(cfg: CpuConfig, progs: &[(&str, &str, ExecType, u64)]) -> (Cpu, VirtualClock) {
    let loaded = progs
        .iter()
        .map(|(name, src, exec, us)| LoadedProgram {
            program: compile_il(name, src, &cfg.devices).unwrap(),
            exec: *exec,
            interval: None,
            sim_time: (*us > 0).then(|| Duration::from_micros(*us)),
            local_devices: true,
        })
        .collect();
    let clock = VirtualClock::new();
    let mut cpu = Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
    softplc_core::tier::apply_env(&mut cpu);
    (cpu, clock)
}

fn int(cpu: &Cpu, d: &str) -> i64 {
    match cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap() {
        Value::Int(v) => v,
        v => panic!("{d}: {v:?}"),
    }
}

#[test]
fn scan_and_low_speed_programs_keep_their_own_index_registers() {
    // 004 §10.6.1 (figure: the low-speed program sets Z0 to 3, the scan
    // program to 6; each sees its own value when it runs again).
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(20)),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_programs(
        &[
            (
                "LD SM400\nMOV Z0 D0\nMOV K6 Z0\nEND\n",
                ExecType::Scan,
                None,
            ),
            (
                "LD SM400\nMOV Z0 D10\nMOV K3 Z0\nMOV K1 Z15\nEND\n",
                ExecType::LowSpeed,
                None,
            ),
        ],
        cfg,
    );
    p.scan_time_us(20_000).scan();
    // Scan 1: both start from 0; after the scan Z0 is the scan program's 6
    // again and Z15 is not the low-speed program's 1.
    assert_eq!((p.int("D0"), p.int("D10")), (0, 0));
    assert_eq!((p.int("Z0"), p.int("Z15")), (6, 0));
    p.scan();
    assert_eq!((p.int("D0"), p.int("D10")), (6, 3));
    assert_eq!((p.int("Z0"), p.int("Z15")), (6, 0));
}

#[test]
fn timers_in_low_speed_programs_add_the_time_between_low_speed_ends() {
    // 004 §10.2.10 (f). Timer base 1 ms; constant scan 10 ms; the scan program
    // takes 4 ms, the low-speed program 10 ms: 10 - 4 - 0.5 = 5.5 ms of spare
    // time a scan (§4.2.3 *1).
    // Scan 1 (t = 10 ms): L runs (OUT T0 starts, adds nothing), 5.5 ms of 10.
    // Scan 2 (t = 20 ms): 4.5 ms more → low END at 20 + 4 + 4.5 = 28.5 ms,
    //   28.5 ms after RUN (t = 0); L starts again: OUT T0 adds 28.5 → 28 (.5
    //   kept); 1 ms of 10 used.
    // Scan 3: 5.5 ms (3.5 owed). Scan 4 (t = 40 ms): 3.5 → low END at
    //   40 + 4 + 3.5 = 47.5 ms, 19 ms after the last; L again: 28.5 + 19 =
    //   47.5 → 47.
    // The scan program's T1 adds the scan time, 10 ms a scan: 0, 10, 20, 30.
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(10)),
        timer_low: Duration::from_millis(1),
        ..softplc_core::profile::default_config()
    };
    let (mut cpu, clock) = cpu(
        cfg,
        &[
            (
                "main.il",
                "LD SM400\nOUT T1 K30000\nEND\n",
                ExecType::Scan,
                4_000,
            ),
            (
                "low.il",
                "LD SM400\nOUT T0 K30000\nEND\n",
                ExecType::LowSpeed,
                10_000,
            ),
        ],
    );
    let mut got = Vec::new();
    for _ in 0..4 {
        clock.advance_us(10_000);
        cpu.scan();
        got.push((int(&cpu, "TN0"), int(&cpu, "TN1"), int(&cpu, "SD430")));
    }
    assert_eq!(got, [(0, 0, 0), (28, 10, 1), (28, 20, 1), (47, 30, 2)]);
}

#[test]
fn timers_in_low_speed_programs_without_execution_times_add_the_scan_time() {
    // Without simulated execution times a low-speed cycle completes in every
    // scan: the time between low-speed ENDs is the scan time, 10 ms, and a
    // 100 ms timer K1 is up after 10 additions (scans 2-11).
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(10)),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_programs(
        &[
            ("LD SM400\nINC D0\nEND\n", ExecType::Scan, None),
            ("LD SM400\nOUT T0 K1\nEND\n", ExecType::LowSpeed, None),
        ],
        cfg,
    );
    p.scans(10);
    assert!(!p.bit("T0"));
    p.scan();
    assert!(p.bit("T0"));
}

#[test]
fn low_speed_execution_monitor_is_prg_time_over() {
    // 004 §4.2.3 (7): monitor 10 ms, a low-speed cycle of 12 ms (low-speed
    // execution time 20 ms, so it completes in one scan): PRG.TIME OVER
    // (5011), measured at low-speed END; a continuation error (§7.19.2
    // factor 5: the CPU keeps running).
    let cfg = CpuConfig {
        low_speed_time: Some(Duration::from_millis(20)),
        low_speed_monitor: Some(Duration::from_millis(10)),
        ..softplc_core::profile::default_config()
    };
    let (mut cpu, clock) = cpu(
        cfg.clone(),
        &[
            ("main.il", "LD SM400\nINC D0\nEND\n", ExecType::Scan, 0),
            (
                "low.il",
                "LD SM400\nINC D1\nEND\n",
                ExecType::LowSpeed,
                12_000,
            ),
        ],
    );
    clock.advance_us(40_000);
    cpu.scan();
    assert_eq!(int(&cpu, "SD0"), 5011);
    assert_eq!(cpu.state(), softplc_core::engine::CpuState::Run);
    assert_eq!((int(&cpu, "SD528"), int(&cpu, "SD529")), (12, 0));
    // Asynchronous (SM330 OFF): the rest of the 20 ms runs the cycle again.
    // Scan 1: 12 ms (END), 8 of the next 12. Scan 2: 4 (END), 12 (END), 4.
    clock.advance_us(40_000);
    cpu.scan();
    assert_eq!((int(&cpu, "D0"), int(&cpu, "D1")), (2, 4));
    // 10 ms is not over 10 ms.
    let (mut cpu, clock) = cpu_with(cfg, 10_000);
    clock.advance_us(40_000);
    cpu.scan();
    assert_eq!(int(&cpu, "SD0"), 0);
}

fn cpu_with(cfg: CpuConfig, low_us: u64) -> (Cpu, VirtualClock) {
    cpu(
        cfg,
        &[
            ("main.il", "LD SM400\nINC D0\nEND\n", ExecType::Scan, 0),
            (
                "low.il",
                "LD SM400\nINC D1\nEND\n",
                ExecType::LowSpeed,
                low_us,
            ),
        ],
    )
}

#[test]
fn low_speed_monitor_in_plc_toml() {
    let files = [
        ("main.il", "LD SM400\nINC D0\nEND\n"),
        ("low.il", "LD SM400\nINC D1\nEND\n"),
    ];
    let progs = "[[program]]\nfile = \"main.il\"\n\
                 [[program]]\nfile = \"low.il\"\ntype = \"low-speed\"\nsim_time = \"12ms\"\n";
    let p = Plc::project(
        &format!("[ras]\nlow_speed_time = \"20ms\"\nlow_speed_monitor = \"10ms\"\n{progs}"),
        &files,
    );
    assert_eq!(
        p.cpu.config().low_speed_monitor,
        Some(Duration::from_millis(10))
    );
    // 10-2000 ms (004 L1727).
    let e = Plc::try_project(
        &format!("[ras]\nlow_speed_time = \"20ms\"\nlow_speed_monitor = \"5ms\"\n{progs}"),
        &files,
    )
    .err()
    .unwrap();
    assert!(e.contains("low_speed_monitor") || e.contains("10ms"), "{e}");
}

#[test]
fn fixed_scan_programs_get_the_index_registers_back_after_them() {
    // 004 §10.6.2 (1), the default (not "high-speed execution"): a fixed-scan
    // program receives the interrupted program's Z0-Z15 (the figure: Z0 = 6
    // becomes 3 in it) and the interrupted program has its values back.
    let mut p = Plc::with_programs(
        &[
            (
                "LD SM400\nMOV Z0 D0\nMOV K6 Z0\nEND\n",
                ExecType::Scan,
                None,
            ),
            (
                "LD SM400\nMOV Z0 D10\nMOV K3 Z0\nEND\n",
                ExecType::FixedScan,
                Some(Duration::from_millis(10)),
            ),
        ],
        softplc_core::profile::default_config(),
    );
    // Scan 1 (t = 10 ms): the fixed-scan program runs first, on Z0 = 0.
    p.scan();
    assert_eq!((p.int("D0"), p.int("D10"), p.int("Z0")), (0, 0, 6));
    p.scan();
    assert_eq!((p.int("D0"), p.int("D10"), p.int("Z0")), (6, 6, 6));
}
