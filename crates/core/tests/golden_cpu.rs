//! CPU functions (004 ch. 4 and 7): program execution types, operating states,
//! latch, initial values. Expected values are worked out from the manual's rules
//! in the comments.

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
        CpuConfig::default(),
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
        CpuConfig::default(),
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
        CpuConfig::default(),
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
            ..CpuConfig::default()
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
    p.cpu.reset().unwrap();
    assert_eq!(p.state(), CpuState::Run);
    assert!(p.cpu.error().is_none());
    assert!(!p.bit("SM0"));
    assert_eq!(p.int("SD0"), 0);
    assert_eq!(p.int("D0"), 0);
    assert!(!p.bit("M5"));
    assert!(p.bit("L5"));
    p.scan();
    assert_eq!(p.int("D0"), 1);
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
        ..CpuConfig::default()
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
        ..CpuConfig::default()
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
        ..CpuConfig::default()
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
