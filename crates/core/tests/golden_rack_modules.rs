//! The simulated analog modules in a rack, driven by a program: the Q64AD
//! (Analog-Digital Converter Module User's Manual, SH-080055) and the
//! Q62DA/Q64DA (Digital-Analog Converter Module User's Manual, SH-080054),
//! in normal resolution mode. Values worked out by hand from the manuals'
//! I/O conversion characteristics (4000 digits over the range) and
//! buffer-memory assignments.

mod common;
use common::{assert_running, Plc};

/// 32 inputs X0-X1F (slot 0), a Q64AD at X/Y20 (slot 1, unit 2), a Q64DA at
/// X/Y30 (slot 2, unit 3).
fn rack(ad: &str, da: &str, program: &str) -> Plc {
    let toml = format!(
        "[[program]]\nfile = \"main.il\"\n\
         [[slot]]\ntype = \"input\"\npoints = 32\n\
         [[slot]]\ntype = \"intelligent\"\nmodule = \"Q64AD\"\n{ad}\n\
         [[slot]]\ntype = \"intelligent\"\nmodule = \"Q64DA\"\n{da}\n"
    );
    Plc::project(&toml, &[("main.il", program)])
}

/// The physical value at input `ch` of the module in `slot`.
fn analog_in(p: &mut Plc, slot: usize, ch: u32, value: f64) {
    p.cpu
        .module_mut(slot)
        .expect("a module in the slot")
        .set_channel(ch, value)
        .expect("an input channel");
}

fn analog_out(p: &Plc, slot: usize, ch: u32) -> f64 {
    p.cpu
        .module(slot)
        .expect("a module in the slot")
        .channel(ch)
        .expect("an output channel")
}

/// SH-080055, I/O conversion characteristic and digital output values
/// (Un\G11-14): with the ranges of switch 1 (`range`), 12 mA on 4-20 mA is
/// 2000, 2.5 V on 0-10 V 1000, -5 V on -10-10 V -2000, 5 V on 1-5 V 4000.
/// The program reads them with FROM once X20 (module READY) and X2E (A/D
/// conversion completed) are ON: the module converts at END, so the first
/// scan sees nothing yet. Un\G20 shows the ranges (codes 0, 5, 4, 2).
#[test]
fn q64ad_digital_output_values() {
    let mut p = rack(
        "range = [\"4-20mA\", \"0-10V\", \"-10-10V\", \"1-5V\"]",
        "",
        "LD X20\nAND X2E\nFROM H2 K11 D0 K4\nMOV U2\\G20 D10\nMOV U2\\G10 D11\nEND\n",
    );
    for (ch, v) in [(1, 12.0), (2, 2.5), (3, -5.0), (4, 5.0)] {
        analog_in(&mut p, 1, ch, v);
    }
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), 0, "X2E is not ON before the first END");
    assert_eq!(p.int("U2\\G11"), 2000, "converted at the first END");
    p.scan();
    assert_eq!(
        (p.int("D0"), p.int("D1"), p.int("D2"), p.int("D3")),
        (2000, 1000, -2000, 4000)
    );
    assert_eq!(p.int("D10"), 0x2450);
    assert_eq!(p.int("D11"), 0xF);
    // Beyond the range the value is fixed at -96..4095: 25 mA is 4095,
    // 2 mA (-500) is -96; -12 V on -10-10 V is -4096.
    analog_in(&mut p, 1, 1, 25.0);
    analog_in(&mut p, 1, 3, -12.0);
    p.scans(2);
    assert_eq!((p.int("D0"), p.int("D2")), (4095, -4096));
    analog_in(&mut p, 1, 1, 2.0);
    p.scans(2);
    assert_eq!(p.int("D0"), -96);
    // Maximum and minimum values of CH1 (Un\G30, Un\G31).
    assert_eq!((p.int("U2\\G30"), p.int("U2\\G31")), (4095, -96));
}

/// SH-080055, A/D conversion methods and the operating condition setting
/// request: the program enables CH1 only (Un\G0 = 000EH), selects time
/// averaging (Un\G9 = 0101H) of 50 ms (Un\G1) and turns Y29 ON; X29 goes
/// OFF until Y29 is OFF again. With one channel a conversion takes 80 µs,
/// so a period is 625 conversions: from the END that took Y29 (10 ms) to
/// the END at 60 ms (10 ms scans). 8 mA (1000) for the first 250, 16 mA
/// (3000) for the last 375: leaving out one maximum and one minimum,
/// (250·1000 + 375·3000 − 3000 − 1000) / 623 = 2200.6 → 2200.
#[test]
fn q64ad_time_averaging_set_by_the_program() {
    let mut p = rack(
        "",
        "",
        "LD X20\nANI M0\nMOV H0E U2\\G0\nMOV H101 U2\\G9\nMOV K50 U2\\G1\nSET Y29\nSET M0\n\
         LD Y29\nANI X29\nRST Y29\n\
         LD X2E\nMOV U2\\G11 D0\nMOV U2\\G10 D1\nEND\n",
    );
    analog_in(&mut p, 1, 1, 8.0);
    p.scan();
    assert!(p.bit("Y29"));
    p.scan();
    assert!(!p.bit("Y29"), "X29 went OFF: the request was taken");
    p.scan();
    analog_in(&mut p, 1, 1, 16.0);
    p.scans(3);
    assert_eq!(p.int("U2\\G11"), 2200, "the first period ends at 60 ms");
    assert_eq!(p.int("D0"), 0, "X2E is seen at the next input refresh");
    p.scan();
    assert_eq!((p.int("D0"), p.int("D1")), (2200, 1));
    assert!(p.bit("X29"));
}

