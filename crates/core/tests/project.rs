//! Projects (`plc.toml`, contract §1 and §4): the example project, defaults,
//! and one failing file per validation rule with the exact `line:col: message`.
//! Positions are worked out by hand (1-based lines, character columns).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::calendar::DateTime;
use softplc_core::engine::{
    Cpu, CpuConfig, ErrorMode, ExecType, LatchRange, StopToRunOutput, VirtualClock,
};
use softplc_core::program::Diagnostics;
use softplc_core::project::{is_project, load_project, ProgramSpec, Project};

// ---------------------------------------------------------------- harness

static NEXT: AtomicUsize = AtomicUsize::new(0);

/// Program files every scratch project has.
const PROGRAM_FILES: &[&str] = &["main.il", "init.il", "fast.il", "sub.il", "low.il"];

/// A fresh directory with `plc.toml` = `toml` and the program files.
fn scratch(toml: &str) -> PathBuf {
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("softplc-project-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for f in PROGRAM_FILES {
        std::fs::write(dir.join(f), "LD X0\nOUT Y0\nEND\n").unwrap();
    }
    std::fs::write(dir.join("plc.toml"), toml).unwrap();
    dir
}

/// Loads a scratch project and removes its directory again.
fn load(toml: &str) -> Result<Project, Diagnostics> {
    let dir = scratch(toml);
    let r = load_project(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    r
}

/// The project must load.
fn ok(toml: &str) -> Project {
    load(toml).unwrap_or_else(|d| panic!("should load:\n{toml}\n{d}"))
}

/// Every diagnostic as `line:col: message` (the file name checked and removed).
fn errors(toml: &str) -> Vec<String> {
    let dir = scratch(toml);
    let r = load_project(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    let d = match r {
        Ok(_) => panic!("should fail:\n{toml}"),
        Err(d) => d,
    };
    let file = dir.join("plc.toml").display().to_string();
    d.0.iter()
        .map(|d| {
            assert_eq!(d.file, file, "diagnostic file of {d}");
            format!("{}:{}: {}", d.line, d.col, d.message)
        })
        .collect()
}

/// The single diagnostic of a failing project.
fn error(toml: &str) -> String {
    let e = errors(toml);
    assert_eq!(e.len(), 1, "expected one diagnostic, got {e:#?}");
    e.into_iter().next().unwrap()
}

/// A scan program, appended after the lines under test so their line numbers
/// start at 1.
const MAIN: &str = "\n[[program]]\nfile = \"main.il\"\n";

fn with_main(s: &str) -> String {
    format!("{s}{MAIN}")
}

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn us(n: u64) -> Duration {
    Duration::from_micros(n)
}

fn latch(kind: DeviceKind, start: u32, end: u32, clearable: bool) -> LatchRange {
    LatchRange {
        kind,
        start,
        end,
        clearable,
    }
}

fn example_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/project")
}

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
            },
            ProgramSpec {
                file: dir.join("main.il"),
                exec: ExecType::Scan,
                interval: None,
                sim_time: None,
            },
            ProgramSpec {
                file: dir.join("fast.il"),
                exec: ExecType::FixedScan,
                interval: Some(ms(50)),
                sim_time: None,
            },
            ProgramSpec {
                file: dir.join("stats.il"),
                exec: ExecType::Standby,
                interval: None,
                sim_time: None,
            },
        ]
    );
    let c = &p.config;
    assert_eq!(c.model, "Q06HCPU");
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
        format!("{:?}", CpuConfig::default())
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
        format!("{:?}", CpuConfig::default())
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
        "2:1: unknown key \"colour\" in [cpu] (expected model, common_pointer)"
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

// ---------------------------------------------------------------- [cpu]

#[test]
fn cpu_model() {
    let p = ok(&with_main("[cpu]\nmodel = \"q25hcpu\"\n"));
    assert_eq!(p.config.model, "Q25HCPU");
    for m in ["Q02CPU", "Q02HCPU", "Q06HCPU", "Q12HCPU", "Q25HCPU"] {
        assert_eq!(
            ok(&with_main(&format!("[cpu]\nmodel = \"{m}\"\n")))
                .config
                .model,
            m
        );
    }
    assert_eq!(
        error(&with_main("[cpu]\nmodel = \"APLC-TCP\"\n")),
        "2:9: model \"APLC-TCP\": the APLC dialect is not implemented yet"
    );
    assert_eq!(
        error(&with_main("[cpu]\nmodel = \"Q99CPU\"\n")),
        "2:9: unknown CPU model \"Q99CPU\" (expected Q02CPU, Q02HCPU, Q06HCPU, Q12HCPU, Q25HCPU, or APLC-TCP)"
    );
    assert_eq!(
        error(&with_main("[cpu]\nmodel = 6\n")),
        "2:9: model must be a CPU model name such as \"Q06HCPU\", not an integer"
    );
}

