//! Process-control I/O instructions of 000 ch. 8 that count executions or
//! pulses: S.DUTY (§8.5), S.BC (§8.6), S.PSUM (§8.7). Values worked out by
//! hand from the manual's formulas (spec/process-control.md §4.5-§4.7, §7).

mod common;
use common::process::{assert_pc_error, f, loop_tag};
use common::Plc;
use softplc_core::program::ProcessSettings;

const DUTY: &str = "LD SM400\nS.DUTY D0 D100 SD1506 D1000\nEND\n";

fn duty(settings: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(DUTY, settings);
    loop_tag(&mut p, 1000);
    p.set("D1068:f32", "10");
    p
}

/// Runs `n` executions and returns BW1 as a 0/1 string.
fn duty_run(p: &mut Plc, n: usize) -> String {
    (0..n)
        .map(|_| {
            p.scan();
            if p.int("D100") & 1 != 0 {
                '1'
            } else {
                '0'
            }
        })
        .collect()
}

/// Spec §7.4 (DEC-1, DEC-12): MV 70 %, CTDUTY = 10, ΔT = 1 → executions
/// 0-9 OFF (the ON counter is 0 after clearing), then 7 ON / 3 OFF per
/// period; MV 50 % from the next reach on gives 5/5.
#[test]
fn s_duty_time_proportional_output() {
    let mut p = duty(ProcessSettings::default());
    p.set("D0:f32", "70").scan();
    assert_eq!((p.real("D1012"), p.int("D100") & 1), (70.0, 0));
    p.set("D0:f32", "0");
    assert_eq!(duty_run(&mut p, 29), "00000000011111110001111111000");
    assert_eq!(p.int("D1121"), 7, "ON counter");
    // MV changes take effect at the next period: set at execution 30.
    p.set("D0:f32", "-20");
    p.scan();
    p.set("D0:f32", "0");
    assert_eq!(duty_run(&mut p, 19), "1111000001111100000");
    // Other bits of D100 are left alone; BB is D101.
    p.set("D100", "H10").scan();
    assert_eq!(p.int("D100") & 0x10, 0x10);
}

/// DEC-1 alternative: the start execution is also a reach, so the first
/// period already carries the duty.
#[test]
fn s_duty_start_execution_switch() {
    let mut p = duty(ProcessSettings {
        counter_start_is_time_zero: false,
        ..ProcessSettings::default()
    });
    p.set("D0:f32", "70");
    let first = duty_run(&mut p, 1);
    p.set("D0:f32", "0");
    assert_eq!(first + &duty_run(&mut p, 19), "11111110001111111000");
}

/// Manual mode: TRKF := 1, the operator's MV 30 % sets the next period's
/// ON count (3); loop stop and the SM1501 hold freeze the output and the
/// counters (DEC-4); the DEC-4 alternative advances them.
#[test]
fn s_duty_manual_mode_loop_stop_and_hold() {
    let mut p = duty(ProcessSettings::default());
    p.set("D1001", "H8").set("D1012:f32", "30");
    assert_eq!(duty_run(&mut p, 20), "00000000001110000000");
    assert_eq!(p.int("D1004"), 0x4000);
    p.scan(); // execution 20: reach, ON
    let (c, o) = (p.int("D1119"), p.int("D1120"));
    p.set("D1003", "H4000");
    assert_eq!(duty_run(&mut p, 5), "11111");
    assert_eq!((p.int("D1119"), p.int("D1120")), (c, o));
    assert_eq!((p.int("D1001"), p.int("D101")), (8, 0));
    p.set("D1003", "H200")
        .set("D1001", "H10")
        .set("SM1501", "1");
    assert_eq!(duty_run(&mut p, 3), "111");
    assert_eq!((p.int("D1119"), p.int("D1120")), (c, o));
    let mut p = duty(ProcessSettings {
        early_end_skips_counters: false,
        ..ProcessSettings::default()
    });
    p.set("D1003", "H4000");
    duty_run(&mut p, 3);
    assert_eq!((p.int("D1118"), p.int("D1119"), p.int("D1120")), (1, 8, 3));
}

/// S.DUTY shares S.OUT1's limiter: MH = 60 limits MV and sets ALM2.
#[test]
fn s_duty_limits_like_s_out1() {
    let mut p = duty(ProcessSettings::default());
    p.set("D1018:f32", "60").set("D0:f32", "70").scan();
    assert_eq!(
        (
            p.real("D1012"),
            p.int("D101"),
            p.int("D1003"),
            p.int("D1116")
        ),
        (60.0, 0b011, 2, 2)
    );
    assert_eq!(p.real("D1062"), f(70.0 - 1.0 / 10.0 * (70.0 - 60.0)));
}

