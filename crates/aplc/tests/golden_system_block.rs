//! Golden tests of the system block's run settings (002 §2.1.6 L969-979,
//! §2.2.1 L1086-1092 and L1148-1158, §2.3 L1223-1243, App. 1 L10698, App. 2
//! L10984-11004) and of STOP (§6.1.10 L3735-3743). Values worked by hand.

mod common;
use common::{config, plc, plc_with};
use softplc_engine::StopOutputs;

/// "当能流有效时，系统将立即停止用户程序的执行" (L3743): the instructions after
/// STOP do not run in that scan, and the CPU is in STOP without an error.
#[test]
fn stop_stops_the_program_at_once() {
    let src = "LD SM0\nOUT M0\nLD X0\nSTOP\nLD SM0\nOUT M1\nMOV 7 D1\n";
    let mut p = plc(src);
    p.scan();
    assert!(p.bit("M0") && p.bit("M1") && p.int("D1") == 7);
    p.set("M1", "0").set("D1", "0").set("X0", "1");
    p.scan();
    assert!(!p.running(), "STOP stops the CPU");
    assert_eq!(p.error_code(), None, "STOP is no error");
    assert!(p.bit("M0"), "before STOP the scan ran");
    assert!(!p.bit("M1"), "after STOP nothing ran");
    assert_eq!(p.int("D1"), 0);
}

/// A scan that reaches STOP does no END processing: SD30 keeps the previous
/// scan's time (10 ms per scan in the harness).
#[test]
fn stop_skips_end_processing() {
    let mut p = plc("LD X0\nSTOP\n");
    p.scan();
    assert_eq!(p.int("SD30"), 10);
    p.set("SD30", "0").set("X0", "1");
    p.scan();
    assert_eq!(p.int("SD30"), 0);
}

/// Program: D4 = D0 / D2 with X1 (D2 = 0: run error 69, SD20 = 69, SM20).
const DIV: &str = "LD X1\nDIV D0 D2 D4\nLD SM0\nOUT M0\n";

/// STOP→RUN without "keep device values" (L1154-1156): the devices are
/// initialised; every SM (L10698) and every SD but SD50-SD55 (L10984) too,
/// the working-state rows back to their values (SD1 softplc 0.1 = 1, SD2 12k
/// steps, SD10 = 10 inputs << 8 | 6 outputs = 2566).
#[test]
fn stop_to_run_reinitialises_devices_sm_and_sd() {
    let mut c = config();
    c.keep_device_values = false;
    let mut p = plc_with(DIV, c);
    p.set("X1", "1");
    p.scan();
    assert_eq!(p.int("SD20"), 69);
    assert!(p.bit("SM20") && p.running());
    p.set("D100", "42")
        .set("M10", "1")
        .set("SD50", "9")
        .set("SD55", "8");
    p.set("SD60", "7").set("SM100", "1").set("X1", "0");
    p.cpu.set_stop();
    p.cpu.set_run().unwrap();
    assert_eq!(p.int("D100"), 0);
    assert!(!p.bit("M10") && !p.bit("M0"));
    assert_eq!(
        p.int("SD20"),
        0,
        "the error history is an SD like the others"
    );
    assert!(!p.bit("SM20") && !p.bit("SM100"));
    assert_eq!(p.int("SD60"), 0);
    assert_eq!((p.int("SD50"), p.int("SD55")), (9, 8), "SD50-SD55 are kept");
    assert_eq!((p.int("SD1"), p.int("SD2"), p.int("SD10")), (1, 12, 2566));
    assert_eq!((p.int("SD0"), p.int("SD3")), (0, 0));
    assert!(!p.bit("SM3"), "no system error");
    assert!(p.bit("SM196"), "EEPROM idle again");
    assert_eq!(p.int("SD34"), 200, "the watchdog shown again");
    p.scan();
    assert!(p.bit("SM1") && p.bit("M0"));
}

/// "元件值保持" (L1154-1156): the device values are kept, while SM and SD are
/// re-initialised all the same (App. 1/2 make no exception).
#[test]
fn keep_device_values_keeps_devices_not_sd() {
    let mut c = config();
    c.keep_device_values = true;
    let mut p = plc_with(DIV, c);
    p.set("X1", "1");
    p.scan();
    p.set("D100", "42").set("M10", "1").set("X1", "0");
    p.cpu.set_stop();
    p.cpu.set_run().unwrap();
    assert_eq!(p.int("D100"), 42);
    assert!(p.bit("M10"));
    assert_eq!(p.int("SD20"), 0);
    assert!(!p.bit("SM20"));
}

/// The EEPROM image outranks the cleared devices (table 2-2 L971-979):
/// D6000 saved by EROMWR comes back at STOP→RUN, D6001 (not saved) is
/// cleared.
#[test]
fn eeprom_data_outranks_the_reinitialisation() {
    let mut c = config();
    c.keep_device_values = false;
    let src = "LD SM1\nMOV 123 D6000\nMOV 5 D6001\nLD M0\nEROMWR D6000 1\nLD SM0\nSET M0\n";
    let mut p = plc_with(src, c);
    p.scans(3);
    p.set("D6000", "0").set("D6001", "0");
    p.cpu.set_stop();
    p.cpu.set_run().unwrap();
    assert_eq!((p.int("D6000"), p.int("D6001")), (123, 0));
}

/// The output table (L1086-1092): "禁止" all OFF, "冻结" the last state,
/// "组态" the configured state; the Y devices keep their values.
#[test]
fn outputs_in_stop_follow_the_output_table() {
    let src = "LD SM0\nOUT Y1\nOUT Y2\n";
    for (mode, y1, y2, y3) in [
        (StopOutputs::Off, false, false, false),
        (StopOutputs::Hold, true, true, false),
        (StopOutputs::Table(vec![2, 3]), false, true, true),
    ] {
        let mut c = config();
        c.stop_outputs = mode.clone();
        let mut p = plc_with(src, c);
        p.scan();
        assert!(p.cpu.output(1) && p.cpu.output(2) && !p.cpu.output(3));
        p.cpu.set_stop();
        p.scan();
        let got = (p.cpu.output(1), p.cpu.output(2), p.cpu.output(3));
        assert_eq!(got, (y1, y2, y3), "{mode:?}");
        assert!(p.bit("Y1"), "device memory is kept in STOP");
    }
}

/// Freeze holds the state at RUN→STOP, not what is written in STOP.
#[test]
fn hold_is_the_state_at_stop() {
    let mut c = config();
    c.stop_outputs = StopOutputs::Hold;
    let mut p = plc_with("LD X0\nOUT Y0\n", c);
    p.set("X0", "1").scan();
    p.cpu.set_stop();
    p.set("Y0", "0");
    assert!(p.cpu.output(0));
}

/// The STOP instruction's outputs follow the output table too.
#[test]
fn stop_instruction_outputs_follow_the_table() {
    let mut c = config();
    c.stop_outputs = StopOutputs::Hold;
    let mut p = plc_with("LD SM0\nOUT Y5\nLD X0\nSTOP\n", c);
    p.set("X0", "1").scan();
    assert!(!p.running());
    assert!(p.cpu.output(5));
}
