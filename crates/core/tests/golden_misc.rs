//! Golden tests of the remaining QnH instructions of `instructions::misc`:
//! TIMCHK, RAMP, RND/SRND, ZPUSH/ZPOP, and the load-time rejections of
//! ROTC, CHKST/CHK/CHKCIR/CHKEND, IX/IXEND, IXDEV/IXSET. Every expected value is
//! worked out by hand in the comment next to it. Q06HCPU defaults: D0-D12287,
//! M0-M8191, Z0-Z15; scans take 10 ms of virtual time unless set otherwise.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};
use softplc_core::engine::ExecType;

/// The single diagnostic of a program that must not load.
fn only_diagnostic(src: &str) -> String {
    let d = diagnostics(src);
    assert_eq!(d.len(), 1, "{d:?}");
    d[0].clone()
}

// ------------------------------------------------------------------ TIMCHK

const TIMCHK: &str = "LD X0\nTIMCHK D0 K5 M0\nEND\n";

#[test]
fn timchk_measures_on_time_in_100ms_units() {
    let mut p = Plc::new(TIMCHK);
    // Scan 1 (X0 newly ON) starts the measurement and adds nothing; scan k adds
    // 10 ms from k = 2, so after scan k D0 = floor(10·(k−1) / 100).
    p.set("X0", "1").scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), 0);
    assert!(!p.bit("M0"));
    p.scans(9); // scan 10: 90 ms
    assert_eq!(p.int("D0"), 0);
    p.scan(); // scan 11: 100 ms
    assert_eq!(p.int("D0"), 1);
    p.scans(39); // scan 50: 490 ms
    assert_eq!(p.int("D0"), 4);
    assert!(!p.bit("M0"));
    p.scan(); // scan 51: 500 ms = K5 → time up
    assert_eq!(p.int("D0"), 5);
    assert!(p.bit("M0"));
    // The measurement goes on past the set value: scan 61 = 600 ms.
    p.scans(10);
    assert_eq!(p.int("D0"), 6);
    assert!(p.bit("M0"));
}

#[test]
fn timchk_holds_while_off_and_restarts_when_on_again() {
    let mut p = Plc::new(TIMCHK);
    p.set("X0", "1").scans(61); // D0 = 6, M0 ON (as above)
    assert_eq!(p.int("D0"), 6);
    // X0 OFF: the instruction does not run; the result of the check stays.
    p.set("X0", "0").scans(5);
    assert_eq!(p.int("D0"), 6);
    assert!(p.bit("M0"));
    // X0 ON again: a new measurement, D0 = 0 and M0 OFF at once.
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 0);
    assert!(!p.bit("M0"));
    p.scans(10); // 100 ms later
    assert_eq!(p.int("D0"), 1);
}

#[test]
fn timchk_one_scan_off_is_a_new_measurement() {
    let mut p = Plc::new(TIMCHK);
    p.set("X0", "1").scans(31); // 300 ms → D0 = 3
    assert_eq!(p.int("D0"), 3);
    p.set("X0", "0").scan(); // OFF for a single scan
    assert_eq!(p.int("D0"), 3);
    p.set("X0", "1").scan(); // restart, adds nothing
    assert_eq!(p.int("D0"), 0);
    p.scans(9); // 90 ms: without the restart this would be 3 + ...
    assert_eq!(p.int("D0"), 0);
}

#[test]
fn timchk_under_mc_off_restarts() {
    // MC OFF: the instructions up to MCR run with their condition OFF.
    let mut p = Plc::new("LD X1\nMC N0 M100\nLD X0\nTIMCHK D0 K5 M0\nMCR N0\nEND\n");
    p.set("X0", "1").set("X1", "1").scans(21); // 200 ms → 2
    assert_eq!(p.int("D0"), 2);
    p.set("X1", "0").scans(2);
    assert_eq!(p.int("D0"), 2);
    p.set("X1", "1").scan();
    assert_eq!(p.int("D0"), 0);
}

