//! CPU functions (004 ch. 4 and 7): program execution types, operating states,
//! latch, initial values. Expected values are worked out from the manual's rules
//! in the comments.
//!
//! This file: program execution types (initial, scan, fixed scan, standby,
//! low speed), operating states, latch, initial values, constant scan and file
//! register blocks.

mod common;
use std::time::Duration;

use common::Plc;
use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{
    CpuConfig, CpuState, ExecType, InitialValue, LatchRange, StopToRunOutput,
};

const INIT: &str = "LD SM400\nMOV K100 D0\nINC D1\nEND\n";
const MAIN: &str = "LD SM400\nINC D2\nLD SM402\nOUT M0\nEND\n";

#[test]
fn initial_programs_run_once_then_scan_programs() {
    // 004 §4.2.1: initial programs run once after power-on, then one END; the
    // scan programs start from the next scan. SD420 does not count the initial scan.
    let mut p = Plc::with_programs(
        &[
            (INIT, ExecType::Initial, None),
            (MAIN, ExecType::Scan, None),
        ],
        softplc_core::profile::default_config(),
    );
    p.scan();
    assert_eq!((p.int("D0"), p.int("D1"), p.int("D2")), (100, 1, 0));
    assert_eq!(p.int("SD420"), 0);
    p.scan();
    // First scan of the scan program: SM402 ON in it.
    assert_eq!((p.int("D1"), p.int("D2")), (1, 1));
    assert!(p.bit("M0"));
    assert_eq!(p.int("SD420"), 1);
    p.scans(3);
    assert_eq!((p.int("D1"), p.int("D2")), (1, 4));
    assert!(!p.bit("M0"));
    // SD522/SD523: the initial scan took one 10 ms step.
    assert_eq!((p.int("SD522"), p.int("SD523")), (10, 0));
}

#[test]
fn fixed_scan_program_runs_at_its_interval() {
    // 50 ms fixed scan with 10 ms scans: due at 50, 100, 150 ms → runs in the
    // scans whose start time reaches those instants (scans 5, 10, 15).
    let mut p = Plc::with_programs(
        &[
            (MAIN, ExecType::Scan, None),
            (
                "LD SM400\nINC D10\nEND\n",
                ExecType::FixedScan,
                Some(Duration::from_millis(50)),
            ),
        ],
        softplc_core::profile::default_config(),
    );
    p.scans(4);
    assert_eq!(p.int("D10"), 0);
    p.scan();
    assert_eq!(p.int("D10"), 1);
    p.scans(10);
    assert_eq!(p.int("D10"), 3);
    // A 120 ms scan covers two intervals (200 and 250 ms): both run.
    p.scan_time_us(120_000).scan();
    assert_eq!(p.int("D10"), 5);
}

#[test]
fn standby_programs_do_not_run() {
    let mut p = Plc::with_programs(
        &[
            (MAIN, ExecType::Scan, None),
            ("LD SM400\nINC D10\nEND\n", ExecType::Standby, None),
        ],
        softplc_core::profile::default_config(),
    );
    p.scans(5);
    assert_eq!((p.int("D2"), p.int("D10")), (5, 0));
}

#[test]
fn stop_keeps_devices_outputs_off_and_run_restarts() {
    let mut p = Plc::new("LD SM400\nOUT Y0\nINC D0\nLD SM402\nINC D1\nEND\n");
    p.scans(3);
    assert!(p.cpu.output(0));
    p.cpu.set_stop();
    p.scans(2);
    // STOP: the program does not run, Y0 device kept, external output OFF.
    assert_eq!(p.state(), CpuState::Stop);
    assert_eq!(p.int("D0"), 3);
    assert!(p.bit("Y0"));
    assert!(!p.cpu.output(0));
    // Devices are writable in STOP.
    p.set("D0", "10");
    p.cpu.set_run().unwrap();
    p.scan();
    // STOP→RUN: SM402 pulses again; device memory continues.
    assert_eq!((p.int("D0"), p.int("D1")), (11, 2));
    assert!(p.cpu.output(0));
}

