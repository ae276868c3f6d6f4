//! Golden tests for sequence instructions, timers, counters, master control and
//! the system relays/registers. Every expected value is worked out by hand from
//! the manual's rules (004 §10.2.10-10.2.11, App. 1/2; notes in qcpu.md §5.2, §6,
//! §8.1) in the comment next to it.
//!
//! Virtual time in the harness: power-on is time 0, the clock is advanced by the
//! scan time before each scan, so scan k (10 ms scans) reads 10·k ms, and the
//! first scan is measured at its END as 10 ms (from power-on).
//!
//! This file: timers and counters.

mod common;
use common::{diagnostics, inputs, outputs, Plc};
use softplc_core::device::DeviceKind;

// ---------------------------------------------------------------- timers

#[test]
fn low_speed_timer_10ms_scans() {
    let mut p = Plc::new(
        "\
LD X0
OUT T0 K10
LD T0
OUT Y0
END
",
    );
    // Base 100 ms, 10 ms scans. The coil turns ON in scan 1 (adds nothing); each
    // later scan adds 10 ms, so TN0 = n at scan 10n+1 and reaches K10 at scan 101.
    p.set("X0", "1").scan();
    assert_eq!(p.int("TN0"), 0);
    p.scans(9); // scan 10: 90 ms accumulated
    assert_eq!(p.int("TN0"), 0);
    p.scan(); // scan 11: 100 ms
    assert_eq!(p.int("TN0"), 1);
    p.scans(89); // scan 100
    assert_eq!(p.int("TN0"), 9);
    assert!(!p.bit("T0") && !p.bit("Y0"));
    p.scan(); // scan 101
    assert_eq!(p.int("TN0"), 10);
    assert!(p.bit("T0") && p.bit("Y0"));
    // Timed out: stays at the set value.
    p.scans(20);
    assert_eq!(p.int("TN0"), 10);
    assert!(p.bit("T0"));
    // Coil OFF → current value 0 and contact OFF at once.
    p.set("X0", "0").scan();
    assert_eq!(p.int("TN0"), 0);
    assert!(!p.bit("T0") && !p.bit("Y0"));
    // Coil ON again: counts from 0 again, time-up 100 scans after the ON scan.
    p.set("X0", "1").scans(100);
    assert_eq!(p.int("TN0"), 9);
    assert!(!p.bit("T0"));
    p.scan();
    assert!(p.bit("T0"));
}

#[test]
fn high_speed_timer_10ms_scans() {
    let mut p = Plc::new(
        "\
LD X0
OUTH T1 K10
END
",
    );
    // Base 10 ms, 10 ms scans: scan 1 (coil ON) 0, scan k → k-1, K10 at scan 11.
    p.set("X0", "1").scan();
    assert_eq!(p.int("TN1"), 0);
    p.scans(9); // scan 10
    assert_eq!(p.int("TN1"), 9);
    assert!(!p.bit("T1"));
    p.scan(); // scan 11
    assert_eq!(p.int("TN1"), 10);
    assert!(p.bit("T1"));
}

#[test]
fn low_speed_timer_7ms_scans_carries_remainder() {
    let mut p = Plc::new(
        "\
LD X0
OUT T2 K5
END
",
    );
    p.scan_time_us(7_000);
    p.scans(3); // coil OFF
    assert_eq!(p.int("TN2"), 0);
    // Coil ON in scan 1 (of this count); scan k adds 7 ms from k = 2, so after
    // scan k the timer holds 7·(k-1) ms and TN2 = floor(7·(k-1) / 100):
    //   k=15:  98 → 0    k=16: 105 → 1
    //   k=29: 196 → 1    k=30: 203 → 2
    //   k=43: 294 → 2    k=44: 301 → 3
    //   k=58: 399 → 3    k=59: 406 → 4
    //   k=72: 497 → 4    k=73: 504 → 5 = K5: time-up
    let expect = [
        (15, 0),
        (16, 1),
        (29, 1),
        (30, 2),
        (43, 2),
        (44, 3),
        (58, 3),
        (59, 4),
        (72, 4),
        (73, 5),
    ];
    p.set("X0", "1");
    let mut k = 0;
    for (at, tn) in expect {
        while k < at {
            p.scan();
            k += 1;
        }
        assert_eq!(p.int("TN2"), tn, "scan {k}");
        assert_eq!(p.bit("T2"), tn == 5, "scan {k}");
    }
    // Coil OFF resets the timer, the 4 ms left over from 504 ms included: timing
    // restarts from the next coil-ON exactly as above (0 at scan 15, 1 at 16; a
    // kept 4 ms would give 4 + 7·14 = 102 ms → 1 already at scan 15).
    p.set("X0", "0").scan();
    assert_eq!(p.int("TN2"), 0);
    p.set("X0", "1").scans(15);
    assert_eq!(p.int("TN2"), 0);
    p.scan();
    assert_eq!(p.int("TN2"), 1);
}

