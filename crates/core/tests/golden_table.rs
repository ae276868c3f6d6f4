//! Golden tests of the table operations FIFW, FIFR, FPOP, FINS, FDEL
//! (programming manual §7.7). A table is its pointer word (number of data)
//! followed by the data, oldest first. Every expected value is worked out by
//! hand in the comment next to it.

mod common;
use common::{assert_running, assert_stopped, Plc};

/// Words `D{first}` … `D{first+n-1}`.
fn words(p: &Plc, first: u32, n: u32) -> Vec<i64> {
    (first..first + n)
        .map(|k| p.int(&format!("D{k}")))
        .collect()
}

/// Loads table D0 with the given data (pointer = their number).
fn table(p: &mut Plc, data: &[i64]) {
    p.set("D0", &data.len().to_string());
    for (k, v) in data.iter().enumerate() {
        p.set(&format!("D{}", k + 1), &v.to_string());
    }
}

// ---------------------------------------------------------------- FIFW

#[test]
fn fifw_appends_and_counts() {
    let mut p = Plc::new(
        "LD SM400\n\
         FIFW K10 D0\n\
         FIFW K20 D0\n\
         FIFW D50 D0\n\
         END\n",
    );
    p.set("D50", "-7").scan();
    assert_running(&p);
    // Empty table (D0 = 0) gets 10 at D1, 20 at D2, −7 at D3; pointer 3.
    assert_eq!(words(&p, 0, 5), [3, 10, 20, -7, 0]);
}

#[test]
fn fifwp_writes_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nFIFWP D50 D0\nEND\n");
    p.set("D50", "1").set("X0", "1").scan();
    // Edge 1: D1 = 1, pointer 1.
    assert_eq!(words(&p, 0, 3), [1, 1, 0]);
    // X0 still ON: nothing more.
    p.set("D50", "2").scan();
    assert_eq!(words(&p, 0, 3), [1, 1, 0]);
    // Edge 2: D2 = 2, pointer 2.
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(words(&p, 0, 3), [2, 1, 2]);
}

#[test]
fn fifw_past_device_end_is_4101() {
    // Table at D12285 with pointer 2: the new datum would go to
    // D12285 + 2 + 1 = D12288, which does not exist (D0-D12287).
    let mut p = Plc::new("LD SM400\nFIFW K1 D12285\nEND\n");
    p.set("D12285", "2").scan();
    assert_stopped(&p, 4101);
    // Pointer unchanged.
    assert_eq!(p.int("D12285"), 2);
}

#[test]
fn fifw_fills_the_last_device_word() {
    // Pointer 1 at D12285: the datum goes to D12287, the last D.
    let mut p = Plc::new("LD SM400\nFIFWP K9 D12285\nEND\n");
    p.set("D12285", "1").scan();
    assert_running(&p);
    assert_eq!(p.int("D12287"), 9);
    assert_eq!(p.int("D12285"), 2);
}

#[test]
fn fifw_negative_or_full_pointer_is_4100() {
    let mut p = Plc::new("LD SM400\nFIFW K1 D0\nEND\n");
    p.set("D0", "-1").scan();
    // A negative pointer is not a number of data.
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD SM400\nFIFW K1 D0\nEND\n");
    p.set("D0", "32767").scan();
    // 32767 data: the pointer cannot count one more.
    assert_stopped(&p, 4100);
}

#[test]
fn fifw_index_modified_table() {
    // Z0 = 100: table D0Z0 = D100.
    let mut p = Plc::new("LD SM400\nMOV K100 Z0\nFIFWP K5 D0Z0\nEND\n");
    p.scan();
    assert_running(&p);
    assert_eq!(words(&p, 100, 2), [1, 5]);
    assert_eq!(p.int("D0"), 0);
}

// ---------------------------------------------------------------- FIFR

#[test]
fn fifr_reads_oldest_and_shifts_up() {
    let mut p = Plc::new("LD X0\nFIFRP D20 D0\nEND\n");
    table(&mut p, &[10, 20, 30]);
    p.set("X0", "1").scan();
    assert_running(&p);
    // Oldest 10 → D20; 20, 30 move up to D1, D2; vacated D3 = 0; pointer 2.
    assert_eq!(p.int("D20"), 10);
    assert_eq!(words(&p, 0, 4), [2, 20, 30, 0]);
    // Next edge: 20.
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D20"), 20);
    assert_eq!(words(&p, 0, 3), [1, 30, 0]);
}