#[test]
fn stop_to_run_output_modes() {
    // Y0 is set by X0 and held; during STOP an HMI writes Y0 OFF.
    let src = "LD X0\nSET Y0\nEND\n";
    for (mode, want) in [
        (StopToRunOutput::Previous, true),
        (StopToRunOutput::Recalculate, false),
    ] {
        let cfg = CpuConfig {
            stop_to_run_output: mode,
            ..softplc_core::profile::default_config()
        };
        let mut p = Plc::with_config(src, cfg);
        p.set("X0", "1").scan().set("X0", "0").scan();
        p.cpu.set_stop();
        p.set("Y0", "0");
        p.cpu.set_run().unwrap();
        // "previous": the Y image saved at RUN→STOP is output again (Y0 ON).
        // "recalculate": Y starts OFF and nothing sets it again.
        assert_eq!(p.bit("Y0"), want, "{mode:?}");
        p.scan();
        assert_eq!(p.cpu.output(0), want, "{mode:?}");
    }
}

#[test]
fn pause_holds_outputs() {
    let mut p = Plc::new("LD SM400\nOUT Y0\nINC D0\nEND\n");
    p.scans(2);
    p.cpu.set_pause().unwrap();
    p.scans(3);
    assert_eq!(p.state(), CpuState::Pause);
    assert_eq!(p.int("D0"), 2);
    assert!(p.cpu.output(0));
    p.cpu.set_run().unwrap();
    p.scan();
    assert_eq!(p.int("D0"), 3);
}

#[test]
fn stop_error_needs_reset_which_clears_unlatched_devices() {
    // Default latch range is L0-L8191 (004 L1060). A division by zero stops the
    // CPU; RUN is refused until RESET; RESET clears D and M, keeps L.
    let mut p = Plc::new("LD SM400\nINC D0\nSET L5\nSET M5\nLD X0\n/ D0 K0 D1\nEND\n");
    p.scans(2);
    p.set("X0", "1").scan();
    assert_eq!(p.state(), CpuState::Stop);
    assert!(p.cpu.set_run().is_err());
    assert!(p.bit("SM0"));
    p.set("X0", "0");
    assert!(p.cpu.scans() >= 2);
    p.cpu.reset().unwrap();
    // RESET is power-on processing: the scan count restarts (contract §3.1
    // `scan` "since power-on"; SD420 from 0, 004 L10434).
    assert_eq!(p.cpu.scans(), 0);
    assert_eq!(p.state(), CpuState::Run);
    assert!(p.cpu.error().is_none());
    assert!(!p.bit("SM0"));
    assert_eq!(p.int("SD0"), 0);
    assert_eq!(p.int("D0"), 0);
    assert!(!p.bit("M5"));
    assert!(p.bit("L5"));
    p.scan();
    assert_eq!(p.int("D0"), 1);
    assert_eq!((p.cpu.scans(), p.int("SD420")), (1, 1));
}

#[test]
fn latch_clear_switch_and_remote() {
    // latch (1): D100-D199 (cleared by latch clear); latch (2): D200-D299 (not by
    // the switch). Remote latch clear clears both and every unlatched device.
    let cfg = CpuConfig {
        latch: vec![
            LatchRange {
                kind: DeviceKind::D,
                start: 100,
                end: 199,
                clearable: true,
            },
            LatchRange {
                kind: DeviceKind::D,
                start: 200,
                end: 299,
                clearable: false,
            },
        ],
        ..softplc_core::profile::default_config()
    };
    let src = "LD SM402\nMOV K1 D100\nMOV K2 D200\nMOV K3 D0\nMOV K4 R0\nEND\n";
    let mut p = Plc::with_config(src, cfg.clone());
    p.scan();
    assert!(p.cpu.latch_clear(false).is_err(), "only in STOP");
    p.cpu.set_stop();
    p.cpu.latch_clear(false).unwrap();
    assert_eq!(
        (p.int("D100"), p.int("D200"), p.int("D0"), p.int("R0")),
        (0, 2, 3, 4)
    );
    let mut p = Plc::with_config(src, cfg);
    p.scan();
    p.cpu.set_stop();
    p.cpu.latch_clear(true).unwrap();
    // File registers are never cleared by latch clear (004 L7028-7031).
    assert_eq!(
        (p.int("D100"), p.int("D200"), p.int("D0"), p.int("R0")),
        (0, 0, 0, 4)
    );
}

