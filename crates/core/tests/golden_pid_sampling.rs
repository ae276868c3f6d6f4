//! Golden tests of the PID control instructions (seed 001; notes
//! `shared/spec/pid-instructions.md`). Every expected value is worked out by
//! hand in the comment next to it from the formulas of 001 §3.1.2/§3.2.2 under
//! the notes' §2.6 [DECISION] policy (f64, MV clamped before stored, round half
//! away from zero for the shown words, first processing seeded with EVn−1 = 0).
//!
//! Unless a test says otherwise: PID control data at D500, I/O data at D600,
//! scans of 1 s with Ts = 1 s (ts = 100), so every scan is one sample; the
//! first scan is the first processing (it uses the configured Ts).
//!
//! This file: sampling time accumulation, loops processed per scan and the
//! range-limit bits.

mod common;
use common::pid::{get, plc, set, write_data, Fam, Loop, ALARM, BASE, MODE, MV, PV, PVF, SV};
use common::{assert_running, Plc};

// ------------------------------------------------------------ sampling, loops per scan

/// Loop data whose integral step equals the sampling time used: reverse,
/// Kp 1.00, TI 0.1 s (ti 1), SV 510, PV 500 → EV 10, ΔMV = ts/(10·1)·10 = ts
/// (10 ms units) after the first processing, which gives 10 + Ts_configured.
const TS_PROBE: Loop = Loop { ti: 1, ..BASE };

/// Runs `scans` scans and returns, for each scan where loop `i`'s MV changed,
/// (scan number, MV increment).
fn increments(p: &mut Plc, fam: Fam, i: u32, scans: u32) -> Vec<(u32, i64)> {
    let mut out = vec![];
    let mut last = get(p, fam, i, MV);
    for s in 1..=scans {
        p.scan();
        assert_running(p);
        let mv = get(p, fam, i, MV);
        if mv != last {
            out.push((s, mv - last));
        }
        last = mv;
    }
    out
}

fn probe(fam: Fam, k: i16, loops: &[Loop], scan_us: u64) -> Plc {
    let mut p = plc(fam, k, loops, 510, 1);
    p.scan_time_us(scan_us);
    for i in 0..loops.len() as u32 {
        set(&mut p, fam, i, PV, 500);
    }
    p
}

/// 001 §5.1.2(2) example: Ts 50 ms, measured 57 ms → computed with 50 ms,
/// measured 64 ms → 60 ms. With 19 ms scans the accumulator runs 19, 38, 57
/// (scan 4: Ts 5, carry 7), 26, 45, 64 (scan 7: Ts 6, carry 4), 23, 42, 61
/// (scan 10: 6, carry 1), 20, 39, 58 (scan 13: 5, carry 8), 27, 46, 65
/// (scan 16: 6, carry 5). First processing (scan 1): 10 + 5 = 15.
#[test]
fn sampling_truncated_to_10ms_with_carry_19ms_scans() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ts: 5, ..TS_PROBE };
        let mut p = probe(fam, 1, &[l], 19_000);
        assert_eq!(
            increments(&mut p, fam, 0, 16),
            [(1, 15), (4, 5), (7, 6), (10, 6), (13, 5), (16, 6)],
            "{fam:?}"
        );
    }
}

/// 7 ms scans, Ts 50 ms (a scan time that does not divide 10 ms): the
/// accumulator reaches 56 (scan 9, carry 6), 55 (16, carry 5), 54 (23),
/// 53 (30), 52 (37), 51 (44), 50 (51, carry 0), then 7·8 = 56 again (59).
/// Every sample uses Ts = 50 ms (+5).
#[test]
fn sampling_with_7ms_scans() {
    let l = Loop { ts: 5, ..TS_PROBE };
    let mut p = probe(Fam::S, 1, &[l], 7_000);
    let want: Vec<(u32, i64)> = [1, 9, 16, 23, 30, 37, 44, 51, 59]
        .iter()
        .map(|&s| (s, if s == 1 { 15 } else { 5 }))
        .collect();
    assert_eq!(increments(&mut p, Fam::S, 0, 60), want);
}

/// Sub-millisecond scan times accumulate exactly (µs remainder in common work
/// word +1): 2.5 ms scans add 2, 3, 2, 3 … ms, so Ts 10 ms is reached every 4
/// scans (scans 5, 9, 13) with Ts used 1.
#[test]
fn sampling_with_sub_millisecond_remainder() {
    let l = Loop { ts: 1, ..TS_PROBE };
    let mut p = probe(Fam::C, 1, &[l], 2_500);
    assert_eq!(
        increments(&mut p, Fam::C, 0, 14),
        [(1, 11), (5, 1), (9, 1), (13, 1)]
    );
}

/// Ts shorter than the scan: the loop runs every scan with the measured scan
/// time (001 §5.1.2 要点): 30 ms scans, Ts 10 ms → +3 each scan.
#[test]
fn ts_shorter_than_scan() {
    let l = Loop { ts: 1, ..TS_PROBE };
    let mut p = probe(Fam::S, 1, &[l], 30_000);
    assert_eq!(
        increments(&mut p, Fam::S, 0, 4),
        [(1, 11), (2, 3), (3, 3), (4, 3)]
    );
}

/// Two loops, loops per scan k = 1, Ts 1 s, 10 ms scans (001 §5.1.1).
/// First-processing flag 0: both loops' first processing in scan 1 (k
/// ignored): 10 + 100 = 110 each. Scan 101: both due; loop 1 (lower number)
/// runs (+100), loop 2 is deferred. Scan 102: loop 2 runs with 1010 ms → Ts
/// 101 (+101). Scan 201: loop 1 again; scan 202: loop 2 (its phase moved).
#[test]
fn two_loops_one_per_scan() {
    for fam in [Fam::C, Fam::S] {
        let mut p = probe(fam, 1, &[TS_PROBE, TS_PROBE], 10_000);
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (110, 110));
        p.scans(99);
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (110, 110));
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (210, 110));
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (210, 211));
        p.scans(98);
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (210, 211));
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (310, 211));
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (310, 311));
    }
}

