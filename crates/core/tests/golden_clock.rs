//! Golden tests of the clock instructions (programming manual §7.15: DATERD,
//! DATEWR, DATE+, DATE-, SECOND, HOUR). Every expected value is worked out by
//! hand next to it.
//!
//! Time base: the harness CPU powers on at virtual time 0 with the calendar at
//! 2000-01-01 00:00:00 (a Saturday, day of week 6), and advances the virtual
//! clock by the scan time *before* each scan; instructions see the clock at the
//! start of their scan. So with 1 s scans the n-th scan reads 00:00:0n, and with
//! the default 10 ms scans the first 100 scans all read 00:00:00.

mod common;
use common::{assert_running, assert_stopped, Plc};
use softplc_core::engine::{CpuConfig, CpuState, ErrorMode};

/// The 7 words DATERD wrote at `D<n>`.
fn clock_at(p: &Plc, n: u32) -> [i64; 7] {
    let mut w = [0; 7];
    for (k, v) in w.iter_mut().enumerate() {
        *v = p.int(&format!("D{}", n + k as u32));
    }
    w
}

/// Writes clock data to D100-D106.
fn put_clock(p: &mut Plc, w: [i64; 7]) {
    for (k, v) in w.iter().enumerate() {
        p.set(&format!("D{}", 100 + k), &v.to_string());
    }
}

/// A CPU that writes D100-D106 to the clock on X0's rising edge and reads the
/// clock into D0-D6 every scan, after the write.
fn writer(mode: ErrorMode) -> Plc {
    let cfg = CpuConfig {
        operation_error: mode,
        ..softplc_core::profile::default_config()
    };
    Plc::with_config("LD X0\nDATEWRP D100\nLD SM400\nDATERD D0\nEND\n", cfg)
}

// ------------------------------------------------------------ DATERD

#[test]
fn daterd_power_on_clock() {
    let mut p = Plc::new("LD SM400\nDATERD D0\nEND\n");
    // First scan at 10 ms: 2000-01-01 00:00:00, Saturday (6).
    p.scan();
    assert_running(&p);
    assert_eq!(clock_at(&p, 0), [2000, 1, 1, 0, 0, 0, 6]);
    // Seven words exactly: D7 is not written.
    assert_eq!(p.int("D7"), 0);
}

#[test]
fn daterd_advances_with_virtual_time() {
    let mut p = Plc::new("LD SM400\nDATERD D0\nEND\n");
    p.scan_time_us(1_000_000).scans(3);
    // Third scan starts at 3 s: 00:00:03.
    assert_eq!(clock_at(&p, 0), [2000, 1, 1, 0, 0, 3, 6]);
    // 3 s + 3599 s = 3602 s = 1:00:02.
    p.scan_time_us(3_599_000_000).scan();
    assert_eq!(clock_at(&p, 0), [2000, 1, 1, 1, 0, 2, 6]);
    // One day later: Sunday 2000-01-02 01:00:02 (day of week 0).
    p.scan_time_us(86_400_000_000).scan();
    assert_eq!(clock_at(&p, 0), [2000, 1, 2, 1, 0, 2, 0]);
    // 31 days later: 2000-02-02, Sunday + 31 days = Sunday + 3 = Wednesday (3).
    p.scan_time_us(31 * 86_400_000_000).scan();
    assert_eq!(clock_at(&p, 0), [2000, 2, 2, 1, 0, 2, 3]);
}

#[test]
fn daterd_index_modification_and_range() {
    let mut p = Plc::new("LD SM400\nDATERD D0Z2\nEND\n");
    // Z2 = 20 → DATERD D20: D20-D26; D0 stays 0.
    p.set("Z2", "20").scan();
    assert_eq!(clock_at(&p, 20), [2000, 1, 1, 0, 0, 0, 6]);
    assert_eq!(p.int("D0"), 0);
    // D12283-D12289 would pass the last point D12287 (12288 points) → 4101.
    let mut p = Plc::new("LD SM400\nDATERD D12283\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12283"), 0);
    // D12281-D12287 fits exactly.
    let mut p = Plc::new("LD SM400\nDATERD D12281\nEND\n");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D12281"), 2000);
    assert_eq!(p.int("D12287"), 6);
}