#[test]
fn cpu_common_pointer() {
    assert_eq!(
        ok(&with_main("[cpu]\ncommon_pointer = \"P2048\"\n")).common_pointer,
        Some(2048)
    );
    assert_eq!(
        error(&with_main("[cpu]\ncommon_pointer = \"P4096\"\n")),
        "2:18: common_pointer \"P4096\" is not a pointer P0-P4095"
    );
}

// ---------------------------------------------------------------- [devices]

#[test]
fn device_points() {
    let p = ok(&with_main(
        "[devices]\nM = 4096\nT = 1024\nst = 32\nC = 512\nD = 16384\nW = 4096\nfile_register = 65536\n",
    ));
    let d = &p.config.devices;
    assert_eq!(d.points(DeviceKind::M), 4096);
    for k in [DeviceKind::TS, DeviceKind::TC, DeviceKind::TN] {
        assert_eq!(d.points(k), 1024);
    }
    for k in [DeviceKind::STS, DeviceKind::STC, DeviceKind::STN] {
        assert_eq!(d.points(k), 32);
    }
    assert_eq!(d.points(DeviceKind::CN), 512);
    assert_eq!(d.points(DeviceKind::D), 16384);
    assert_eq!(d.points(DeviceKind::ZR), 65536);
    assert_eq!(d.points(DeviceKind::R), 32768, "R is block 0 of ZR");
    let p = ok(&with_main("[devices]\nfile_register = 16384\n"));
    assert_eq!(p.config.devices.points(DeviceKind::R), 16384);
    let p = ok(&with_main("[devices]\nfile_register = 0\n"));
    assert_eq!(p.config.devices.points(DeviceKind::R), 0);
}

#[test]
fn device_points_in_16_point_units_up_to_32k() {
    assert_eq!(
        error(&with_main("[devices]\nM = 8200\n")),
        "2:5: M = 8200 is out of range (0-32768 points in 16-point units)"
    );
    assert_eq!(
        error(&with_main("[devices]\nD = 32784\n")),
        "2:5: D = 32784 is out of range (0-32768 points in 16-point units)"
    );
    assert_eq!(
        error(&with_main("[devices]\nW = \"8K\"\n")),
        "2:5: W must be a number of points (an integer), not a string"
    );
    assert_eq!(
        error(&with_main("[devices]\nM = 4096\nm = 8192\n")),
        "3:1: M is given twice"
    );
}

#[test]
fn fixed_devices_cannot_be_changed() {
    assert_eq!(
        error(&with_main("[devices]\nX = 4096\n")),
        "2:1: X has a fixed size (8192 points) and cannot be changed"
    );
    assert_eq!(
        error(&with_main("[devices]\nSB = 1024\n")),
        "2:1: SB has a fixed size (2048 points) and cannot be changed"
    );
    assert_eq!(
        error(&with_main("[devices]\nZR = 1024\n")),
        "2:1: set the file register size with file_register (ZR points; R is the first 32768 of them)"
    );
    assert_eq!(
        error(&with_main("[devices]\nQ = 16\n")),
        "2:1: unknown key \"Q\" in [devices] (expected M, L, F, V, B, T, ST, C, D, W, file_register)"
    );
}

#[test]
fn file_register_size() {
    assert_eq!(
        error(&with_main("[devices]\nfile_register = 1000\n")),
        "2:17: file_register = 1000 is out of range (0-1042432 points in 1K-point (1024) units)"
    );
    assert_eq!(
        error(&with_main("[devices]\nfile_register = 1043456\n")),
        "2:17: file_register = 1043456 is out of range (0-1042432 points in 1K-point (1024) units)"
    );
    let p = ok(&with_main("[devices]\nfile_register = 1042432\n"));
    assert_eq!(p.config.devices.points(DeviceKind::ZR), 1_042_432);
}

