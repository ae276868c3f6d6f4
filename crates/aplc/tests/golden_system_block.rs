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

/// A CPU whose run input is X3 (SM9 ON, SD9 = 3).
fn run_input_plc(src: &str) -> common::Plc {
    let mut c = config();
    c.run_input = Some(3);
    c.system = softplc_aplc::system_with_run_input(200, 0, Vec::new(), Some(3));
    plc_with(src, c)
}

/// §2.3.2 "复位方式" (L1225-1229): with the run input, power-on enters RUN
/// only when the input is ON; "输入点开机模式" (L1231-1235): in STOP, its
/// OFF→ON change starts RUN; the next scan is the first (SM1).
#[test]
fn run_input_waits_at_power_on_for_its_rising_edge() {
    let mut p = run_input_plc("LD SM0\nOUT M0\nLD SM1\nOUT M1\n");
    assert!(!p.running(), "X3 OFF at power-on: STOP");
    p.scans(2);
    assert!(!p.running() && !p.bit("M0"));
    assert!(p.bit("SM9"));
    assert_eq!(p.int("SD9"), 3);
    p.set("X3", "1").scan();
    assert!(p.running(), "the rising edge at END in STOP starts RUN");
    p.scan();
    assert!(p.bit("M0") && p.bit("M1"), "the first scan after STOP→RUN");
    // §2.3.2's ways to STOP are the STOP instruction, an error and the
    // programming tool: the input going OFF is not one of them.
    p.set("X3", "0").scans(2);
    assert!(p.running() && p.bit("M0"));
}

/// Power-on (RESET) with the input ON enters RUN at once; without it the
/// RESET leaves the CPU in STOP.
#[test]
fn run_input_on_at_reset_runs() {
    let mut p = run_input_plc("LD SM0\nOUT M0\n");
    p.set("X3", "1");
    p.cpu.set_stop();
    p.cpu.reset().unwrap();
    assert!(p.running());
    p.cpu.set_stop();
    p.set("X3", "0");
    p.cpu.reset().unwrap();
    assert!(!p.running());
}

/// After the STOP instruction (the switch still at RUN) the input must go
/// OFF and ON again: an input held ON is no change. An ON pulse that ends
/// between two ENDs is an edge all the same.
#[test]
fn run_input_restarts_after_the_stop_instruction() {
    let mut p = run_input_plc("LD X0\nSTOP\n");
    p.set("X3", "1").scan();
    assert!(p.running());
    p.set("X0", "1").scan();
    assert!(!p.running(), "STOP instruction");
    p.set("X0", "0").scans(2);
    assert!(!p.running(), "X3 still ON: no OFF→ON change");
    p.set("X3", "0").scan();
    p.set("X3", "1").set("X3", "0").scan();
    assert!(p.running(), "a pulse shorter than a scan starts RUN");
}

/// "模式选择开关应处于 ON 位置" (L1237): with the switch at STOP the input does
/// not start RUN; the switch to RUN does, whatever the input.
#[test]
fn run_input_needs_the_switch_at_run() {
    let mut p = run_input_plc("LD SM0\nOUT M0\n");
    p.cpu.set_stop();
    p.set("X3", "1").scan();
    assert!(!p.running(), "the switch is at STOP");
    p.set("X3", "0").scan();
    p.cpu.set_run().unwrap();
    assert!(p.running(), "the switch to RUN");
}

/// App. 1 SM90-SM97 (L10783-10797): the rising edge of X0-X7 sets the
/// relay, which stays ON until the program resets it; an input turned ON
/// and OFF again between two scans is caught although X0 never shows it.
#[test]
fn pulse_catch_holds_each_rising_edge() {
    let src = "LD SM90\nOUT M0\nLD SM97\nOUT M7\nLD M10\nRST SM90\n";
    let mut p = plc(src);
    p.scan();
    assert!(!p.bit("M0"));
    p.set("X0", "1").set("X0", "0").scan();
    assert!(!p.bit("X0") && p.bit("M0") && p.bit("SM90"));
    p.scans(2);
    assert!(p.bit("M0"), "held until the program resets it");
    p.set("M10", "1").scan().set("M10", "0").scan();
    assert!(!p.bit("SM90") && !p.bit("M0"));
    // X7 is SM97; X10 (input 8) has no pulse catch.
    p.set("X7", "1").set("X10", "1").scan();
    assert!(p.bit("M7") && p.bit("SM97"));
    assert!(!p.bit("SM100"));
    // An input held ON is no new edge after the program reset the relay.
    p.set("X0", "1").scan();
    assert!(p.bit("SM90"));
    p.set("M10", "1").scan().set("M10", "0").scans(2);
    assert!(p.bit("X0") && !p.bit("SM90"));
}

/// "由 STOP 到 RUN 时清除" (L10794): an edge in STOP is not shown after
/// STOP→RUN, nor one caught before it.
#[test]
fn pulse_catch_is_cleared_at_stop_to_run() {
    let mut p = plc("LD SM0\nOUT M0\n");
    p.set("X1", "1").scan();
    assert!(p.bit("SM91"));
    p.cpu.set_stop();
    p.set("X2", "1").scan();
    p.cpu.set_run().unwrap();
    p.scan();
    assert!(!p.bit("SM91") && !p.bit("SM92"));
}

/// App. 2 L11065-11070: the positioning parameters' initial values; SD85
/// (high word) and SD86 hold 100000 = 16#0001_86A0.
#[test]
fn positioning_registers_start_at_their_initial_values() {
    let p = plc("LD SM0\nOUT M0\n");
    let got: Vec<i64> = (84..=89).map(|n| p.int(&format!("SD{n}"))).collect();
    assert_eq!(got, [0, 1, 0x86A0u16 as i16 as i64, 100, 100, 100]);
}