#[test]
fn reset_keeps_overlapping_latch_ranges_and_file_registers() {
    // RESET clears every device outside the latch ranges and the file
    // registers; overlapping and unsorted ranges, bit ranges and timer ranges
    // (contact, coil and value together) are all kept, their neighbours cleared.
    let range = |kind, start, end| LatchRange {
        kind,
        start,
        end,
        clearable: true,
    };
    let cfg = CpuConfig {
        latch: vec![
            range(DeviceKind::D, 150, 250),
            range(DeviceKind::D, 100, 199),
            range(DeviceKind::M, 10, 19),
            range(DeviceKind::TN, 5, 6),
        ],
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("LD SM400\nOUT M100\nEND\n", cfg);
    for d in [
        "D99", "D100", "D150", "D199", "D250", "D251", "D12287", "TN4", "TN5", "TN6", "TN7", "W0",
        "R0", "ZR517119",
    ] {
        p.set(d, "7");
    }
    for m in [
        "M9", "M10", "M19", "M20", "L0", "L8191", "B0", "Y0", "TS5", "TS7",
    ] {
        p.set(m, "1");
    }
    p.cpu.set_stop();
    p.cpu.reset().unwrap();
    for (d, v) in [
        ("D99", 0),
        ("D100", 7),
        ("D150", 7),
        ("D199", 7),
        ("D250", 7),
        ("D251", 0),
        ("D12287", 0),
        ("TN4", 0),
        ("TN5", 7),
        ("TN6", 7),
        ("TN7", 0),
        ("W0", 0),
        ("R0", 7),
        ("ZR517119", 7),
    ] {
        assert_eq!(p.int(d), v, "{d}");
    }
    for (m, v) in [
        ("M9", false),
        ("M10", true),
        ("M19", true),
        ("M20", false),
        // The ranges replace the default L0-L8191 latch.
        ("L0", false),
        ("L8191", false),
        ("B0", false),
        ("Y0", false),
        ("TS5", true),
        ("TS7", false),
    ] {
        assert_eq!(p.bit(m), v, "{m}");
    }
}

#[test]
fn initial_values_at_power_on_and_stop_to_run() {
    let cfg = CpuConfig {
        initial_values: vec![
            InitialValue {
                device: DeviceSpec::parse("D10").unwrap(),
                value: "1234".into(),
            },
            InitialValue {
                device: DeviceSpec::parse("D20:f32").unwrap(),
                value: "1.5".into(),
            },
        ],
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("LD SM400\nINC D10\nEND\n", cfg);
    assert_eq!(p.int("D10"), 1234);
    assert_eq!(p.real("D20"), 1.5);
    p.scans(3);
    assert_eq!(p.int("D10"), 1237);
    p.cpu.set_stop();
    p.cpu.set_run().unwrap();
    assert_eq!(p.int("D10"), 1234);
}

#[test]
fn constant_scan_overrun_is_prg_time_over() {
    // Constant scan 10 ms; a 12 ms scan is PRG.TIME OVER (5010), a continuation
    // error: SD0 = 5010, the CPU keeps running (004 §7.1).
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(10)),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("LD SM400\nINC D0\nEND\n", cfg);
    p.scans(2);
    assert!(p.cpu.error().is_none());
    p.scan_time_us(12_000).scan();
    assert_eq!(p.int("SD0"), 5010);
    assert_eq!(p.state(), CpuState::Run);
    p.scan();
    assert_eq!(p.int("D0"), 4);
}

#[test]
fn stop_instruction_then_remote_run() {
    let mut p = Plc::new("LD X0\nSTOP\nLD SM400\nINC D0\nEND\n");
    p.scan().set("X0", "1").scan();
    assert_eq!(p.state(), CpuState::Stop);
    assert_eq!(p.int("D0"), 2);
    p.set("X0", "0");
    p.cpu.set_run().unwrap();
    p.scan();
    assert_eq!(p.int("D0"), 3);
}

#[test]
fn low_speed_programs_run_once_per_scan_with_their_registers() {
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(20)),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_programs(
        &[
            (MAIN, ExecType::Scan, None),
            (
                "LD SM404\nINC D30\nLD SM510\nINC D31\nEND\n",
                ExecType::LowSpeed,
                None,
            ),
        ],
        cfg,
    );
    p.scan_time_us(20_000).scans(3);
    // SM404 only in the first low-speed scan; SM510 ON while it runs; SD430 counts.
    assert_eq!((p.int("D30"), p.int("D31"), p.int("SD430")), (1, 3, 3));
    assert!(!p.bit("SM510"));
    // SD528/529: the low-speed scan time is the programs' execution time, which
    // is 0 without a simulated execution time (sim_time).
    assert_eq!((p.int("SD528"), p.int("SD529")), (0, 0));
}