#[test]
fn device_memory_limit() {
    // 3788.8 + (8192·2 + 2048·2 + 8192)/16 + (28672 + 8192) + (2048 + 1024)/16·18
    // = 3788.8 + 1792 + 36864 + 3456 = 45900.8 words > 29696.
    assert_eq!(
        error(&with_main("[devices]\nD = 28672\n")),
        "1:1: the device points need 45900.8 words of device memory, more than 29K (29696): \
         3.7K + (M+L+F+V+B)/16 + (D+W) + (T+ST+C)/16×18 = 3788.8 + 1792 + 36864 + 3456"
    );
    // Exactly at the limit is fine: D = 12288 + 176 → 29692.8 words.
    ok(&with_main("[devices]\nD = 12464\n"));
    assert!(load(&with_main("[devices]\nD = 12480\n")).is_err());
}

#[test]
fn bit_device_total_limit() {
    // Memory: 3788.8 + (3·32768 + 2048·2)/16 + 0 + (2048+1024)/16·18 = 3788.8 + 6400 + 3456
    // Bits: 98304 + 4096 + 2048 + 8192 + 2·3072 = 118784 > 65536.
    assert_eq!(
        error(&with_main(
            "[devices]\nM = 32768\nL = 32768\nB = 32768\nD = 0\nW = 0\n"
        )),
        "1:1: the bit devices total 118784 points, more than 64K (65536): M+L+F+V+B+SB+S + 2×(T+ST+C)"
    );
}

// ---------------------------------------------------------------- [timers]

#[test]
fn timer_bases() {
    let p = ok(&with_main("[timers]\nlow = \"50ms\"\nhigh = \"0.5ms\"\n"));
    assert_eq!((p.config.timer_low, p.config.timer_high), (ms(50), us(500)));
    let p = ok(&with_main("[timers]\nlow = \"1s\"\nhigh = \"100us\"\n"));
    assert_eq!(
        (p.config.timer_low, p.config.timer_high),
        (ms(1000), us(100))
    );
    assert_eq!(
        error(&with_main("[timers]\nlow = \"1.5ms\"\n")),
        "2:7: low \"1.5ms\" is out of range (1ms-1000ms in 1 ms steps)"
    );
    assert_eq!(
        error(&with_main("[timers]\nhigh = \"0.15ms\"\n")),
        "2:8: high \"0.15ms\" is out of range (0.1ms-100ms in 0.1 ms steps)"
    );
    assert_eq!(
        error(&with_main("[timers]\nhigh = \"101ms\"\n")),
        "2:8: high \"101ms\" is out of range (0.1ms-100ms in 0.1 ms steps)"
    );
}

// ---------------------------------------------------------------- [ras]

#[test]
fn ras_settings() {
    let p = ok(&with_main(
        "[ras]\nwatchdog = \"1s\"\nconstant_scan = \"999.5ms\"\noperation_error = \"continue\"\n\
         stop_to_run_output = \"recalculate\"\nlow_speed_time = \"20ms\"\ninitial_monitor = \"2000ms\"\n",
    ));
    let c = &p.config;
    assert_eq!(c.watchdog, ms(1000));
    assert_eq!(c.constant_scan, Some(us(999_500)));
    assert_eq!(c.operation_error, ErrorMode::Continue);
    assert_eq!(c.stop_to_run_output, StopToRunOutput::Recalculate);
    assert_eq!(c.low_speed_time, Some(ms(20)));
    assert_eq!(c.initial_monitor, Some(ms(2000)));
    let p = ok(&with_main(
        "[ras]\nconstant_scan = \"off\"\nlow_speed_time = \"off\"\ninitial_monitor = \"off\"\n",
    ));
    assert_eq!(p.config.constant_scan, None);
    assert_eq!(p.config.low_speed_time, None);
    assert_eq!(p.config.initial_monitor, None);
}

