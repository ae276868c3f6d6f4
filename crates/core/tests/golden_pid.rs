//! Golden tests of the PID control instructions (seed 001; notes
//! `shared/spec/pid-instructions.md`). Every expected value is worked out by
//! hand in the comment next to it from the formulas of 001 §3.1.2/§3.2.2 under
//! the notes' §2.6 [DECISION] policy (f64, MV clamped before stored, round half
//! away from zero for the shown words, first processing seeded with EVn−1 = 0).
//!
//! Unless a test says otherwise: PID control data at D500, I/O data at D600,
//! scans of 1 s with Ts = 1 s (ts = 100), so every scan is one sample; the
//! first scan is the first processing (it uses the configured Ts).

mod common;
use common::{assert_running, assert_stopped, Plc};
use softplc_core::device::DeviceKind;
use softplc_core::engine::{CpuConfig, CpuState, ErrorCode, ErrorMode};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Fam {
    /// S.PIDINIT / S.PIDCONT (incomplete derivative, 001 ch. 8).
    S,
    /// PIDINIT / PIDCONT (complete derivative, 001 ch. 9).
    C,
}

impl Fam {
    fn params(self) -> u32 {
        match self {
            Fam::S => 14,
            Fam::C => 10,
        }
    }
    fn io(self) -> u32 {
        match self {
            Fam::S => 23,
            Fam::C => 18,
        }
    }
    fn prefix(self) -> &'static str {
        match self {
            Fam::S => "S.",
            Fam::C => "",
        }
    }
    /// SP.PIDINIT D500 once, S.PIDCONT D600 every scan (or the plain forms).
    fn program(self) -> String {
        match self {
            Fam::S => "LD SM400\nSP.PIDINIT D500\nS.PIDCONT D600\nEND\n".into(),
            Fam::C => "LD SM400\nPIDINITP D500\nPIDCONT D600\nEND\n".into(),
        }
    }
}

/// One loop's PID control data (001 §5.1(3)).
#[derive(Clone, Copy, Debug)]
struct Loop {
    select: i16,
    ts: i16,
    kp: i16,
    ti: i16,
    td: i16,
    alpha: i16,
    mvll: i16,
    mvhl: i16,
    dmvl: i16,
    dpvl: i16,
    kd: i16,
}

/// §5.8 common settings: reverse, Ts 1 s, Kp 1.00, TI ∞, TD 0, α 0, MV 0..2000,
/// rate limits 2000 (no alarm).
const BASE: Loop = Loop {
    select: 1,
    ts: 100,
    kp: 100,
    ti: 32767,
    td: 0,
    alpha: 0,
    mvll: 0,
    mvhl: 2000,
    dmvl: 2000,
    dpvl: 2000,
    kd: 0,
};

fn dev(n: u32) -> String {
    format!("D{n}")
}

/// Writes the control data at `base`: n = loops.len(), k, then each loop.
fn write_data(p: &mut Plc, fam: Fam, base: u32, k: i16, loops: &[Loop]) {
    p.set(&dev(base), &loops.len().to_string());
    p.set(&dev(base + 1), &k.to_string());
    for (i, l) in loops.iter().enumerate() {
        write_loop(p, fam, base + 2 + fam.params() * i as u32, l);
    }
}

/// Writes one loop's words at `at` (the PIDPRMW layout).
fn write_loop(p: &mut Plc, fam: Fam, at: u32, l: &Loop) {
    let mut w = vec![
        l.select, l.ts, l.kp, l.ti, l.td, l.alpha, l.mvll, l.mvhl, l.dmvl, l.dpvl,
    ];
    if fam == Fam::S {
        w.extend([0, l.kd, 0, 0]);
    }
    for (j, v) in w.iter().enumerate() {
        p.set(&dev(at + j as u32), &v.to_string());
    }
}

