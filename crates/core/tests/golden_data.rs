//! Golden tests of the data processing instructions (programming manual §7.5):
//! SER, SUM, DECO, ENCO, SEG, DIS, UNI, NDIS, NUNI, WTOB, BTOW, MAX, MIN, SORT,
//! WSUM and their 32-bit forms. Every expected value is worked out by hand in
//! the comment next to it.

mod common;
use common::{assert_running, assert_stopped, Plc};

/// Sets `D{first}`, `D{first+1}` … to `values` (16-bit).
fn set_words(p: &mut Plc, first: u32, values: &[i64]) {
    for (k, v) in values.iter().enumerate() {
        p.set(&format!("D{}", first + k as u32), &v.to_string());
    }
}

fn words(p: &Plc, first: u32, n: u32) -> Vec<i64> {
    (first..first + n)
        .map(|k| p.int(&format!("D{k}")))
        .collect()
}

fn mbits(p: &Plc, first: u32, n: u32) -> Vec<bool> {
    (first..first + n)
        .map(|k| p.bit(&format!("M{k}")))
        .collect()
}

// ---------------------------------------------------------------- SER

#[test]
fn ser_first_position_and_count() {
    let mut p = Plc::new("LD SM400\nSER K123 D100 D10 K5\nEND\n");
    set_words(&mut p, 100, &[10, 123, 500, 123, -123]);
    p.scan();
    assert_running(&p);
    // Matches at D101 and D103: first at relative position 2 (D100 is 1), 2 matches.
    // −123 does not match 123.
    assert_eq!(words(&p, 10, 2), [2, 2]);
}

#[test]
fn ser_match_at_first_word_is_position_1() {
    let mut p = Plc::new("LD SM400\nSER D0 D100 D10 K3\nEND\n");
    p.set("D0", "-5");
    set_words(&mut p, 100, &[-5, 0, 0]);
    p.scan();
    assert_eq!(words(&p, 10, 2), [1, 1]);
}

#[test]
fn ser_not_found_clears_result() {
    let mut p = Plc::new("LD SM400\nSER K7 D100 D10 K4\nEND\n");
    set_words(&mut p, 100, &[1, 2, 3, 4]);
    // D104 = 7 is outside the 4 searched points.
    p.set("D104", "7").set("D10", "9").set("D11", "9").scan();
    assert_running(&p);
    assert_eq!(words(&p, 10, 2), [0, 0]);
}

#[test]
fn ser_n_zero_or_negative_does_nothing() {
    for n in ["K0", "K-3"] {
        let mut p = Plc::new(&format!("LD SM400\nSER K0 D100 D10 {n}\nEND\n"));
        p.set("D10", "9").set("D11", "9").scan();
        assert_running(&p);
        assert_eq!(words(&p, 10, 2), [9, 9], "n = {n}");
    }
}

#[test]
fn dser_32_bit() {
    // Key 65537 = 00010001H; 1 = 00000001H has the same low word but does not match.
    let mut p = Plc::new("LD SM400\nDSER K65537 D100 D10 K3\nEND\n");
    p.set("D100:i32", "1")
        .set("D102:i32", "65537")
        .set("D104:i32", "65537");
    p.scan();
    assert_running(&p);
    // Matches at the 2nd and 3rd 32-bit values.
    assert_eq!(words(&p, 10, 2), [2, 2]);
}

#[test]
fn ser_binary_search_with_sm702() {
    // Sorted data 1 3 3 3 5 7 9 11 13 15: key 3 first at position 2, 3 matches.
    let mut p = Plc::new(
        "LD SM400\n\
         SER K3 D100 D10 K10\n\
         SER K4 D100 D12 K10\n\
         SER K15 D100 D14 K10\n\
         END\n",
    );
    set_words(&mut p, 100, &[1, 3, 3, 3, 5, 7, 9, 11, 13, 15]);
    p.set("SM702", "1").scan();
    assert_running(&p);
    assert_eq!(words(&p, 10, 2), [2, 3]);
    // 4 is not there.
    assert_eq!(words(&p, 12, 2), [0, 0]);
    // 15 is the last element.
    assert_eq!(words(&p, 14, 2), [10, 1]);
}

