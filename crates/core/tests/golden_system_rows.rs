//! A sample of the special relays and registers COMPATIBILITY.md's SM/SD
//! table says are maintained (004 App. 1, App. 2), observed from a program
//! or the device memory after a few scans.

mod common;
use common::Plc;

/// SM5 / SM16: error common / individual information present (App. 1
/// L9529-9531). An operation error has its program location (SD5-SD15, SD4
/// = 4): SM5 ON, SM16 OFF; an annunciator its number (SD16, SD4 = 0600H):
/// SM16 ON, SM5 OFF.
#[test]
fn error_information_present() {
    let mut p = Plc::new("LD SM400\n/ K1 K0 D0\nEND\n");
    p.scan();
    assert_eq!(p.int("SD0"), 4100);
    assert_eq!(p.int("SD4"), 4);
    assert!(p.bit("SM5"));
    assert!(!p.bit("SM16"));
    let mut p = Plc::new("LD X0\nSET F5\nEND\n");
    p.scan();
    assert!(!p.bit("SM5") && !p.bit("SM16"));
    p.set("X0", "1").scan();
    assert_eq!(p.int("SD4"), 0x0600);
    assert_eq!(p.int("SD16"), 5);
    assert!(p.bit("SM16"));
    assert!(!p.bit("SM5"));
}

/// Rows written at power-on: SD414/SD415 default 30 (L10427-10430), SD290
/// the X points, SD640 = 1, SD647 the file-register capacity in K words.
#[test]
fn power_on_rows() {
    let mut p = Plc::new("END\n");
    p.scan();
    assert_eq!((p.int("SD414"), p.int("SD415")), (30, 30));
    assert_eq!(p.int("SD290"), 8192);
    assert_eq!(p.int("SD640"), 1);
    assert!(p.int("SD647") > 0);
}