#[test]
fn daterdp_reads_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nDATERDP D0\nLD X0\nDATERD D10\nEND\n");
    p.scan_time_us(1_000_000);
    // Scan 1 (1 s): X0 rises → both read 00:00:01.
    p.set("X0", "1").scan();
    assert_eq!(p.int("D5"), 1);
    assert_eq!(p.int("D15"), 1);
    // Scan 2 (2 s): X0 still ON → only DATERD reads 00:00:02.
    p.scan();
    assert_eq!(p.int("D5"), 1);
    assert_eq!(p.int("D15"), 2);
    // Scan 3 OFF, scan 4 (4 s) ON: new edge → DATERDP reads 00:00:04.
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D5"), 4);
}

// ------------------------------------------------------------ DATEWR

#[test]
fn datewr_manual_example() {
    // 004 L3652-3661: Tue 10 Aug 1999 11:35:24 → 1999, 8, 10, 11, 35, 24, 2.
    let mut p = writer(ErrorMode::Stop);
    put_clock(&mut p, [1999, 8, 10, 11, 35, 24, 2]);
    p.scan_time_us(1_000_000).set("X0", "1").scan();
    assert_running(&p);
    // Read in the same scan, after the write: exactly the written time.
    assert_eq!(clock_at(&p, 0), [1999, 8, 10, 11, 35, 24, 2]);
    // The clock runs from there: two 1 s scans later 11:35:26.
    p.scans(2);
    assert_eq!(clock_at(&p, 0), [1999, 8, 10, 11, 35, 26, 2]);
}

#[test]
fn datewr_weekday_is_derived_from_the_date() {
    // 10 Aug 1999 was a Tuesday; a written day of week 5 (in range) is accepted but
    // the clock keeps the true weekday (softplc decision, see clock.rs).
    let mut p = writer(ErrorMode::Stop);
    put_clock(&mut p, [1999, 8, 10, 0, 0, 0, 5]);
    p.set("X0", "1").scan();
    assert_running(&p);
    assert_eq!(p.int("D6"), 2);
}

#[test]
fn leap_days_and_month_ends() {
    let mut p = writer(ErrorMode::Stop);
    p.scan_time_us(1_000_000);
    // 2000 is a leap year (divisible by 400): 28 Feb 23:59:59 + 1 s = 29 Feb.
    // 1 Jan 2000 = Saturday; 1 Feb = Saturday + 31 days = Tuesday; 29 Feb = 1 Feb
    // + 28 days = Tuesday (2).
    put_clock(&mut p, [2000, 2, 28, 23, 59, 59, 1]);
    p.set("X0", "1").scan();
    assert_eq!(clock_at(&p, 0), [2000, 2, 28, 23, 59, 59, 1]);
    p.scan();
    assert_eq!(clock_at(&p, 0), [2000, 2, 29, 0, 0, 0, 2]);
    // One day later: 1 March 2000, Wednesday (3).
    p.scan_time_us(86_400_000_000).scan();
    assert_eq!(clock_at(&p, 0), [2000, 3, 1, 0, 0, 0, 3]);
    // 2023 is not a leap year: 28 Feb 2023 (a Tuesday) + 1 day = 1 March
    // (Wednesday). 1 Jan 2023 = Sunday; + 31 + 27 = 58 days = 8 weeks + 2 → Tuesday.
    p.set("X0", "0").scan();
    put_clock(&mut p, [2023, 2, 28, 12, 0, 0, 2]);
    p.set("X0", "1").scan();
    assert_eq!(clock_at(&p, 0), [2023, 2, 28, 12, 0, 0, 2]);
    p.scan();
    assert_eq!(clock_at(&p, 0), [2023, 3, 1, 12, 0, 0, 3]);
    // New Year: 31 Dec 2023 23:59:59 (Sunday) + 1 s = 1 Jan 2024 (Monday, 1).
    p.scan_time_us(1_000_000).set("X0", "0").scan();
    put_clock(&mut p, [2023, 12, 31, 23, 59, 59, 0]);
    p.set("X0", "1").scan();
    p.scan();
    assert_eq!(clock_at(&p, 0), [2024, 1, 1, 0, 0, 0, 1]);
    // 29 Feb 2024 exists: 1 Jan 2024 Monday + 59 days (8 weeks + 3) = Thursday (4).
    p.set("X0", "0").scan();
    put_clock(&mut p, [2024, 2, 29, 8, 0, 0, 4]);
    p.set("X0", "1").scan();
    assert_running(&p);
    assert_eq!(clock_at(&p, 0), [2024, 2, 29, 8, 0, 0, 4]);
}