#[test]
fn ras_ranges() {
    assert_eq!(
        error(&with_main("[ras]\nconstant_scan = \"2500ms\"\n")),
        "2:17: constant_scan \"2500ms\" is out of range (0.5ms-2000ms in 0.5 ms steps)"
    );
    assert_eq!(
        error(&with_main("[ras]\nwatchdog = \"205ms\"\n")),
        "2:12: watchdog \"205ms\" is out of range (10ms-2000ms in 10 ms steps)"
    );
    assert_eq!(
        error(&with_main("[ras]\nwatchdog = \"2010ms\"\n")),
        "2:12: watchdog \"2010ms\" is out of range (10ms-2000ms in 10 ms steps)"
    );
    assert_eq!(
        error(&with_main(
            "[ras]\nlow_speed_time = \"0.5ms\"\nconstant_scan = \"10ms\"\n"
        )),
        "2:18: low_speed_time \"0.5ms\" is out of range (1ms-2000ms in 1 ms steps)"
    );
    assert_eq!(
        error(&with_main("[ras]\ninitial_monitor = \"15ms\"\n")),
        "2:19: initial_monitor \"15ms\" is out of range (10ms-2000ms in 10 ms steps)"
    );
}

#[test]
fn ras_value_types() {
    assert_eq!(
        error(&with_main("[ras]\nwatchdog = \"fast\"\n")),
        "2:12: watchdog \"fast\" is not a duration (write a number and a unit: \"100ms\", \"0.5ms\", \"2s\", \"500us\")"
    );
    assert_eq!(
        error(&with_main("[ras]\nwatchdog = 200\n")),
        "2:12: watchdog must be a duration string such as \"100ms\", not an integer"
    );
    assert_eq!(
        error(&with_main("[ras]\noperation_error = \"halt\"\n")),
        "2:19: operation_error \"halt\" is not one of stop, continue"
    );
    assert_eq!(
        error(&with_main("[ras]\nstop_to_run_output = true\n")),
        "2:22: stop_to_run_output must be one of previous, recalculate (a string), not a boolean"
    );
}

#[test]
fn watchdog_must_exceed_constant_scan() {
    assert_eq!(
        error(&with_main("[ras]\nconstant_scan = \"200ms\"\n")),
        "2:17: constant_scan \"200ms\" must be shorter than the watchdog (200ms, the default); \
         the CPU requires watchdog > constant scan"
    );
    assert_eq!(
        error(&with_main(
            "[ras]\nconstant_scan = \"300ms\"\nwatchdog = \"250ms\"\n"
        )),
        "2:17: constant_scan \"300ms\" must be shorter than the watchdog (250ms); \
         the CPU requires watchdog > constant scan"
    );
    ok(&with_main(
        "[ras]\nconstant_scan = \"300ms\"\nwatchdog = \"310ms\"\n",
    ));
}

// ---------------------------------------------------------------- [latch]

#[test]
fn latch_default_is_l_latch1() {
    let p = ok(MAIN);
    assert_eq!(p.config.latch, vec![latch(DeviceKind::L, 0, 8191, true)]);
    // It follows the L points.
    let p = ok(&with_main("[devices]\nL = 1024\n"));
    assert_eq!(p.config.latch, vec![latch(DeviceKind::L, 0, 1023, true)]);
    let p = ok(&with_main("[devices]\nL = 0\n"));
    assert_eq!(p.config.latch, vec![]);
}

#[test]
fn latch_ranges() {
    let p = ok(&with_main(
        "[latch]\nlatch1 = [\"D1000-D1999\", \"B0-B1F\", \"t0-t9\", \"W100\"]\n\
         latch2 = [\"L100-L199\", \"D2000-D2099\", \"CN0-CN9\"]\n",
    ));
    assert_eq!(
        p.config.latch,
        vec![
            latch(DeviceKind::L, 0, 99, true),
            latch(DeviceKind::L, 200, 8191, true),
            latch(DeviceKind::D, 1000, 1999, true),
            latch(DeviceKind::B, 0, 0x1F, true),
            latch(DeviceKind::TS, 0, 9, true),
            latch(DeviceKind::W, 0x100, 0x100, true),
            latch(DeviceKind::L, 100, 199, false),
            latch(DeviceKind::D, 2000, 2099, false),
            latch(DeviceKind::CS, 0, 9, false),
        ]
    );
    let p = ok(&with_main("[latch]\nlatch1 = []\nlatch2 = []\n"));
    assert_eq!(p.config.latch, vec![latch(DeviceKind::L, 0, 8191, true)]);
}

