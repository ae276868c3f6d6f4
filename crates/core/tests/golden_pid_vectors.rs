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
//! This file: the worked vectors of the notes (§5.8) and further hand-computed
//! vectors (filter, derivative, action, clamps, manual/auto, PIDSTOP/PIDRUN/PIDPRMW).

mod common;
use common::pid::{
    get, plc, plc_src, run_pv, set, write_loop, Fam, Loop, ALARM, BASE, MODE, MV, MVMAN, PV, PVF,
    SV,
};
use common::{assert_running, assert_stopped};

// ------------------------------------------------------------ notes §5.8 vectors

/// §5.8 A: PIDCONT, reverse, TI 10.0 s, SV 600, PV 500 constant. EV = 100,
/// Ts/TI = 100/(10·100) = 0.1. Sample 1 (EVn−1 = 0): ΔMV = 100 + 10 = 110;
/// then ΔMV = (100 − 100) + 10 = 10 per sample.
#[test]
fn vector_a_pi_reverse() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(
            run_pv(&mut p, fam, &[500; 5]),
            [110, 120, 130, 140, 150],
            "{fam:?}"
        );
    }
}

/// §5.8 B: PIDCONT, reverse, TI ∞, TD 1.00 s, SV 600, PV 500, 510, 530.
/// D = (td/ts)·(−PVf + 2·PVf1 − PVf2): 0; −(510 − 1000 + 500) = −10;
/// −(530 − 1020 + 500) = −10. EV 100, 90, 70: ΔMV = 100; (90−100) − 10 = −20;
/// (70−90) − 10 = −30. MV 100, 80, 50.
#[test]
fn vector_b_complete_derivative() {
    let l = Loop { td: 100, ..BASE };
    let mut p = plc(Fam::C, 1, &[l], 600, 1000);
    assert_eq!(run_pv(&mut p, Fam::C, &[500, 510, 530]), [100, 80, 50]);
}

/// §5.8 C: α = 50 %, PV 0 then 1000: PVf = 0; 1000 + 0.5·(0 − 1000) = 500;
/// 750; 875; 937.5 → 938 (half away from zero); 968.75 → 969.
#[test]
fn vector_c_filter() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { alpha: 50, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        let mut pvf = vec![];
        for pv in [0, 1000, 1000, 1000, 1000, 1000] {
            set(&mut p, fam, 0, PV, pv);
            p.scan();
            pvf.push(get(&p, fam, 0, PVF));
        }
        assert_eq!(pvf, [0, 500, 750, 875, 938, 969], "{fam:?}");
    }
}

/// §5.8 D: S.PIDCONT, reverse, TI ∞, TD 1.00 s, KD 8.00 (kd 800): c1 =
/// 100·800/(100·800 + 100·100) = 0.8889, c2 = 10000/90000 = 0.1111.
/// SV 600, PV 500, 500, 600, 600: D = 0, 0, 0.8889·(−100) = −88.889,
/// 0.8889·(+100) + 0.1111·(−88.889) = 79.012. ΔMV = 100, 0, −100 − 88.889,
/// +79.012. MV = 100, 100, 0 (clamped at MVLL; anti-windup), 79.012 → 79.
/// The same data with PIDCONT: D = 0, 0, −100, +100 → MV 100, 100, 0, 100.
#[test]
fn vector_d_incomplete_derivative_and_lower_clamp() {
    let l = Loop {
        td: 100,
        kd: 800,
        ..BASE
    };
    let mut p = plc(Fam::S, 1, &[l], 600, 1000);
    assert_eq!(
        run_pv(&mut p, Fam::S, &[500, 500, 600, 600]),
        [100, 100, 0, 79]
    );
    let mut p = plc(Fam::C, 1, &[l], 600, 1000);
    assert_eq!(
        run_pv(&mut p, Fam::C, &[500, 500, 600, 600]),
        [100, 100, 0, 100]
    );
}

