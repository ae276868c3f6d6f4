//! S.AT1, Ziegler-Nichols step-response auto-tuning (000 §13.1; spec §4.37,
//! DEC-32 … DEC-35), driven by a discrete first-order-plus-dead-time process
//! simulated here: E1 is written before every scan from the MV the loop tag
//! held after the previous scans. Expected values from the spec's formulas in
//! f32.
//!
//! `S.AT1 D0 D100 D200 D1000 D300`: E1 D0, e1 D2; BB D100; PN D200; loop tag
//! D1000; local memory D300..D321. ΔT = AT1ST = 1 s, MV 30 %, AT1STEPMV 10 %,
//! MODE MAN.

mod common;
#[path = "common/process_loop.rs"]
mod lp;

use common::Plc;
use lp::{defaults, getf, setf, tag, tf, tw, word, AUT, MAN, SPA};
use softplc_core::program::ProcessSettings;

const SRC: &str = "LD SM400\nS.AT1 D0 D100 D200 D1000 D300\nEND\n";
const BB1: u16 = 1;
const BB2: u16 = 1 << 1;
const BB3: u16 = 1 << 2;
const BB4: u16 = 1 << 3;
const BB5: u16 = 1 << 4;
const BB6: u16 = 1 << 5;
const BB7: u16 = 1 << 6;
const BB8: u16 = 1 << 7;
const BB16: u16 = 1 << 15;
const PHA: u16 = 1 << 6;
const HHA: u16 = 1 << 8;
const PLA: u16 = 1 << 5;
const LLA: u16 = 1 << 7;

/// y(k+1) = y(k) + (1 − a)·(PV0 + K·(u(k − dead) − MV0) − y(k)), u(j) the MV
/// after scan j (MV0 before the step): a first-order lag (a = e^(−ΔT/T))
/// plus `dead` scans of dead time. With a = 15/16, K = 0.8, STEP 10: the
/// first increment is (1/16)·8 = 0.5 % at sample dead + 1, the largest.
struct Fopdt {
    a: f32,
    k: f32,
    dead: usize,
    mv0: f32,
    pv0: f32,
    y: f32,
    u: Vec<f32>,
}

impl Fopdt {
    fn new(dead: usize) -> Fopdt {
        Fopdt {
            a: 0.9375,
            k: 0.8,
            dead,
            mv0: 30.0,
            pv0: 20.0,
            y: 20.0,
            u: vec![],
        }
    }

    /// One scan: E1 := y(k), scan, record MV, advance y.
    fn scan(&mut self, p: &mut Plc) {
        setf(p, "D0", self.y);
        p.scan();
        self.u.push(tag(p, 12));
        let k = self.u.len() - 1;
        let u = if k >= self.dead {
            self.u[k - self.dead]
        } else {
            self.mv0
        };
        let ss = self.pv0 + self.k * (u - self.mv0);
        self.y += (1.0 - self.a) * (ss - self.y);
    }
}

fn at1(s: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(SRC, s);
    defaults(&mut p);
    tw(&mut p, 1, MAN);
    tf(&mut p, 12, 30.0);
    tf(&mut p, 70, 10.0);
    tf(&mut p, 56, 1.0);
    p.set("D200", "0").set("D2", "1");
    p
}

fn bb(p: &Plc) -> u16 {
    word(p, "D100")
}

fn local(p: &Plc, off: u32) -> f32 {
    getf(p, &format!("D{}", 300 + off))
}

fn localw(p: &Plc, off: u32) -> u16 {
    word(p, &format!("D{}", 300 + off))
}

/// The counter flags D3+0/+2/+4 and the step flag D3+6.
fn flags(p: &Plc) -> [u16; 4] {
    [localw(p, 0), localw(p, 2), localw(p, 4), localw(p, 6)]
}