#[test]
fn timchk_carries_the_part_below_100ms() {
    let mut p = Plc::new(TIMCHK);
    p.scan_time_us(7_000);
    // Scan 1 starts; after scan k the measurement holds 7·(k−1) ms:
    //   k=15: 98 → 0   k=16: 105 → 1   k=30: 203 → 2   k=72: 497 → 4   k=73: 504 → 5
    p.set("X0", "1").scans(15);
    assert_eq!(p.int("D0"), 0);
    p.scan();
    assert_eq!(p.int("D0"), 1);
    p.scans(14);
    assert_eq!(p.int("D0"), 2);
    p.scans(42);
    assert_eq!(p.int("D0"), 4);
    assert!(!p.bit("M0"));
    p.scan();
    assert_eq!(p.int("D0"), 5);
    assert!(p.bit("M0"));
}

#[test]
fn timchk_current_value_stops_at_32767() {
    let mut p = Plc::new(TIMCHK);
    // 1000 s scans = 10000 units each: 0, 10000, 20000, 30000, then 40000 → 32767.
    p.scan_time_us(1_000_000_000);
    p.set("X0", "1").scans(4);
    assert_eq!(p.int("D0"), 30000);
    p.scan();
    assert_eq!(p.int("D0"), 32767);
    p.scan();
    assert_eq!(p.int("D0"), 32767);
    assert_running(&p);
}

#[test]
fn timchk_set_value_from_a_device_zero_and_negative() {
    let mut p = Plc::new("LD X0\nTIMCHK D0 D1 M0\nEND\n");
    // S2 = 0: time up at the first execution (as a timer's set value 0).
    p.set("D1", "0").set("X0", "1").scan();
    assert_eq!(p.int("D0"), 0);
    assert!(p.bit("M0"));
    // S2 = −1: OPERATION ERROR 4100.
    p.set("D1", "-1").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn timchk_index_modification() {
    let mut p = Plc::new("LD X0\nTIMCHK D0Z0 K1 M0Z1\nEND\n");
    // Z0 = 10 → S1 = D10; Z1 = 5 → D = M5.
    p.set("Z0", "10").set("Z1", "5").set("X0", "1").scans(11); // 100 ms → 1 = K1
    assert_eq!(p.int("D10"), 1);
    assert!(p.bit("M5"));
    assert_eq!(p.int("D0"), 0);
    assert!(!p.bit("M0"));
    // Z0 = 12288 → D12288, past D12287: 4101.
    p.set("Z0", "12288").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn timchk_has_no_pulse_form() {
    let d = only_diagnostic("LD X0\nTIMCHKP D0 K5 M0\nEND\n");
    assert!(d.contains("TIMCHK has no pulse form"), "{d}");
    let d = only_diagnostic("LD X0\nTIMCHK D0 K5\nEND\n");
    assert!(d.contains("takes 3 operands"), "{d}");
}

// -------------------------------------------------------------------- RAMP

#[test]
fn ramp_moves_from_n1_to_n2_in_n3_scans() {
    let mut p = Plc::new("LD X0\nRAMP K10 K100 D0 K6 M0\nEND\n");
    // D0 = 10 + 90·k/6 = 10 + 15k: 25, 40, 55, 70, 85, 100; D1 = k.
    p.set("X0", "1");
    for (k, v) in [(1, 25), (2, 40), (3, 55), (4, 70), (5, 85)] {
        p.scan();
        assert_eq!((p.int("D0"), p.int("D1")), (v, k));
        assert!(!p.bit("M0"));
    }
    p.scan(); // k = 6: the final value, M0 ON
    assert_eq!((p.int("D0"), p.int("D1")), (100, 6));
    assert!(p.bit("M0"));
    // Completed: held while the condition stays ON.
    p.scans(3);
    assert_eq!((p.int("D0"), p.int("D1")), (100, 6));
    assert!(p.bit("M0"));
    assert_running(&p);
}

#[test]
fn ramp_reads_n2_at_every_execution() {
    // Mitsubishi's example (fa-faq 14530): 10 → 100 in 6, n2 changed to 200
    // before the 3rd execution: 10 + 190·k/6 truncated = 105 (k=3: 95),
    // 136 (k=4: 126.67), 168 (k=5: 158.33), 200 (k=6).
    let mut p = Plc::new("LD X0\nRAMP K10 D10 D0 K6 M0\nEND\n");
    p.set("D10", "100").set("X0", "1").scans(2);
    assert_eq!(p.int("D0"), 40);
    p.set("D10", "200");
    for v in [105, 136, 168] {
        p.scan();
        assert_eq!(p.int("D0"), v);
        assert!(!p.bit("M0"));
    }
    p.scan();
    assert_eq!(p.int("D0"), 200);
    assert!(p.bit("M0"));
}

#[test]
fn ramp_down_truncates_toward_zero() {
    // 100 → 10 in 7: 100 + (−90·k)/7 truncated toward 0:
    // k=1: −12.86 → −12 → 88; k=2: −25.71 → −25 → 75; k=3: −38.57 → −38 → 62.
    let mut p = Plc::new("LD X0\nRAMP K100 K10 D0 K7 M0\nEND\n");
    p.set("X0", "1");
    for v in [88, 75, 62] {
        p.scan();
        assert_eq!(p.int("D0"), v);
    }
    p.scans(4); // k = 7
    assert_eq!((p.int("D0"), p.int("D1")), (10, 7));
    assert!(p.bit("M0"));
}

#[test]
fn ramp_interrupted_by_off_restarts_from_n1() {
    let mut p = Plc::new("LD X0\nRAMP K0 K100 D0 K4 M0\nEND\n");
    // 0 + 100·k/4 = 25k.
    p.set("X0", "1").scans(2);
    assert_eq!((p.int("D0"), p.int("D1")), (50, 2));
    // OFF: interrupted, values held.
    p.set("X0", "0").scans(3);
    assert_eq!((p.int("D0"), p.int("D1")), (50, 2));
    // ON again: D1 cleared, first step again.
    p.set("X0", "1").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (25, 1));
    // Complete, then OFF and ON: M0 OFF again at the restart.
    p.scans(3);
    assert_eq!(p.int("D0"), 100);
    assert!(p.bit("M0"));
    p.set("X0", "0").scan();
    assert!(p.bit("M0"));
    p.set("X0", "1").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (25, 1));
    assert!(!p.bit("M0"));
}