#[test]
fn datewr_invalid_data_stops_and_keeps_the_clock() {
    let cases: [[i64; 7]; 12] = [
        [2023, 2, 29, 0, 0, 0, 3],  // no 29 Feb in 2023
        [2100, 2, 29, 0, 0, 0, 0],  // year beyond 2079 (and 2100 is no leap year)
        [1979, 12, 31, 0, 0, 0, 1], // year before 1980
        [2080, 1, 1, 0, 0, 0, 1],   // year after 2079
        [2000, 13, 1, 0, 0, 0, 0],  // month 13
        [2000, 0, 1, 0, 0, 0, 0],   // month 0
        [2000, 4, 31, 0, 0, 0, 0],  // April has 30 days
        [2000, 1, 0, 0, 0, 0, 0],   // day 0
        [2000, 1, 1, 24, 0, 0, 6],  // hour 24
        [2000, 1, 1, 0, 60, 0, 6],  // minute 60
        [2000, 1, 1, 0, 0, -1, 6],  // second −1
        [2000, 1, 1, 0, 0, 0, 7],   // day of week 7
    ];
    for w in cases {
        let mut p = writer(ErrorMode::Stop);
        put_clock(&mut p, w);
        p.set("X0", "1").scan();
        assert_stopped(&p, 4100);
    }
    // With "operation error: continue" the faulty DATEWR is skipped and the clock
    // keeps running from power-on: DATERD in the same scan reads 2000-01-01 00:00:00.
    let mut p = writer(ErrorMode::Continue);
    put_clock(&mut p, [2000, 13, 1, 0, 0, 0, 0]);
    p.set("X0", "1").scan();
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("SD0"), 4100);
    assert_eq!(clock_at(&p, 0), [2000, 1, 1, 0, 0, 0, 6]);
}

#[test]
fn datewr_range_limits_are_accepted() {
    // 1 Jan 1980 was a Tuesday (2); 31 Dec 2079 is a Sunday (0).
    let mut p = writer(ErrorMode::Stop);
    put_clock(&mut p, [1980, 1, 1, 0, 0, 0, 2]);
    p.set("X0", "1").scan();
    assert_running(&p);
    assert_eq!(clock_at(&p, 0), [1980, 1, 1, 0, 0, 0, 2]);
    p.set("X0", "0").scan();
    put_clock(&mut p, [2079, 12, 31, 23, 59, 59, 0]);
    p.set("X0", "1").scan();
    assert_running(&p);
    assert_eq!(clock_at(&p, 0), [2079, 12, 31, 23, 59, 59, 0]);
}

