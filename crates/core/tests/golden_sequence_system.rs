//! Golden tests for sequence instructions, timers, counters, master control and
//! the system relays/registers. Every expected value is worked out by hand from
//! the manual's rules (004 §10.2.10-10.2.11, App. 1/2; notes in qcpu.md §5.2, §6,
//! §8.1) in the comment next to it.
//!
//! Virtual time in the harness: power-on is time 0, the clock is advanced by the
//! scan time before each scan, so scan k (10 ms scans) reads 10·k ms, and the
//! first scan is measured at its END as 10 ms (from power-on).
//!
//! This file: the special relays and registers (SM/SD): first scans, clocks,
//! scan times, the one-second counter.

mod common;
use common::Plc;

// ---------------------------------------------------------------- SM / SD

#[test]
fn sm400_to_sm403_first_scans() {
    let mut p = Plc::new(
        "\
LD SM400
OUT M0
LD SM401
OUT M1
LD SM402
OUT M2
LD SM403
OUT M3
END
",
    );
    // Scan 1: SM400 ON, SM401 OFF, SM402 ON (first scan only), SM403 OFF.
    p.scan();
    assert_eq!(
        [p.bit("M0"), p.bit("M1"), p.bit("M2"), p.bit("M3")],
        [true, false, true, false]
    );
    // Scan 2 and later: SM402 OFF, SM403 ON.
    for _ in 0..2 {
        p.scan();
        assert_eq!(
            [p.bit("M0"), p.bit("M1"), p.bit("M2"), p.bit("M3")],
            [true, false, false, true]
        );
    }
}

#[test]
fn clock_relays_in_virtual_time() {
    let prog = "\
LD SM409
OUT M9
LD SM410
OUT M10
LD SM412
OUT M12
END
";
    // 10 ms scans, scan k at t = 10·k ms. The clocks start OFF at power-on and
    // toggle every half period: SM410 (50 ms) ON when floor(t / 50) is odd (t in
    // [50, 100), [150, 200) … ms), SM412 (500 ms) ON for t in [500, 1000) ms.
    let mut p = Plc::new(prog);
    for k in 1..=120u32 {
        p.scan();
        let t = 10 * k;
        let m10 = (t / 50) % 2 == 1;
        let m12 = (t / 500) % 2 == 1;
        assert_eq!(p.bit("M10"), m10, "SM410 at scan {k}");
        assert_eq!(p.bit("M12"), m12, "SM412 at scan {k}");
    }
    // Spot checks of the same, written out: scans 4/5/9/10 and 49/50/99/100.
    let mut p = Plc::new(prog);
    p.scans(4);
    assert!(!p.bit("M10"));
    p.scan();
    assert!(p.bit("M10"));
    p.scans(4); // scan 9, 90 ms
    assert!(p.bit("M10"));
    p.scan(); // scan 10, 100 ms
    assert!(!p.bit("M10"));
    p.scans(39); // scan 49, 490 ms
    assert!(!p.bit("M12"));
    p.scan(); // 500 ms
    assert!(p.bit("M12"));
    p.scans(49); // 990 ms
    assert!(p.bit("M12"));
    p.scan(); // 1000 ms
    assert!(!p.bit("M12"));

    // SM409 (5 ms ON / 5 ms OFF) with 3 ms scans, t = 3, 6, 9, …:
    // floor(t/5) = 0 1 1 2 3 3 4 4 5 6 → ON when odd.
    let mut p = Plc::new(prog);
    p.scan_time_us(3_000);
    for (k, want) in [
        false, true, true, false, true, true, false, false, true, false,
    ]
    .into_iter()
    .enumerate()
    {
        p.scan();
        assert_eq!(p.bit("M9"), want, "SM409 at t = {} ms", 3 * (k + 1));
    }
}

#[test]
fn scan_time_registers() {
    let mut p = Plc::new(
        "\
LD SM400
MOV SD420 D0
END
",
    );
    // Scan 1: 50 ms (measured from power-on).
    p.scan_time_us(50_000).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (50, 0));
    assert_eq!((p.int("SD524"), p.int("SD525")), (50, 0));
    // Scan 2: 10 ms. Minimum 10; maximum excludes the first scan → 10, not 50.
    p.scan_time_us(10_000).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (10, 0));
    assert_eq!((p.int("SD524"), p.int("SD525")), (10, 0));
    assert_eq!((p.int("SD526"), p.int("SD527")), (10, 0));
    // Scan 3: 23.6 ms → SD520 = 23, SD521 = 600 µs (L10445-10447); new maximum.
    p.scan_time_us(23_600).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (23, 600));
    assert_eq!((p.int("SD524"), p.int("SD525")), (10, 0));
    assert_eq!((p.int("SD526"), p.int("SD527")), (23, 600));
    // Scan 4: 15.03 ms: 100 µs resolution → 15 / 0; neither min nor max changes.
    p.scan_time_us(15_030).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (15, 0));
    assert_eq!((p.int("SD524"), p.int("SD525")), (10, 0));
    assert_eq!((p.int("SD526"), p.int("SD527")), (23, 600));
    // SD420 counts scans at END: 4 after 4 scans; the program read it in scan 4
    // before END, i.e. 3.
    assert_eq!(p.int("SD420"), 4);
    assert_eq!(p.int("D0"), 3);
}

#[test]
fn one_second_counter_sd412() {
    let mut p = Plc::new(
        "\
LD SM400
OUT Y0
END
",
    );
    // +1 per second after RUN (RUN at power-on, time 0); 10 ms scans.
    p.scans(99); // 990 ms
    assert_eq!(p.int("SD412"), 0);
    p.scan(); // 1000 ms
    assert_eq!(p.int("SD412"), 1);
    p.scans(99); // 1990 ms
    assert_eq!(p.int("SD412"), 1);
    p.scan(); // 2000 ms
    assert_eq!(p.int("SD412"), 2);
    p.scans(50);
    assert_eq!(p.int("SD420"), 250);
    // SD420 wraps 32767 → -32768 → … → -1 → 0 (App. 2, L10431-10437).
    p.set("SD420", "32767").scan();
    assert_eq!(p.int("SD420"), -32768);
    p.set("SD420", "-1").scan();
    assert_eq!(p.int("SD420"), 0);
}
