//! Projects (`plc.toml`, contract §1 and §4): the example project, defaults,
//! and one failing file per validation rule with the exact `line:col: message`.
//! Positions are worked out by hand (1-based lines, character columns).
//!
//! This file: the example project, paths, defaults, the order of diagnostics,
//! TOML syntax and unknown keys.

use std::path::Path;

use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::calendar::DateTime;
use softplc_core::engine::{Cpu, ErrorMode, ExecType, StopToRunOutput, VirtualClock};
use softplc_core::project::{is_project, load_project, ProgramSpec};

mod common;
use common::project::{error, errors, example_dir, latch, ms, ok, scratch, with_main, MAIN};

// ---------------------------------------------------------------- the example

#[test]
fn example_project_loads() {
    let dir = example_dir();
    let p = load_project(&dir).unwrap_or_else(|d| panic!("{d}"));
    assert_eq!(p.dir, dir);
    assert_eq!(p.manifest, dir.join("plc.toml"));
    assert_eq!(p.state_dir, dir.join("state"));
    assert_eq!(p.common_pointer, Some(100));
    assert_eq!(
        p.programs,
        vec![
            ProgramSpec {
                file: dir.join("init.il"),
                exec: ExecType::Initial,
                interval: None,
                sim_time: None,
                local_devices: true,
            },
            ProgramSpec {
                file: dir.join("main.il"),
                exec: ExecType::Scan,
                interval: None,
                sim_time: None,
                local_devices: true,
            },
            ProgramSpec {
                file: dir.join("fast.il"),
                exec: ExecType::FixedScan,
                interval: Some(ms(50)),
                sim_time: None,
                local_devices: true,
            },
            ProgramSpec {
                file: dir.join("stats.il"),
                exec: ExecType::Standby,
                interval: None,
                sim_time: None,
                local_devices: true,
            },
        ]
    );
    let c = &p.config;
    assert_eq!(c.profile.model, "Q06HCPU");
    assert_eq!(c.devices.points(DeviceKind::STS), 16);
    assert_eq!(c.devices.points(DeviceKind::STN), 16);
    assert_eq!(c.devices.points(DeviceKind::ZR), 32768);
    assert_eq!(c.devices.points(DeviceKind::R), 32768);
    assert_eq!(c.devices.points(DeviceKind::D), 12288);
    assert_eq!(c.watchdog, ms(200));
    assert_eq!(c.constant_scan, Some(ms(20)));
    assert_eq!(c.operation_error, ErrorMode::Stop);
    assert_eq!(c.stop_to_run_output, StopToRunOutput::Recalculate);
    assert_eq!(c.low_speed_time, None);
    assert_eq!(c.initial_monitor, Some(ms(100)));
    assert_eq!((c.timer_low, c.timer_high), (ms(100), ms(10)));
    assert_eq!(c.interrupt_periods, [ms(100), ms(40), ms(20), ms(10)]);
    assert_eq!(
        c.clock_start,
        DateTime {
            year: 2024,
            month: 1,
            day: 1,
            hour: 6,
            minute: 0,
            second: 0
        }
    );
    assert_eq!(
        c.latch,
        vec![
            latch(DeviceKind::L, 0, 8191, true),
            latch(DeviceKind::D, 1000, 1009, true),
            latch(DeviceKind::CS, 0, 0, true),
            latch(DeviceKind::D, 1010, 1019, false),
            latch(DeviceKind::STS, 0, 15, false),
        ]
    );
    let iv: Vec<(&str, &str)> = c
        .initial_values
        .iter()
        .map(|v| (v.device.text.as_str(), v.value.as_str()))
        .collect();
    assert_eq!(iv, vec![("D110", "1"), ("D120:f32", "1")]);
}