#[test]
fn execution_type_changes_take_effect_at_end() {
    // p0 switches p1 (standby, named "P1") to scan with PSCAN, back with PSTOP,
    // and POFF turns its outputs OFF once before it becomes standby
    // (qcpu.md §2.2 table; file names are p0.il, p1.il in the harness).
    let main = "LD X0\nPSCAN \"P1\"\nLD X1\nPSTOP \"P1\"\nLD X2\nPOFF \"P1\"\nEND\n";
    let sub = "LD SM400\nINC D0\nOUT Y5\nEND\n";
    let mut p = Plc::with_programs(
        &[(main, ExecType::Scan, None), (sub, ExecType::Standby, None)],
        softplc_core::profile::default_config(),
    );
    p.scans(2);
    assert_eq!(p.int("D0"), 0);
    // PSCAN in scan 3 takes effect at its END: p1 runs from scan 4.
    p.set("X0", "1").scan().set("X0", "0");
    assert_eq!(p.int("D0"), 0);
    p.scans(3);
    assert_eq!(p.int("D0"), 3);
    assert!(p.bit("Y5"));
    // PSTOP: p1 stops; its output stays as it was.
    p.set("X1", "1").scan().set("X1", "0").scans(2);
    assert_eq!(p.int("D0"), 4);
    assert!(p.bit("Y5"));
    // POFF: at the next scan p1 runs once with conditions OFF (Y5 OFF, no INC).
    p.set("X2", "1").scan().set("X2", "0").scan();
    assert!(!p.bit("Y5"));
    assert_eq!(p.int("D0"), 4);
    // An unknown program name is error 2410 when executed.
    let mut p = Plc::new("LD X0\nPSCAN \"NONE\"\nEND\n");
    p.set("X0", "1").scan();
    assert_eq!((p.state(), p.int("SD0")), (CpuState::Stop, 2410));
}

#[test]
fn file_register_blocks_with_rset() {
    // R0-R32767 address block SD648 of ZR: block 1 starts at ZR32768 (004 §10.7).
    // Default file registers: 517120 points → 16 blocks (SD647 = 505 K words).
    let src = "LD SM400\nMOV K11 R5\nRSET K1\nMOV K22 R5\nMOV R5 D0\nRSET K0\nMOV R5 D1\n\
               LD X0\nRSET K16\nEND\n";
    let mut p = Plc::new(src);
    p.scan();
    assert_eq!((p.int("ZR5"), p.int("ZR32773")), (11, 22));
    assert_eq!((p.int("D0"), p.int("D1")), (22, 11));
    assert_eq!((p.int("SD647"), p.int("SD648")), (505, 0));
    // Block 16 is beyond the registered file registers (16 × 32768 ≥
    // 517120): RSET selects it with no error, and R there is outside the
    // registered range, which is no error either (004 §10.7.5 (1);
    // golden_file_register.rs).
    p.set("X0", "1").scan();
    assert_eq!((p.state(), p.int("SD0")), (CpuState::Run, 0));
    assert_eq!(p.int("SD648"), 16);
    // RSET K32 is past the largest file (blocks 0-31): 4101.
    let mut p = Plc::new("LD SM400\nRSET K32\nEND\n");
    p.scan();
    assert_eq!((p.state(), p.int("SD0")), (CpuState::Stop, 4101));
}

