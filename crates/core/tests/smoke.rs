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