#[test]
fn timer_set_value_zero_and_from_d() {
    let mut p = Plc::new(
        "\
LD X0
OUT T3 K0
LD X1
OUTH T4 D0
END
",
    );
    p.set("D0", "3");
    // Set value 0: contact ON at the first execution with the coil ON (L6507).
    p.set("X0", "1").scan();
    assert!(p.bit("T3"));
    assert_eq!(p.int("TN3"), 0);
    // OUTH T4 D0, D0 = 3: 0, 1, 2, then 3 at the 4th scan.
    p.set("X1", "1").scans(3);
    assert_eq!(p.int("TN4"), 2);
    assert!(!p.bit("T4"));
    p.scan();
    assert_eq!(p.int("TN4"), 3);
    assert!(p.bit("T4"));
}

#[test]
fn raising_set_value_after_time_up_keeps_contact() {
    let mut p = Plc::new(
        "\
LD X0
OUTH T5 D1
END
",
    );
    p.set("D1", "2");
    // 0, 1, 2: timed out at scan 3.
    p.set("X0", "1").scans(3);
    assert!(p.bit("T5"));
    assert_eq!(p.int("TN5"), 2);
    // Set value raised above the current value: stays timed out, no further
    // timing (L6509-6510).
    p.set("D1", "5").scans(5);
    assert!(p.bit("T5"));
    assert_eq!(p.int("TN5"), 2);
}

#[test]
fn timer_and_counter_update_at_out_not_at_end() {
    let mut p = Plc::new(
        "\
LD T6
OUT Y0
LD C2
OUT Y2
LD X0
OUTH T6 K2
LD X0
OUT C2 K1
LD T6
OUT Y1
LD C2
OUT Y3
END
",
    );
    // Coil, current value and contact are processed when OUT T/OUT C executes,
    // never at END (L6474-6490, 10.2.11 (2)(a)): a contact read before the OUT
    // sees the new state one scan later than one read after it.
    // T6 (10 ms base, K2): 0, 1, 2 → ON in scan 3. C2 (K1): ON in scan 1.
    p.set("X0", "1").scan();
    assert_eq!(outputs(&p, 4), "0001");
    p.scan();
    assert_eq!(outputs(&p, 4), "0011");
    p.scan();
    assert_eq!(outputs(&p, 4), "0111");
    p.scan();
    assert_eq!(outputs(&p, 4), "1111");
}

#[test]
fn timer_out_twice_per_scan_adds_twice() {
    let mut p = Plc::new(
        "\
LD X0
OUTH T7 K100
LD X0
OUTH T7 K100
END
",
    );
    // Each OUT T with the coil ON adds the last scan time (L6495-6497). Scan 1:
    // the first OUT turns the coil ON (adds nothing), the second adds the scan
    // time measured at the previous END; there was none yet, so 0. Later scans
    // add 10 ms twice: scan k → 2·(k-1).
    p.set("X0", "1").scan();
    assert_eq!(p.int("TN7"), 0);
    p.scans(2);
    assert_eq!(p.int("TN7"), 4);
}