/// I/O word of loop `i` (0-based): 0 SV, 1 PV, 2 MV, 3 PVf, 4 MVMAN, 5 MAN/AUTO, 6 ALARM.
fn io(fam: Fam, i: u32, off: u32) -> String {
    dev(600 + 10 + fam.io() * i + off)
}

const SV: u32 = 0;
const PV: u32 = 1;
const MV: u32 = 2;
const PVF: u32 = 3;
const MVMAN: u32 = 4;
const MODE: u32 = 5;
const ALARM: u32 = 6;

/// A CPU with the family's program, `loops` registered at D500, every loop in
/// auto with SV `sv`, and `scan_ms` scans.
fn plc(fam: Fam, k: i16, loops: &[Loop], sv: i16, scan_ms: u64) -> Plc {
    plc_src(&fam.program(), fam, k, loops, sv, scan_ms)
}

fn plc_src(src: &str, fam: Fam, k: i16, loops: &[Loop], sv: i16, scan_ms: u64) -> Plc {
    let mut p = Plc::new(src);
    p.scan_time_us(scan_ms * 1000);
    write_data(&mut p, fam, 500, k, loops);
    for i in 0..loops.len() as u32 {
        p.set(&io(fam, i, SV), &sv.to_string());
        p.set(&io(fam, i, MODE), "1");
    }
    p
}

fn set(p: &mut Plc, fam: Fam, i: u32, off: u32, v: i64) {
    p.set(&io(fam, i, off), &v.to_string());
}

fn get(p: &Plc, fam: Fam, i: u32, off: u32) -> i64 {
    p.int(&io(fam, i, off))
}

/// Runs one scan per PV value and collects the MV word of loop 1 after each.
fn run_pv(p: &mut Plc, fam: Fam, pvs: &[i64]) -> Vec<i64> {
    pvs.iter()
        .map(|&pv| {
            set(p, fam, 0, PV, pv);
            p.scan();
            assert_running(p);
            get(p, fam, 0, MV)
        })
        .collect()
}

fn continue_on_error() -> CpuConfig {
    CpuConfig {
        operation_error: ErrorMode::Continue,
        ..CpuConfig::default()
    }
}

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

// ------------------------------------------------------------ state in the work words

/// Clearing a loop's I/O data (MV and the work words) restarts it: the next
/// execution is a first processing (001 §5.2(4)(b) 4)).
#[test]
fn clearing_the_area_restarts_the_loop() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        for off in MV..fam.io() {
            if off != MODE {
                set(&mut p, fam, 0, off, 0);
            }
        }
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120], "{fam:?}");
    }
}

/// The running state is only in the devices: a new CPU (power cycle) with the
/// I/O area copied (latched) continues the loop after PIDINIT, instead of a
/// first processing (which would give 110).
#[test]
fn latched_area_survives_power_cycle() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        let mut q = plc(fam, 1, &[l], 600, 1000);
        for w in 600..600 + 10 + fam.io() {
            let v = p.int(&dev(w));
            q.set(&dev(w), &v.to_string());
        }
        // Scan 1 after power-on: scan time 0 → not due; scan 2: 1 s → sample.
        assert_eq!(run_pv(&mut q, fam, &[500, 500]), [120, 130], "{fam:?}");
    }
}

/// Both families in one program are independent: the S. family's registration
/// does not satisfy PIDCONT (4103), and each uses its own data.
#[test]
fn families_are_independent() {
    let src = "LD SM400\nSP.PIDINIT D500\nS.PIDCONT D600\nPIDCONT D700\nEND\n";
    let mut p = Plc::new(src);
    write_data(&mut p, Fam::S, 500, 1, &[BASE]);
    p.scan();
    assert_stopped(&p, 4103);

    let src = "LD SM400\nSP.PIDINIT D500\nPIDINITP D550\nS.PIDCONT D600\nPIDCONT D700\nEND\n";
    let mut p = Plc::new(src);
    p.scan_time_us(1_000_000);
    write_data(&mut p, Fam::S, 500, 1, &[Loop { ti: 100, ..BASE }]);
    write_data(&mut p, Fam::C, 550, 1, &[Loop { kp: 200, ..BASE }]);
    for (sv, pv, mode) in [(610, 611, 615), (710, 711, 715)] {
        p.set(&dev(sv), "600")
            .set(&dev(pv), "500")
            .set(&dev(mode), "1");
    }
    p.scans(2);
    assert_running(&p);
    // S.: PI, 110 then 120. Plain: P only with Kp 2: 200 then 200.
    assert_eq!((p.int("D612"), p.int("D712")), (120, 200));
}