/// ON-time conversion errors at processing 4: CTDUTY/ΔT > 32767 is 4, ΔT
/// = 0 is 5, CTDUTY < 0 is 2; a NaN ΔMV is 1 at 1; DEC-12 has no
/// described alternative.
#[test]
fn s_duty_errors() {
    for (ct, dt, detail) in [("40000", "1", 4), ("10", "0", 5), ("-1", "1", 2)] {
        let mut p = duty(ProcessSettings::default());
        p.set("D1068:f32", ct).set("SD1500:f32", dt).scan();
        assert_pc_error(&p, detail, 4);
    }
    let mut p = duty(ProcessSettings::default());
    p.set("D0", "-1").set("D1", "-1").scan();
    assert_pc_error(&p, 1, 1);
    let d = common::process_diagnostics_with(
        DUTY,
        ProcessSettings {
            duty_on_count_rounds: false,
            ..ProcessSettings::default()
        },
    );
    assert!(d[0].contains("duty_on_count_rounds"), "{d:?}");
}

const BC: &str = "LD SM400\nS.BC D0 D100 SD1506 D1000\nEND\n";

fn bc(settings: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(BC, settings);
    loop_tag(&mut p, 1000);
    p.set("D1014:i32", "100")
        .set("D1016:i32", "200")
        .set("D1026:i32", "250");
    p.set("D1042:f32", "0").set("D1044:i32", "10");
    p
}

/// 000 §8.6: BW1 = E1 ≥ SV1, BW2 = E1 ≥ SV2, both 0 for E1 < 0; E1 > PH →
/// PHA = BB2 = 1 (PHI/ERRI inhibit).
#[test]
fn s_bc_batch_outputs_and_high_alarm() {
    let mut p = bc(ProcessSettings::default());
    for (e1, bw, bb, almw) in [
        ("50", 0, 0, 0),
        ("100", 1, 0, 0),
        ("199", 1, 0, 0),
        ("200", 3, 0, 0),
        ("250", 3, 0, 0),
        ("251", 3, 0b011, 0x40),
        ("-1", 0, 0, 0),
    ] {
        p.set("D0:i32", e1).scan();
        assert_eq!(
            (p.int("D100"), p.int("D101"), p.int("D1003")),
            (bw, bb, almw),
            "E1 = {e1}"
        );
    }
    p.set("D0:i32", "300").set("D1004", "H40").scan();
    assert_eq!((p.int("D101"), p.int("D1003")), (0, 0));
    p.set("D1004", "H8000").scan();
    assert_eq!((p.int("D101"), p.int("D1003")), (0, 0));
    assert_eq!(p.error(), None);
}

/// DEC-18: CTIM = 4, ΔT = 1 → m = 4; the start execution takes Xn-m,
/// every 4th execution evaluates Xn − Xn-m ≥ DPL (10) and re-takes it; the
/// alarm holds in between. The alternative evaluates on every execution.
#[test]
fn s_bc_change_rate_window() {
    let run = |p: &mut Plc, xs: &[i32]| -> String {
        xs.iter()
            .map(|x| {
                p.set("D0:i32", &x.to_string()).scan();
                if p.int("D101") & 0b100 != 0 {
                    assert_eq!(p.int("D1003") & 0x10, 0x10);
                    assert_eq!(p.int("D101") & 1, 1);
                    '1'
                } else {
                    '0'
                }
            })
            .collect()
    };
    let xs = [0, 5, 11, 11, 12, 13, 14, 15, 15, 30, 30, 30, 20];
    let mut p = bc(ProcessSettings::default());
    p.set("D1042:f32", "4");
    assert_eq!(run(&mut p, &xs), "0000111100000");
    assert_eq!(p.int("D1126:i32"), 20, "re-taken at execution 12");
    let mut p = bc(ProcessSettings {
        change_rate_window: false,
        ..ProcessSettings::default()
    });
    p.set("D1042:f32", "4");
    assert_eq!(run(&mut p, &xs), "0011100001110");
    // m = int(0.5/1) = 0: nothing is done, the counter is not started.
    let mut p = bc(ProcessSettings::default());
    p.set("D1042:f32", "0.5")
        .set("D101", "4")
        .set("D1003", "H10");
    assert_eq!(run(&mut p, &[0, 50]), "11");
    assert_eq!((p.int("D1124"), p.int("D1125")), (0, 0));
}

/// Processing 2 errors: ΔT = 0 is 5, m > 32767 is 4, CTIM < 0 is 2, a NaN
/// CTIM is 1; the high check before it has run.
#[test]
fn s_bc_errors() {
    for (ctim, dt, detail) in [("4", "0", 5), ("40000", "1", 4), ("-4", "1", 2)] {
        let mut p = bc(ProcessSettings::default());
        p.set("D1042:f32", ctim)
            .set("SD1500:f32", dt)
            .set("D0:i32", "300")
            .scan();
        assert_pc_error(&p, detail, 2);
        assert_eq!(p.int("D1003"), 0x40);
    }
    let mut p = bc(ProcessSettings::default());
    p.set("D1042", "-1").set("D1043", "-1").scan();
    assert_pc_error(&p, 1, 2);
}