#[test]
fn retentive_timer_keeps_value() {
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(DeviceKind::STS, 16);
    let mut p = Plc::with_config(
        "\
LD X0
OUTH ST0 K5
LD X1
RST ST0
END
",
        cfg,
    );
    // 10 ms base, 10 ms scans: 0, 1, 2.
    p.set("X0", "1").scans(3);
    assert_eq!(p.int("STN0"), 2);
    // Coil OFF: value kept (a plain timer would go to 0).
    p.set("X0", "0").scans(2);
    assert_eq!(p.int("STN0"), 2);
    assert!(!p.bit("ST0"));
    // Coil ON again: resumes from 2. The coil-ON execution adds nothing, then
    // +1 per scan: 2, 3, 4, 5 → time-up at the 4th scan.
    p.set("X0", "1").scans(3);
    assert_eq!(p.int("STN0"), 4);
    assert!(!p.bit("ST0"));
    p.scan();
    assert_eq!(p.int("STN0"), 5);
    assert!(p.bit("ST0"));
    // Coil OFF: contact and value kept.
    p.set("X0", "0").scans(2);
    assert!(p.bit("ST0"));
    assert_eq!(p.int("STN0"), 5);
    // RST ST0 clears both.
    p.set("X1", "1").scan();
    assert!(!p.bit("ST0"));
    assert_eq!(p.int("STN0"), 0);
}

#[test]
fn retentive_timer_needs_points() {
    // The default configuration has 0 ST points (004: retentive timers need
    // points assigned), so the program must not load.
    let d = diagnostics(
        "\
LD X0
OUT ST0 K10
END
",
    );
    assert!(
        d.iter()
            .any(|m| m.starts_with("2:") && m.contains("0 points")),
        "{d:?}"
    );
}

// ---------------------------------------------------------------- counters

#[test]
fn counter_counts_rising_edges() {
    let mut p = Plc::new(
        "\
LD X1
RST C0
LD X0
OUT C0 K3
LD C0
OUT Y0
LD X2
OUT C1 D0
END
",
    );
    // C1's set value, in D0, is given before the first scan.
    p.set("D0", "2");
    // +1 only on OFF→ON of the coil (not ON→ON, ON→OFF, OFF→OFF).
    for (x0, cn, c) in [
        ("1", 1, false), // rise
        ("1", 1, false), // ON→ON
        ("0", 1, false), // ON→OFF: value kept
        ("1", 2, false), // rise
        ("0", 2, false),
        ("1", 3, true), // rise: 3 = K3, contact ON
        ("0", 3, true), // coil OFF: value and contact kept
        ("1", 3, true), // counted out: no further counting
    ] {
        inputs(&mut p, x0);
        p.scan();
        assert_eq!(p.int("CN0"), cn);
        assert_eq!(p.bit("C0"), c);
        assert_eq!(p.bit("Y0"), c);
    }
    // RST C0 clears value and contact at once.
    inputs(&mut p, "01");
    p.scan();
    assert_eq!(p.int("CN0"), 0);
    assert!(!p.bit("C0") && !p.bit("Y0"));
    inputs(&mut p, "10");
    p.scan();
    assert_eq!(p.int("CN0"), 1);

    // Set value in D0 = 2: the second rising edge of X2 turns C1 ON.
    assert_eq!(p.int("CN1"), 0);
    assert!(!p.bit("C1"));
    p.set("X2", "1").scan();
    assert_eq!(p.int("CN1"), 1);
    assert!(!p.bit("C1"));
    p.set("X2", "0").scan();
    p.set("X2", "1").scan();
    assert_eq!(p.int("CN1"), 2);
    assert!(p.bit("C1"));
}

#[test]
fn counter_set_value_zero_counts_as_one() {
    // Set value 0 is processed as 1: nothing before the first count, ON at it.
    let mut p = Plc::new("LD X0\nOUT C1 D0\nEND\n");
    p.scan();
    assert!(!p.bit("C1"));
    p.set("X0", "1").scan();
    assert!(p.bit("C1"));
    assert_eq!(p.int("CN1"), 1);
}