/// Pulse forms run once per rising edge; time is only counted on executions
/// (notes §4: allowed, not useful). SP.PIDCONT on X0: the first processing at
/// the first edge (MV 110); the second edge adds one scan (1 s) → sample.
#[test]
fn pulse_forms() {
    for (fam, src) in [
        (
            Fam::S,
            "LD SM400\nSP.PIDINIT D500\nLD X0\nSP.PIDCONT D600\nEND\n",
        ),
        (
            Fam::C,
            "LD SM400\nPIDINITP D500\nLD X0\nPIDCONTP D600\nEND\n",
        ),
    ] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc_src(src, fam, 1, &[l], 600, 1000);
        set(&mut p, fam, 0, PV, 500);
        p.set("X0", "1").scans(3);
        assert_eq!(get(&p, fam, 0, MV), 110);
        p.set("X0", "0").scans(2);
        p.set("X0", "1").scans(2);
        assert_eq!(get(&p, fam, 0, MV), 120);
        assert_running(&p);
    }
}

// ------------------------------------------------------------ errors (001 §8.1, §9.1; notes §6)

/// 4103: PIDCONT (and S.PIDCONT) before any PIDINIT of the family.
#[test]
fn error_4103_pidcont_before_pidinit() {
    for src in [
        "LD SM400\nPIDCONT D600\nPIDINIT D500\nEND\n",
        "LD SM400\nS.PIDCONT D600\nEND\n",
    ] {
        let mut p = Plc::new(src);
        write_data(&mut p, Fam::C, 500, 1, &[BASE]);
        p.scan();
        assert_stopped(&p, 4103);
    }
}

/// 4103: PIDSTOP/PIDRUN before PIDINIT and PIDCONT have both executed;
/// PIDPRMW (both families, [DECISION] notes §4) before PIDINIT.
#[test]
fn error_4103_order_of_stop_run_prmw() {
    for (fam, body) in [
        (Fam::C, "PIDINIT D500\nPIDSTOP K1\nPIDCONT D600"),
        (Fam::C, "PIDINIT D500\nPIDRUN K1\nPIDCONT D600"),
        (Fam::S, "S.PIDINIT D500\nS.PIDSTOP K1\nS.PIDCONT D600"),
        (Fam::S, "S.PIDINIT D500\nS.PIDRUN K1\nS.PIDCONT D600"),
        (Fam::C, "PIDPRMW K1 D500\nPIDINIT D500\nPIDCONT D600"),
        (Fam::S, "S.PIDPRMW K1 D502\nS.PIDINIT D500\nS.PIDCONT D600"),
    ] {
        let mut p = Plc::new(&format!("LD SM400\n{body}\nEND\n"));
        write_data(&mut p, fam, 500, 1, &[BASE]);
        p.scan();
        assert_stopped(&p, 4103);
    }
    // In the right order, none of them fails.
    let mut p = Plc::new(
        "LD SM400\nPIDINIT D500\nPIDCONT D600\nPIDSTOP K1\nPIDRUN K1\nPIDPRMW K1 D502\nEND\n",
    );
    write_data(&mut p, Fam::C, 500, 1, &[BASE]);
    p.scans(2);
    assert_running(&p);
}