/// The low-speed worked schedules of 004 §4.2.3 (L1630-1680; figures lost, the
/// expectations below follow the text's rules): scan programs 4 ms, low-speed
/// A = 1 ms and B = 3 ms, END 0 ms. A counts its runs in D0, B in D1; SD430
/// counts low-speed END processings.
fn low_speed_cpu(
    cfg: CpuConfig,
    sync: bool,
) -> (
    softplc_core::engine::Cpu,
    softplc_core::engine::VirtualClock,
) {
    use softplc_core::engine::{LoadedProgram, VirtualClock};
    use softplc_core::program::compile_il;
    let main = if sync {
        "LD SM400\nOUT SM330\nEND\n"
    } else {
        "LD SM400\nOUT M0\nEND\n"
    };
    let progs = [
        ("main.il", main, ExecType::Scan, 4),
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
    let mut cpu =
        softplc_core::engine::Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
    softplc_core::tier::apply_env(&mut cpu);
    (cpu, clock)
}

fn counts(cpu: &softplc_core::engine::Cpu) -> (i64, i64, i64) {
    let get = |d: &str| match cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap() {
        softplc_core::access::Value::Int(v) => v,
        v => panic!("{v:?}"),
    };
    (get("D0"), get("D1"), get("SD430"))
}

#[test]
fn low_speed_async_with_constant_scan() {
    // Constant scan 8 ms: spare 4 ms, usable 3.5 ms (cut 0.5 ms before the next
    // scan). Scan 1: A (1), B starts (2.5 of 3). Scan 2: B ends (0.5) → low END 1,
    // A again (1), B starts (2 of 3). Scan 3: B ends (1) → END 2, A (1), B (1.5).
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(8)),
        ..softplc_core::profile::default_config()
    };
    let (mut cpu, clock) = low_speed_cpu(cfg, false);
    let mut got = Vec::new();
    for _ in 0..4 {
        clock.advance_us(8_000);
        cpu.scan();
        got.push(counts(&cpu));
    }
    assert_eq!(got, [(1, 1, 0), (2, 2, 1), (3, 3, 2), (4, 4, 3)]);
    // Low-speed scan time = execution time of a cycle (§4.2.3 (6)): A + B = 4 ms.
    let get = |d: &str| cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap();
    assert_eq!(get("SD528"), softplc_core::access::Value::Int(4));
    assert_eq!(get("SD529"), softplc_core::access::Value::Int(0));
    assert_eq!(cpu.busy_us(), 8_000 - 500);
}

#[test]
fn low_speed_async_with_low_speed_time() {
    // Low-speed execution time 3 ms per scan, no constant scan (scan = 7 ms).
    // Scan 1: A (1), B (2 of 3). Scan 2: B ends (1) → END 1, A (1), B (1 of 3).
    // Scan 3: B ends (2) → END 2, A (1) → 3 ms used, B not started.
    let cfg = CpuConfig {
        low_speed_time: Some(Duration::from_millis(3)),
        ..softplc_core::profile::default_config()
    };
    let (mut cpu, clock) = low_speed_cpu(cfg, false);
    let mut got = Vec::new();
    for _ in 0..4 {
        clock.advance_us(7_000);
        cpu.scan();
        got.push(counts(&cpu));
    }
    // Scan 4: B starts (3 of 3) and ends exactly at the budget → END 3.
    assert_eq!(got, [(1, 1, 0), (2, 2, 1), (3, 2, 2), (3, 3, 3)]);
    assert_eq!(cpu.busy_us(), 7_000);
}

#[test]
fn low_speed_sync_with_constant_scan() {
    // SM330 ON: after a low-speed END no new cycle starts in the same scan; the
    // rest of the constant scan is waited out.
    // Scan 1: A, B (2.5 of 3). Scan 2: B ends → END 1, wait. Scan 3: A, B (2.5).
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(8)),
        ..softplc_core::profile::default_config()
    };
    let (mut cpu, clock) = low_speed_cpu(cfg, true);
    let mut got = Vec::new();
    for _ in 0..4 {
        clock.advance_us(8_000);
        cpu.scan();
        got.push(counts(&cpu));
    }
    assert_eq!(got, [(1, 1, 0), (1, 1, 1), (2, 2, 1), (2, 2, 2)]);
}

#[test]
fn low_speed_sync_with_low_speed_time() {
    // SM330 ON, low-speed time 3 ms: scan 1: A, B (2 of 3); scan 2: B ends (1 ms)
    // → END 1 and the scan programs start again at once (scan = 4 + 1 ms).
    let cfg = CpuConfig {
        low_speed_time: Some(Duration::from_millis(3)),
        ..softplc_core::profile::default_config()
    };
    let (mut cpu, clock) = low_speed_cpu(cfg, true);
    clock.advance_us(7_000);
    cpu.scan();
    assert_eq!((counts(&cpu), cpu.busy_us()), ((1, 1, 0), 7_000));
    clock.advance_us(7_000);
    cpu.scan();
    assert_eq!((counts(&cpu), cpu.busy_us()), ((1, 1, 1), 5_000));
    clock.advance_us(5_000);
    cpu.scan();
    assert_eq!((counts(&cpu), cpu.busy_us()), ((2, 2, 1), 7_000));
}
