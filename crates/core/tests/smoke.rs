mod common;
use common::Plc;

#[test]
fn blink_example_hand_worked() {
    // 10 ms scans, 100 ms timer base: T0 times out at scan 51 (50 × 10 ms after
    // the coil turned ON in scan 1), then T1 counts from scan 52.
    let mut p = Plc::new(include_str!("../../../examples/blink.il"));
    p.set("X0", "1").scans(50);
    assert!(!p.bit("Y0"));
    assert_eq!(p.int("TN0"), 4);
    p.scan();
    assert!(p.bit("Y0"));
    assert_eq!(p.int("TN0"), 5);
    assert_eq!(p.int("CN0"), 1);
    p.scans(49);
    assert_eq!(p.int("TN1"), 4);
}

#[test]
fn clock_registers_read_and_set() {
    // Power-on clock is 2000-01-01 00:00:00 (a Saturday). With SM213 ON the clock
    // is read into SD210-SD213 in BCD at END: year 00 | month 01, day 01 | hour 00,
    // minute | second, century 20 | day of week 6.
    let mut p = Plc::new("LD SM400\nOUT SM213\nEND\n");
    p.scan_time_us(1_000_000).scans(2);
    // Scan 2 ends 2 s after power-on.
    assert_eq!(p.int("SD210:u16"), 0x0001);
    assert_eq!(p.int("SD211:u16"), 0x0100);
    assert_eq!(p.int("SD212:u16"), 0x0002);
    assert_eq!(p.int("SD213:u16"), 0x2006);
    // Set 2024-02-29 23:59:58 through SM210 (OFF→ON); SM213 keeps reading.
    p.set("SD210", "H2402")
        .set("SD211", "H2923")
        .set("SD212", "H5958")
        .set("SD213", "H2000");
    p.set("SM210", "1").scan();
    assert!(!p.bit("SM211"));
    p.scans(2);
    // Two seconds later: 2024-03-01 00:00:00, a Friday (5).
    assert_eq!(p.int("SD210:u16"), 0x2403);
    assert_eq!(p.int("SD211:u16"), 0x0100);
    assert_eq!(p.int("SD212:u16"), 0x0000);
    assert_eq!(p.int("SD213:u16"), 0x2005);
    // Month 13 is refused with SM211.
    p.set("SM210", "0").scan();
    p.set("SD210", "H2413").set("SM210", "1").scan();
    assert!(p.bit("SM211"));
}