#[test]
fn latch_devices_per_kind() {
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"L0-L99\"]\n")),
        "2:11: L is always latched (latch (1)) over its whole range; put a part of it in latch2 to keep it through latch clear"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"M0-M99\"]\n")),
        "2:11: M cannot be in latch1; latch1 allows B, F, V, T, ST, C, D, W"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch2 = [\"B0-BF\"]\n")),
        "2:11: B cannot be in latch2; latch2 allows L, F, V, T, ST, C, D, W"
    );
}

#[test]
fn latch_range_checks() {
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"D0-D12288\"]\n")),
        "2:11: \"D0-D12288\": D12288 is outside the configured points (D has 12288)"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"ST0-ST9\"]\n")),
        "2:11: \"ST0-ST9\": ST9 is outside the configured points (ST has 0)"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"D10-D5\"]\n")),
        "2:11: range \"D10-D5\" ends before it starts"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"D0-W5\"]\n")),
        "2:11: \"D0-W5\": a range must start and end in the same device"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"D0..D5\"]\n")),
        "2:11: \"D0..D5\" is not a device range (write e.g. \"D1000-D1999\" or \"B0-B1F\")"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = \"D0-D5\"\n")),
        "2:10: latch1 must be an array of ranges such as [\"D1000-D1999\"], not a string"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [100]\n")),
        "2:11: latch1 must be device ranges such as \"D1000-D1999\", not an integer"
    );
}

#[test]
fn latch_one_range_per_device_and_no_overlap() {
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"D0-D9\", \"D100-D109\"]\n")),
        "2:20: latch1 already has a range for D (\"D0-D9\"); the parameter allows one range per device"
    );
    assert_eq!(
        error(&with_main("[latch]\nlatch1 = [\"T0-T9\", \"TN20-TN29\"]\n")),
        "2:20: latch1 already has a range for T (\"T0-T9\"); the parameter allows one range per device"
    );
    assert_eq!(
        error(&with_main(
            "[latch]\nlatch1 = [\"D1000-D1999\"]\nlatch2 = [\"D1500-D2500\"]\n"
        )),
        "3:11: latch2 range \"D1500-D2500\" overlaps the latch1 range \"D1000-D1999\""
    );
    // Adjacent ranges do not overlap.
    ok(&with_main(
        "[latch]\nlatch1 = [\"D1000-D1999\"]\nlatch2 = [\"D2000-D2500\"]\n",
    ));
}

// ---------------------------------------------------------------- [interrupts]

#[test]
fn interrupt_periods() {
    let p = ok(&with_main(
        "[interrupts]\nI28 = \"1000ms\"\ni29 = \"0.5ms\"\nI31 = \"12.5ms\"\n",
    ));
    assert_eq!(
        p.config.interrupt_periods,
        [ms(1000), us(500), ms(20), us(12_500)]
    );
    assert_eq!(
        error(&with_main("[interrupts]\nI30 = \"0.75ms\"\n")),
        "2:7: I30 \"0.75ms\" is out of range (0.5ms-1000ms in 0.5 ms steps)"
    );
    assert_eq!(
        error(&with_main("[interrupts]\nI28 = \"1001ms\"\n")),
        "2:7: I28 \"1001ms\" is out of range (0.5ms-1000ms in 0.5 ms steps)"
    );
    assert_eq!(
        error(&with_main("[interrupts]\nI27 = \"10ms\"\n")),
        "2:1: I27 has no settable period: only I28-I31 are fixed-cycle interrupts"
    );
    assert_eq!(
        error(&with_main("[interrupts]\nI28 = \"10ms\"\ni28 = \"20ms\"\n")),
        "3:1: I28 is given twice"
    );
    assert_eq!(
        error(&with_main("[interrupts]\nperiod = \"10ms\"\n")),
        "2:1: unknown key \"period\" in [interrupts] (expected I28, I29, I30, I31)"
    );
}

// ---------------------------------------------------------------- [[program]]