#[test]
fn fifo_round_trip() {
    // Three writes then three reads give the data back in the same order.
    let mut p = Plc::new(
        "LD SM400\n\
         FIFW K1 D0\n\
         FIFW K2 D0\n\
         FIFW K3 D0\n\
         FIFR D20 D0\n\
         FIFR D21 D0\n\
         FIFR D22 D0\n\
         END\n",
    );
    p.scan();
    assert_running(&p);
    assert_eq!(words(&p, 20, 3), [1, 2, 3]);
    assert_eq!(words(&p, 0, 4), [0, 0, 0, 0]);
}

#[test]
fn fifr_empty_table_is_4100() {
    let mut p = Plc::new("LD SM400\nFIFR D20 D0\nEND\n");
    p.set("D20", "5").scan();
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D20"), 5);
}

#[test]
fn fifr_table_past_device_end_is_4101() {
    // Pointer 5 at D12285: the data would be D12286-D12290.
    let mut p = Plc::new("LD SM400\nFIFR D20 D12285\nEND\n");
    p.set("D12285", "5").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12285"), 5);
}

#[test]
fn fifr_into_digit_specified_destination() {
    // Oldest datum 0AH = 1010B into K1M0: M1 and M3 ON.
    let mut p = Plc::new("LD SM400\nFIFRP K1M0 D0\nEND\n");
    table(&mut p, &[10]);
    p.scan();
    assert_running(&p);
    assert!(!p.bit("M0") && p.bit("M1") && !p.bit("M2") && p.bit("M3"));
    assert_eq!(p.int("D0"), 0);
}

// ---------------------------------------------------------------- FPOP

#[test]
fn fpop_reads_newest() {
    let mut p = Plc::new("LD SM400\nFPOPP D20 D0\nEND\n");
    table(&mut p, &[10, 20, 30]);
    p.scan();
    assert_running(&p);
    // Newest 30 (D3) → D20; D3 becomes 0; pointer 2; D1, D2 stay.
    assert_eq!(p.int("D20"), 30);
    assert_eq!(words(&p, 0, 4), [2, 10, 20, 0]);
}

#[test]
fn fpop_every_scan_empties_then_4100() {
    let mut p = Plc::new("LD SM400\nFPOP D20 D0\nEND\n");
    table(&mut p, &[7, 8]);
    p.scan();
    assert_eq!(p.int("D20"), 8);
    p.scan();
    assert_eq!(p.int("D20"), 7);
    assert_running(&p);
    // Third scan: the table is empty.
    p.scan();
    assert_stopped(&p, 4100);
}

#[test]
fn fpopp_is_the_pulse_form_of_fpop() {
    // "FPOPP" is FPOP + P, not an instruction "FPOPP" of its own.
    let mut p = Plc::new("LD X0\nFPOPP D20 D0\nEND\n");
    table(&mut p, &[1, 2, 3]);
    p.set("X0", "1").scans(3);
    // One execution for one rising edge.
    assert_eq!(p.int("D20"), 3);
    assert_eq!(p.int("D0"), 2);
}

// ---------------------------------------------------------------- FINS

#[test]
fn fins_inserts_at_position() {
    let mut p = Plc::new("LD SM400\nFINSP K15 D0 K2\nEND\n");
    table(&mut p, &[10, 20, 30]);
    p.scan();
    assert_running(&p);
    // 15 becomes the 2nd datum: 10, 15, 20, 30; pointer 4.
    assert_eq!(words(&p, 0, 5), [4, 10, 15, 20, 30]);
}

#[test]
fn fins_first_and_append() {
    let mut p = Plc::new(
        "LD SM400\n\
         FINSP K1 D0 K1\n\
         FINSP K9 D0 K4\n\
         END\n",
    );
    table(&mut p, &[5, 6]);
    p.scan();
    assert_running(&p);
    // n = 1: 1, 5, 6 (pointer 3); then n = 4 = pointer + 1 appends: 1, 5, 6, 9.
    assert_eq!(words(&p, 0, 5), [4, 1, 5, 6, 9]);
}

