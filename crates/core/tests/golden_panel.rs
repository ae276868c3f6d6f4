//! The CPU's front panel (004 §7.19, App. 1, App. 2): SD200 the switch,
//! SD201 the LEDs, SM202/SD202 the LED OFF command, SD207-SD209 the LED
//! display priority, LEDR's order (§10.2.4 L6294-6297), and the battery
//! relays SM51/SM52. Values worked out by hand; SD201's layout (two bits an
//! LED: RUN b0-b1, ERROR b2-b3, USER b4-b5, BAT. b6-b7, MODE b14-b15; 0 OFF,
//! 1 ON, 2 flashing) is the QCPU's, whose figure the manual in hand lost.

mod common;
use common::Plc;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{CpuConfig, ErrorMode};

/// RUN ON, MODE ON (Q mode, nothing forced).
const RUNNING: i64 = 0x4001;
/// The ERROR, USER and BAT. LEDs ON.
const ERROR_ON: i64 = 1 << 2;
const USER_ON: i64 = 1 << 4;
const BAT_ON: i64 = 1 << 6;

fn continuing(src: &str) -> Plc {
    let cfg = CpuConfig {
        operation_error: ErrorMode::Continue,
        ..softplc_core::profile::default_config()
    };
    Plc::with_config(src, cfg)
}

/// SD207-SD209 hold the default priority at power-on: causes 1-4, 5-8, 9
/// and A, priority 1 in the lowest digit (L5392-5406).
#[test]
fn default_led_priority() {
    let mut p = Plc::new("END\n");
    p.scan();
    // Read as signed words: 8765H is -30875.
    let words = [p.int("SD207"), p.int("SD208"), p.int("SD209")];
    assert_eq!(words.map(|w| w as u16), [0x4321, 0x8765, 0x00A9]);
}

/// SD200 b0-b3: the switch, 0 RUN, 1 STOP (L10318-10329); the key switch
/// is `set_stop`/`set_run`.
#[test]
fn switch_status() {
    let mut p = Plc::new("END\n");
    p.scan();
    assert_eq!(p.int("SD200"), 0);
    p.cpu.set_stop();
    assert_eq!(p.int("SD200"), 1);
    assert_eq!(p.int("SD201"), 0x4000, "RUN OFF in STOP");
    p.cpu.set_run().unwrap();
    assert_eq!(p.int("SD200"), 0);
    p.scan();
    assert_eq!(p.int("SD201"), RUNNING);
}

/// The LEDs (L5330-5336): a continuation error lights ERROR, an annunciator
/// USER; a stop error turns RUN OFF and flashes ERROR; forced I/O flashes
/// MODE (L4237).
#[test]
fn led_status() {
    let mut p = continuing("LD X0\n/ K1 K0 D0\nLD X1\nSET F5\nEND\n");
    p.scan();
    assert_eq!(p.int("SD201"), RUNNING);
    p.set("X0", "1").scan();
    assert_eq!(p.int("SD201"), RUNNING | ERROR_ON);
    p.set("X0", "0").set("X1", "1").scan();
    // The annunciator is the latest error: USER ON, ERROR OFF.
    assert_eq!(p.int("SD201"), RUNNING | USER_ON);
    let mut p = Plc::new("LD SM400\n/ K1 K0 D0\nEND\n");
    p.scan();
    assert_eq!(p.int("SD201"), 0x4000 | 2 << 2);
    let mut p = Plc::new("END\n");
    p.cpu.force(DeviceKind::Y, 0, true).unwrap();
    p.scan();
    assert_eq!(p.int("SD201") as u16, 0x8001);
}

/// A cause whose number is in no digit of SD207-SD209 does not light its
/// LED; SM0/SD0 are set all the same (L5408-5418).
#[test]
fn a_cause_left_out_of_the_priority_does_not_light() {
    let mut p = continuing("LD X0\n/ K1 K0 D0\nEND\n");
    p.scan();
    // Priority 3 (cause 3, OPERATION ERROR) set to 0.
    p.set("SD207", "16897"); // 4201H
    p.set("X0", "1").scan();
    assert_eq!(p.int("SD0"), 4100);
    assert!(p.bit("SM0"));
    assert_eq!(p.int("SD201"), RUNNING);
}