#[test]
fn ramp_continues_from_d1_plus_1() {
    let mut p = Plc::new("LD X0\nRAMP K0 K100 D0 K4 M0\nEND\n");
    p.set("X0", "1").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (25, 1));
    // The program sets the count to 2: the next execution is k = 3 → 75.
    p.set("D1", "2").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (75, 3));
    // A negative count is taken as 0 → k = 1; one above n3 as complete.
    p.set("D1", "-5").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (25, 1));
    p.set("D1", "9").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (100, 4));
    assert!(p.bit("M0"));
}

#[test]
fn ramp_one_transfer_and_errors() {
    let mut p = Plc::new("LD X0\nRAMP K-5 K5 D0 D20 M0\nEND\n");
    // n3 = 1: the final value at the first execution.
    p.set("D20", "1").set("X0", "1").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (5, 1));
    assert!(p.bit("M0"));
    // n3 = 0: 4100.
    p.set("D20", "0").scan();
    assert_stopped(&p, 4100);
    let mut p = Plc::new("LD X0\nRAMP K-5 K5 D0 D20 M0\nEND\n");
    p.set("D20", "-3").set("X0", "1").scan();
    assert_stopped(&p, 4100);
    // Nothing was written.
    assert_eq!((p.int("D0"), p.int("D1")), (0, 0));
}

#[test]
fn ramp_index_modification_and_range() {
    let mut p = Plc::new("LD X0\nRAMP K0 K10 D0Z0 K2 M0Z1\nEND\n");
    // Z0 = 100: D1 = D100 (count in D101); Z1 = 50: D2 = M50. k=1: 0 + 10·1/2 = 5.
    p.set("Z0", "100").set("Z1", "50").set("X0", "1").scan();
    assert_eq!((p.int("D100"), p.int("D101")), (5, 1));
    assert_eq!((p.int("D0"), p.int("D1")), (0, 0));
    p.scan();
    assert_eq!(p.int("D100"), 10);
    assert!(p.bit("M50"));
    assert!(!p.bit("M0"));
    // Z0 = 12287 → D12287: its count word D12288 does not exist → 4101.
    p.set("Z0", "12287").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12287"), 0);
}