/// Spec §7: STEP 10 %, R′ 0.5 %/s, L 4 s, PID type → Kp 1.2·10/(0.5·4) =
/// 6.0, TI 2·L = 8 s, TD 0.5·L = 2 s. Dead time 4 samples: the maximum slope
/// 0.5 is sample 5 (PV 20.5), so b = 20.5 − 0.5·5·1 = 18 and L = (20 −
/// 18)/0.5 = 4; AT1TOUT2 = 10 s after it the identification ends the tuning
/// on scan 15 and MV returns to 30.
#[test]
fn s_at1_zn_on_a_first_order_plus_dead_time_process() {
    let mut p = at1(ProcessSettings::default());
    let mut plant = Fopdt::new(4);
    for k in 0..15 {
        plant.scan(&mut p);
        assert_eq!(bb(&p), 0, "scan {k}");
        assert_eq!(tag(&p, 12), 40.0, "stepped MV, scan {k}");
    }
    assert_eq!(localw(&p, 6), 1);
    assert_eq!(
        (local(&p, 8), local(&p, 12), local(&p, 14), local(&p, 16)),
        (20.0, 0.5, 5.0, 20.5)
    );
    assert_eq!(localw(&p, 7), 14, "14 samples observed");
    plant.scan(&mut p);
    let r = 0.5f32.abs() / 100.0;
    let l = (20.0f32 - (20.5 - 0.5 * (5.0 * 1.0))) / 0.5;
    assert_eq!(l, 4.0);
    let kp = 1.2f32 / (r * l) * (10.0f32.abs() / 100.0);
    assert!((kp - 6.0).abs() < 1e-5, "{kp}");
    assert_eq!((tag(&p, 52), tag(&p, 54), tag(&p, 56)), (kp, 8.0, 2.0));
    assert_eq!(
        (local(&p, 18), local(&p, 20)),
        (r, 4.0),
        "R = |R′|/100 (DEC-33), L"
    );
    assert_eq!(bb(&p), BB16);
    assert_eq!(tag(&p, 12), 30.0, "MV restored");
    assert_eq!(flags(&p), [0, 0, 0, 0], "DEC-34");
    // (1,1) ends: nothing moves while e1 stays on.
    plant.scan(&mut p);
    assert_eq!((bb(&p), tag(&p, 12)), (BB16, 30.0));
    // e1 off: (0,1) clears BB16, then (0,0) does not restore a second time.
    p.set("D2", "0");
    plant.scan(&mut p);
    assert_eq!(bb(&p), 0);
    plant.scan(&mut p);
    assert_eq!(tag(&p, 12), 30.0);
}

/// A falling response (PN 0, STEP −10): the extreme slope is the most
/// negative, R′ = −0.5, b = 19.5 + 0.5·5 = 22, L = (20 − 22)/(−0.5) = 4.
#[test]
fn s_at1_negative_step() {
    let mut p = at1(ProcessSettings::default());
    tf(&mut p, 70, -10.0);
    let mut plant = Fopdt::new(4);
    for _ in 0..16 {
        plant.scan(&mut p);
    }
    assert_eq!(local(&p, 12), -0.5);
    assert_eq!(local(&p, 20), 4.0);
    let kp = 1.2f32 / (0.005 * 4.0) * (10.0 / 100.0);
    assert_eq!((tag(&p, 52), tag(&p, 54), tag(&p, 56)), (kp, 8.0, 2.0));
    assert_eq!((bb(&p), tag(&p, 12)), (BB16, 30.0));
}

/// The control type follows the loop's current I and D (000 §13.1 (11)): D =
/// 0 → PI (0.9, TI 3.33·L); I = 0 → P (1.0, TI = TD = 0).
#[test]
fn s_at1_pi_and_p_constants() {
    for (i, d, c, ti, td) in [
        (10.0, 0.0, 0.9f32, 3.33f32 * 4.0, 0.0),
        (0.0, 1.0, 1.0, 0.0, 0.0),
    ] {
        let mut p = at1(ProcessSettings::default());
        tf(&mut p, 54, i);
        tf(&mut p, 56, d);
        let mut plant = Fopdt::new(4);
        for _ in 0..16 {
            plant.scan(&mut p);
        }
        let kp = c / (0.005f32 * 4.0) * (10.0 / 100.0);
        assert_eq!((tag(&p, 52), tag(&p, 54), tag(&p, 56)), (kp, ti, td));
    }
}