/// The example's programs compile and link (main.il calls the common pointer
/// P100 of the standby program stats.il), and the line fills, counts and stops
/// as its README says.
#[test]
fn example_project_runs() {
    let p = load_project(&example_dir()).unwrap_or_else(|d| panic!("{d}"));
    let clock = VirtualClock::new();
    let mut cpu = p
        .build_cpu(Box::new(clock.clone()))
        .unwrap_or_else(|d| panic!("{d}"));
    let scan = |cpu: &mut Cpu, n: usize| {
        for _ in 0..n {
            clock.advance_us(20_000);
            cpu.scan();
        }
    };
    let read = |cpu: &Cpu, d: &str| {
        cpu.read_device(&DeviceSpec::parse(d).unwrap())
            .unwrap()
            .to_string()
    };
    let write = |cpu: &mut Cpu, d: &str, v: &str| {
        cpu.write_device(&DeviceSpec::parse(d).unwrap(), v).unwrap()
    };
    scan(&mut cpu, 1);
    // init.il chose recipe 1 from the initial value D110 = 1.
    assert_eq!(read(&cpu, "D100"), "500");
    assert_eq!(read(&cpu, "D102"), "12");
    assert_eq!(read(&cpu, "D120:f32"), "1.0");
    // A short recipe for the test: 5 ml, 2 bottles per case.
    write(&mut cpu, "D100", "5");
    write(&mut cpu, "D102", "2");
    cpu.set_input(0, true);
    scan(&mut cpu, 1);
    cpu.set_input(0, false);
    scan(&mut cpu, 1);
    assert_eq!(read(&cpu, "Y0"), "true", "conveyor runs");
    for bottle in 1..=2 {
        cpu.set_input(2, true);
        scan(&mut cpu, 1);
        assert_eq!(read(&cpu, "Y1"), "true", "valve opens");
        assert_eq!(read(&cpu, "Y0"), "false", "conveyor stops while filling");
        // Flow-meter pulses: X3 toggles every 60 ms, sampled by fast.il every 50 ms.
        for k in 0..120 {
            cpu.set_input(3, k % 6 < 3);
            scan(&mut cpu, 1);
        }
        assert_eq!(read(&cpu, "D0"), "5", "filled to target");
        assert_eq!(read(&cpu, "Y1"), "false", "valve closed");
        assert_eq!(read(&cpu, "Y2"), "true", "bottle done");
        assert_eq!(read(&cpu, "D1000:i32"), bottle.to_string());
        assert_eq!(read(&cpu, "D200:f32"), "5.0", "average ml per bottle");
        cpu.set_input(2, false);
        scan(&mut cpu, 2);
    }
    assert_eq!(read(&cpu, "Y3"), "true", "case full");
    assert_eq!(read(&cpu, "Y0"), "false", "conveyor waits for a new case");
    assert_eq!(read(&cpu, "D1002:i32"), "10");
    assert_eq!(read(&cpu, "D1004:f32"), format!("{:?}", 0.01f32 as f64));
    cpu.set_input(4, true);
    scan(&mut cpu, 1);
    cpu.set_input(4, false);
    scan(&mut cpu, 1);
    assert_eq!(read(&cpu, "Y0"), "true", "new case");
    // No flow: the 10 s fill timeout raises the alarm and stops the line.
    cpu.set_input(2, true);
    scan(&mut cpu, 520);
    assert_eq!(read(&cpu, "Y7"), "true");
    assert_eq!(read(&cpu, "M0"), "false");
    assert!(cpu.error().is_none());
}

