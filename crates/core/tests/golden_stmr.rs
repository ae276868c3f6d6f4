//! Golden tests of STMR (`instructions::timing`), the special timer that acts
//! while its condition is OFF. `STMR T0 K5 M0`: 500 ms in 100 ms units in TN0;
//! M0 off delay, M1 one shot after OFF, M2 one shot after ON, M3 ON delay +
//! OFF delay. Scans take 10 ms; as with `OUT T`, the scan that sees the
//! condition change adds nothing, so after the j-th scan since the change the
//! elapsed time is 10·(j−1) ms.

mod common;
use common::{assert_stopped, diagnostics, Plc};

const STMR: &str = "LD X0\nSTMR T0 K5 M0\nEND\n";

fn outputs(p: &Plc) -> [bool; 4] {
    [p.bit("M0"), p.bit("M1"), p.bit("M2"), p.bit("M3")]
}

#[test]
fn stmr_all_four_outputs_through_a_long_on_and_off() {
    let mut p = Plc::new(STMR);
    p.scan(); // X0 OFF since RUN: nothing happens.
    assert_eq!(outputs(&p), [false; 4]);
    p.set("X0", "1").scan(); // ON scan 1: 0 ms
    assert_eq!(outputs(&p), [true, false, true, false]);
    assert_eq!(p.int("TN0"), 0);
    p.scans(49); // ON scan 50: 490 ms
    assert_eq!(p.int("TN0"), 4);
    assert_eq!(outputs(&p), [true, false, true, false]);
    p.scan(); // ON scan 51: 500 ms → one shot after ON ends, ON delay done
    assert_eq!(p.int("TN0"), 5);
    assert_eq!(outputs(&p), [true, false, false, true]);
    p.scans(20); // stays there, TN0 held at the set value
    assert_eq!(p.int("TN0"), 5);
    assert_eq!(outputs(&p), [true, false, false, true]);
    p.set("X0", "0").scan(); // OFF scan 1: one shot after OFF starts
    assert_eq!(p.int("TN0"), 0);
    assert_eq!(outputs(&p), [true, true, false, true]);
    p.scans(49); // OFF scan 50: 490 ms
    assert_eq!(p.int("TN0"), 4);
    assert_eq!(outputs(&p), [true, true, false, true]);
    p.scan(); // OFF scan 51: 500 ms → off delays end
    assert_eq!(p.int("TN0"), 5);
    assert_eq!(outputs(&p), [false; 4]);
}

#[test]
fn stmr_short_on_ends_the_on_one_shot_and_never_starts_the_on_delay() {
    let mut p = Plc::new(STMR);
    p.set("X0", "1").scans(20); // 190 ms ON
    assert_eq!(p.int("TN0"), 1);
    assert_eq!(outputs(&p), [true, false, true, false]);
    p.set("X0", "0").scan(); // OFF: M2 OFF at once, M1 starts
    assert_eq!(outputs(&p), [true, true, false, false]);
    p.scans(50); // OFF scan 51: 500 ms
    assert_eq!(outputs(&p), [false; 4]);
}

#[test]
fn stmr_short_off_keeps_the_off_delays_on_and_restarts_the_on_one_shot() {
    let mut p = Plc::new(STMR);
    p.set("X0", "1").scans(60); // M3 ON
    assert_eq!(outputs(&p), [true, false, false, true]);
    p.set("X0", "0").scans(10); // 90 ms OFF: M0, M3 still ON, M1 one shot ON
    assert_eq!(p.int("TN0"), 0);
    assert_eq!(outputs(&p), [true, true, false, true]);
    p.set("X0", "1").scan(); // ON again: M1 OFF, M2 one shot ON, M3 stays ON
    assert_eq!(outputs(&p), [true, false, true, true]);
    p.scans(50); // ON scan 51
    assert_eq!(outputs(&p), [true, false, false, true]);
}

#[test]
fn stmr_under_an_off_master_control_sees_its_condition_off() {
    // MC N0 M100 with X1: while X1 is OFF the STMR's condition is OFF.
    let src = "LD X1\nMC N0 M100\nLD X0\nSTMR T0 K2 M0\nMCR N0\nEND\n";
    let mut p = Plc::new(src);
    p.set("X1", "1").set("X0", "1").scans(30); // 290 ms ≥ 200 ms: M3 ON
    assert_eq!(outputs(&p), [true, false, false, true]);
    p.set("X1", "0").scan(); // MC OFF: condition OFF
    assert_eq!(outputs(&p), [true, true, false, true]);
    p.scans(20); // 200 ms after: off delays end
    assert_eq!(outputs(&p), [false; 4]);
}

#[test]
fn stmr_negative_set_value_is_4100() {
    let mut p = Plc::new("LD X0\nSTMR T0 D0 M0\nEND\n");
    p.set("D0", "-1").set("X0", "1").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn stmr_operands_are_checked_at_load() {
    let d = diagnostics("LD X0\nSTMR D0 K5 M0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:6: `D0`: STMR needs a timer T"), "{d:?}");
    let d = diagnostics("LD X0\nSTMR T0 K5 M8190\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("STMR uses 4 bits"), "{d:?}");
    let d = diagnostics("LD X0\nSTMRP T0 K5 M0\nEND\n");
    assert_eq!(d, ["2:1: `STMRP`: STMR has no pulse form"]);
}