/// SM202 OFF→ON with SD202 = 10H turns the USER LED off (L5356-5370);
/// another annunciator turning ON lights it again.
#[test]
fn led_off_command() {
    let mut p = Plc::new("LD X0\nSET F5\nLD X1\nSET F6\nEND\n");
    p.set("X0", "1").scan();
    assert_eq!(p.int("SD201"), RUNNING | USER_ON);
    p.set("SD202", "16").set("SM202", "1").scan();
    assert_eq!(p.int("SD201"), RUNNING);
    p.scan();
    assert_eq!(p.int("SD201"), RUNNING, "stays off while SM202 stays ON");
    p.set("X1", "1").scan();
    assert_eq!(p.int("SD201"), RUNNING | USER_ON);
    // SD202 = 100H (BOOT only) leaves USER lit.
    p.set("SM202", "0").scan();
    p.set("SD202", "256").set("SM202", "1").scan();
    assert_eq!(p.int("SD201"), RUNNING | USER_ON);
}

/// LEDR clears a continuation error that outranks the annunciators before
/// it turns an annunciator OFF (L6294-6297): OPERATION ERROR is priority 3,
/// annunciators 7. The next LEDR turns F5 OFF.
#[test]
fn ledr_clears_a_higher_priority_error_first() {
    let src = "LD X0\nSET F5\nLD X1\n/ K1 K0 D0\nLD X2\nLEDR\nEND\n";
    let mut p = continuing(src);
    p.set("X0", "1").scan();
    p.set("X0", "0").set("X1", "1").scan();
    assert_eq!(p.int("SD0"), 4100);
    p.set("X1", "0").set("X2", "1").scan();
    assert!(p.cpu.error().is_none());
    assert!(!p.bit("SM0"));
    assert_eq!(p.int("SD0"), 0);
    assert!(p.bit("F5"));
    assert_eq!((p.int("SD62"), p.int("SD63")), (5, 1));
    assert_eq!(p.int("SD201"), RUNNING | USER_ON);
    p.scan();
    assert!(!p.bit("F5"));
    assert_eq!((p.int("SD62"), p.int("SD63")), (0, 0));
    assert_eq!(p.int("SD201"), RUNNING);
}

/// With the annunciators moved to priority 1 (SD207 = 3217H), LEDR turns
/// the annunciator OFF first and the error stays; ANR never clears errors.
#[test]
fn ledr_follows_the_priority() {
    let src = "LD X0\nSET F5\nLD X1\n/ K1 K0 D0\nLD X2\nLEDR\nLD X3\nANR\nEND\n";
    let mut p = continuing(src);
    p.set("SD207", "12823"); // 3217H
    p.set("X0", "1").scan();
    p.set("X0", "0").set("X1", "1").scan();
    p.set("X1", "0").set("X2", "1").scan();
    assert!(!p.bit("F5"));
    assert_eq!(p.int("SD0"), 4100);
    assert_eq!(p.int("SD201"), RUNNING | ERROR_ON);
    // ANR with the default priority: the annunciator, not the error.
    let mut p = continuing(src);
    p.set("X0", "1").scan();
    p.set("X0", "0").set("X1", "1").scan();
    p.set("X1", "0").set("X3", "1").scan();
    assert!(!p.bit("F5"));
    assert_eq!(p.int("SD0"), 4100);
}

/// BATTERY ERROR (1600) turns SM51 (latched) and SM52 ON and lights BAT.,
/// not ERROR (L9535-9536, L5333-5335); clearing it (SM50, SD50 = 1600)
/// turns SM52 and BAT. OFF, SM51 stays. M9006/M9007 (SM1006/SM1007) copy
/// SM52/SM51.
#[test]
fn battery_error_relays_and_led() {
    let mut p = Plc::new("END\n");
    p.scan();
    p.cpu.report_battery_error(false);
    p.scan();
    assert_eq!(p.int("SD0"), 1600);
    assert!(p.bit("SM51") && p.bit("SM52"));
    assert!(p.bit("SM1006") && p.bit("SM1007"));
    assert_eq!(p.int("SD201"), RUNNING | BAT_ON);
    p.set("SD50", "1600").set("SM50", "1").scan();
    assert!(p.cpu.error().is_none());
    assert!(p.bit("SM51") && !p.bit("SM52"));
    assert!(!p.bit("SM1006") && p.bit("SM1007"));
    assert_eq!(p.int("SD201"), RUNNING);
}