/// 4100 at PIDINIT for the common data: n < k, n = 0, n = 33 (no loop runs:
/// PIDCONT then reports 4100 too, and writes nothing).
#[test]
fn error_4100_common_data() {
    for (n, k) in [(1, 2), (0, 0), (33, 1), (2, 0)] {
        let mut p = plc_src(&Fam::C.program(), Fam::C, 1, &[BASE, BASE], 600, 1000);
        p.set("D500", &n.to_string()).set("D501", &k.to_string());
        p.scan();
        assert_stopped(&p, 4100);
        let mut p = Plc::with_config(
            "LD SM400\nPIDINITP D500\nLD SM400\nPIDCONT D600\nEND\n",
            continue_on_error(),
        );
        write_data(&mut p, Fam::C, 500, 1, &[BASE, BASE]);
        p.set("D500", &n.to_string()).set("D501", &k.to_string());
        set(&mut p, Fam::C, 0, PV, 500);
        set(&mut p, Fam::C, 0, MODE, 1);
        p.scans(2);
        assert_eq!(p.state(), CpuState::Run);
        assert_eq!(p.error(), Some(ErrorCode(4100)));
        assert_eq!(get(&p, Fam::C, 0, MV), 0, "no loop runs ({n}, {k})");
    }
}

/// 4100 for one loop's data (out of range, MVHL < MVLL, S. reserved words,
/// S. KD < 0): that loop is skipped, the other loop runs (operation error
/// "continue"); PIDCONT reports 4100 again on every execution.
#[test]
fn error_4100_one_loop_skipped() {
    #[allow(clippy::type_complexity)]
    let bad_loops: [(Fam, Loop, Option<(u32, i16)>); 9] = [
        (Fam::C, Loop { ts: 0, ..BASE }, None),
        (Fam::C, Loop { kp: 10001, ..BASE }, None),
        (Fam::C, Loop { ti: 0, ..BASE }, None),
        (Fam::C, Loop { td: 30001, ..BASE }, None),
        (Fam::C, Loop { alpha: 101, ..BASE }, None),
        (Fam::C, Loop { select: 2, ..BASE }, None),
        (
            Fam::S,
            Loop {
                mvll: 10,
                mvhl: 9,
                ..BASE
            },
            None,
        ),
        (Fam::S, Loop { kd: -1, ..BASE }, None),
        // Reserved word +12 of loop 1 (D514).
        (Fam::S, BASE, Some((514, 7))),
    ];
    for (fam, bad, poke) in bad_loops {
        let mut p = Plc::with_config(&fam.program(), continue_on_error());
        p.scan_time_us(1_000_000);
        write_data(&mut p, fam, 500, 2, &[bad, BASE]);
        if let Some((d, v)) = poke {
            p.set(&dev(d), &v.to_string());
        }
        for i in 0..2 {
            set(&mut p, fam, i, SV, 600);
            set(&mut p, fam, i, PV, 500);
            set(&mut p, fam, i, MODE, 1);
        }
        p.scan();
        assert_eq!(p.error(), Some(ErrorCode(4100)), "{fam:?} {bad:?}");
        assert_eq!(p.state(), CpuState::Run);
        assert_eq!(get(&p, fam, 0, MV), 0, "loop 1 skipped");
        assert_eq!(get(&p, fam, 1, MV), 100, "loop 2 runs");
        p.set("SD0", "0").set("SM0", "0").scan();
        assert_eq!(p.int("SD0"), 4100, "reported again by PIDCONT");
        // With the default "stop" setting the CPU stops at PIDINIT.
        let mut p = plc(fam, 2, &[bad, BASE], 600, 1000);
        if let Some((d, v)) = poke {
            p.set(&dev(d), &v.to_string());
        }
        p.scan();
        assert_stopped(&p, 4100);
    }
}