#[test]
fn ser_sm702_really_searches_binary() {
    // Unsorted 5 1 9 3, key 1. Sequential: position 2. Binary: the first
    // element ≥ 1 is narrowed to index 0 (mid 2: 9 ≥ 1, mid 1: 1 ≥ 1, mid 0:
    // 5 ≥ 1), and 5 ≠ 1 → not found, as the manual warns for unsorted data.
    let mut p = Plc::new("LD SM400\nSER K1 D100 D10 K4\nEND\n");
    set_words(&mut p, 100, &[5, 1, 9, 3]);
    p.scan();
    assert_eq!(words(&p, 10, 2), [2, 1]);
    p.set("SM702", "1").scan();
    assert_eq!(words(&p, 10, 2), [0, 0]);
}

#[test]
fn ser_search_range_past_device_end_is_4101() {
    // 4 points from D12285 need D12285-D12288.
    let mut p = Plc::new("LD SM400\nSER K0 D12285 D10 K4\nEND\n");
    p.set("D10", "9").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D10"), 9);
}

#[test]
fn ser_result_past_device_end_is_rejected_at_load() {
    // D and D+1: D12287 has no D+1.
    let d = common::diagnostics("LD SM400\nSER K0 D0 D12287 K1\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:11:"), "{d:?}");
}

#[test]
fn ser_index_modified() {
    // Z0 = 100: S2 = D0Z0 = D100; Z1 = 2: D = D10Z1 = D12.
    let mut p = Plc::new("LD SM400\nMOV K100 Z0\nMOV K2 Z1\nSER K8 D0Z0 D10Z1 K3\nEND\n");
    set_words(&mut p, 100, &[0, 0, 8]);
    p.scan();
    assert_running(&p);
    assert_eq!(words(&p, 12, 2), [3, 1]);
}

#[test]
fn ser_index_modified_result_out_of_range_is_4101() {
    // Z1 = 1: D12286Z1 = D12287, its D+1 does not exist.
    let mut p = Plc::new("LD SM400\nMOV K1 Z1\nSER K8 D0 D12286Z1 K3\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn serp_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nSERP K1 D100 D10 K2\nEND\n");
    p.set("D100", "1").set("X0", "1").scan();
    assert_eq!(words(&p, 10, 2), [1, 1]);
    // Still ON, data changed: not executed.
    p.set("D101", "1").scan();
    assert_eq!(words(&p, 10, 2), [1, 1]);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(words(&p, 10, 2), [1, 2]);
}

// ---------------------------------------------------------------- SUM

#[test]
fn sum_counts_one_bits() {
    let mut p = Plc::new(
        "LD SM400\n\
         SUM D0 D10\n\
         SUM D1 D11\n\
         SUM K7 D12\n\
         SUM K4M0 D13\n\
         DSUM D2 D14\n\
         DSUM K65537 D15\n\
         END\n",
    );
    p.set("D0", "-1").set("D1", "21845"); // FFFFH; 5555H
    p.set("D2:i32", "-1")
        .set("M0", "1")
        .set("M5", "1")
        .set("M16", "1");
    p.scan();
    assert_running(&p);
    // FFFFH: 16 ones; 5555H = 0101…0101B: 8 ones; 7 = 111B: 3.
    assert_eq!(words(&p, 10, 3), [16, 8, 3]);
    // K4M0 = M0-M15: M0 and M5 → 2 (M16 is outside).
    assert_eq!(p.int("D13"), 2);
    // DSUM FFFFFFFFH: 32; 65537 = 00010001H: 2.
    assert_eq!(words(&p, 14, 2), [32, 2]);
}

// ---------------------------------------------------------------- DECO

#[test]
fn deco_into_bit_devices() {
    // Low 3 bits of FFF5H = 101B = 5 → M5 ON, M0-M4, M6, M7 OFF; M8 untouched.
    let mut p = Plc::new("LD SM400\nDECO D0 M0 K3\nEND\n");
    p.set("D0:u16", "65525")
        .set("M0", "1")
        .set("M8", "1")
        .scan();
    assert_running(&p);
    assert_eq!(
        mbits(&p, 0, 9),
        [false, false, false, false, false, true, false, false, true]
    );
}