const PSUM: &str = "LD SM400\nS.PSUM D0 D100 D10 D1000\nEND\n";

fn psum(settings: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(PSUM, settings);
    p.set("D10", "1")
        .set("D11", "1")
        .set("D12:i32", "2147483647")
        .set("D14", "0");
    p.set("D2", "1");
    p
}

/// 000 §8.7: the increment E1 − E1n-1 (a 16-bit counter going from 65530
/// to 5 gives 11, DEC-13), weighted T1·W/U with the remainder carried in
/// SUM2; e2 holds, e1 = 0 resets.
#[test]
fn s_psum_integrates_pulses() {
    let mut p = psum(ProcessSettings::default());
    p.set("D0:u32", "100").scan();
    assert_eq!(
        (p.int("D100:i32"), p.int("D102:i32"), p.int("D1010:i32")),
        (100, 0, 100)
    );
    assert_eq!(p.int("D1116:u32"), 100);
    p.set("D1116:u32", "65530").set("D0:u32", "5").scan();
    assert_eq!(p.int("D100:i32"), 111);
    // 24-bit counter: 0xFFFFF0 → 0x000004 is 20.
    p.set("D1116:u32", "16777200").set("D0:u32", "4").scan();
    assert_eq!(p.int("D100:i32"), 131);
    // No width fits (43400 > 32767 even modulo 2^16): 0.
    p.set("D1116:u32", "H12345678").set("D0:u32", "0").scan();
    assert_eq!(p.int("D100:i32"), 131);
    // W = 3, U = 10, SUM2 = 9: T1 = 7 → 21 = 2·10 + 1; 9 + 1 = 10 → carry.
    p.set("D10", "3")
        .set("D11", "10")
        .set("D1012:i32", "9")
        .set("D0:u32", "7")
        .scan();
    assert_eq!((p.int("D100:i32"), p.int("D102:i32")), (134, 0));
    assert_eq!((p.int("D1010:i32"), p.int("D1012:i32")), (134, 0));
    p.set("D0:u32", "11").scan();
    assert_eq!((p.int("D100:i32"), p.int("D102:i32")), (135, 2));
    // e2 = 1 holds (E1n-1 still follows E1).
    p.set("D2", "3").set("D0:u32", "50").scan();
    assert_eq!(
        (p.int("D100:i32"), p.int("D102:i32"), p.int("D1116:u32")),
        (135, 2, 50)
    );
    // e1 = 0 resets.
    p.set("D2", "2").set("D0:u32", "60").scan();
    assert_eq!(
        (p.int("D100:i32"), p.int("D102:i32"), p.int("D1010:i32")),
        (0, 0, 0)
    );
}

/// HILMT = 1000: SUMPTN 0 wraps (995 + 10 → 5), SUMPTN 1 holds at HILMT
/// with SUM2 = 0. DEC-13's alternative takes the 32-bit difference as
/// signed.
#[test]
fn s_psum_high_limit_and_dec_13() {
    let mut p = psum(ProcessSettings::default());
    p.set("D12:i32", "1000")
        .set("D1010:i32", "995")
        .set("D0:u32", "10")
        .scan();
    assert_eq!((p.int("D100:i32"), p.int("D1010:i32")), (5, 5));
    p.set("D14", "1")
        .set("D1010:i32", "995")
        .set("D1012:i32", "0")
        .set("D0:u32", "20")
        .scan();
    assert_eq!(
        (p.int("D100:i32"), p.int("D102:i32"), p.int("D1010:i32")),
        (1000, 0, 1000)
    );
    let mut p = psum(ProcessSettings {
        psum_wraparound: false,
        ..ProcessSettings::default()
    });
    p.set("D1010:i32", "100")
        .set("D1116:u32", "65530")
        .set("D0:u32", "5")
        .scan();
    assert_eq!(p.int("D100:i32"), 100 + 5 - 65530);
}

/// Processing 2: U = 0 is 5, U = 7 or W = 0 is 3; processing 3: SUMPTN 2
/// or HILMT 0 is 3. The increment step has stored E1n-1.
#[test]
fn s_psum_errors() {
    for (dev, v, detail, step) in [
        ("D11", "0", 5, 2),
        ("D11", "7", 3, 2),
        ("D10", "0", 3, 2),
        ("D14", "2", 3, 3),
        ("D12:i32", "0", 3, 3),
    ] {
        let mut p = psum(ProcessSettings::default());
        p.set(dev, v).set("D0:u32", "9").scan();
        assert_pc_error(&p, detail, step);
        assert_eq!(p.int("D1116:u32"), 9);
    }
}