/// Loop stop and the A-group mode alarm end the tuning and restore MV
/// (000 §13.1 (2), (3)); BB1 = BB2 ∨ … ∨ BB8 (DEC-35).
#[test]
fn s_at1_loop_stop_and_mode_alarm_restore_mv() {
    for (alm, mode, bits) in [(SPA, MAN, BB16), (0, AUT, BB1 | BB7 | BB16)] {
        let mut p = at1(ProcessSettings::default());
        let mut plant = Fopdt::new(4);
        for _ in 0..3 {
            plant.scan(&mut p);
        }
        assert_eq!(tag(&p, 12), 40.0);
        tw(&mut p, 3, alm);
        tw(&mut p, 1, mode);
        plant.scan(&mut p);
        assert_eq!(bb(&p), bits);
        assert_eq!(tag(&p, 12), 30.0);
        assert_eq!(flags(&p), [0, 0, 0, 0]);
    }
}

/// The input alarms end without restoring MV (L23259-23270); the bits stay
/// until e1 goes off: (0,1) clears BB16, (0,0) clears BB2..BB8 and restores.
#[test]
fn s_at1_input_alarms_keep_mv_until_e1_goes_off() {
    for (alm, bit) in [(PHA, BB2), (HHA, BB2), (PLA, BB3), (LLA, BB3)] {
        let mut p = at1(ProcessSettings::default());
        let mut plant = Fopdt::new(4);
        plant.scans(&mut p, 3);
        tw(&mut p, 3, alm);
        plant.scan(&mut p);
        assert_eq!(bb(&p), BB1 | bit | BB16);
        assert_eq!((tag(&p, 12), localw(&p, 6)), (40.0, 1), "MV stays stepped");
        p.set("D2", "0");
        plant.scan(&mut p);
        assert_eq!((bb(&p), tag(&p, 12)), (BB1 | bit, 40.0));
        plant.scan(&mut p);
        assert_eq!((bb(&p), tag(&p, 12), localw(&p, 6)), (0, 30.0, 0));
    }
}

impl Fopdt {
    fn scans(&mut self, p: &mut Plc, n: usize) {
        for _ in 0..n {
            self.scan(p);
        }
    }
}

/// AT1TOUT1 reached (counted from the step execution, DEC-1): BB6, MV not
/// restored (L23277-23281). A flat PV never updates the maximum.
#[test]
fn s_at1_timeout() {
    let mut p = at1(ProcessSettings::default());
    tf(&mut p, 74, 8.0);
    setf(&mut p, "D0", 20.0);
    p.scans(8);
    assert_eq!(bb(&p), 0);
    p.scan();
    assert_eq!(bb(&p), BB1 | BB6 | BB16);
    assert_eq!((tag(&p, 12), localw(&p, 6)), (40.0, 1));
}

/// The step out of range (000 §13.1 (7)): T1 > MH → BB4, T1 < ML → BB5; MV
/// unchanged, no step made.
#[test]
fn s_at1_step_out_of_range() {
    for (mv, step, bit) in [(95.0, 10.0, BB4), (5.0, -10.0, BB5)] {
        let mut p = at1(ProcessSettings::default());
        tf(&mut p, 12, mv);
        tf(&mut p, 70, step);
        setf(&mut p, "D0", 20.0);
        p.scan();
        assert_eq!(bb(&p), BB1 | bit | BB16);
        assert_eq!((tag(&p, 12), localw(&p, 6)), (mv, 0));
    }
}

/// Identification failures (000 §13.1 (10)): no dead time puts the maximum
/// slope at sample 1, b = 20.5 − 0.5 = PV0, L = 0 ≤ 0 → BB8, MV restored;
/// a maximum slope of 0 (forced into D3+12) gives R = 0 → BB8.
#[test]
fn s_at1_identification_failures() {
    let mut p = at1(ProcessSettings::default());
    let mut plant = Fopdt::new(0);
    plant.scans(&mut p, 11);
    assert_eq!(bb(&p), 0);
    plant.scan(&mut p);
    assert_eq!(bb(&p), BB1 | BB8 | BB16);
    assert_eq!((local(&p, 20), tag(&p, 12), localw(&p, 6)), (0.0, 30.0, 0));
    assert_eq!(tag(&p, 52), 1.0, "P untouched");
    let mut p = at1(ProcessSettings::default());
    let mut plant = Fopdt::new(4);
    plant.scans(&mut p, 15);
    setf(&mut p, "D312", 0.0);
    plant.scan(&mut p);
    assert_eq!(bb(&p), BB1 | BB8 | BB16);
    assert_eq!((local(&p, 18), tag(&p, 12)), (0.0, 30.0));
}