/// 4100: MAN/AUTO ∉ {0, 1} skips that loop, the other one runs.
#[test]
fn error_4100_man_auto_word() {
    let fam = Fam::S;
    let mut p = Plc::with_config(&fam.program(), continue_on_error());
    p.scan_time_us(1_000_000);
    write_data(&mut p, fam, 500, 2, &[BASE, BASE]);
    for i in 0..2 {
        set(&mut p, fam, i, SV, 600);
        set(&mut p, fam, i, PV, 500);
        set(&mut p, fam, i, MODE, 1);
    }
    set(&mut p, fam, 0, MODE, 2);
    p.scan();
    assert_eq!(p.error(), Some(ErrorCode(4100)));
    assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (0, 100));
    let mut p = plc(fam, 1, &[BASE], 600, 1000);
    set(&mut p, fam, 0, MODE, -1);
    p.scan();
    assert_stopped(&p, 4100);
}

/// 4100: PIDSTOP/PIDRUN/PIDPRMW loop number 0, 33, or above the loops used;
/// PIDPRMW data out of range.
#[test]
fn error_4100_loop_numbers_and_prmw_data() {
    for (body, code) in [
        ("PIDSTOP K0", 4100),
        ("PIDSTOP K2", 4100),
        ("PIDRUN K33", 4100),
        ("PIDRUN D0", 4100),
        ("PIDPRMW K2 D502", 4100),
        ("PIDPRMW K-1 D502", 4100),
        ("PIDPRMW K1 D900", 4100),
        ("PIDSTOP K1", 0),
    ] {
        let mut p = Plc::new(&format!(
            "LD SM400\nPIDINIT D500\nPIDCONT D600\n{body}\nEND\n"
        ));
        write_data(&mut p, Fam::C, 500, 1, &[BASE]);
        p.scan();
        if code == 0 {
            assert_running(&p);
        } else {
            assert_stopped(&p, code);
        }
    }
}

/// 4101: an area past the last D (D0-D12287): S.PIDINIT at D12280 with n = 1
/// needs 16 words; PIDCONT at D12270 with n = 1 needs 28; PIDPRMW at D12280
/// needs 10; S.PIDPRMW at D12275 needs 14.
#[test]
fn error_4101_areas_past_the_device_end() {
    let mut p = Plc::new("LD SM400\nS.PIDINIT D12280\nEND\n");
    p.set("D12280", "1").set("D12281", "1");
    p.scan();
    assert_stopped(&p, 4101);

    let mut p = Plc::new("LD SM400\nPIDINIT D500\nPIDCONT D12270\nEND\n");
    write_data(&mut p, Fam::C, 500, 1, &[BASE]);
    p.scan();
    assert_stopped(&p, 4101);

    for src in [
        "LD SM400\nPIDINIT D500\nPIDPRMW K1 D12280\nEND\n",
        "LD SM400\nS.PIDINIT D500\nS.PIDPRMW K1 D12275\nEND\n",
    ] {
        let mut p = Plc::new(src);
        write_data(&mut p, Fam::C, 500, 1, &[BASE]);
        write_data(&mut p, Fam::S, 500, 1, &[BASE]);
        p.scan();
        assert_stopped(&p, 4101);
    }
    // Index modification counts: D12200Z0 with Z0 = 80 → D12280.
    let mut p = Plc::new("LD SM400\nPIDINIT D12200Z0\nEND\n");
    p.set("Z0", "80").set("D12280", "1").set("D12281", "1");
    p.scan();
    assert_stopped(&p, 4101);
}

// ------------------------------------------------------------ load-time checks

#[test]
fn pid57_rejected_at_load() {
    for src in [
        "LD X2\nPID57 H0C K1 D0\nEND\n",
        "LD X2\nPID57P H0C K1 D0\nEND\n",
    ] {
        let d = common::diagnostics(src);
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(d[0].contains("needs an AD57"), "{d:?}");
        assert!(d[0].starts_with("2:"), "{d:?}");
    }
}

