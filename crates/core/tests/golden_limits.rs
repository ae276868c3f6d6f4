//! Golden tests of the data control instructions LIMIT, BAND, ZONE and their
//! 32-bit forms (programming manual §7.13). Every expected value is worked out
//! by hand in the comment next to it.

mod common;
use common::{assert_running, assert_stopped, Plc};

// ---------------------------------------------------------------- LIMIT

#[test]
fn limit_clamps_to_lower_and_upper() {
    // Lower limit 100, upper 500; inputs below, inside, above and on the limits.
    let mut p = Plc::new(
        "LD SM400\n\
         LIMIT K100 K500 D0 D10\n\
         LIMIT K100 K500 D1 D11\n\
         LIMIT K100 K500 D2 D12\n\
         LIMIT K100 K500 D3 D13\n\
         LIMIT K100 K500 D4 D14\n\
         LIMIT K-50 K50 D5 D15\n\
         END\n",
    );
    p.set("D0", "50").set("D1", "300").set("D2", "900");
    p.set("D3", "100").set("D4", "500").set("D5", "-32768");
    p.scan();
    assert_running(&p);
    // 50 < 100 → lower limit 100.
    assert_eq!(p.int("D10"), 100);
    // 100 ≤ 300 ≤ 500 → 300 unchanged.
    assert_eq!(p.int("D11"), 300);
    // 900 > 500 → upper limit 500.
    assert_eq!(p.int("D12"), 500);
    // On the limits the input itself: 100 and 500.
    assert_eq!(p.int("D13"), 100);
    assert_eq!(p.int("D14"), 500);
    // Signed compare: −32768 < −50 → −50.
    assert_eq!(p.int("D15"), -50);
}

#[test]
fn limit_lower_above_upper_is_4100_and_d_unchanged() {
    let mut p = Plc::new("LD SM400\nLIMIT K500 K100 D0 D10\nEND\n");
    p.set("D0", "300").set("D10", "7").scan();
    // Lower 500 > upper 100: OPERATION ERROR 4100, D10 keeps 7.
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D10"), 7);
}

#[test]
fn limit_equal_limits_is_allowed() {
    // Lower = upper = 42: every input gives 42, no error.
    let mut p = Plc::new("LD SM400\nLIMIT K42 K42 D0 D10\nEND\n");
    p.set("D0", "-1000").scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 42);
}

#[test]
fn dlimit_32_bit() {
    // Lower −100000, upper 100000 (beyond 16 bits).
    let mut p = Plc::new(
        "LD SM400\n\
         DLIMIT K-100000 K100000 D0 D10\n\
         DLIMIT K-100000 K100000 D2 D12\n\
         DLIMIT K-100000 K100000 D4 D14\n\
         END\n",
    );
    p.set("D0:i32", "-200000")
        .set("D2:i32", "70000")
        .set("D4:i32", "2147483647");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D10:i32"), -100000);
    // 70000 = 11170H: inside the limits, unchanged (a 16-bit compare would see 1170H).
    assert_eq!(p.int("D12:i32"), 70000);
    assert_eq!(p.int("D14:i32"), 100000);
}

#[test]
fn dlimit_lower_above_upper_is_4100() {
    let mut p = Plc::new("LD SM400\nDLIMIT K65536 K1 D0 D10\nEND\n");
    p.scan();
    // 65536 = 10000H > 1: an error only the 32-bit compare sees (the low
    // words alone, 0 and 1, are in order).
    assert_stopped(&p, 4100);
}

#[test]
fn limitp_runs_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nLIMITP K0 K10 D0 D10\nEND\n");
    p.set("D0", "5").set("X0", "1").scan();
    assert_eq!(p.int("D10"), 5);
    // Still ON: no new execution, D10 keeps 5 although D0 is now 8.
    p.set("D0", "8").scan();
    assert_eq!(p.int("D10"), 5);
    // OFF then ON: executes again.
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D10"), 8);
}

// ---------------------------------------------------------------- BAND

#[test]
fn band_dead_band() {
    // Dead band −100 … 100.
    let mut p = Plc::new(
        "LD SM400\n\
         BAND K-100 K100 D0 D10\n\
         BAND K-100 K100 D1 D11\n\
         BAND K-100 K100 D2 D12\n\
         BAND K-100 K100 D3 D13\n\
         END\n",
    );
    p.set("D0", "-150")
        .set("D1", "0")
        .set("D2", "250")
        .set("D3", "100");
    p.scan();
    assert_running(&p);
    // Below: −150 − (−100) = −50.
    assert_eq!(p.int("D10"), -50);
    // Inside: 0.
    assert_eq!(p.int("D11"), 0);
    // Above: 250 − 100 = 150.
    assert_eq!(p.int("D12"), 150);
    // On the upper limit: inside, 0.
    assert_eq!(p.int("D13"), 0);
}

