//! The registers the system writes at every END and scan start keep their
//! values whoever wrote them in between (004 App. 1, App. 2): a program or
//! a door write of SD520, SD203, SD201, SD412 or SM400 is overwritten at the
//! next END or scan start, and the A-series twins follow. Scans take 10 ms.

mod common;
use common::Plc;

#[test]
fn scan_time_registers_and_their_twins_are_written_at_every_end() {
    // The program overwrites the current scan time and the 1 s counter.
    let mut p = Plc::new("LD SM400\nMOV K999 SD520\nMOV K77 SD412\nEND\n");
    p.scans(3);
    // 10 ms: SD520 = 10 ms, SD521 = 0 µs; SD1018 in 10 ms units, SD1021 in ms.
    assert_eq!((p.int("SD520"), p.int("SD521")), (10, 0));
    assert_eq!((p.int("SD1018"), p.int("SD1021")), (1, 10));
    // 30 ms since RUN: SD412 and its twin SD1022 count whole seconds.
    assert_eq!((p.int("SD412"), p.int("SD1022")), (0, 0));
    // The scan counter SD420 counts every END: three.
    assert_eq!(p.int("SD420"), 3);
    p.set("SD520", "555").set("SD1018", "9");
    p.scan_time_us(23_600).scan();
    assert_eq!((p.int("SD520"), p.int("SD521")), (23, 600));
    assert_eq!((p.int("SD1018"), p.int("SD1021")), (2, 23));
}

#[test]
fn one_second_counter_across_a_second_boundary() {
    let mut p = Plc::new("LD SM400\nMOV K77 SD412\nEND\n");
    p.scans(99);
    // 990 ms since RUN.
    assert_eq!((p.int("SD412"), p.int("SD1022")), (0, 0));
    p.scan();
    assert_eq!((p.int("SD412"), p.int("SD1022")), (1, 1));
}

#[test]
fn status_and_panel_are_written_again_after_a_door_write() {
    let mut p = Plc::new("LD SM400\nOUT M0\nEND\n");
    p.scan();
    // RUN: SD203 = 0; SD201: RUN LED ON (b0-b1 = 1), MODE ON (b14-b15 = 1).
    assert_eq!((p.int("SD203"), p.int("SD1015")), (0, 0));
    assert_eq!(p.int("SD201"), 0x4001);
    assert_eq!(p.int("SD200"), 0);
    p.set("SD203", "85")
        .set("SD1015", "85")
        .set("SD201", "0")
        .set("SD200", "7");
    p.scan();
    assert_eq!((p.int("SD203"), p.int("SD1015")), (0, 0));
    assert_eq!(p.int("SD201"), 0x4001);
    assert_eq!(p.int("SD200"), 0);
}

#[test]
fn scan_start_relays_and_twins_are_set_before_the_program_reads_them() {
    // The door turns SM400 and SM1036 OFF between scans: the next scan
    // start turns both ON before the program copies them.
    let mut p = Plc::new("LD SM400\nOUT M0\nLD SM1036\nOUT M1\nEND\n");
    p.scan();
    p.set("SM400", "0").set("SM1036", "0").scan();
    assert!(p.bit("M0") && p.bit("M1"));
    assert!(p.bit("SM400") && p.bit("SM1036"));
}

#[test]
fn clock_registers_follow_the_calendar_across_a_second_boundary() {
    // SM213 ON reads the clock into SD210-SD213 at every END (BCD).
    let mut p = Plc::new("LD SM400\nOUT M0\nEND\n");
    p.set("SM213", "1").scans(99);
    // Power-on clock 2000-01-01 00:00:00 (a Saturday, 6), 0.99 s later.
    assert_eq!(p.int("SD210"), 0x0001);
    assert_eq!(p.int("SD211"), 0x0100);
    assert_eq!(p.int("SD212"), 0x0000);
    assert_eq!(p.int("SD213"), 0x2006);
    p.set("SD212", "4660"); // a door write between ENDs (H1234)
    p.scan();
    // 1.00 s: minute 00, second 01.
    assert_eq!(p.int("SD212"), 0x0001);
    // SM213 OFF: the registers keep what was written last.
    p.set("SM213", "0").scans(100);
    assert_eq!(p.int("SD212"), 0x0001);
}

#[test]
fn a_cpu_with_fewer_sm_and_sd_points_gets_the_registers_it_has() {
    use softplc_core::device::DeviceKind;
    // SM0-SM409 and SD0-SD529: SM400-SM409 and SD520-SD529 are written,
    // the rest of each group does not exist.
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(DeviceKind::SM, 410);
    cfg.devices.set_points(DeviceKind::SD, 530);
    let mut p = Plc::with_config("LD SM400\nOUT M0\nLD SM403\nOUT M1\nEND\n", cfg);
    p.scans(2);
    assert!(p.bit("M0") && p.bit("M1"));
    assert!(p.bit("SM400") && !p.bit("SM402") && p.bit("SM403"));
    // 20 ms since power-on: the 10 ms clock SM409 ((20000 / 5000) & 1) OFF.
    assert!(!p.bit("SM409"));
    assert_eq!((p.int("SD520"), p.int("SD521")), (10, 0));
    assert_eq!((p.int("SD524"), p.int("SD526")), (10, 10));
    assert_eq!((p.int("SD420"), p.int("SD412")), (2, 0));
    assert_eq!(p.int("SD203"), 0);
}