#[test]
fn operand_checks_at_load() {
    for (src, what) in [
        ("LD SM400\nPIDINIT K100\nEND\n", "word device"),
        ("LD SM400\nS.PIDCONT M0\nEND\n", "word device"),
        ("LD SM400\nPIDCONT D0 D1\nEND\n", "operand"),
        ("LD SM400\nS.PIDPRMW K1\nEND\n", "operand"),
        ("LD SM400\nPIDPRMW K1 K2\nEND\n", "word device"),
        ("LD SM400\nS.PIDINITP D0\nEND\n", "SP.PIDINIT"),
        ("LD SM400\nS.PIDSTOPP K1\nEND\n", "SP.PIDSTOP"),
    ] {
        let d = common::diagnostics(src);
        assert!(d.iter().any(|m| m.contains(what)), "{src}: {d:?}");
    }
    // Accepted operand kinds: word devices (D, W, R, ZR, index-modified) and,
    // for the loop number, K/H constants, words and digit-specified bits.
    let src = "LD SM400\nPIDINIT W100\nPIDINITP R0\nSP.PIDINIT ZR10\nS.PIDINIT D0Z1\n\
               PIDCONT D600\nPIDCONTP W200\nS.PIDCONT R100\nSP.PIDCONT ZR1000\n\
               PIDSTOP K1\nPIDSTOPP H1\nPIDRUN D0\nPIDRUNP K1M0\n\
               S.PIDSTOP K1\nSP.PIDSTOP D1\nS.PIDRUN K4X0\nSP.PIDRUN H2\n\
               PIDPRMW K1 D100\nPIDPRMWP D0 R0\nS.PIDPRMW K1 W0\nSP.PIDPRMW D2 ZR0\nEND\n";
    let prog = softplc_core::program::compile_il("t.il", src, &CpuConfig::default().devices);
    assert!(prog.is_ok(), "{:?}", prog.err().map(|d| d.to_string()));
}

// ------------------------------------------------------------ STOP → RUN

/// STOP→RUN clears the registration (the program's hidden state) but not the
/// I/O data: SP.PIDINIT runs again on the first scan after RUN and the loop
/// continues from its work words (no first processing, which would give 110).
#[test]
fn stop_run_keeps_the_loop_state() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        p.cpu.set_stop();
        p.scans(3);
        p.cpu.set_run().unwrap();
        // The first scan after RUN adds the scan time the engine measured last
        // (0 or 1 s, an engine detail), so it is 120 (not due) or 130; a first
        // processing would give 110.
        let mv = run_pv(&mut p, fam, &[500, 500, 500]);
        assert!(mv[0] == 120 || mv[0] == 130, "{fam:?} {mv:?}");
        assert_eq!([mv[1] - mv[0], mv[2] - mv[1]], [10, 10], "{fam:?} {mv:?}");
    }
}

// ------------------------------------------------------------ chapter 8/9 examples

/// Runs a shipped example (examples/pid/) with 100 ms scans and X0 ON.
fn example(src: &str) -> Plc {
    let mut p = Plc::new(src);
    p.scan_time_us(100_000);
    p.set("X0", "1");
    p
}

/// Asserts |PV − SV| ≤ 2 counts (0.1 % of the 0..2000 range).
fn assert_settled(p: &Plc, sv: &str, pv: &str) {
    let (s, v) = (p.int(sv), p.int(pv));
    assert!((s - v).abs() <= 2, "{pv} = {v}, {sv} = {s}");
}

/// 001 §8.2.2 and §9.2.2: 2 loops in auto, SV 600 / 1000; the simulated
/// plants settle within ±2 counts in 120 s (1200 scans of 100 ms).
#[test]
fn examples_auto_two_loops_settle() {
    for (src, loop2) in [
        (
            include_str!("../../../examples/pid/ex822_spid_auto.il"),
            633,
        ),
        (include_str!("../../../examples/pid/ex922_pid_auto.il"), 628),
    ] {
        let mut p = example(src);
        p.scans(1200);
        assert_running(&p);
        assert_eq!((p.int("D610"), p.int(&dev(loop2))), (600, 1000));
        assert_settled(&p, "D610", "D611");
        assert_settled(&p, &dev(loop2), &dev(loop2 + 1));
        // Loop 1's plant gain is 0.8: MV ≈ 600 / 0.8 = 750.
        assert!((p.int("D612") - 750).abs() <= 3, "MV {}", p.int("D612"));
        // X1 stops PID control: the D/A output goes to 0.
        p.set("X1", "1").scan();
        assert_eq!(p.int("D820"), 0);
    }
}