/// The alternatives of DEC-32 (sampling starts at the first sampling
/// judgment: every sample one ΔT late, so L = 3), DEC-33 (D3+18 holds R′)
/// and DEC-34 (no flag clearing: the (0,0) branch restores a second time).
#[test]
fn s_at1_decision_alternatives() {
    let s = |f: fn(&mut ProcessSettings)| {
        let mut s = ProcessSettings::default();
        f(&mut s);
        s
    };
    let mut p = at1(s(|s| s.at1_step_starts_sampling = false));
    let mut plant = Fopdt::new(4);
    plant.scans(&mut p, 20);
    assert_eq!((local(&p, 14), local(&p, 20)), (4.0, 3.0));
    let mut p = at1(s(|s| s.at1_stores_r = false));
    let mut plant = Fopdt::new(4);
    plant.scans(&mut p, 16);
    assert_eq!(local(&p, 18), 0.5);
    let mut p = at1(s(|s| s.at1_restore_clears_flags = false));
    let mut plant = Fopdt::new(4);
    plant.scans(&mut p, 16);
    assert_eq!((tag(&p, 12), localw(&p, 6)), (30.0, 1));
    p.set("D2", "0");
    plant.scans(&mut p, 2);
    assert_eq!(tag(&p, 12), 20.0);
    // DEC-35 has no described alternative: rejected at load.
    let dialect =
        softplc_core::program::dialect_for(common::process_cpu(), s(|s| s.at1_bb1_or = false));
    let e = softplc_core::program::compile_il_in(
        "t.il",
        SRC,
        &softplc_core::profile::default_config().devices,
        &dialect,
    )
    .unwrap_err();
    assert!(e.0[0].message.contains("at1_bb1_or"));
}

/// Table 14.2 for S.AT1: 1 input check (here the (0,0) restore), 2 timeout,
/// 3 post-max-slope timeout, 4 step MV, 5 sampling, 6 observation, 7
/// identification, 8 PID constants.
#[test]
fn s_at1_error_codes() {
    let run = |setup: &dyn Fn(&mut Plc), before: usize, after: &dyn Fn(&mut Plc)| {
        let mut p = at1(ProcessSettings::default());
        setup(&mut p);
        let mut plant = Fopdt::new(4);
        for _ in 0..before {
            plant.scan(&mut p);
            if p.error().is_some() {
                return (p.int("SD1502"), p.int("SD1503"));
            }
        }
        setf(&mut p, "D0", 20.0);
        after(&mut p);
        lp::error_after(&mut p, 20)
    };
    let none = |_: &mut Plc| {};
    let nan_mv = |p: &mut Plc| tw(p, 13, 0x7fc0);
    assert_eq!(
        run(&none, 2, &|p| {
            nan_mv(p);
            p.set("D2", "0");
        }),
        (1, 1)
    );
    assert_eq!(run(&|p| tw(p, 75, 0x7fc0), 1, &none), (1, 2));
    assert_eq!(run(&|p| tf(p, 74, 40000.0), 1, &none), (4, 2));
    assert_eq!(run(&|p| tf(p, 76, 40000.0), 8, &none), (4, 3));
    assert_eq!(run(&nan_mv, 1, &none), (1, 4));
    assert_eq!(run(&|p| tf(p, 72, 1e5), 1, &none), (4, 5));
    assert_eq!(
        run(&none, 1, &|p| {
            p.set("D1", "32704");
        }),
        (1, 6)
    );
    assert_eq!(run(&none, 15, &|p| tf(p, 72, 0.0)), (5, 7));
    assert_eq!(run(&none, 15, &|p| tw(p, 55, 0x7fc0)), (1, 8));
}