#[test]
fn ramp_load_errors() {
    let d = only_diagnostic("LD X0\nRAMPP K0 K10 D0 K2 M0\nEND\n");
    assert!(d.contains("RAMP has no pulse form"), "{d}");
    // D1 and D1+1: D12287 has no D12288.
    let d = only_diagnostic("LD X0\nRAMP K0 K10 D12287 K2 M0\nEND\n");
    assert!(d.contains("2 words"), "{d}");
}

// --------------------------------------------------------------- RND / SRND
//
// Generator: s' = s·1103515245 + 12345 (mod 2³²), number = bits 16-30 of s'.
// Seed 1 (power-on): s1 = 1103515245 + 12345 = 1103527590 = 41C67EA6H;
//   41C6H = 16838, bit 15 clear → 16838.
// Then (products reduced mod 2³² = 4294967296):
//   s2 = 1103527590·1103515245 + 12345 = 1217759518843121895
//        − 283531732·2³² = 2524885223 = 967EB0E7H; 967EH & 7FFFH = 167EH = 5758.
//   s3 = 2524885223·1103515245 + 12345 = 2786249335455736980
//        − 648724226·2³² = 662824084 = 2781E494H; 2781H = 10113.

#[test]
fn rnd_default_series() {
    let mut p = Plc::new("LD SM400\nRND D0\nEND\n");
    for v in [16838, 5758, 10113] {
        p.scan();
        assert_eq!(p.int("D0"), v);
    }
    assert_running(&p);
}

#[test]
fn srnd_sets_the_seed() {
    let mut p = Plc::new("LD X0\nSRNDP D10\nLD SM400\nRND D0\nEND\n");
    // Seed 100: 100·1103515245 + 12345 = 110351536845 − 25·2³² (107374182400)
    // = 2977354445 = B176D2CDH; B176H = 45430, & 7FFFH = 45430 − 32768 = 12662.
    p.set("D10", "100").set("X0", "1").scan();
    assert_eq!(p.int("D0"), 12662);
    // SRNDP only on the rising edge: the series goes on with the next number,
    // 23392 (worked out in rnd_series_is_cpu_wide_and_restarts_at_stop_to_run).
    p.scan();
    assert_eq!(p.int("D0"), 23392);
    // Seed FFFFH (D10 = −1, taken as 65535): 65535·1103515245 + 12345 =
    // 72318871593420 − 16838·2³² (72318659330048) = 212263372 = 0CA6E1CCH →
    // 0CA6H = 3238.
    p.set("D10", "-1").set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 3238);
    // Seed 1 gives the power-on series again.
    p.set("D10", "1").set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 16838);
    p.scan();
    assert_eq!(p.int("D0"), 5758);
}

#[test]
fn srnd_constant_seed_zero() {
    // Seed 0: s1 = 12345 = 00003039H → 0; s2 = 12345·1103515245 + 12345 =
    // 13622895711870 − 3171·2³² (13619341295616) = 3554416254 = D3DC167EH →
    // D3DCH = 54236, & 7FFFH = 54236 − 32768 = 21468.
    let mut p = Plc::new("LD SM402\nSRND K0\nLD SM400\nRND D0\nEND\n");
    p.scan();
    assert_eq!(p.int("D0"), 0);
    p.scan();
    assert_eq!(p.int("D0"), 21468);
}

#[test]
fn rndp_draws_once_per_rising_edge() {
    let mut p = Plc::new("LD X0\nRNDP D0\nEND\n");
    p.set("X0", "1").scans(3);
    assert_eq!(p.int("D0"), 16838);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 5758);
}

