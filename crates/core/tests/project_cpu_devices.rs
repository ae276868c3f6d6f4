//! Projects (`plc.toml`, contract §1 and §4): the example project, defaults,
//! and one failing file per validation rule with the exact `line:col: message`.
//! Positions are worked out by hand (1-based lines, character columns).
//!
//! This file: the `[cpu]`, `[devices]`, `[timers]`, `[ras]` and `[latch]` sections.

use softplc_core::device::DeviceKind;
use softplc_core::engine::{ErrorMode, StopToRunOutput};

mod common;
use common::project::{error, latch, load, ms, ok, us, with_main, MAIN};

// ---------------------------------------------------------------- [cpu]

#[test]
fn cpu_model() {
    let p = ok(&with_main("[cpu]\nmodel = \"q25hcpu\"\n"));
    assert_eq!(p.config.profile.model, "Q25HCPU");
    for m in ["Q02CPU", "Q02HCPU", "Q06HCPU", "Q12HCPU", "Q25HCPU"] {
        assert_eq!(
            ok(&with_main(&format!("[cpu]\nmodel = \"{m}\"\n")))
                .config
                .profile
                .model,
            m
        );
    }
    // APLC-TCP selects the APLC dialect (contract §4).
    let p = ok(&with_main("[cpu]\nmodel = \"APLC-TCP\"\n"));
    assert_eq!(p.config.profile.model, "APLC-TCP");
    // The APLC's own system: its error numbers (an operation error is 64).
    use softplc_core::engine::{ErrorCode, Fault};
    assert!(
        p.config.system.code(Fault::Operation) == Some(ErrorCode(64)) && p.config.latch.is_empty()
    );
    assert_eq!(
        error(&with_main("[cpu]\nmodel = \"Q99CPU\"\n")),
        "2:9: unknown CPU model \"Q99CPU\" (expected Q02CPU, Q02HCPU, Q06HCPU, Q12HCPU, Q25HCPU, \
         Q02PHCPU, Q06PHCPU, Q12PHCPU, Q25PHCPU, Q12PRHCPU, Q25PRHCPU, Q00UJCPU, Q00UCPU, Q01UCPU, \
         Q02UCPU, Q03UDCPU, \
         Q03UDECPU, Q03UDVCPU, Q04UDHCPU, Q04UDEHCPU, Q04UDVCPU, Q06UDHCPU, Q06UDEHCPU, Q06UDVCPU, \
         Q10UDHCPU, Q10UDEHCPU, Q13UDHCPU, Q13UDEHCPU, Q13UDVCPU, Q20UDHCPU, Q20UDEHCPU, \
         Q26UDHCPU, Q26UDEHCPU, Q26UDVCPU, or APLC-TCP)"
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
        "2:1: unknown key \"Q\" in [devices] (expected M, L, F, V, B, T, ST, C, D, W, file_register, file_register_name, local)"
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