#[test]
fn program_types_and_intervals() {
    let p = ok("[ras]\nconstant_scan = \"10ms\"\n\
                [[program]]\nfile = \"init.il\"\ntype = \"initial\"\n\
                [[program]]\nfile = \"main.il\"\ntype = \"scan\"\n\
                [[program]]\nfile = \"low.il\"\ntype = \"low-speed\"\n\
                [[program]]\nfile = \"sub.il\"\ntype = \"standby\"\n\
                [[program]]\nfile = \"fast.il\"\ntype = \"fixed-scan\"\ninterval = \"2s\"\n");
    let got: Vec<(String, ExecType, Option<Duration>)> = p
        .programs
        .iter()
        .map(|s| {
            (
                s.file.file_name().unwrap().to_string_lossy().into_owned(),
                s.exec,
                s.interval,
            )
        })
        .collect();
    assert_eq!(
        got,
        vec![
            ("init.il".into(), ExecType::Initial, None),
            ("main.il".into(), ExecType::Scan, None),
            ("low.il".into(), ExecType::LowSpeed, None),
            ("sub.il".into(), ExecType::Standby, None),
            ("fast.il".into(), ExecType::FixedScan, Some(ms(2000))),
        ]
    );
    for (iv, d) in [
        ("0.5ms", us(500)),
        ("999.5ms", us(999_500)),
        ("1000ms", ms(1000)),
        ("60s", ms(60_000)),
    ] {
        let p = ok(&format!(
            "[[program]]\nfile = \"main.il\"\n[[program]]\nfile = \"fast.il\"\ntype = \"fixed-scan\"\ninterval = \"{iv}\"\n"
        ));
        assert_eq!(p.programs[1].interval, Some(d), "{iv}");
    }
}