/// Priority (001 §5.1.1 要点): a loop left over from the previous scan beats a
/// lower-numbered one. Loop 1 Ts 10 ms (due every scan), loop 2 Ts 1 s, k = 1.
/// Scan 101: both due → loop 1 (+1), loop 2 deferred. Scan 102: loop 2 (Ts
/// 1010 ms → +101) before loop 1, which is deferred. Scan 103: loop 1 runs
/// first with 20 ms (+2).
#[test]
fn deferred_loop_has_priority() {
    let fam = Fam::C;
    let l1 = Loop { ts: 1, ..TS_PROBE };
    let mut p = probe(fam, 1, &[l1, TS_PROBE], 10_000);
    let d1 = increments(&mut p, fam, 0, 100);
    assert_eq!(d1.len(), 100);
    assert_eq!(get(&p, fam, 1, MV), 110);
    p.scan();
    assert_eq!(get(&p, fam, 0, MV), 11 + 99 + 1);
    assert_eq!(get(&p, fam, 1, MV), 110);
    p.scan();
    assert_eq!(get(&p, fam, 0, MV), 111);
    assert_eq!(get(&p, fam, 1, MV), 211);
    p.scan();
    assert_eq!(get(&p, fam, 0, MV), 113);
}

/// First-processing flag ≠ 0 (001 §5.2(4) 3)): first processings spread k per
/// scan in loop order, each loop sampling from its own first scan. k = 1:
/// loop 1 in scan 1, loop 2 in scan 2; then loop 1 at scan 101, loop 2 at 102.
#[test]
fn first_processing_split() {
    for fam in [Fam::C, Fam::S] {
        let mut p = probe(fam, 1, &[TS_PROBE, TS_PROBE], 10_000);
        p.set("D600", "1");
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (110, 0));
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (110, 110));
        p.scans(98);
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (210, 110));
        p.scan();
        assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (210, 210));
    }
}

// ------------------------------------------------------------ range limits

/// SD774 b0 (PIDCONT loop 1), read at every execution (001 §4.3.5).
/// Reverse, P only, MVLL −100, MVHL 3000, ΔMVL 32767, ΔPVL 3000.
/// * limited (bit 0): s1 SV 3000 → 2000, PV −100 → −50: EV 2050 → MV
///   min(2050, MVHL → 2050) = 2050; PVf −50; ΔMV 2050 > ΔMVL (→ 2000) → b1.
///   s2 SV 0, PV 2100 → 2050: EV −2050, ΔMV −4100 → −50 (MVLL → −50); PVf
///   2050; |2050 − (−50)| = 2100 > ΔPVL (3000 → 2000) → b0.
/// * unlimited (bit 1): s1 EV 3100 → MV 3000, PVf −100. s2 EV −2100, ΔMV
///   −5200 → −100; PVf 2100; PV change 2200 ≤ 3000 and |ΔMV| ≤ 32767 → no alarm.
#[test]
fn range_limit_bit_on_and_off() {
    for (sd, want) in [
        (0, [(2050, -50, 2), (-50, 2050, 3)]),
        (1, [(3000, -100, 0), (-100, 2100, 0)]),
    ] {
        let fam = Fam::C;
        let l = Loop {
            mvll: -100,
            mvhl: 3000,
            dmvl: 32767,
            dpvl: 3000,
            ..BASE
        };
        let mut p = plc(fam, 1, &[l], 3000, 1000);
        p.set("SD774", &sd.to_string());
        let mut got = vec![];
        for (sv, pv) in [(3000, -100), (0, 2100)] {
            set(&mut p, fam, 0, SV, sv);
            set(&mut p, fam, 0, PV, pv);
            p.scan();
            assert_running(&p);
            got.push((
                get(&p, fam, 0, MV),
                get(&p, fam, 0, PVF),
                get(&p, fam, 0, ALARM),
            ));
        }
        assert_eq!(got, want, "SD774 = {sd}");
    }
}

/// SD794/SD795 of the S. family: 17 loops, loop 17 follows SD795 b0 and loop 1
/// SD794 b0. P only, reverse, SV 3000, PV 0, MVHL 3000: limited → 2000,
/// unlimited → 3000.
#[test]
fn range_limit_bits_s_family_loop_17() {
    let fam = Fam::S;
    let l = Loop { mvhl: 3000, ..BASE };
    // 17 loops: control data D2000-D2239, I/O data D600-D1000.
    let mut p = Plc::new("LD SM400\nSP.PIDINIT D2000\nS.PIDCONT D600\nEND\n");
    p.scan_time_us(1_000_000);
    write_data(&mut p, fam, 2000, 17, &[l; 17]);
    for i in 0..17 {
        set(&mut p, fam, i, SV, 3000);
        set(&mut p, fam, i, MODE, 1);
    }
    p.set("SD795", "1");
    p.scan();
    assert_running(&p);
    assert_eq!(get(&p, fam, 0, MV), 2000);
    assert_eq!(get(&p, fam, 15, MV), 2000);
    assert_eq!(get(&p, fam, 16, MV), 3000);
    // The plain family's SD775 does not affect the S. family.
    p.set("SD795", "0").set("SD775", "1").set("SD794", "1");
    p.scan();
    assert_eq!(get(&p, fam, 0, MV), 3000);
    assert_eq!(get(&p, fam, 16, MV), 2000);
}