#[test]
fn deco_into_word_devices() {
    let mut p = Plc::new(
        "LD SM400\n\
         DECO K10 D100 K4\n\
         DECO K5 D101 K3\n\
         DECO K200 D120 K8\n\
         END\n",
    );
    p.set("D101", "-1");
    set_words(&mut p, 120, &[7; 16]);
    p.scan();
    assert_running(&p);
    // n = 4: bit 10 of D100 → 1024.
    assert_eq!(p.int("D100"), 1024);
    // n = 3: bit 5 → 32; the rest of the word is cleared (was FFFFH).
    assert_eq!(p.int("D101"), 32);
    // n = 8: 256 bits = D120-D135; bit 200 = word 12 (200 = 12·16 + 8), bit 8
    // → D132 = 256, the other 15 words 0.
    let mut want = vec![0i64; 16];
    want[12] = 256;
    assert_eq!(words(&p, 120, 16), want);
}

#[test]
fn deco_n_zero_and_invalid_n() {
    let mut p = Plc::new("LD SM400\nDECO K1 D100 D0\nEND\n");
    p.set("D100", "77").scan();
    // n = 0: no processing.
    assert_running(&p);
    assert_eq!(p.int("D100"), 77);
    for n in ["9", "-1"] {
        let mut p = Plc::new("LD SM400\nDECO K1 D100 D0\nEND\n");
        p.set("D0", n).scan();
        assert_stopped(&p, 4100);
    }
}