#[test]
fn datewr_block_past_device_end() {
    // DATEWR D12282 needs D12282-D12288; D has 12288 points (D0-D12287) → 4101.
    let mut p = Plc::new("LD SM400\nDATEWR D12282\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

// ------------------------------------------------------------ DATE+, DATE-

/// Runs `DATE± D10 D20 D30` with the given time data.
fn date_op(op: &str, a: [i64; 3], b: [i64; 3]) -> Plc {
    let mut p = Plc::new(&format!("LD SM400\n{op} D10 D20 D30\nEND\n"));
    for k in 0..3 {
        p.set(&format!("D{}", 10 + k), &a[k].to_string());
        p.set(&format!("D{}", 20 + k), &b[k].to_string());
    }
    p.set("D30", "-1").set("D31", "-1").set("D32", "-1").scan();
    p
}

fn time_at(p: &Plc, n: u32) -> [i64; 3] {
    [
        p.int(&format!("D{n}")),
        p.int(&format!("D{}", n + 1)),
        p.int(&format!("D{}", n + 2)),
    ]
}

#[test]
fn date_add_wraps_at_24_hours() {
    // 10:20:30 + 1:02:03 = 11:22:33.
    let p = date_op("DATE+", [10, 20, 30], [1, 2, 3]);
    assert_running(&p);
    assert_eq!(time_at(&p, 30), [11, 22, 33]);
    // 10:20:30 + 20:20:20 = 30:40:50 → − 24 h = 6:40:50.
    let p = date_op("DATE+", [10, 20, 30], [20, 20, 20]);
    assert_eq!(time_at(&p, 30), [6, 40, 50]);
    // Carries: 23:59:59 + 0:00:01 = 24:00:00 → 0:00:00.
    let p = date_op("DATE+", [23, 59, 59], [0, 0, 1]);
    assert_eq!(time_at(&p, 30), [0, 0, 0]);
    // 0:59:59 + 0:00:01 = 1:00:00; 23:59:59 + 23:59:59 = 47:59:58 → 23:59:58.
    let p = date_op("DATE+", [0, 59, 59], [0, 0, 1]);
    assert_eq!(time_at(&p, 30), [1, 0, 0]);
    let p = date_op("DATE+", [23, 59, 59], [23, 59, 59]);
    assert_eq!(time_at(&p, 30), [23, 59, 58]);
}

#[test]
fn date_sub_wraps_below_zero() {
    // 11:22:33 − 1:02:03 = 10:20:30.
    let p = date_op("DATE-", [11, 22, 33], [1, 2, 3]);
    assert_running(&p);
    assert_eq!(time_at(&p, 30), [10, 20, 30]);
    // 10:20:30 − 20:20:20 = −(9:59:50) → + 24 h = 14:00:10.
    let p = date_op("DATE-", [10, 20, 30], [20, 20, 20]);
    assert_eq!(time_at(&p, 30), [14, 0, 10]);
    // 0:00:00 − 0:00:01 = 23:59:59; equal times give 0:00:00.
    let p = date_op("DATE-", [0, 0, 0], [0, 0, 1]);
    assert_eq!(time_at(&p, 30), [23, 59, 59]);
    let p = date_op("DATE-", [5, 6, 7], [5, 6, 7]);
    assert_eq!(time_at(&p, 30), [0, 0, 0]);
    // Borrow across minutes and hours: 1:00:00 − 0:00:01 = 0:59:59.
    let p = date_op("DATE-", [1, 0, 0], [0, 0, 1]);
    assert_eq!(time_at(&p, 30), [0, 59, 59]);
}

#[test]
fn date_arith_invalid_time_data() {
    for (a, b) in [
        ([24, 0, 0], [0, 0, 0]),
        ([0, 60, 0], [0, 0, 0]),
        ([0, 0, 60], [0, 0, 0]),
        ([0, 0, 0], [-1, 0, 0]),
        ([0, 0, 0], [0, 0, -1]),
        ([0, 0, 0], [25, 0, 0]),
    ] {
        for op in ["DATE+", "DATE-"] {
            let p = date_op(op, a, b);
            assert_stopped(&p, 4100);
            // D30-D32 keep the −1 written before.
            assert_eq!(time_at(&p, 30), [-1, -1, -1], "{op} {a:?} {b:?}");
        }
    }
}

#[test]
fn date_add_overlapping_destination_and_pulse() {
    // DATE+P D10 D20 D10: the result replaces S1 once per rising edge.
    let mut p = Plc::new("LD X0\nDATE+P D10 D20 D10\nEND\n");
    p.set("D10", "23").set("D11", "0").set("D12", "0");
    p.set("D20", "0").set("D21", "30").set("D22", "0");
    // Edge: 23:00:00 + 0:30:00 = 23:30:00.
    p.set("X0", "1").scan();
    assert_eq!(time_at(&p, 10), [23, 30, 0]);
    // Still ON: no second addition.
    p.scan();
    assert_eq!(time_at(&p, 10), [23, 30, 0]);
    // New edge: 23:30:00 + 0:30:00 = 24:00:00 → 0:00:00.
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(time_at(&p, 10), [0, 0, 0]);
}

// ------------------------------------------------------------ SECOND, HOUR

#[test]
fn second_converts_time_to_32_bit_seconds() {
    let mut p = Plc::new(
        "LD SM400\n\
         SECOND D10 D0\n\
         SECOND D20 D2\n\
         SECOND D30 D4\n\
         END\n",
    );
    // 1:01:01 = 3600 + 60 + 1 = 3661.
    p.set("D10", "1").set("D11", "1").set("D12", "1");
    // 23:59:59 = 82800 + 3540 + 59 = 86399: more than 16 bits (D3 = 1, D2 = 20863).
    p.set("D20", "23").set("D21", "59").set("D22", "59");
    // 0:00:00 = 0 (D4 preset to −1 to see the high word cleared).
    p.set("D4:i32", "-1");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D0:i32"), 3661);
    assert_eq!(p.int("D2:i32"), 86_399);
    // 86399 = 1·65536 + 20863.
    assert_eq!(p.int("D3"), 1);
    assert_eq!(p.int("D2:u16"), 20_863);
    assert_eq!(p.int("D4:i32"), 0);
}

#[test]
fn second_invalid_time_data() {
    for (h, m, s) in [(24, 0, 0), (0, 60, 0), (0, 0, 60), (-1, 0, 0)] {
        let mut p = Plc::new("LD SM400\nSECOND D10 D0\nEND\n");
        p.set("D10", &h.to_string())
            .set("D11", &m.to_string())
            .set("D12", &s.to_string())
            .set("D0:i32", "5")
            .scan();
        assert_stopped(&p, 4100);
        assert_eq!(p.int("D0:i32"), 5);
    }
}

#[test]
fn hour_converts_seconds_to_time_data() {
    let mut p = Plc::new(
        "LD SM400\n\
         HOUR D0 D10\n\
         HOUR D2 D20\n\
         HOUR K45296 D30\n\
         HOUR K0 D40\n\
         END\n",
    );
    // 3661 = 1·3600 + 1·60 + 1 → 1:01:01.
    p.set("D0:i32", "3661");
    // 86399 = 23·3600 + 59·60 + 59 → 23:59:59.
    p.set("D2:i32", "86399");
    p.set("D40", "9").scan();
    assert_running(&p);
    assert_eq!(time_at(&p, 10), [1, 1, 1]);
    assert_eq!(time_at(&p, 20), [23, 59, 59]);
    // 45296 = 12·3600 (43200) + 34·60 (2040) + 56 → 12:34:56.
    assert_eq!(time_at(&p, 30), [12, 34, 56]);
    assert_eq!(time_at(&p, 40), [0, 0, 0]);
}

#[test]
fn hour_out_of_range() {
    for v in ["86400", "-1", "100000"] {
        let mut p = Plc::new("LD SM400\nHOUR D0 D10\nEND\n");
        p.set("D0:i32", v).set("D10", "7").scan();
        assert_stopped(&p, 4100);
        assert_eq!(p.int("D10"), 7, "{v}");
    }
}

#[test]
fn second_and_hour_round_trip_with_pulse() {
    // SECONDP then HOUR: 7:08:09 → 25689 s → 7:08:09.
    let mut p = Plc::new("LD X0\nSECONDP D10 D0\nLD SM400\nHOUR D0 D20\nEND\n");
    p.set("D10", "7").set("D11", "8").set("D12", "9");
    p.set("X0", "1").scan();
    // 7·3600 + 8·60 + 9 = 25200 + 480 + 9 = 25689.
    assert_eq!(p.int("D0:i32"), 25_689);
    assert_eq!(time_at(&p, 20), [7, 8, 9]);
    // X0 stays ON: SECONDP does not run again, D0 keeps 25689.
    p.set("D10", "8").scan();
    assert_eq!(p.int("D0:i32"), 25_689);
}

#[test]
fn load_time_operand_checks() {
    let d = common::diagnostics("LD SM400\nDATERD K4M0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    let d = common::diagnostics("LD SM400\nDATE+ D0 D10\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    let d = common::diagnostics("LD SM400\nDATEWR K5\nEND\n");
    assert!(d[0].starts_with("2:8:"), "{d:?}");
}
