//! Golden tests of the block data comparisons BKCMP□ / DBKCMP□ (programming
//! manual §6.1). Every expected value is worked out by hand in the comment next
//! to it.

mod common;
use common::{assert_running, assert_stopped, Plc};

fn bits(p: &Plc, first: u32, n: u32) -> Vec<bool> {
    (first..first + n)
        .map(|k| p.bit(&format!("M{k}")))
        .collect()
}

#[test]
fn bkcmp_eq_block_against_block() {
    let mut p = Plc::new("LD SM400\nBKCMP= D0 D10 M0 K4\nEND\n");
    for (k, v) in [1, 2, 3, 4].iter().enumerate() {
        p.set(&format!("D{k}"), &v.to_string());
    }
    for (k, v) in [1, 0, 3, 9].iter().enumerate() {
        p.set(&format!("D{}", 10 + k), &v.to_string());
    }
    p.set("M1", "1").set("SM704", "1").scan();
    assert_running(&p);
    // 1=1 ON, 2=0 OFF (M1 was ON: turned OFF), 3=3 ON, 4=9 OFF.
    assert_eq!(bits(&p, 0, 4), [true, false, true, false]);
    // Not all equal: SM704 OFF.
    assert!(!p.bit("SM704"));
    // M4 is past the n = 4 results: untouched.
    assert!(!p.bit("M4"));
}

#[test]
fn bkcmp_all_match_sets_sm704_then_clears_it() {
    let mut p = Plc::new("LD SM400\nBKCMP= D0 D10 M0 K3\nEND\n");
    // Both blocks all zero: 0=0 three times → M0-M2 ON, SM704 ON.
    p.scan();
    assert_eq!(bits(&p, 0, 3), [true, true, true]);
    assert!(p.bit("SM704"));
    // D12 = 5 ≠ D2 = 0: M2 OFF, SM704 OFF.
    p.set("D12", "5").scan();
    assert_eq!(bits(&p, 0, 3), [true, true, false]);
    assert!(!p.bit("SM704"));
}

#[test]
fn bkcmp_constant_first_operand_signed() {
    // K10 against each of 5, 10, 15, −20 with >: 10>5 ON, 10>10 OFF,
    // 10>15 OFF, 10>−20 ON (signed: −20 = FFECH is not 65516).
    let mut p = Plc::new("LD SM400\nBKCMP> K10 D10 M0 K4\nEND\n");
    p.set("D10", "5")
        .set("D11", "10")
        .set("D12", "15")
        .set("D13", "-20");
    p.scan();
    assert_running(&p);
    assert_eq!(bits(&p, 0, 4), [true, false, false, true]);
    assert!(!p.bit("SM704"));
}

#[test]
fn bkcmp_every_operator() {
    // S1 = K0 against D10-D12 = −1, 0, 1.
    let mut p = Plc::new(
        "LD SM400\n\
         BKCMP<> K0 D10 M0 K3\n\
         BKCMP<= K0 D10 M10 K3\n\
         BKCMP< K0 D10 M20 K3\n\
         BKCMP>= K0 D10 M30 K3\n\
         BKCMP> K0 D10 M40 K3\n\
         BKCMP= K0 D10 M50 K3\n\
         END\n",
    );
    p.set("D10", "-1").set("D11", "0").set("D12", "1").scan();
    assert_running(&p);
    // 0<>−1 ON, 0<>0 OFF, 0<>1 ON.
    assert_eq!(bits(&p, 0, 3), [true, false, true]);
    // 0<=−1 OFF, 0<=0 ON, 0<=1 ON.
    assert_eq!(bits(&p, 10, 3), [false, true, true]);
    // 0<−1 OFF, 0<0 OFF, 0<1 ON.
    assert_eq!(bits(&p, 20, 3), [false, false, true]);
    // 0>=−1 ON, 0>=0 ON, 0>=1 OFF.
    assert_eq!(bits(&p, 30, 3), [true, true, false]);
    // 0>−1 ON, 0>0 OFF, 0>1 OFF.
    assert_eq!(bits(&p, 40, 3), [true, false, false]);
    // 0=−1 OFF, 0=0 ON, 0=1 OFF; the last BKCMP leaves SM704 OFF.
    assert_eq!(bits(&p, 50, 3), [false, true, false]);
    assert!(!p.bit("SM704"));
}

#[test]
fn sm704_reflects_the_last_executed_bkcmp() {
    // First BKCMP all true, second not: SM704 OFF; swapped order: ON.
    let src = |a: &str, b: &str| {
        format!("LD SM400\nBKCMP{a} K0 D10 M0 K2\nBKCMP{b} K0 D10 M10 K2\nEND\n")
    };
    // D10 = D11 = 0: "=" all true, "<>" all false.
    let mut p = Plc::new(&src("=", "<>"));
    p.scan();
    assert!(!p.bit("SM704"));
    let mut p = Plc::new(&src("<>", "="));
    p.scan();
    assert!(p.bit("SM704"));
}

#[test]
fn dbkcmp_32_bit() {
    // Pairs (100000, 100000) and (−1, 65535): 32-bit compare, 2 results.
    // 65535 = 0000FFFFH ≠ −1 = FFFFFFFFH although their low words are equal.
    let mut p = Plc::new(
        "LD SM400\n\
         DBKCMP= D0 D10 M0 K2\n\
         DBKCMP< D0 D10 M10 K2\n\
         END\n",
    );
    p.set("D0:i32", "100000").set("D2:i32", "-1");
    p.set("D10:i32", "100000").set("D12:i32", "65535");
    p.scan();
    assert_running(&p);
    assert_eq!(bits(&p, 0, 2), [true, false]);
    // 100000<100000 OFF; −1<65535 ON.
    assert_eq!(bits(&p, 10, 2), [false, true]);
}

