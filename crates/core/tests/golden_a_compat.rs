//! Golden tests of the A-series compatibility area (004 App. 1 (9) L9760-9927,
//! App. 2 (9) L10697-10865; parameter "A-series CPU compatibility", ON by
//! default, L5831): SM1000/SD1000 copied from their Q devices.

mod common;
use common::Plc;
use softplc_melsec::system::a_compat::{mirrors, Conv};

/// The relays a converted program reads every scan, copied into M.
const PROG: &str = "\
LD SM1036
OUT M0
LD SM1037
OUT M1
LD SM1038
OUT M2
LD SM1039
OUT M3
LD SM1032
OUT M4
LD SM412
OUT M5
LD SM1030
OUT M6
LD SM410
OUT M7
END
";

/// M9036 always ON, M9037 always OFF, M9038 ON / M9039 OFF for the first
/// scan only (L9817-9827), as SM400-SM403.
#[test]
fn always_on_off_and_first_scan() {
    let mut p = Plc::new(PROG);
    p.scan();
    let m = |p: &Plc| [p.bit("M0"), p.bit("M1"), p.bit("M2"), p.bit("M3")];
    assert_eq!(m(&p), [true, false, true, false]);
    for _ in 0..3 {
        p.scan();
        assert_eq!(m(&p), [true, false, false, true]);
    }
}

/// M9030 0.1 s and M9032 1 s clocks (L9812-9815) toggle with SM410/SM412,
/// seen by the program in the same scan.
#[test]
fn clocks_follow_the_q_clocks() {
    let mut p = Plc::new(PROG);
    let mut toggles = 0;
    let mut last = false;
    for k in 1..=250 {
        p.scan();
        assert_eq!(p.bit("M4"), p.bit("M5"), "SM1032 vs SM412 at scan {k}");
        assert_eq!(p.bit("M6"), p.bit("M7"), "SM1030 vs SM410 at scan {k}");
        toggles += (p.bit("M4") != last) as u32;
        last = p.bit("M4");
    }
    // 10 ms scans to 2.5 s: SM412 ON at 0.5 s, OFF at 1 s, ON 1.5 s, OFF 2 s,
    // ON 2.5 s.
    assert_eq!(toggles, 5);
}

/// SM1034, the 1-minute clock (L9812): OFF for 30 s, then ON for 30 s.
#[test]
fn minute_clock() {
    let mut p = Plc::new("LD SM1034\nOUT M0\nEND\n");
    p.scan_time_us(1_000_000);
    p.scans(29);
    assert!(!p.bit("M0"));
    p.scan();
    assert!(p.bit("M0"));
    p.scans(29);
    assert!(p.bit("M0"));
    p.scan();
    assert!(!p.bit("M0"));
}

/// After every END, each mirrored A-series device holds its Q device's
/// value (converted): checked over scans with errors, annunciators, the
/// carry, a file-register block and a scan time of 23 ms.
#[test]
fn every_mirror_holds_its_q_device() {
    let mut p = Plc::new(
        "\
LD X0
SET F7
LD X1
SET F3
LD X2
RSET K2
LD SM400
DUTY K1 K2 SM420
END
",
    );
    p.scan_time_us(23_000);
    let check = |p: &Plc, when: &str| {
        for m in mirrors() {
            if m.relay {
                let (a, q) = (format!("SM{}", m.a), format!("SM{}", m.q));
                assert_eq!(p.bit(&a), p.bit(&q), "{a} = {q} {when}");
                continue;
            }
            let (a, q) = (format!("SD{}", m.a), format!("SD{}", m.q));
            let qv = p.int(&q) as u16;
            let want = match m.conv {
                Conv::Same => qv,
                Conv::TenMs => qv / 10,
                Conv::Bcd => ((qv / 10 % 10) << 4) | (qv % 10),
            };
            assert_eq!(p.int(&a) as u16, want, "{a} = {q} {when}");
        }
    };
    p.scans(3);
    check(&p, "after 3 scans");
    p.set("X0", "1").set("X1", "1").set("X2", "1").scans(2);
    check(&p, "after annunciators and RSET");
    assert!(p.bit("SM1009"));
    assert_eq!(p.int("SD1009"), 7, "D9009: the first annunciator");
    assert_eq!(p.int("SD1124"), 2, "D9124: annunciators ON");
    assert_eq!((p.int("SD1125"), p.int("SD1126")), (7, 3));
    assert_eq!(p.int("SD1035"), 2, "D9035: the block number");
    assert_eq!(p.int("SD1018"), 2, "D9018: 23 ms in 10 ms units");
    assert_eq!(p.int("SD1021"), 23, "D9021: scan time in ms");
    assert_eq!(p.int("SD1008"), 9000, "D9008 = SD0");
    assert!(p.bit("SM1008"));
}