/// 001 §8.2.3 and §9.2.3: auto/manual switching with SM794/SM774 OFF and the
/// 10-step SV restore. Auto for 60 s (PV → 600); manual from scan 601 with the
/// manual MV switch at 900 (BCD): SV tracks PV (→ 720 = 0.8·900); back to auto
/// at scan 1201: MV continues from 900 (bumpless), the SV walks 720 → 600 in
/// 10 steps of (720 − 600)/10 = 12, and PV settles at 600 again.
#[test]
fn examples_manual_auto_switching() {
    for src in [
        include_str!("../../../examples/pid/ex823_spid_manual_auto.il"),
        include_str!("../../../examples/pid/ex923_pid_manual_auto.il"),
    ] {
        let mut p = example(src);
        p.set("K4X20", "H900");
        p.scans(600);
        assert_settled(&p, "D610", "D611");
        p.set("X6", "1").scans(4);
        // Auto → manual copied MV into MV_MAN; then the switch X4 loads 900.
        assert!((p.int("D614") - 750).abs() <= 3);
        p.set("X4", "1").scan();
        p.set("X4", "0").scans(595);
        assert_eq!(p.int("D614"), 900);
        assert_eq!(p.int("D611"), 720);
        assert_eq!(p.int("D610"), 720, "SV tracks PV in manual");
        p.set("X6", "0").scan();
        assert_eq!(p.int("D612"), 900, "bumpless: MV starts from MV_MAN");
        let mut svs = vec![p.int("D610")];
        for _ in 0..150 {
            p.scan();
            if p.int("D610") != *svs.last().unwrap() {
                svs.push(p.int("D610"));
            }
        }
        assert_eq!(
            svs,
            [720, 708, 696, 684, 672, 660, 648, 636, 624, 612, 600],
            "10 steps"
        );
        p.scans(700);
        assert_running(&p);
        assert_settled(&p, "D610", "D611");
    }
}

// ------------------------------------------------------------ no allocation

/// Counts heap allocations made by the current thread while `COUNTING` is set.
mod alloc_count {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    thread_local! {
        pub static COUNTING: Cell<bool> = const { Cell::new(false) };
        pub static COUNT: Cell<usize> = const { Cell::new(0) };
    }

    pub struct Counting;

    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, l: Layout) -> *mut u8 {
            let _ = COUNTING.try_with(|c| {
                if c.get() {
                    COUNT.with(|n| n.set(n.get() + 1));
                }
            });
            unsafe { System.alloc(l) }
        }
        unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
            unsafe { System.dealloc(p, l) }
        }
    }
}

#[global_allocator]
static ALLOC: alloc_count::Counting = alloc_count::Counting;