/// §5.8 E: as A, MV word 1950 before the first processing, PV 500, 500, 700,
/// 700: ΔMV 110, 10, (−100 − 100) − 10 = −210, 0 − 10 = −10. MV 2060 → 2000,
/// 2010 → 2000, 1790, 1780 (1800/1790 without the anti-windup clamp).
#[test]
fn vector_e_upper_clamp_anti_windup() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        set(&mut p, fam, 0, MV, 1950);
        assert_eq!(
            run_pv(&mut p, fam, &[500, 500, 700, 700]),
            [2000, 2000, 1790, 1780],
            "{fam:?}"
        );
    }
}

/// §5.8 Alarm: ΔPVL = 10, PV 500 → 520 (change 20 > 10) sets ALARM b0; it
/// stays after PV settles until the user writes 0. A change of exactly ΔPVL
/// does not set it ("exceeds").
#[test]
fn vector_alarm_pv_latched() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { dpvl: 10, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        run_pv(&mut p, fam, &[500, 510]);
        assert_eq!(get(&p, fam, 0, ALARM), 0, "a change of exactly 10");
        run_pv(&mut p, fam, &[530]);
        assert_eq!(get(&p, fam, 0, ALARM), 1);
        run_pv(&mut p, fam, &[530, 530]);
        assert_eq!(get(&p, fam, 0, ALARM), 1, "latched");
        set(&mut p, fam, 0, ALARM, 0);
        run_pv(&mut p, fam, &[530]);
        assert_eq!(get(&p, fam, 0, ALARM), 0, "cleared by the user");
    }
}

/// ΔMVL = 50: the first ΔMV of §5.8 A is 110 > 50 → ALARM b1. After the user
/// clears it, ΔMV = 10 ≤ 50 leaves it 0. MV itself is never rate-limited.
#[test]
fn mv_change_alarm_latched() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop {
            ti: 100,
            dmvl: 50,
            ..BASE
        };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500]), [110], "not limited");
        assert_eq!(get(&p, fam, 0, ALARM), 2);
        run_pv(&mut p, fam, &[500]);
        assert_eq!(get(&p, fam, 0, ALARM), 2, "latched");
        set(&mut p, fam, 0, ALARM, 0);
        run_pv(&mut p, fam, &[500]);
        assert_eq!(get(&p, fam, 0, ALARM), 0);
    }
}

// ------------------------------------------------------------ own vectors

/// Filter α = 30 %: PV 0 then 100: PVf 0; 100 + 0.3·(0 − 100) = 70;
/// 100 − 0.3·30 = 91; 97.3 → 97; 99.19 → 99; 99.757 → 100.
/// α = 100 % freezes PVf at the seeded first PV (legal, notes §2.2).
#[test]
fn filter_alpha_30_and_100() {
    let l = Loop { alpha: 30, ..BASE };
    let mut p = plc(Fam::S, 1, &[l], 600, 1000);
    let mut pvf = vec![];
    for pv in [0, 100, 100, 100, 100, 100] {
        set(&mut p, Fam::S, 0, PV, pv);
        p.scan();
        pvf.push(get(&p, Fam::S, 0, PVF));
    }
    assert_eq!(pvf, [0, 70, 91, 97, 99, 100]);

    let l = Loop { alpha: 100, ..BASE };
    let mut p = plc(Fam::C, 1, &[l], 600, 1000);
    for pv in [300, 1000, 1500] {
        set(&mut p, Fam::C, 0, PV, pv);
        p.scan();
        assert_eq!(get(&p, Fam::C, 0, PVF), 300);
    }
}