/// M9028 reads the clock into D9025-D9028 (BCD; D9028 the day of week
/// only), M9025 OFF→ON writes them to the clock (L9797-9809, L10750-10765).
#[test]
fn clock_data_read_and_set() {
    let mut p = Plc::new("LD SM400\nDATERD D0\nEND\n");
    p.set("SM1028", "1").scan();
    // Power-on clock: 2000-01-01 00:00:00, a Saturday (6).
    assert_eq!(p.int("SD1025"), 0x0001);
    assert_eq!(p.int("SD1026"), 0x0100);
    assert_eq!(p.int("SD1028"), 6);
    p.set("SM1028", "0");
    // 1999-12-31 23:59:50: a 2-digit year 80-99 is 19xx.
    p.set("SD1025:u16", "39186") // H9912
        .set("SD1026:u16", "12579") // H3123
        .set("SD1027:u16", "22864") // H5950
        .set("SD1028", "5")
        .set("SM1025", "1")
        .scan();
    assert!(!p.bit("SM1026"));
    p.scan();
    assert_eq!(p.int("D0"), 1999);
    assert_eq!(p.int("D1"), 12);
    assert_eq!(p.int("D2"), 31);
    // Invalid data (month 13): M9026 ON, the clock unchanged.
    p.set("SM1025", "0").scan();
    // H9913
    p.set("SD1025:u16", "39187").set("SM1025", "1").scan();
    assert!(p.bit("SM1026"));
}

/// `[cpu] a_compatibility = false`: the area is plain memory.
#[test]
fn off_in_plc_toml() {
    let toml = "[cpu]\na_compatibility = false\n\n[[program]]\nfile = \"a.il\"\n";
    let mut p = Plc::project(toml, &[("a.il", PROG)]);
    p.scans(3);
    assert!(!p.bit("M0"), "SM1036 is not maintained");
    assert!(p.bit("SM400"));
    let toml = "[cpu]\na_compatibility = true\n\n[[program]]\nfile = \"a.il\"\n";
    let mut p = Plc::project(toml, &[("a.il", PROG)]);
    p.scans(3);
    assert!(p.bit("M0"));
    let err = Plc::try_project(
        "[cpu]\nmodel = \"APLC-TCP\"\na_compatibility = true\n\n[[program]]\nfile = \"a.apl\"\n",
        &[("a.apl", "")],
    )
    .err()
    .unwrap_or_default();
    assert!(
        err.contains("a_compatibility is a MELSEC-Q parameter"),
        "{err}"
    );
}

/// D9010 = SD1010: the step of an operation error, written at each one (004
/// App. 2 L10743), the same step as SD14.
#[test]
fn sd1010_is_the_step_of_the_operation_error() {
    let mut p = Plc::new("LD SM400\nMOV K0 D1\nLD X0\n/ D0 D1 D2\nEND\n");
    p.scan();
    assert_eq!(p.int("SD1010"), 0);
    p.set("X0", "1").scan();
    assert_eq!(p.int("SD0"), 4100);
    assert!(p.int("SD14") > 0);
    assert_eq!(p.int("SD1010"), p.int("SD14"));
}