/// PIDINIT, PIDCONT (32 loops, every loop computed each scan, manual/auto
/// transfers), PIDSTOP, PIDRUN and PIDPRMW execute without allocating.
#[test]
fn exec_does_not_allocate() {
    // The counter works: one Vec allocation is seen.
    alloc_count::COUNT.with(|n| n.set(0));
    alloc_count::COUNTING.with(|c| c.set(true));
    drop(std::hint::black_box(Vec::<u8>::with_capacity(8)));
    alloc_count::COUNTING.with(|c| c.set(false));
    assert_eq!(alloc_count::COUNT.with(|n| n.get()), 1);
    for fam in [Fam::C, Fam::S] {
        let pre = fam.prefix();
        let src = format!(
            "LD SM400\n{pre}PIDINIT D2000\n{pre}PIDCONT D600\n{pre}PIDSTOP K3\n\
             {pre}PIDRUN K3\n{pre}PIDPRMW K2 D2002\nEND\n"
        );
        let mut p = Plc::new(&src);
        p.scan_time_us(10_000);
        let l = Loop {
            ts: 1,
            ti: 100,
            td: 100,
            kd: 800,
            alpha: 20,
            ..BASE
        };
        write_data(&mut p, fam, 2000, 32, &[l; 32]);
        for i in 0..32 {
            set(&mut p, fam, i, SV, 600);
            set(&mut p, fam, i, PV, 500 + i as i64);
            set(&mut p, fam, i, MODE, 1);
        }
        p.scans(3);
        assert_running(&p);
        alloc_count::COUNT.with(|n| n.set(0));
        alloc_count::COUNTING.with(|c| c.set(true));
        for s in 0..20 {
            // Mode changes in place (no allocation in the harness either).
            let mode = p.cpu.memory().get_word(DeviceKind::D, 615).unwrap();
            if s % 5 == 0 {
                p.cpu
                    .memory_mut()
                    .set_word(DeviceKind::D, 615, mode ^ 1)
                    .unwrap();
            }
            p.scan();
        }
        alloc_count::COUNTING.with(|c| c.set(false));
        assert_running(&p);
        assert_eq!(alloc_count::COUNT.with(|n| n.get()), 0, "{fam:?}");
    }
}

/// PIDINIT in an initial program registers the loops that PIDCONT uses in a
/// scan program of another file: the registration is CPU-wide (001 §8.1.1
/// "registered in the CPU module").
#[test]
fn pidinit_and_pidcont_in_different_program_files() {
    use softplc_core::engine::{Cpu, CpuConfig, ExecType, LoadedProgram, VirtualClock};
    use softplc_core::program::compile_il;
    let cfg = CpuConfig::default();
    let init = "LD SM400\nS.PIDINIT D100\nEND\n";
    let main = "LD SM400\nS.PIDCONT D300\nEND\n";
    let progs = [
        ("init.il", init, ExecType::Initial),
        ("main.il", main, ExecType::Scan),
    ]
    .iter()
    .map(|(n, s, e)| LoadedProgram {
        program: compile_il(n, s, &cfg.devices).unwrap(),
        exec: *e,
        interval: None,
        sim_time: None,
    })
    .collect();
    let clock = VirtualClock::new();
    let mut cpu = Cpu::with_programs(progs, cfg, Box::new(clock.clone())).unwrap();
    // Control data: 1 loop, 1 per scan, reverse action (heating: EV = SV − PV), Ts 1 (10 ms), KP 100 (1.00),
    // TI 10 (1 s), TD 0, α 0, MVLL 0, MVHL 2000, ΔMV/ΔPV alarm limits 0 (off).
    let spec = |d: &str| softplc_core::access::DeviceSpec::parse(d).unwrap();
    for (d, v) in [
        ("D100", 1),
        ("D101", 1),
        ("D102", 1),
        ("D103", 1),
        ("D104", 100),
        ("D105", 10),
        ("D108", 0),
        ("D109", 2000),
    ] {
        cpu.write_device(&spec(d), &v.to_string()).unwrap();
    }
    // I/O data: SV 1000, PV 0, auto.
    for (d, v) in [("D310", 1000), ("D311", 0), ("D315", 1)] {
        cpu.write_device(&spec(d), &v.to_string()).unwrap();
    }
    for _ in 0..20 {
        clock.advance_us(10_000);
        cpu.scan();
    }
    // Without the registration PIDCONT would stop the CPU with 4103.
    assert!(cpu.error().is_none(), "{:?}", cpu.error());
    assert_eq!(cpu.state(), softplc_core::engine::CpuState::Run);
    // The loop runs: MV (m+2) has moved up from 0 towards SV − PV.
    match cpu.read_device(&spec("D312")).unwrap() {
        softplc_core::access::Value::Int(mv) => assert!(mv > 0, "MV {mv}"),
        v => panic!("{v:?}"),
    }
}