/// Incomplete derivative with KD = 1.00 (kd 100), forward action, TI ∞,
/// TD 2.00 s (td 200), SV 500, MV word 1000 before the first processing.
/// den = ts·kd + 100·td = 10000 + 20000 = 30000; c1 = td·kd/den = 2/3,
/// c2 = 100·td/den = 2/3. PV 500, 510, 520, 520:
/// * s1: EV 0, D 0 → MV 1000.
/// * s2: dd = 510 − 1000 + 500 = 10, D = 6.667; ΔMV = 10 + 6.667 → 1016.667 → 1017.
/// * s3: dd = 520 − 1020 + 500 = 0, D = (2/3)·6.667 = 4.444; ΔMV = 10 + 4.444 → 1031.111 → 1031.
/// * s4: dd = 520 − 1040 + 510 = −10, D = −6.667 + 2.963 = −3.704 → 1027.407 → 1027.
///
/// Complete derivative (PIDCONT), D = (td/ts)·dd = 2·dd: ΔMV 0, 30, 10, −20 →
/// 1000, 1030, 1040, 1020. S. family with KD = ∞ (kd 30001) equals the
/// complete form; KD = 0 gives D = 0: 1000, 1010, 1020, 1020.
#[test]
fn incomplete_derivative_kd() {
    let run = |fam: Fam, kd: i16| {
        let l = Loop {
            select: 0,
            td: 200,
            kd,
            ..BASE
        };
        let mut p = plc(fam, 1, &[l], 500, 1000);
        set(&mut p, fam, 0, MV, 1000);
        run_pv(&mut p, fam, &[500, 510, 520, 520])
    };
    assert_eq!(run(Fam::S, 100), [1000, 1017, 1031, 1027]);
    assert_eq!(run(Fam::C, 0), [1000, 1030, 1040, 1020]);
    assert_eq!(run(Fam::S, 30001), [1000, 1030, 1040, 1020]);
    assert_eq!(run(Fam::S, 0), [1000, 1010, 1020, 1020]);
}

/// Forward and reverse action (001 §4.2.2), PI with TI 10 s, SV 600, MV word
/// 1000 before the first processing. PV 700: forward EV = +100 → MV 1110, 1120;
/// reverse EV = −100 → 890, 880. PV 500: forward 890, 880; reverse 1110, 1120.
#[test]
fn forward_and_reverse_action() {
    for fam in [Fam::C, Fam::S] {
        for (select, pv, want) in [
            (0, 700, [1110, 1120]),
            (1, 700, [890, 880]),
            (0, 500, [890, 880]),
            (1, 500, [1110, 1120]),
        ] {
            let l = Loop {
                select,
                ti: 100,
                ..BASE
            };
            let mut p = plc(fam, 1, &[l], 600, 1000);
            set(&mut p, fam, 0, MV, 1000);
            assert_eq!(
                run_pv(&mut p, fam, &[pv, pv]),
                want,
                "{fam:?} {select} {pv}"
            );
        }
    }
}

/// MV limits MVLL 100 / MVHL 300, P only, reverse, SV 600:
/// PV 0: EV 600 → ΔMV 600 → 300 (upper); PV 1000: EV −400, ΔMV −1000 →
/// −700 → 100 (lower); PV 550: EV 50, ΔMV 450 → 550 → 300; PV 600: ΔMV −50 → 250
/// (from the clamped 300: anti-windup at both limits).
#[test]
fn clamp_at_both_limits() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop {
            mvll: 100,
            mvhl: 300,
            ..BASE
        };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(
            run_pv(&mut p, fam, &[0, 1000, 550, 600]),
            [300, 100, 300, 250]
        );
    }
}