#[test]
fn directory_and_manifest_paths_both_work() {
    let dir = scratch(MAIN);
    let a = load_project(&dir).unwrap();
    let b = load_project(&dir.join("plc.toml")).unwrap();
    assert_eq!(a.dir, dir);
    assert_eq!(b.dir, dir);
    assert_eq!(a.manifest, dir.join("plc.toml"));
    assert_eq!(b.manifest, dir.join("plc.toml"));
    assert_eq!(a.programs, b.programs);
    assert_eq!(a.programs[0].file, dir.join("main.il"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn is_project_recognises_directories_and_manifests() {
    let dir = scratch(MAIN);
    assert!(is_project(&dir));
    assert!(is_project(&dir.join("plc.toml")));
    assert!(is_project(Path::new("does/not/exist/plc.toml")));
    assert!(!is_project(&dir.join("main.il")));
    assert!(!is_project(&dir.join("missing")));
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert!(!is_project(&empty));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_directory_without_plc_toml_is_an_error() {
    let dir = scratch(MAIN);
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let d = load_project(&empty).unwrap_err();
    assert_eq!(d.0.len(), 1);
    assert!(d.0[0].message.contains("no plc.toml"), "{d}");
    let d = load_project(&dir.join("nothing/plc.toml")).unwrap_err();
    assert!(d.0[0].message.contains("cannot read file"), "{d}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn defaults_when_keys_are_absent() {
    let p = ok(MAIN);
    assert_eq!(
        format!("{:?}", p.config),
        format!("{:?}", softplc_core::profile::default_config())
    );
    assert_eq!(p.state_dir, p.dir.join("state"));
    assert_eq!(p.common_pointer, None);
    assert_eq!(p.programs[0].exec, ExecType::Scan, "type defaults to scan");
    // Empty sections change nothing either.
    let p = ok(&with_main(
        "[cpu]\n[devices]\n[timers]\n[ras]\n[interrupts]\n[initial]\n[clock]\n[state]\n",
    ));
    assert_eq!(
        format!("{:?}", p.config),
        format!("{:?}", softplc_core::profile::default_config())
    );
}

#[test]
fn every_error_is_reported_in_file_order() {
    let e = errors(&with_main(
        "[ras]\nwatchdog = \"15ms\"\nconstant_scan = \"0.7ms\"\n[timers]\nlow = \"0ms\"\n",
    ));
    assert_eq!(
        e,
        vec![
            "2:12: watchdog \"15ms\" is out of range (10ms-2000ms in 10 ms steps)",
            "3:17: constant_scan \"0.7ms\" is out of range (0.5ms-2000ms in 0.5 ms steps)",
            "5:7: low \"0ms\" is out of range (1ms-1000ms in 1 ms steps)",
        ]
    );
}

// ---------------------------------------------------------------- syntax and keys

#[test]
fn toml_syntax_error() {
    let e = error("[ras]\nwatchdog = \n");
    assert!(e.starts_with("2:12: TOML syntax error: "), "{e}");
}

#[test]
fn unknown_keys_are_errors() {
    assert_eq!(
        error(&with_main("[rass]\n")),
        "1:2: unknown key \"rass\"; did you mean \"ras\"?"
    );
    assert_eq!(
        error(&with_main("[ras]\nwatchdg = \"200ms\"\n")),
        "2:1: unknown key \"watchdg\" in [ras]; did you mean \"watchdog\"?"
    );
    assert_eq!(
        error(&with_main("[cpu]\ncolour = \"red\"\n")),
        "2:1: unknown key \"colour\" in [cpu] (expected model, common_pointer, exec, a_compatibility, online_write_steps, online_reserve_steps)"
    );
    assert_eq!(
        error("[[program]]\nfile = \"main.il\"\nintervall = \"5ms\"\n"),
        "3:1: unknown key \"intervall\" in [[program]]; did you mean \"interval\"?"
    );
    assert_eq!(
        error(&with_main(
            "[clock]\nstart = \"2000-01-01T00:00:00\"\nzone = \"UTC\"\n"
        )),
        "3:1: unknown key \"zone\" in [clock] (expected start)"
    );
    assert_eq!(
        error(&with_main("[state]\ndirectory = \"s\"\n")),
        "2:1: unknown key \"directory\" in [state] (expected dir, on_damage)"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch3 = []\n")),
        "2:1: unknown key \"latch3\" in [latch]; did you mean \"latch1\"?"
    );
    assert_eq!(
        error(&with_main("[timers]\nmedium = \"50ms\"\n")),
        "2:1: unknown key \"medium\" in [timers] (expected low, high)"
    );
}

#[test]
fn sections_must_be_tables() {
    assert_eq!(
        error(&with_main("ras = \"fast\"\n")),
        "1:7: [ras] must be a table, not a string"
    );
    assert_eq!(
        error(&with_main("[[cpu]]\nmodel = \"Q06HCPU\"\n")),
        "1:1: [cpu] must be a single table; write [cpu] once"
    );
}

#[test]
fn cpu_exec_chooses_the_tier() {
    use softplc_core::tier::Exec;
    assert_eq!(ok(&with_main("")).exec, None);
    assert_eq!(
        ok(&with_main("[cpu]\nexec = \"jit\"\n")).exec,
        Some(Exec::Jit)
    );
    assert_eq!(
        ok(&with_main("[cpu]\nexec = \"interp\"\n")).exec,
        Some(Exec::Interp)
    );
    assert_eq!(
        error(&with_main("[cpu]\nexec = \"fast\"\n")),
        "2:8: exec \"fast\" is not one of auto, jit, interp"
    );
}