#[test]
fn missing_program_file_is_named() {
    let dir = scratch("[[program]]\nfile = \"mian.il\"\n");
    let d = load_project(&dir).unwrap_err();
    assert_eq!(d.0.len(), 1);
    assert_eq!((d.0[0].line, d.0[0].col), (2, 8));
    assert_eq!(
        d.0[0].message,
        format!(
            "program file \"mian.il\" not found ({})",
            dir.join("mian.il").display()
        )
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn program_table_errors() {
    assert_eq!(
        error("[[program]]\ntype = \"scan\"\n"),
        "1:1: [[program]] needs a file = \"name.il\""
    );
    assert_eq!(
        error("[[program]]\nfile = \"main.il\"\ntype = \"cyclic\"\n"),
        "3:8: type \"cyclic\" is not one of initial, scan, low-speed, standby, fixed-scan"
    );
    assert_eq!(
        error("[[program]]\nfile = \"main.il\"\n[[program]]\nfile = \"main.il\"\n"),
        "4:8: program file \"main.il\" is listed twice (first as \"main.il\")"
    );
    assert_eq!(
        error("[program]\nfile = \"main.il\"\n"),
        "1:1: program must be an array of tables: write a [[program]] table for each program file"
    );
    assert_eq!(
        error("[ras]\nwatchdog = \"200ms\"\n"),
        "1:1: the project has no programs: add a [[program]] table with file and type for each program file"
    );
}

#[test]
fn interval_only_and_required_for_fixed_scan() {
    assert_eq!(
        error("[[program]]\nfile = \"main.il\"\ninterval = \"50ms\"\n"),
        "3:1: interval is only for fixed-scan programs (this one is scan)"
    );
    assert_eq!(
        error(&with_main("[[program]]\nfile = \"fast.il\"\ntype = \"fixed-scan\"\n")),
        "3:8: a fixed-scan program needs an interval (0.5ms-999.5ms in 0.5 ms steps, or 1s-60s in 1 s steps)"
    );
    assert_eq!(
        error(&with_main(
            "[[program]]\nfile = \"fast.il\"\ntype = \"fixed-scan\"\ninterval = \"1500ms\"\n"
        )),
        "4:12: interval \"1500ms\" is out of range (0.5ms-999.5ms in 0.5 ms steps, or 1s-60s in 1 s steps)"
    );
    assert_eq!(
        error(&with_main(
            "[[program]]\nfile = \"fast.il\"\ntype = \"fixed-scan\"\ninterval = \"61s\"\n"
        )),
        "4:12: interval \"61s\" is out of range (0.5ms-999.5ms in 0.5 ms steps, or 1s-60s in 1 s steps)"
    );
}

#[test]
fn a_scan_or_initial_program_is_required() {
    assert_eq!(
        error("[[program]]\nfile = \"sub.il\"\ntype = \"standby\"\n"),
        "1:1: no program of type scan or initial: a project needs at least one"
    );
    ok("[[program]]\nfile = \"init.il\"\ntype = \"initial\"\n");
}

#[test]
fn low_speed_programs_need_constant_scan_or_low_speed_time() {
    let progs =
        "[[program]]\nfile = \"main.il\"\n[[program]]\nfile = \"low.il\"\ntype = \"low-speed\"\n";
    assert_eq!(
        error(progs),
        "5:8: a low-speed program runs only in the spare time of a constant scan or for a \
         low-speed execution time: set [ras] constant_scan or low_speed_time"
    );
    ok(&format!("[ras]\nlow_speed_time = \"5ms\"\n{progs}"));
    ok(&format!("[ras]\nconstant_scan = \"5ms\"\n{progs}"));
}

#[test]
fn program_count_per_model() {
    // 60 program files for a Q06HCPU; 28 for a Q02CPU (004 Table 3.1).
    let dir = scratch(MAIN);
    let mut toml = String::from("[cpu]\nmodel = \"Q02CPU\"\n");
    for i in 0..29 {
        let f = format!("p{i}.il");
        std::fs::write(dir.join(&f), "END\n").unwrap();
        toml.push_str(&format!("[[program]]\nfile = \"{f}\"\n"));
    }
    std::fs::write(dir.join("plc.toml"), &toml).unwrap();
    let d = load_project(&dir).unwrap_err();
    assert_eq!(d.0.len(), 1, "{d}");
    // The 29th [[program]] starts at line 3 + 2·28.
    assert_eq!((d.0[0].line, d.0[0].col), (59, 1));
    assert_eq!(
        d.0[0].message,
        "too many programs (29): a Q02CPU executes at most 28 program files"
    );
    std::fs::write(dir.join("plc.toml"), toml.replace("Q02CPU", "Q06HCPU")).unwrap();
    assert_eq!(load_project(&dir).unwrap().programs.len(), 29);
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------- [initial]

#[test]
fn initial_values() {
    let p = ok(&with_main(
        "[initial]\n\"D0\" = 100\n\"D10:f32\" = 1.5\n\"D12:i32\" = -70000\n\"W1F:u16\" = \"HFFFF\"\n\
         \"D20:str\" = \"AB\"\n\"TN5\" = 7\n\"STN0\" = 1\n\"CN3\" = 2\n\"SD100\" = 3\n\"SW0\" = 4\n\
         \"R0\" = 5\n\"ZR100000\" = 6\n\"D30:f32\" = 2\n[devices]\nST = 16\n",
    ));
    let got: Vec<(&str, &str)> = p
        .config
        .initial_values
        .iter()
        .map(|v| (v.device.text.as_str(), v.value.as_str()))
        .collect();
    assert_eq!(
        got,
        vec![
            ("D0", "100"),
            ("D10:f32", "1.5"),
            ("D12:i32", "-70000"),
            ("W1F:u16", "HFFFF"),
            ("D20:str", "AB"),
            ("TN5", "7"),
            ("STN0", "1"),
            ("CN3", "2"),
            ("SD100", "3"),
            ("SW0", "4"),
            ("R0", "5"),
            ("ZR100000", "6"),
            ("D30:f32", "2"),
        ]
    );
}

#[test]
fn initial_value_devices() {
    assert_eq!(
        error(&with_main("[initial]\n\"M0\" = 1\n")),
        "2:1: M cannot have an initial value; initial values are for TN, STN, CN (current values), D, SD, W, SW, R, ZR"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"T0\" = 5\n")),
        "2:1: \"T0\" is a contact; write TN0 for the current value"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0.3\" = 1\n")),
        "2:1: \"D0.3\" is a bit operand; initial values are set for word devices (TN, STN, CN (current values), D, SD, W, SW, R, ZR)"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0Z1\" = 1\n")),
        "2:1: \"D0Z1\": index modification is not allowed for initial values"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0:f64\" = 1\n")),
        "2:1: \"D0:f64\": unknown type `f64` (i16, u16, i32, u32, f32, str)"
    );
    assert_eq!(
        error(&with_main("[initial]\nD12287 = 1\n\"D12287:i32\" = 1\n")),
        "3:1: D12287:i32: D12288 is outside the configured range (12288 points)"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"STN0\" = 1\n")),
        "2:1: STN0: STN0 is outside the configured range (0 points)"
    );
}