#[test]
fn deco_past_device_end_is_4101() {
    // n = 2: 4 bits from M8190 need M8190-M8193 (M0-M8191).
    let mut p = Plc::new("LD SM400\nDECO K0 M8190 K2\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    // n = 8 into words: 16 words from D12280 need D12280-D12295.
    let mut p = Plc::new("LD SM400\nDECOP K0 D12280 K8\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

// ---------------------------------------------------------------- ENCO

#[test]
fn enco_highest_on_bit() {
    let mut p = Plc::new(
        "LD SM400\n\
         ENCO M0 D10 K3\n\
         ENCO D0 D11 K4\n\
         ENCO D100 D12 K8\n\
         END\n",
    );
    // M1, M6 ON (M9 beyond the 8 bits): highest is 6.
    p.set("M1", "1").set("M6", "1").set("M9", "1");
    // D0 = 0105H: bits 0, 2, 8 → 8.
    p.set("D0", "261");
    // 256 bits D100-D115: bit 15 of D115 = bit 255; bit 3 of D100 too → 255.
    p.set("D115:u16", "32768").set("D100", "8");
    p.scan();
    assert_running(&p);
    assert_eq!(words(&p, 10, 3), [6, 8, 255]);
}

#[test]
fn enco_no_bit_on_is_4100() {
    let mut p = Plc::new("LD SM400\nENCO M0 D10 K4\nEND\n");
    // M16 is outside the 16 bits M0-M15.
    p.set("M16", "1").set("D10", "5").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D10"), 5);
}

#[test]
fn enco_n_zero_and_invalid_n() {
    let mut p = Plc::new("LD SM400\nENCO M0 D10 K0\nEND\n");
    p.set("D10", "5").scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 5);
    let mut p = Plc::new("LD SM400\nENCO M0 D10 K9\nEND\n");
    p.set("M0", "1").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn enco_decode_round_trip_pulse() {
    // DECOP D0 → M100-M115, ENCOP back → D1, once per rising edge of X0.
    let mut p = Plc::new("LD X0\nDECOP D0 M100 K4\nLD X0\nENCOP M100 D1 K4\nEND\n");
    p.set("D0", "13").set("X0", "1").scan();
    assert!(p.bit("M113"));
    assert_eq!(p.int("D1"), 13);
    // Still ON: D0 changes but nothing runs.
    p.set("D0", "2").scan();
    assert_eq!(p.int("D1"), 13);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D1"), 2);
}

// ---------------------------------------------------------------- SEG

#[test]
fn seg_table_0_to_f() {
    // Segments a-g = bits 0-6. 0: abcdef = 3FH; 1: bc = 06H; 2: abdeg = 5BH;
    // 3: abcdg = 4FH; 4: bcfg = 66H; 5: acdfg = 6DH; 6: acdefg = 7DH;
    // 7: abcf = 27H; 8: all = 7FH; 9: abcdfg = 6FH; A: abcefg = 77H;
    // b: cdefg = 7CH; C: adef = 39H; d: bcdeg = 5EH; E: adefg = 79H; F: aefg = 71H.
    let want = [
        0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x27, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79,
        0x71,
    ];
    let mut p = Plc::new("LD SM400\nSEG D0 D10\nEND\n");
    for (digit, w) in want.iter().enumerate() {
        // High bits of the source are ignored: 10H + digit.
        p.set("D0", &(16 + digit).to_string()).scan();
        assert_eq!(p.int("D10"), *w, "digit {digit:X}");
    }
}

#[test]
fn seg_word_keeps_high_byte() {
    let mut p = Plc::new("LD SM400\nSEG K0 D10\nEND\n");
    // 1200H before; low byte becomes 3FH → 123FH = 4671.
    p.set("D10", "4608").scan();
    assert_eq!(p.int("D10"), 0x123F);
}

#[test]
fn seg_bit_device_and_digits() {
    let mut p = Plc::new("LD SM400\nSEG K15 M10\nSEG K7 K2M20\nEND\n");
    p.set("M17", "1").set("M28", "1").scan();
    assert_running(&p);
    // F = 71H = 0111 0001B: M10, M14, M15, M16 ON; M11-M13 and M17 (bit 7) OFF.
    assert_eq!(
        mbits(&p, 10, 8),
        [true, false, false, false, true, true, true, false]
    );
    // 7 = 27H = 0010 0111B into K2M20 (M20-M27): M20, M21, M22, M25 ON; M28 untouched.
    assert_eq!(
        mbits(&p, 20, 9),
        [true, true, true, false, false, true, false, false, true]
    );
}

#[test]
fn seg_bit_device_past_end_is_4101() {
    let mut p = Plc::new("LD SM400\nSEGP K1 M8185\nEND\n");
    p.scan();
    // 8 points from M8185 need M8185-M8192.
    assert_stopped(&p, 4101);
}

// ---------------------------------------------------------------- DIS / UNI

#[test]
fn dis_digits_into_words() {
    let mut p = Plc::new("LD SM400\nDIS D0 D10 K3\nDIS D0 D20 K4\nEND\n");
    // 1234H.
    p.set("D0", "4660").set("D12", "-1").set("D13", "99").scan();
    assert_running(&p);
    // Digits from the lowest: 4, 3, 2 (D12's high 12 bits cleared); D13 untouched.
    assert_eq!(words(&p, 10, 4), [4, 3, 2, 99]);
    assert_eq!(words(&p, 20, 4), [4, 3, 2, 1]);
}

#[test]
fn dis_invalid_n_is_4100_and_zero_does_nothing() {
    let mut p = Plc::new("LD SM400\nDIS K1 D10 D0\nEND\n");
    p.set("D10", "7").scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 7);
    for n in ["5", "-1"] {
        let mut p = Plc::new("LD SM400\nDIS K1 D10 D0\nEND\n");
        p.set("D0", n).scan();
        assert_stopped(&p, 4100);
    }
}

#[test]
fn dis_past_device_end_is_4101() {
    let mut p = Plc::new("LD SM400\nDIS K1 D12286 K3\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn uni_links_low_digits() {
    let mut p = Plc::new("LD SM400\nUNI D10 D0 K3\nEND\n");
    // Low 4 bits only: 0FF4H → 4, 3, 0012H → 2.
    set_words(&mut p, 10, &[0x0FF4, 3, 0x12]);
    p.set("D0", "-1").scan();
    assert_running(&p);
    // 234H = 564; the 4th digit of D0 is cleared.
    assert_eq!(p.int("D0"), 0x234);
}

#[test]
fn uni_into_digits_and_invalid_n() {
    let mut p = Plc::new("LD SM400\nUNIP D10 K2M0 K2\nEND\n");
    set_words(&mut p, 10, &[5, 10]);
    p.scan();
    // A5H = 1010 0101B into M0-M7.
    assert_eq!(
        mbits(&p, 0, 8),
        [true, false, true, false, false, true, false, true]
    );
    let mut p = Plc::new("LD SM400\nUNI D10 D0 K5\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
}

// ---------------------------------------------------------------- NDIS / NUNI

#[test]
fn ndis_fields_of_any_width() {
    let mut p = Plc::new("LD SM400\nNDIS D0 D10 D20\nEND\n");
    // D0 = ABCDH, D1 = 0012H; widths 4, 8, 12, end.
    p.set("D0:u16", "43981").set("D1", "18");
    set_words(&mut p, 20, &[4, 8, 12, 0]);
    p.set("D13", "99").scan();
    assert_running(&p);
    // Bits from bit 0 of D0: 4 bits = DH = 13; 8 bits = BCH = 188;
    // 12 bits = AH (bits 12-15 of D0) + 12H·16 (bits 0-7 of D1) = 12AH = 298.
    assert_eq!(words(&p, 10, 4), [13, 188, 298, 99]);
}

#[test]
fn nuni_packs_fields() {
    let mut p = Plc::new("LD SM400\nNUNI D10 D0 D20\nEND\n");
    // Fields 13 (FFFDH: only the low 4 bits count), 188, 298; widths 4, 8, 12.
    p.set("D10:u16", "65533")
        .set("D11", "188")
        .set("D12", "298");
    set_words(&mut p, 20, &[4, 8, 12, 0]);
    p.set("D1", "-1").set("D2", "99").scan();
    assert_running(&p);
    // Inverse of the NDIS example: D0 = ABCDH, D1 = 0012H (its high byte
    // cleared, 24 bits used); D2 untouched.
    assert_eq!(p.int("D0:u16"), 0xABCD);
    assert_eq!(words(&p, 1, 2), [0x12, 99]);
}

#[test]
fn ndis_full_width_field_and_empty_list() {
    let mut p = Plc::new("LD SM400\nNDIS D0 D10 D20\nNDIS D0 D30 D25\nEND\n");
    // Widths 16, 0: D10 = D0 unchanged value −2. Second list empty: no processing.
    p.set("D0", "-2").set("D20", "16").set("D30", "5").scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), -2);
    assert_eq!(p.int("D30"), 5);
}

#[test]
fn ndis_invalid_width_is_4100() {
    for w in ["17", "-1"] {
        let mut p = Plc::new("LD SM400\nNDIS D0 D10 D20\nEND\n");
        p.set("D20", "4").set("D21", w).scan();
        assert_stopped(&p, 4100);
        // Nothing written, not even the valid first field.
        assert_eq!(p.int("D10"), 0, "width {w}");
    }
}

#[test]
fn nuni_unterminated_width_list_is_4101() {
    // Widths from D12286: 1, 1 and then the device ends without a 0.
    let mut p = Plc::new("LD SM400\nNUNI D10 D0 D12286\nEND\n");
    p.set("D12286", "1").set("D12287", "1").scan();
    assert_stopped(&p, 4101);
}

// ---------------------------------------------------------------- WTOB / BTOW

#[test]
fn wtob_splits_bytes() {
    let mut p = Plc::new("LD SM400\nWTOB D0 D10 K3\nEND\n");
    // 1234H, 5678H.
    p.set("D0", "4660")
        .set("D1", "22136")
        .set("D13", "99")
        .scan();
    assert_running(&p);
    // Bytes low first: 34H, 12H, 78H; D13 untouched (n = 3).
    assert_eq!(words(&p, 10, 4), [0x34, 0x12, 0x78, 99]);
}

#[test]
fn btow_packs_bytes() {
    let mut p = Plc::new("LD SM400\nBTOW D10 D20 K3\nEND\n");
    // High bytes of the sources are ignored: FF34H → 34H.
    p.set("D10:u16", "65332").set("D11", "18").set("D12", "120");
    p.set("D21", "-1").scan();
    assert_running(&p);
    // 34H, 12H → 1234H; 78H with high byte 0 (odd n) → 0078H.
    assert_eq!(words(&p, 20, 2), [0x1234, 0x78]);
}

#[test]
fn wtob_btow_in_place() {
    let mut p = Plc::new("LD X0\nWTOBP D0 D0 K4\nLD X1\nBTOWP D0 D0 K4\nEND\n");
    p.set("D0", "4660").set("D1", "22136").set("X0", "1").scan();
    // 1234H 5678H → 34H 12H 78H 56H.
    assert_eq!(words(&p, 0, 4), [0x34, 0x12, 0x78, 0x56]);
    p.set("X1", "1").scan();
    // Back: 1234H 5678H; D2, D3 keep 78H, 56H.
    assert_eq!(words(&p, 0, 4), [0x1234, 0x5678, 0x78, 0x56]);
}

#[test]
fn wtob_n_zero_negative_and_range() {
    let mut p = Plc::new("LD SM400\nWTOB D0 D10 K0\nEND\n");
    p.set("D0", "1").set("D10", "7").scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 7);
    let mut p = Plc::new("LD SM400\nWTOB D0 D10 K-2\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
    // 4 bytes into 4 words from D12285: D12288 does not exist.
    let mut p = Plc::new("LD SM400\nWTOB D0 D12285 K4\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

// ---------------------------------------------------------------- MAX / MIN

#[test]
fn max_min_value_position_count() {
    let mut p = Plc::new("LD SM400\nMAX D0 D10 K5\nMIN D0 D20 K5\nEND\n");
    set_words(&mut p, 0, &[3, 9, -4, 9, 1]);
    p.scan();
    assert_running(&p);
    // Max 9, first at position 2, twice.
    assert_eq!(words(&p, 10, 3), [9, 2, 2]);
    // Min −4 (signed), position 3, once.
    assert_eq!(words(&p, 20, 3), [-4, 3, 1]);
}

#[test]
fn dmax_dmin_32_bit() {
    let mut p = Plc::new("LD SM400\nDMAX D0 D10 K4\nDMIN D0 D20 K4\nEND\n");
    p.set("D0:i32", "70000").set("D2:i32", "-5");
    p.set("D4:i32", "70000").set("D6:i32", "65535");
    p.scan();
    assert_running(&p);
    // Max 70000 at positions 1 and 3: position 1, count 2.
    assert_eq!(p.int("D10:i32"), 70000);
    assert_eq!(words(&p, 12, 2), [1, 2]);
    // Min −5 at position 2 (65535 = 0000FFFFH is positive in 32 bits).
    assert_eq!(p.int("D20:i32"), -5);
    assert_eq!(words(&p, 22, 2), [2, 1]);
}

#[test]
fn max_n_zero_does_nothing_and_ranges() {
    let mut p = Plc::new("LD SM400\nMAX D0 D10 K0\nEND\n");
    p.set("D10", "5").scan();
    assert_running(&p);
    assert_eq!(p.int("D10"), 5);
    // Source past the device end.
    let mut p = Plc::new("LD SM400\nMINP D12286 D10 K3\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
    // DMAX needs D to D+3: D12285 has only 3 words left.
    let d = common::diagnostics("LD SM400\nDMAX D0 D12285 K1\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("4 words"), "{d:?}");
}

#[test]
fn max_index_modified_source() {
    // Z0 = 3: S = D0Z0 = D3; values D3, D4 = 1, 2.
    let mut p = Plc::new("LD SM400\nMOV K3 Z0\nMAX D0Z0 D10 K2\nEND\n");
    set_words(&mut p, 0, &[100, 100, 100, 1, 2]);
    p.scan();
    assert_eq!(words(&p, 10, 3), [2, 2, 1]);
}

// ---------------------------------------------------------------- WSUM

#[test]
fn wsum_32_bit_sum() {
    let mut p = Plc::new("LD SM400\nWSUM D0 D10 K3\nEND\n");
    set_words(&mut p, 0, &[32767, 32767, -2]);
    p.scan();
    assert_running(&p);
    // 32767 + 32767 − 2 = 65532: beyond 16 bits, exact in 32.
    assert_eq!(p.int("D10:i32"), 65532);
}

#[test]
fn dwsum_64_bit_sum() {
    let mut p = Plc::new("LD SM400\nDWSUM D0 D10 K2\nDWSUM D4 D20 K2\nEND\n");
    p.set("D0:i32", "2147483647").set("D2:i32", "2147483647");
    p.set("D4:i32", "-1").set("D6:i32", "-1");
    p.scan();
    assert_running(&p);
    // 2·2147483647 = 4294967294 = 00000000FFFFFFFEH: D10 = FFFEH, D11 = FFFFH, D12 = D13 = 0.
    assert_eq!(p.int("D10:u32"), 4294967294);
    assert_eq!(words(&p, 12, 2), [0, 0]);
    // −2 = FFFFFFFFFFFFFFFEH.
    assert_eq!(p.int("D20:i32"), -2);
    assert_eq!(words(&p, 22, 2), [-1, -1]);
}

#[test]
fn wsum_n_zero_and_pulse() {
    let mut p = Plc::new("LD X0\nWSUMP D0 D10 D20\nEND\n");
    set_words(&mut p, 0, &[1, 2, 3]);
    p.set("D10", "9").set("X0", "1").scan();
    // n = D20 = 0: nothing.
    assert_eq!(p.int("D10"), 9);
    p.set("D20", "3").scan();
    // Not a new rising edge: still nothing.
    assert_eq!(p.int("D10"), 9);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D10:i32"), 6);
}

// ---------------------------------------------------------------- SORT

#[test]
fn sort_over_several_scans() {
    let mut p = Plc::new("LD X0\nSORT D0 K5 K2 M0 D50\nEND\n");
    set_words(&mut p, 0, &[5, 3, 4, 1, 2]);
    p.set("M0", "1").set("X0", "1");
    // n = 5: 5·4/2 = 10 comparisons, 2 per scan → 5 scans. Exchange sort,
    // element i against each later j:
    // scan 1: (0,1) 5>3 swap → 3 5 4 1 2; (0,2) 3<4.
    p.scan();
    assert_eq!(words(&p, 0, 5), [3, 5, 4, 1, 2]);
    // The sort's first execution turned M0 OFF.
    assert!(!p.bit("M0"));
    // scan 2: (0,3) 3>1 swap → 1 5 4 3 2; (0,4) 1<2.
    p.scan();
    assert_eq!(words(&p, 0, 5), [1, 5, 4, 3, 2]);
    // scan 3: (1,2) 5>4 swap → 1 4 5 3 2; (1,3) 4>3 swap → 1 3 5 4 2.
    p.scan();
    assert_eq!(words(&p, 0, 5), [1, 3, 5, 4, 2]);
    // scan 4: (1,4) 3>2 swap → 1 2 5 4 3; (2,3) 5>4 swap → 1 2 4 5 3.
    p.scan();
    assert_eq!(words(&p, 0, 5), [1, 2, 4, 5, 3]);
    assert!(!p.bit("M0"));
    // scan 5: (2,4) 4>3 swap → 1 2 3 5 4; (3,4) 5>4 swap → 1 2 3 4 5: done.
    p.scan();
    assert_eq!(words(&p, 0, 5), [1, 2, 3, 4, 5]);
    assert!(p.bit("M0"));
    // X0 OFF: M0 stays ON (the user resets it).
    p.set("X0", "0").scans(2);
    assert!(p.bit("M0"));
    // D50, D51 (system work area) are not used by softplc.
    assert_eq!(words(&p, 50, 2), [0, 0]);
    assert_running(&p);
}

#[test]
fn sort_restarts_after_completion() {
    let mut p = Plc::new("LD SM400\nSORT D0 K3 K1 M0 D50\nEND\n");
    set_words(&mut p, 0, &[3, 2, 1]);
    // 3 comparisons, 1 per scan: done in scan 3.
    p.scans(3);
    assert_eq!(words(&p, 0, 3), [1, 2, 3]);
    assert!(p.bit("M0"));
    // Scan 4 starts a new sort: M0 OFF, 1 comparison (0,1) 1<2.
    p.scan();
    assert!(!p.bit("M0"));
    p.scans(2);
    assert!(p.bit("M0"));
}

#[test]
fn sort_interrupted_resumes() {
    let mut p = Plc::new("LD X0\nSORT D0 K3 K1 M0 D50\nEND\n");
    set_words(&mut p, 0, &[3, 2, 1]);
    // Scan 1: (0,1) 3>2 swap → 2 3 1.
    p.set("X0", "1").scan();
    assert_eq!(words(&p, 0, 3), [2, 3, 1]);
    // Condition OFF: nothing happens.
    p.set("X0", "0").scans(2);
    assert_eq!(words(&p, 0, 3), [2, 3, 1]);
    // ON again: the sort continues with (0,2) 2>1 swap → 1 3 2, then (1,2)
    // 3>2 swap → 1 2 3 and M0 ON.
    p.set("X0", "1").scan();
    assert_eq!(words(&p, 0, 3), [1, 3, 2]);
    assert!(!p.bit("M0"));
    p.scan();
    assert_eq!(words(&p, 0, 3), [1, 2, 3]);
    assert!(p.bit("M0"));
}

#[test]
fn sort_descending_with_sm703() {
    let mut p = Plc::new("LD SM400\nSORT D0 K5 K10 M0 D50\nEND\n");
    set_words(&mut p, 0, &[5, 3, -4, 1, 2]);
    // All 10 comparisons in one scan.
    p.set("SM703", "1").scan();
    assert_eq!(words(&p, 0, 5), [5, 3, 2, 1, -4]);
    assert!(p.bit("M0"));
}

#[test]
fn dsort_32_bit() {
    let mut p = Plc::new("LD SM400\nDSORT D0 K3 K3 M0 D50\nEND\n");
    p.set("D0:i32", "70000")
        .set("D2:i32", "-70000")
        .set("D4:i32", "65535");
    p.scan();
    // Signed 32-bit ascending: −70000, 65535, 70000.
    assert_eq!(p.int("D0:i32"), -70000);
    assert_eq!(p.int("D2:i32"), 65535);
    assert_eq!(p.int("D4:i32"), 70000);
    assert!(p.bit("M0"));
}

#[test]
fn sort_trivial_sizes_complete_at_once() {
    for n in ["K0", "K1"] {
        let mut p = Plc::new(&format!("LD SM400\nSORT D0 {n} K1 M0 D50\nEND\n"));
        p.set("D0", "9").scan();
        assert_running(&p);
        assert!(p.bit("M0"), "n = {n}");
        assert_eq!(p.int("D0"), 9);
    }
}

#[test]
fn sort_errors() {
    // n negative, comparisons per scan 0: 4100.
    let mut p = Plc::new("LD SM400\nSORT D0 K-1 K1 M0 D50\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD SM400\nSORT D0 K5 K0 M0 D50\nEND\n");
    p.scan();
    assert_stopped(&p, 4100);
    // 5 values from D12285: past the device end.
    let mut p = Plc::new("LD SM400\nSORT D12285 K5 K1 M0 D50\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn sort_has_no_pulse_form_and_work_area_is_checked() {
    let d = common::diagnostics("LD SM400\nSORTP D0 K5 K1 M0 D50\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("no pulse form"), "{d:?}");
    let d = common::diagnostics("LD SM400\nDSORT D0 K5 K1 M0 D12287\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("2 words"), "{d:?}");
}

#[test]
fn two_sorts_keep_separate_state() {
    let mut p = Plc::new(
        "LD SM400\n\
         SORT D0 K3 K1 M0 D50\n\
         SORT D10 K3 K1 M1 D52\n\
         END\n",
    );
    set_words(&mut p, 0, &[3, 2, 1]);
    set_words(&mut p, 10, &[1, 3, 2]);
    p.scans(3);
    assert_eq!(words(&p, 0, 3), [1, 2, 3]);
    assert_eq!(words(&p, 10, 3), [1, 2, 3]);
    assert!(p.bit("M0") && p.bit("M1"));
}

// ---------------------------------------------------------------- not QnH

#[test]
fn mean_is_not_a_qnh_instruction() {
    let d = common::diagnostics("LD SM400\nMEAN D0 D10 K3\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("MEAN"), "{d:?}");
}