/// Manual ↔ auto, bumpless (001 §4.3.1) with SM774 OFF (PV → SV, 001 §4.3.4).
/// Reverse, TI 10 s, SV 600, PV 500: s1 110, s2 120.
/// * s3 manual, PV 550: auto→manual copies MV (120) into MV_MAN; the manual
///   sample writes PV into SV (550); MV held at 120.
/// * s4 the user writes MV_MAN 800: nothing moves (MV 120, SV 550).
/// * s5 auto: MV_MAN → MV (800) and MV state; EV = 550 − 550 = 0, EVn−1 =
///   550 − 550 = 0 → ΔMV 0 → MV 800 (no bump).
/// * s6 the user restores SV 600: EV 50, ΔMV = 50 + 5 → 855.
#[test]
fn manual_auto_bumpless_with_tracking() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        set(&mut p, fam, 0, MODE, 0);
        assert_eq!(run_pv(&mut p, fam, &[550]), [120]);
        assert_eq!(get(&p, fam, 0, MVMAN), 120);
        assert_eq!(get(&p, fam, 0, SV), 550);
        set(&mut p, fam, 0, MVMAN, 800);
        assert_eq!(run_pv(&mut p, fam, &[550]), [120]);
        assert_eq!(get(&p, fam, 0, SV), 550);
        set(&mut p, fam, 0, MODE, 1);
        assert_eq!(run_pv(&mut p, fam, &[550]), [800]);
        set(&mut p, fam, 0, SV, 600);
        assert_eq!(run_pv(&mut p, fam, &[550]), [855]);
    }
}

/// SM794/SM774 ON: no PV → SV copy in manual. Same sequence as above: SV stays
/// 600; at s5 MV ← 800, EV = 50 and EVn−1 = 600 − 550 = 50 (manual history) →
/// ΔMV = 0 + 5 → 805.
#[test]
fn manual_auto_without_tracking() {
    for (fam, sm) in [(Fam::C, "SM774"), (Fam::S, "SM794")] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        p.set(sm, "1");
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        set(&mut p, fam, 0, MODE, 0);
        assert_eq!(run_pv(&mut p, fam, &[550]), [120]);
        assert_eq!(get(&p, fam, 0, SV), 600);
        set(&mut p, fam, 0, MVMAN, 800);
        set(&mut p, fam, 0, MODE, 1);
        assert_eq!(run_pv(&mut p, fam, &[550]), [805]);
    }
}

/// The transfer happens at the execution where the new mode is seen, the PV →
/// SV copy only at sampling instants (notes §1.3, §1.4). 10 ms scans, Ts 1 s:
/// samples at scans 1, 101, 201. Manual at scan 50: MV_MAN = 110 after scan
/// 50, SV still 600 until the sample at scan 101 writes PV (500) into it.
/// Limited range: MV_MAN 3000 is converted to 2050 when copied to MV.
#[test]
fn transfer_at_execution_tracking_at_sample() {
    let fam = Fam::C;
    let l = Loop { ti: 100, ..BASE };
    let mut p = plc(fam, 1, &[l], 600, 10);
    set(&mut p, fam, 0, PV, 500);
    p.scans(49);
    assert_eq!(get(&p, fam, 0, MV), 110);
    set(&mut p, fam, 0, MODE, 0);
    p.scan();
    assert_eq!(get(&p, fam, 0, MVMAN), 110);
    assert_eq!(get(&p, fam, 0, SV), 600);
    p.scans(50);
    assert_eq!(get(&p, fam, 0, SV), 600, "scan 100");
    p.scan();
    assert_eq!(get(&p, fam, 0, SV), 500, "sample at scan 101");
    set(&mut p, fam, 0, MVMAN, 3000);
    set(&mut p, fam, 0, MODE, 1);
    p.scan();
    assert_eq!(get(&p, fam, 0, MV), 2050);
    assert_running(&p);
}