#[test]
fn initial_value_values() {
    assert_eq!(
        error(&with_main("[initial]\n\"D0\" = 70000\n")),
        "2:8: initial value 70000 is not valid for D0 (a 16-bit integer: -32768 to 65535, or H0-HFFFF)"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0\" = \"ten\"\n")),
        "2:8: initial value \"ten\" is not valid for D0 (a 16-bit integer: -32768 to 65535, or H0-HFFFF)"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0\" = 1.5\n")),
        "2:8: initial value 1.5 is not valid for D0 (a 16-bit integer: -32768 to 65535, or H0-HFFFF); write D0:f32 for a real number"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0:f32\" = 1e39\n")),
        "2:12: initial value 1000000000000000000000000000000000000000 is not valid for D0:f32 (a finite 32-bit real number)"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0\" = true\n")),
        "2:8: the initial value of D0 must be a number or a string, not a boolean"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0:str\" = 12\n")),
        "2:12: the initial value of D0:str must be text (a string)"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D12286:str\" = \"ABCD\"\n")),
        "2:16: the text for D12286:str does not fit: D12288 is outside the configured range (12288 points)"
    );
}

#[test]
fn initial_values_must_not_overlap() {
    assert_eq!(
        error(&with_main("[initial]\n\"D0:i32\" = 1\n\"D1\" = 2\n")),
        "3:1: D1 overlaps the initial value of D0:i32"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"R5\" = 1\n\"ZR5\" = 2\n")),
        "3:1: ZR5 overlaps the initial value of R5"
    );
}

// ---------------------------------------------------------------- [clock], [state]

#[test]
fn clock_start() {
    let want = DateTime {
        year: 2024,
        month: 2,
        day: 29,
        hour: 23,
        minute: 59,
        second: 58,
    };
    let p = ok(&with_main("[clock]\nstart = \"2024-02-29T23:59:58\"\n"));
    assert_eq!(p.config.clock_start, want);
    let p = ok(&with_main("[clock]\nstart = 2024-02-29T23:59:58\n"));
    assert_eq!(
        p.config.clock_start, want,
        "a TOML local date-time works too"
    );
    assert_eq!(
        error(&with_main("[clock]\nstart = \"2023-02-29T00:00:00\"\n")),
        "2:9: start \"2023-02-29T00:00:00\" is not a valid local date and time (write \"YYYY-MM-DDTHH:MM:SS\", e.g. \"2000-01-01T00:00:00\")"
    );
    assert_eq!(
        error(&with_main("[clock]\nstart = 2000-01-01T00:00:00Z\n")),
        "2:9: start \"2000-01-01T00:00:00Z\" is not a valid local date and time (write \"YYYY-MM-DDTHH:MM:SS\", e.g. \"2000-01-01T00:00:00\")"
    );
    assert_eq!(
        error(&with_main("[clock]\nstart = \"1970-01-01T00:00:00\"\n")),
        "2:9: start \"1970-01-01T00:00:00\" is outside the clock's years 1980-2079"
    );
    assert_eq!(
        error(&with_main("[clock]\nstart = 2000\n")),
        "2:9: start must be a date and time such as \"2000-01-01T00:00:00\", not an integer"
    );
}

#[test]
fn state_dir() {
    let p = ok(&with_main("[state]\ndir = \"var/plc\"\n"));
    assert_eq!(p.state_dir, p.dir.join("var/plc"));
    assert_eq!(
        error(&with_main("[state]\ndir = \"\"\n")),
        "2:7: dir must not be empty"
    );
    assert_eq!(
        error(&with_main("[state]\ndir = 5\n")),
        "2:7: dir must be a directory path (a string), not an integer"
    );
}

#[test]
fn columns_count_characters_not_bytes() {
    // "é" is two bytes but one column.
    assert_eq!(
        error(&with_main("[ras] # é\nwatchdog = \"é\"\n")),
        "2:12: watchdog \"é\" is not a duration (write a number and a unit: \"100ms\", \"0.5ms\", \"2s\", \"500us\")"
    );
    assert_eq!(
        error(&with_main("[cpu]\n\"modèl\" = 1\n")),
        "2:1: unknown key \"modèl\" in [cpu]; did you mean \"model\"?"
    );
    assert_eq!(
        error(&with_main("[clock]\n  start = \"é\" \n")),
        "2:11: start \"é\" is not a valid local date and time (write \"YYYY-MM-DDTHH:MM:SS\", e.g. \"2000-01-01T00:00:00\")"
    );
}