#[test]
fn dbkcmp_constant_32_bit() {
    // K70000 against D10:i32 = 70000 and D12:i32 = 4464 (= 1170H, the low word
    // of 70000 = 11170H): only the first matches.
    let mut p = Plc::new("LD SM400\nDBKCMP= K70000 D10 M0 K2\nEND\n");
    p.set("D10:i32", "70000").set("D12:i32", "4464").scan();
    assert_running(&p);
    assert_eq!(bits(&p, 0, 2), [true, false]);
    assert!(!p.bit("SM704"));
}

#[test]
fn bkcmp_word_device_destination_uses_bits() {
    // Results into bits 0-2 of D100: 5=5 ON, 5=6 OFF, 5=5 ON → 101B = 5.
    // Bit 15 of D100 was set before and is not one of the 3 results.
    let mut p = Plc::new("LD SM400\nBKCMP= K5 D10 D100 K3\nEND\n");
    p.set("D10", "5").set("D11", "6").set("D12", "5");
    p.set("D100:u16", "32770").scan(); // 8002H: bit 15 and bit 1
    assert_running(&p);
    // bit 1 cleared (5≠6), bits 0 and 2 set, bit 15 kept: 8005H = 32773.
    assert_eq!(p.int("D100:u16"), 0x8005);
}

#[test]
fn bkcmp_n_zero_does_nothing() {
    let mut p = Plc::new("LD SM400\nBKCMP= D0 D10 M0 K0\nEND\n");
    p.set("D10", "1").set("M0", "1").set("SM704", "1").scan();
    assert_running(&p);
    // Nothing compared: M0 and SM704 keep their values.
    assert!(p.bit("M0"));
    assert!(p.bit("SM704"));
}

#[test]
fn bkcmp_negative_n_is_4100() {
    let mut p = Plc::new("LD SM400\nBKCMP= D0 D10 M0 D20\nEND\n");
    p.set("D20", "-1").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn bkcmp_source_block_past_device_end_is_4101() {
    // D12286 + 4 words runs past D12287.
    let mut p = Plc::new("LD SM400\nBKCMP= D0 D12286 M0 K4\nEND\n");
    p.set("M0", "1").scan();
    assert_stopped(&p, 4101);
    // Nothing written.
    assert!(p.bit("M0"));
}

#[test]
fn bkcmp_result_bits_past_device_end_is_4101() {
    // M8190 + 4 bits runs past M8191.
    let mut p = Plc::new("LD SM400\nBKCMP= D0 D10 M8190 K4\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn dbkcmp_block_of_n_32_bit_values_past_device_end_is_4101() {
    // 3 32-bit values from D12282 need D12282-D12287: fits. From D12283: D12288 does not exist.
    let mut p = Plc::new("LD SM400\nDBKCMP= D0 D12282 M0 K3\nDBKCMP= D0 D12283 M10 K3\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    // The first instruction ran: 0 = 0 three times.
    assert_eq!(bits(&p, 0, 3), [true, true, true]);
}

#[test]
fn bkcmp_index_modification() {
    // Z0 = 10: S1 = D0Z0 = D10, D = M0Z0 = M10.
    let mut p = Plc::new("LD SM400\nMOV K10 Z0\nBKCMP= D0Z0 D20 M0Z0 K2\nEND\n");
    p.set("D10", "7")
        .set("D11", "8")
        .set("D20", "7")
        .set("D21", "9");
    p.scan();
    assert_running(&p);
    // 7=7 ON, 8=9 OFF at M10, M11; M0 untouched.
    assert_eq!(bits(&p, 10, 2), [true, false]);
    assert!(!p.bit("M0"));
}

#[test]
fn bkcmpp_pulse_form_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nBKCMP=P D0 D10 M0 K1\nEND\n");
    p.set("X0", "1").scan();
    // 0=0: M0 ON.
    assert!(p.bit("M0"));
    // X0 stays ON, D0 changes: no new execution, M0 stays ON.
    p.set("D0", "1").scan();
    assert!(p.bit("M0"));
    // New rising edge: 1=0 OFF.
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert!(!p.bit("M0"));
}

#[test]
fn dbkcmp_pulse_form() {
    let mut p = Plc::new("LD X0\nDBKCMP<>P K1 D10 M0 K1\nEND\n");
    p.set("X0", "1").scan();
    // 1<>0 ON.
    assert!(p.bit("M0"));
    p.set("D10:i32", "1").scan();
    // Not executed again: still ON.
    assert!(p.bit("M0"));
}

#[test]
fn fx_style_cmp_and_zcp_are_not_q_instructions() {
    // CMP/DCMP/ECMP/ZCP are FX instructions: not loadable on the Q.
    for src in [
        "LD SM400\nCMP D0 D1 M0\nEND\n",
        "LD SM400\nZCP D0 D1 D2 M0\nEND\n",
    ] {
        let d = common::diagnostics(src);
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(d[0].starts_with("2:1:"), "{d:?}");
    }
}

#[test]
fn bkcmp_operand_errors_at_load() {
    // A digit-specified block (blocks must be word devices), then a missing n.
    let d = common::diagnostics("LD SM400\nBKCMP= D0 K4M0 M0 K2\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("K4M0"), "{d:?}");
    let d = common::diagnostics("LD SM400\nBKCMP= D0 D10 M0\nEND\n");
    assert!(d[0].contains("takes 4 operands"), "{d:?}");
}
