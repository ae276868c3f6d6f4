//! Projects (`plc.toml`, contract §1 and §4): the example project, defaults,
//! and one failing file per validation rule with the exact `line:col: message`.
//! Positions are worked out by hand (1-based lines, character columns).
//!
//! This file: the `[interrupts]`, `[[program]]`, `[initial]`, `[clock]` and `[state]`
//! sections, and columns counted in characters.

use std::time::Duration;

use softplc_core::engine::calendar::DateTime;
use softplc_core::engine::ExecType;
use softplc_core::project::load_project;

mod common;
use common::project::{error, ms, ok, scratch, us, with_main, MAIN};

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
        "2:1: unknown key \"period\" in [interrupts] (expected I28, I29, I30, I31, counter_start)"
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
        "2:1: M cannot have an initial value; initial values are for TN, STN, CN (current values), D, SD, W, SW, R, ZR and buffer memory U\\G"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"T0\" = 5\n")),
        "2:1: \"T0\" is a contact; write TN0 for the current value"
    );
    assert_eq!(
        error(&with_main("[initial]\n\"D0.3\" = 1\n")),
        "2:1: \"D0.3\" is a bit operand; initial values are set for word devices (TN, STN, CN (current values), D, SD, W, SW, R, ZR and buffer memory U\\G)"
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