/// PIDSTOP / PIDRUN (001 §8.1.3, §9.1.4). 1 s scans, §5.8 A data.
/// s1 110, s2 120; X1 → PIDSTOPP K1 after PIDCONT in s3 (MV 130). s4, s5:
/// stopped, MV held although PV moves to 400. PIDINIT again (X3) does not
/// restart it. X2 → PIDRUNP in s6 (after PIDCONT, which still sees it
/// stopped). s7: accumulator 0 + 1 s ≥ Ts → sample with the held history:
/// EV 200, EVn−1 100 → ΔMV = 100 + 20 → 250. PIDRUN on a running loop: no-op.
#[test]
fn pidstop_pidrun() {
    for fam in [Fam::C, Fam::S] {
        let pre = fam.prefix();
        let pulse = |m: &str| match fam {
            Fam::S => format!("SP.{m}"),
            Fam::C => format!("{m}P"),
        };
        let src = format!(
            "LD SM400\n{init} D500\nLD X3\n{init} D500\nLD SM400\n{pre}PIDCONT D600\n\
             LD X1\n{stop} K1\nLD X2\n{run} K1\nEND\n",
            init = pulse("PIDINIT"),
            stop = pulse("PIDSTOP"),
            run = pulse("PIDRUN"),
        );
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc_src(&src, fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        p.set("X1", "1");
        assert_eq!(run_pv(&mut p, fam, &[500]), [130]);
        p.set("X3", "1");
        assert_eq!(run_pv(&mut p, fam, &[400, 400]), [130, 130]);
        p.set("X2", "1");
        assert_eq!(run_pv(&mut p, fam, &[400]), [130]);
        assert_eq!(run_pv(&mut p, fam, &[400]), [250], "{fam:?}");
        // RUN again (rising edge) on a running loop changes nothing.
        p.set("X2", "0").scan();
        p.set("X2", "1");
        assert_eq!(run_pv(&mut p, fam, &[400]), [290]);
    }
}

/// PIDPRMW (001 §8.1.4, §9.1.5): loop 1 gets Kp 2.00 at the end of s3; s4:
/// ΔMV = 2·(0 + 10) = 20 → 150. For S.PIDPRMW a reserved word ≠ 0 is 4100 and
/// the loop keeps its data.
#[test]
fn pidprmw_changes_one_loop() {
    for fam in [Fam::C, Fam::S] {
        let pre = fam.prefix();
        let (init, prmw) = match fam {
            Fam::S => ("SP.PIDINIT", "SP.PIDPRMW"),
            Fam::C => ("PIDINITP", "PIDPRMWP"),
        };
        let src = format!("LD SM400\n{init} D500\n{pre}PIDCONT D600\nLD X1\n{prmw} K1 D700\nEND\n");
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc_src(&src, fam, 1, &[l], 600, 1000);
        write_loop(&mut p, fam, 700, &Loop { kp: 200, ..l });
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        p.set("X1", "1");
        assert_eq!(run_pv(&mut p, fam, &[500]), [130]);
        p.set("X1", "0");
        assert_eq!(run_pv(&mut p, fam, &[500]), [150], "{fam:?}");
        if fam == Fam::S {
            // Reserved word +10 ≠ 0: 4100, Kp stays 2.00 (ΔMV 20 → 170).
            p.set("D710", "1").set("D702", "300").set("X1", "1").scan();
            assert_stopped(&p, 4100);
        }
    }
}

/// A non-pulse PIDINIT every scan re-registers D500 each time (001 §5 要点:
/// harmless), so a PIDPRMW change lasts only until the next PIDINIT.
#[test]
fn pidinit_every_scan_overrides_pidprmw() {
    let src = "LD SM400\nPIDINIT D500\nPIDCONT D600\nLD X1\nPIDPRMWP K1 D700\nEND\n";
    let l = Loop { ti: 100, ..BASE };
    let mut p = plc_src(src, Fam::C, 1, &[l], 600, 1000);
    write_loop(&mut p, Fam::C, 700, &Loop { kp: 200, ..l });
    assert_eq!(run_pv(&mut p, Fam::C, &[500, 500]), [110, 120]);
    p.set("X1", "1");
    // s3: PIDINIT (Kp 1) then PIDCONT (130) then PIDPRMW (Kp 2); s4: PIDINIT
    // restores Kp 1 before PIDCONT: ΔMV 10 → 140.
    assert_eq!(run_pv(&mut p, Fam::C, &[500, 500]), [130, 140]);
}