#[test]
fn fins_into_empty_table() {
    let mut p = Plc::new("LD SM400\nFINSP K-3 D0 K1\nEND\n");
    p.scan();
    assert_running(&p);
    assert_eq!(words(&p, 0, 2), [1, -3]);
}

#[test]
fn fins_position_out_of_range_is_4100() {
    for n in ["K0", "K4", "K-1"] {
        // Table of 2: valid positions 1-3.
        let mut p = Plc::new(&format!("LD SM400\nFINS K1 D0 {n}\nEND\n"));
        table(&mut p, &[5, 6]);
        p.scan();
        assert_stopped(&p, 4100);
        // Unchanged table.
        assert_eq!(words(&p, 0, 4), [2, 5, 6, 0], "n = {n}");
    }
}

#[test]
fn fins_past_device_end_is_4101() {
    // Pointer 1 at D12286: inserting needs D12286-D12288.
    let mut p = Plc::new("LD SM400\nFINS K1 D12286 K1\nEND\n");
    p.set("D12286", "1").set("D12287", "4").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12287"), 4);
}

// ---------------------------------------------------------------- FDEL

#[test]
fn fdel_deletes_nth() {
    let mut p = Plc::new("LD SM400\nFDELP D20 D0 K2\nEND\n");
    table(&mut p, &[10, 20, 30]);
    p.scan();
    assert_running(&p);
    // 2nd datum 20 → D20; 30 moves up; D3 = 0; pointer 2.
    assert_eq!(p.int("D20"), 20);
    assert_eq!(words(&p, 0, 4), [2, 10, 30, 0]);
}

#[test]
fn fdel_last_and_first() {
    let mut p = Plc::new(
        "LD SM400\n\
         FDELP D20 D0 K3\n\
         FDELP D21 D0 K1\n\
         END\n",
    );
    table(&mut p, &[10, 20, 30]);
    p.scan();
    assert_running(&p);
    // Delete the 3rd (30): 10, 20; then the 1st (10): 20.
    assert_eq!(words(&p, 20, 2), [30, 10]);
    assert_eq!(words(&p, 0, 4), [1, 20, 0, 0]);
}

#[test]
fn fdel_position_out_of_range_or_empty_is_4100() {
    for (data, n) in [(&[5, 6][..], "K0"), (&[5, 6][..], "K3"), (&[][..], "K1")] {
        let mut p = Plc::new(&format!("LD SM400\nFDEL D20 D0 {n}\nEND\n"));
        table(&mut p, data);
        p.scan();
        assert_stopped(&p, 4100);
        assert_eq!(p.int("D0"), data.len() as i64, "n = {n}");
    }
}

#[test]
fn fdel_index_modified_position_and_table() {
    // Z1 = 2: n = D10Z1 = D12 = 1; table D0Z1 = D2 with [2 data: 7, 8].
    let mut p = Plc::new("LD SM400\nMOV K2 Z1\nFDELP D20 D0Z1 D10Z1\nEND\n");
    p.set("D12", "1")
        .set("D2", "2")
        .set("D3", "7")
        .set("D4", "8");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D20"), 7);
    assert_eq!(words(&p, 2, 3), [1, 8, 0]);
}

#[test]
fn index_modified_table_out_of_range_is_4101() {
    // Z0 = −1: D0Z0 = D−1 does not exist.
    let mut p = Plc::new("LD SM400\nMOV K-1 Z0\nFIFW K1 D0Z0\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

#[test]
fn table_operand_errors_at_load() {
    // Constant table, digit-specified table, missing n.
    let d = common::diagnostics("LD SM400\nFIFW K1 K2\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:9:"), "{d:?}");
    let d = common::diagnostics("LD SM400\nFIFR D0 K4M0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].contains("word device"), "{d:?}");
    let d = common::diagnostics("LD SM400\nFINS K1 D0\nEND\n");
    assert!(d[0].contains("takes 3 operands"), "{d:?}");
}