#[test]
fn rnd_series_is_cpu_wide_and_restarts_at_stop_to_run() {
    // SRND in one program file, RND in both: one series.
    let mut p = Plc::with_programs(
        &[
            ("LD SM400\nSRND K100\nRND D0\nEND\n", ExecType::Scan, None),
            ("LD SM400\nRND D1\nEND\n", ExecType::Scan, None),
        ],
        softplc_core::profile::default_config(),
    );
    p.scan();
    // Seed 100: 12662 (srnd_sets_the_seed) in the first program, then in the
    // second 2977354445·1103515245 + 12345 = 3285556019826026370
    // − 764978122·2³² = 3680528258 = DB606782H → DB60H = 56160,
    // & 7FFFH = 56160 − 32768 = 23392.
    assert_eq!((p.int("D0"), p.int("D1")), (12662, 23392));
    // STOP → RUN: the series starts from seed 1 again.
    let mut q = Plc::new("LD SM400\nRND D0\nEND\n");
    q.scans(2);
    assert_eq!(q.int("D0"), 5758);
    q.cpu.set_stop();
    q.scan();
    q.cpu.set_run().unwrap();
    q.scan();
    assert_eq!(q.int("D0"), 16838);
}

#[test]
fn rnd_stays_in_range_and_index_modification() {
    let mut p = Plc::new("LD SM400\nRND D0Z0\nEND\n");
    p.set("Z0", "5");
    let mut seen_high = false;
    for _ in 0..2000 {
        p.scan();
        let v = p.int("D5");
        assert!((0..=32767).contains(&v), "{v}");
        seen_high |= v > 30000;
    }
    assert!(seen_high);
    assert_eq!(p.int("D0"), 0);
    // Z0 = 12288 → D12288, past D12287: 4101.
    p.set("Z0", "12288").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn rnd_to_digit_specified_device() {
    // 16838 = 41C6H; K2Y0 takes the low 8 bits C6H = 1100 0110b.
    let mut p = Plc::new("LD SM400\nRND K2Y0\nEND\n");
    p.scan();
    assert_eq!(p.int("K2Y0"), 0xC6);
    assert!(!p.bit("Y0") && p.bit("Y1") && p.bit("Y2") && p.bit("Y7"));
    assert!(!p.bit("Y8"));
}

// ------------------------------------------------------------- ZPUSH / ZPOP

fn set_z(p: &mut Plc, base: i64) {
    for k in 0..16 {
        p.set(&format!("Z{k}"), &(base + k).to_string());
    }
}

#[test]
fn zpush_zpop_nest() {
    let mut p = Plc::new("LD X0\nZPUSHP D100\nLD X1\nZPOPP D100\nEND\n");
    // Z0-Z15 = 1..16, push: D100 = 1 save, D101-D116 = Z0-Z15.
    set_z(&mut p, 1);
    p.set("X0", "1").scan();
    assert_eq!(p.int("D100"), 1);
    assert_eq!((p.int("D101"), p.int("D108"), p.int("D116")), (1, 8, 16));
    // Z = 101..116, push again: save 2 in D117-D132.
    set_z(&mut p, 101);
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D100"), 2);
    assert_eq!((p.int("D117"), p.int("D132")), (101, 116));
    // Z = −1 everywhere, pop: save 2 back (Z0 = 101 … Z15 = 116), D100 = 1.
    set_z(&mut p, -1000);
    p.set("X1", "1").scan();
    assert_eq!(p.int("D100"), 1);
    assert_eq!((p.int("Z0"), p.int("Z7"), p.int("Z15")), (101, 108, 116));
    // Pop again: save 1 (Z0 = 1 … Z15 = 16), D100 = 0; the saves stay in D.
    p.set("X1", "0").scan();
    p.set("X1", "1").scan();
    assert_eq!(p.int("D100"), 0);
    assert_eq!((p.int("Z0"), p.int("Z15")), (1, 16));
    assert_eq!(p.int("D117"), 101);
    assert_running(&p);
    // Nothing saved: 4100.
    p.set("X1", "0").scan();
    p.set("X1", "1").scan();
    assert_stopped(&p, 4100);
}

#[test]
fn zpush_without_pulse_saves_every_scan() {
    let mut p = Plc::new("LD X0\nZPUSH D0\nEND\n");
    set_z(&mut p, 7);
    p.set("X0", "1").scans(3);
    // 3 saves: D0 = 3, save 3 in D33-D48.
    assert_eq!(p.int("D0"), 3);
    assert_eq!((p.int("D33"), p.int("D48")), (7, 22));
}

#[test]
fn zpush_area_range() {
    let mut p = Plc::new("LD X0\nZPUSH D12270\nEND\n");
    // Save 1 needs D12270-D12286: fits (D12287 is the last).
    p.set("Z3", "33").set("X0", "1").scan();
    assert_running(&p);
    assert_eq!((p.int("D12270"), p.int("D12274")), (1, 33));
    // Save 2 would need D12287-D12302: 4101, nothing written.
    p.scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D12270"), 1);
    assert_eq!(p.int("D12287"), 0);
}

#[test]
fn zpush_negative_count_and_zpop_range() {
    let mut p = Plc::new("LD X0\nZPUSH D0\nEND\n");
    p.set("D0", "-1").set("X0", "1").scan();
    assert_stopped(&p, 4100);
    // ZPOP with D12280 = 1: save 1 would be D12281-D12296: 4101.
    let mut p = Plc::new("LD X0\nZPOP D12280\nEND\n");
    p.set("D12280", "1").set("X0", "1").scan();
    assert_stopped(&p, 4101);
}

#[test]
fn zpush_index_modified_area_resolved_before_z_changes() {
    let mut p = Plc::new("LD X0\nZPUSHP D100Z0\nLD X1\nZPOPP D100Z0\nEND\n");
    // Z0 = 10: the area is D110; Z0 itself is saved as 10 in D111.
    p.set("Z0", "10").set("Z1", "5").set("X0", "1").scan();
    assert_eq!((p.int("D110"), p.int("D111"), p.int("D112")), (1, 10, 5));
    assert_eq!(p.int("D100"), 0);
    // Z1 = 99; ZPOP D100Z0 with Z0 = 10 restores from D110: Z1 = 5.
    p.set("Z1", "99").set("X1", "1").scan();
    assert_eq!((p.int("Z0"), p.int("Z1"), p.int("D110")), (10, 5, 0));
}

// ----------------------------------------------------------------- rejected

#[test]
fn rotc_is_rejected() {
    let d = only_diagnostic("LD X0\nROTC D0 K10 K2 M0\nEND\n");
    assert!(d.starts_with("2:1: unsupported instruction `ROTC`"), "{d}");
}

#[test]
fn chk_family_is_rejected() {
    for m in ["CHKST", "CHK D0 D1", "CHKCIR", "CHKEND"] {
        let d = only_diagnostic(&format!("LD X0\n{m}\nEND\n"));
        let name = m.split(' ').next().unwrap_or(m);
        assert!(
            d.contains(&format!(
                "unsupported instruction `{name}`: CHKST/CHK/CHKCIR/CHKEND special-format failure checks"
            )),
            "{m}: {d}"
        );
    }
}

#[test]
fn ix_blocks_and_ixdev_are_rejected() {
    let d = diagnostics("LD SM400\nIX D0\nLD X0\nOUT Y0\nIXEND\nEND\n");
    assert_eq!(d.len(), 2, "{d:?}");
    assert!(
        d[0].starts_with("2:1: unsupported instruction `IX`: IX/IXEND index-modification blocks"),
        "{d:?}"
    );
    assert!(
        d[1].starts_with(
            "5:1: unsupported instruction `IXEND`: IX/IXEND index-modification blocks"
        ),
        "{d:?}"
    );
    let d = diagnostics("LD SM400\nIXDEV\nLD X10\nOUT Y20\nIXSET D0 D100\nEND\n");
    assert_eq!(d.len(), 2, "{d:?}");
    assert!(
        d[0].contains("unsupported instruction `IXDEV`: IXDEV/IXSET"),
        "{d:?}"
    );
    assert!(
        d[1].contains("unsupported instruction `IXSET`: IXDEV/IXSET"),
        "{d:?}"
    );
}

// --------------------------------------------------------------------- WDT

#[test]
fn wdt_and_wdtp_run_without_disturbing_the_scan() {
    // WDT restarts the watchdog only (004 §7.9): the scan goes on, and the
    // scan-time registers are untouched (10 ms scans: SD520 = 10 ms).
    let mut p = Plc::new("LD X0\nWDT\nLD X1\nWDTP\nLD SM400\nMOV K1 D0\nEND\n");
    p.set("X0", "1").set("X1", "1").scans(3);
    assert_running(&p);
    assert_eq!((p.int("D0"), p.int("SD520")), (1, 10));
}