#[test]
fn band_result_wraps_at_16_bits() {
    // −32768 − 10 = −32778 = FFFF7FF6H; low 16 bits 7FF6H = 32758.
    let mut p = Plc::new("LD SM400\nBAND K10 K20 K-32768 D10\nEND\n");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 32758);
}

#[test]
fn band_lower_above_upper_is_4100() {
    let mut p = Plc::new("LD SM400\nBAND K1 K0 D0 D10\nEND\n");
    p.set("D10", "3").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D10"), 3);
}

#[test]
fn dband_32_bit() {
    let mut p = Plc::new(
        "LD SM400\n\
         DBAND K-50000 K50000 D0 D10\n\
         DBAND K-50000 K50000 D2 D12\n\
         END\n",
    );
    p.set("D0:i32", "-1000000").set("D2:i32", "1000000");
    p.scan();
    assert_running(&p);
    // −1000000 − (−50000) = −950000.
    assert_eq!(p.int("D10:i32"), -950000);
    // 1000000 − 50000 = 950000.
    assert_eq!(p.int("D12:i32"), 950000);
}

// ---------------------------------------------------------------- ZONE

#[test]
fn zone_adds_bias_by_sign() {
    // Negative bias −100, positive bias 200.
    let mut p = Plc::new(
        "LD SM400\n\
         ZONE K-100 K200 D0 D10\n\
         ZONE K-100 K200 D1 D11\n\
         ZONE K-100 K200 D2 D12\n\
         END\n",
    );
    p.set("D0", "50").set("D1", "0").set("D2", "-50");
    p.scan();
    assert_running(&p);
    // 50 > 0: 50 + 200 = 250.
    assert_eq!(p.int("D10"), 250);
    // 0: 0.
    assert_eq!(p.int("D11"), 0);
    // −50 < 0: −50 + (−100) = −150.
    assert_eq!(p.int("D12"), -150);
}

#[test]
fn zone_has_no_limit_order_error_and_wraps() {
    // Biases in any order are accepted (ZONE has no lower/upper check):
    // S1 = 1000, S2 = −1000. Input 32000 > 0: 32000 + (−1000) = 31000.
    // Input 32767 with S1=1000, S2=1: 32767 + 1 = 32768 → wraps to −32768.
    let mut p = Plc::new(
        "LD SM400\n\
         ZONE K1000 K-1000 K32000 D10\n\
         ZONE K1000 K1 K32767 D11\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 31000);
    assert_eq!(p.int("D11"), -32768);
}

#[test]
fn dzone_32_bit() {
    let mut p = Plc::new("LD SM400\nDZONE K-70000 K70000 D0 D10\nEND\n");
    p.set("D0:i32", "-1").scan();
    assert_running(&p);
    // −1 + (−70000) = −70001.
    assert_eq!(p.int("D10:i32"), -70001);
}

// ---------------------------------------------------------------- operands

#[test]
fn index_modified_operands() {
    // Z0 = 5: input D0Z0 = D5, output D10Z0 = D15.
    let mut p = Plc::new("LD SM400\nMOV K5 Z0\nLIMIT K0 K100 D0Z0 D10Z0\nEND\n");
    p.set("D5", "150").scan();
    assert_running(&p);
    assert_eq!(p.int("D15"), 100);
    assert_eq!(p.int("D10"), 0);
}

#[test]
fn index_modified_output_past_device_end_is_4101() {
    // D12287 is the last D; Z0 = 1 → D12288 does not exist.
    let mut p = Plc::new("LD SM400\nMOV K1 Z0\nLIMIT K0 K100 K5 D12287Z0\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn digit_specified_output() {
    // LIMIT into K2Y0: 300 clamped to 255 = FFH → Y0-Y7 all ON, Y8 untouched.
    let mut p = Plc::new("LD SM400\nLIMIT K0 K255 K300 K2Y0\nEND\n");
    p.scan();
    assert_running(&p);
    assert!(p.bit("Y0") && p.bit("Y7"));
    assert!(!p.bit("Y8"));
}

#[test]
fn constant_output_is_rejected_at_load() {
    let d = common::diagnostics("LD SM400\nLIMIT K0 K1 K2 K3\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:"), "{d:?}");
    assert!(d[0].contains("destination"), "{d:?}");
}

#[test]
fn wrong_operand_count_is_rejected_at_load() {
    let d = common::diagnostics("LD SM400\nBAND K0 K1 D0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("takes 4 operands"), "{d:?}");
}