/// SH-080055 error codes: an averaging count out of 4-62500 is 30□ (□ the
/// channel) with XF (X2F) ON; YF (Y2F) clears it.
#[test]
fn q64ad_averaging_error() {
    let mut p = rack(
        "",
        "",
        "LD X0\nMOV H2 U2\\G9\nMOV K3 U2\\G2\nOUT Y29\nLD X1\nOUT Y2F\nLD X2F\nOUT M0\nEND\n",
    );
    p.set("X0", "1").scans(2);
    assert_eq!(p.int("U2\\G19"), 302);
    assert!(p.bit("M0"));
    p.set("X0", "0").set("X1", "1").scans(2);
    assert_eq!(p.int("U2\\G19"), 0);
    assert!(!p.bit("M0"));
}

/// SH-080054: the program enables the conversion of CH1 and CH2 (Un\G0 = 0
/// with Y39), writes the digital values (Un\G1, Un\G2) and turns the
/// output enable signals Y31, Y32 ON. CH1 4-20 mA: 2000 is 12 mA; CH2
/// 0-5 V: 3000 is 3.75 V. Output enable OFF gives the offset value (4 mA).
/// In STOP, CH1 (CLEAR) gives the offset value and CH2 (HOLD, switch 3)
/// keeps 3.75 V.
#[test]
fn q64da_analog_outputs() {
    let mut p = rack(
        "",
        "range = [\"4-20mA\", \"0-5V\"]\nswitches = [0, 0, 0x0010, 0, 0]",
        "LD X30\nANI M0\nMOV H0 U3\\G0\nSET Y39\nSET M0\n\
         LD Y39\nANI X39\nRST Y39\n\
         LD SM400\nMOV D100 U3\\G1\nMOV D101 U3\\G2\n\
         LD M1\nOUT Y31\nOUT Y32\nEND\n",
    );
    assert_eq!(analog_out(&p, 2, 1), 0.0, "power-on: disabled, 0 mA");
    p.set("D100", "2000").set("D101", "3000").set("M1", "1");
    p.scan();
    assert_running(&p);
    assert_eq!(analog_out(&p, 2, 1), 12.0);
    assert_eq!(analog_out(&p, 2, 2), 3.75);
    assert_eq!(p.int("U3\\G20"), 0x0030);
    p.set("M1", "0").scan();
    assert_eq!(analog_out(&p, 2, 1), 4.0);
    p.set("M1", "1").scan();
    assert_eq!(analog_out(&p, 2, 1), 12.0);
    p.cpu.set_stop();
    p.scan();
    assert_eq!(analog_out(&p, 2, 1), 4.0, "CLEAR");
    assert_eq!(analog_out(&p, 2, 2), 3.75, "HOLD");
}

/// A Q64AD's digital output feeds a Q64DA through the program: the loop
/// closes inside the rack. 10 V on 0-10 V (4000) drives CH1 4-20 mA to
/// 20 mA.
#[test]
fn ad_to_da() {
    let mut p = rack(
        "range = [\"0-10V\"]",
        "",
        "LD X30\nANI M0\nMOV H0E U3\\G0\nSET Y39\nSET M0\nLD Y39\nANI X39\nRST Y39\n\
         LD X2E\nMOV U2\\G11 U3\\G1\nOUT Y31\nEND\n",
    );
    analog_in(&mut p, 1, 1, 10.0);
    p.scans(3);
    assert_eq!(analog_out(&p, 2, 1), 20.0);
    analog_in(&mut p, 1, 1, 5.0);
    p.scans(2);
    assert_eq!(analog_out(&p, 2, 1), 12.0);
}

/// The switch setting is checked at load: a range the module has not
/// (0-10V on a D/A), a range on a module without ranges, on a slot without
/// a module, switch 4 (offset/gain setting mode) and a malformed list.
#[test]
fn switch_setting_errors() {
    let load = |slot: &str| {
        let toml = format!("[[program]]\nfile = \"main.il\"\n[[slot]]\n{slot}\n");
        Plc::try_project(&toml, &[("main.il", "LD X0\nOUT Y0\nEND\n")])
            .err()
            .unwrap_or_default()
    };
    let e = load("type = \"intelligent\"\nmodule = \"Q62DA\"\nrange = [\"0-10V\"]");
    assert!(e.contains("slot 0 (Q62DA): CH1: no range \"0-10V\""), "{e}");
    let e = load("type = \"intelligent\"\nrange = [\"0-10V\"]");
    assert!(e.contains("the generic module has no analog ranges"), "{e}");
    let e = load("type = \"input\"\npoints = 16\nrange = [\"0-10V\"]");
    assert!(
        e.contains("slot 0: range is for a slot holding a module"),
        "{e}"
    );
    let e = load("type = \"intelligent\"\nmodule = \"Q64AD\"\nswitches = [0, 0, 0, 1, 0]");
    assert!(e.contains("switch 4 must be 0"), "{e}");
    let e = load("type = \"intelligent\"\nmodule = \"Q64AD\"\nswitches = [0, 0, 0, 0, 0, 0]");
    assert!(e.contains("switches must be up to 5 numbers"), "{e}");
    let e = load("type = \"intelligent\"\nmodule = \"Q64AD\"\nrange = [\"4-20mA\", 5]");
    assert!(e.contains("range must be an array of range names"), "{e}");
}
