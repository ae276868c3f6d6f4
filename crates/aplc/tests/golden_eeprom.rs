//! Golden tests of EROMWR and the power-on retention of D6000-D6999 (002
//! §6.8.8 L6572-6628, §2.1.8 L985-991; spec aplc.md §4.11, decisions D5 and
//! D12). RESET is the power-on processing, so it shows what a power cycle
//! keeps; crates/core/tests/aplc_eeprom.rs does the same through a state
//! directory.

mod common;
use common::{plc, Plc};

/// Power off and on: STOP, then RESET (which runs again).
fn power_cycle(p: &mut Plc) {
    p.cpu.set_stop();
    p.cpu.reset().unwrap();
    assert!(p.running());
}

/// The manual's listing (L6598-6626): SM1 sets M1, so on the second scan M1
/// sets M1000, fills D6016/D6032, and `EROMWR D6016 2` sees its rising edge;
/// M1001 then writes the 16 words from D6032 and is reset.
const MANUAL: &str = "LD M1\nSET M1000\nRST M1\nMOV 16 D6016\nMOV 32 D6032\n\
LD SM1\nSET M1\n\
LD M1000\nAND SM196\nEROMWR D6016 2\n\
LD M1001\nAND SM196\nEROMWR D6032 16\nRST M1001\n";

#[test]
fn manual_example_survives_power_on() {
    let mut p = plc(MANUAL);
    p.scan();
    assert!(p.bit("SM196"), "EEPROM idle");
    assert!(p.bit("M1") && !p.bit("M1000"));
    p.scan();
    assert!(p.bit("M1000") && !p.bit("M1"));
    assert_eq!((p.int("D6016"), p.int("D6032")), (16, 32));
    // D6032 is not written yet: a power cycle brings back only D6016-D6017.
    p.set("D0", "7").set("D6100", "5");
    power_cycle(&mut p);
    assert_eq!(
        (p.int("D6016"), p.int("D6032"), p.int("D0"), p.int("D6100")),
        (16, 0, 0, 0)
    );
    assert!(!p.bit("M1000"), "M is cleared at power-on");
    // After the power cycle the program runs again (SM1): both MOVs, the
    // first write; then M1001 writes D6032-D6047.
    p.scans(2);
    p.set("D6047", "-3").set("M1001", "1").scan();
    assert!(!p.bit("M1001"));
    power_cycle(&mut p);
    assert_eq!(
        (p.int("D6016"), p.int("D6032"), p.int("D6047")),
        (16, 32, -3)
    );
    assert_eq!(p.error_code(), None);
}

/// The write happens on the rising edge only: holding the power flow does not
/// write again (L6594 "上升沿时指令执行").
#[test]
fn rising_edge_only() {
    let mut p = plc("LD M0\nEROMWR D6000 1\n");
    p.set("D6000", "11").set("M0", "1").scan();
    p.set("D6000", "22").scans(3);
    power_cycle(&mut p);
    assert_eq!(p.int("D6000"), 11);
    p.set("D6000", "33").set("M0", "1").scan();
    p.set("M0", "0").scan();
    p.set("D6000", "44").set("M0", "1").scan();
    power_cycle(&mut p);
    assert_eq!(p.int("D6000"), 44, "a new rising edge writes again");
}

/// D12: 0 ≤ S2 ≤ 16 and the block ends by D6999; otherwise error 64 and
/// nothing written. S2 from a register; S2 = 0 writes nothing, no error.
#[test]
fn count_rules_are_error_64() {
    let src = "LD M0\nEROMWR D6984 16\nLD M1\nEROMWR D6990 16\nLD M2\nEROMWR D6000 D0\nLD M3\nEROMWR D6010 D1Z1\n";
    let mut p = plc(src);
    for d in [6984, 6999, 6990, 6000, 6010] {
        p.set(&format!("D{d}"), &(d - 6000).to_string());
    }
    p.set("M0", "1").scan();
    assert_eq!(p.error_code(), None, "D6984 + 16 ends at D6999");
    p.set("M1", "1").set("D6990", "1").scan();
    assert_eq!(p.error_code(), Some(64));
    assert!(p.running(), "64 keeps running");
    p.set("D0", "17").set("M2", "1").scan();
    assert_eq!((p.int("SD20"), p.int("SD21")), (64, 0));
    // S2 from D1Z1 = D2 = 0: nothing written, no new error.
    p.set("Z1", "1").set("M3", "1").scan();
    power_cycle(&mut p);
    assert_eq!(p.error_code(), None, "power-on clears the error");
    assert_eq!(
        (
            p.int("D6984"),
            p.int("D6999"),
            p.int("D6990"),
            p.int("D6000"),
            p.int("D6010")
        ),
        (984, 999, 990, 0, 0),
        "D6990 holds what the first write stored"
    );
}

#[test]
fn operand_diagnostics() {
    for (src, want) in [
        (
            "LD M0\nEROMWR D7000 1\n",
            "t.apl:2:8: `D7000`: EROMWR writes from D6000-D6999, without index",
        ),
        (
            "LD M0\nEROMWR D6000Z1 1\n",
            "`D6000Z1`: EROMWR writes from D6000-D6999, without index",
        ),
        (
            "LD M0\nEROMWR V0 1\n",
            "`V0`: EROMWR writes from D6000-D6999",
        ),
        (
            "LD M0\nEROMWR D6000\n",
            "`EROMWR` takes 2 operands, found 1",
        ),
        ("LD M0\nEROMWRP D6000 1\n", "EROMWRP"),
    ] {
        let e = common::errors(src);
        assert!(e.contains(want), "{src}: {e}");
    }
}

/// STOP→RUN: the saved words come back from the EEPROM over the device values
/// (table 2-2 L971-979: EEPROM data "high", device values "low"); a word
/// EROMWR never saved keeps its value, as every other device does.
#[test]
fn stop_to_run_loads_the_saved_words() {
    let mut p = plc("LD M0\nEROMWR D6500 1\n");
    p.set("D6500", "5").set("M0", "1").scan();
    p.set("D6500", "6").set("D6501", "7").set("D1", "8").scan();
    p.cpu.set_stop();
    p.cpu.set_run().unwrap();
    assert_eq!((p.int("D6500"), p.int("D6501"), p.int("D1")), (5, 7, 8));
    power_cycle(&mut p);
    assert_eq!((p.int("D6500"), p.int("D6501")), (5, 0));
}

/// Steps (L6576, spec §4.11): 6, and 7 with an index-modified S2. `LD M0`
/// is 1 step.
#[test]
fn step_count() {
    let steps = |src: &str| {
        softplc_aplc::load_bytes("t.apl", src.as_bytes())
            .unwrap()
            .steps
    };
    assert_eq!(steps("LD M0\nEROMWR D6000 16\n"), 1 + 6);
    assert_eq!(steps("LD M0\nEROMWR D6000 D1Z1\n"), 1 + 7);
}
