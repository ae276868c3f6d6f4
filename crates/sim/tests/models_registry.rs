//! Golden tests of the plant models against closed-form solutions, the
//! constructor registry, scaling, a no-NaN property test and a throughput check.
//!
//! Tolerances: 1e-9 relative error at every sample point for the closed-form
//! step responses (FOPDT with and without dead time, integrator, second order
//! for ζ = 0.2, 1, 2, heater, tank draining and filling). Where the reference
//! value is exactly 0 (before a dead time, an empty tank) the model must give
//! exactly 0. Where a reference passes through 0 (the rate of an under-damped
//! response) the error is relative to the response's scale.
//!
//! This file: scaling, the constructor registry, the no-NaN property tests and
//! the throughput check.

use std::time::Instant;

use proptest::prelude::*;
use softplc_sim::model::scaling::*;
use softplc_sim::model::*;

mod common;
use common::{assert_rel, fopdt, run1, table};

// ---------------------------------------------------------------- scaling

#[test]
fn scaling_to_raw() {
    assert_eq!(to_raw(5.0, V_0_10, RAW_0_4000), 2000);
    assert_eq!(to_raw(12.0, MA_4_20, RAW_0_4000), 2000);
    assert_eq!(to_raw(0.0, V_PM_10, RAW_PM_16000), 0);
    assert_eq!(to_raw(-10.0, V_PM_10, RAW_PM_16000), -16000);
    assert_eq!(to_raw(2.5, (0.0, 100.0), RAW_0_2000), 50);
    // Rounding half away from zero: 0.5 raw → 1, −0.5 raw → −1, 1.5 → 2.
    assert_eq!(to_raw(0.5, (0.0, 4000.0), RAW_0_4000), 1);
    assert_eq!(to_raw(1.5, (0.0, 4000.0), RAW_0_4000), 2);
    assert_eq!(to_raw(2.5, (0.0, 4000.0), RAW_0_4000), 3);
    assert_eq!(to_raw(-0.5, (-16000.0, 16000.0), RAW_PM_16000), -1);
    assert_eq!(to_raw(0.49, (0.0, 4000.0), RAW_0_4000), 0);
    // Clamping.
    assert_eq!(to_raw(11.0, V_0_10, RAW_0_4000), 4000);
    assert_eq!(to_raw(-1.0, V_0_10, RAW_0_4000), 0);
    assert_eq!(to_raw(1e300, V_PM_10, RAW_PM_16000), 16000);
    assert_eq!(to_raw(f64::NEG_INFINITY, V_PM_10, RAW_PM_16000), -16000);
    assert_eq!(to_raw(f64::NAN, V_0_10, RAW_0_12000), 0);
    // Reverse-acting.
    assert_eq!(to_raw(25.0, (100.0, 0.0), RAW_0_4000), 3000);
    assert_eq!(to_raw(150.0, (100.0, 0.0), RAW_0_4000), 0);
    // Degenerate range.
    assert_eq!(to_raw(3.0, (1.0, 1.0), RAW_0_4000), 0);
}

#[test]
fn scaling_from_raw_and_round_trips() {
    assert_eq!(from_raw(2000, RAW_0_4000, V_0_10), 5.0);
    assert_eq!(from_raw(0, RAW_0_4000, MA_4_20), 4.0);
    assert_eq!(from_raw(4000, RAW_0_4000, MA_4_20), 20.0);
    assert_eq!(from_raw(-16000, RAW_PM_16000, V_PM_10), -10.0);
    assert_eq!(from_raw(6000, RAW_0_12000, (0.0, 150.0)), 75.0);
    // Not clamped / clamped.
    assert_eq!(from_raw(4400, RAW_0_4000, V_0_10), 11.0);
    assert_eq!(from_raw_clamped(4400, RAW_0_4000, V_0_10), 10.0);
    assert_eq!(from_raw_clamped(-5, RAW_0_4000, V_0_10), 0.0);
    for (raw_range, eng) in [
        (RAW_0_2000, (0.0, 100.0)),
        (RAW_PM_2000, (-1.0, 1.0)),
        (RAW_0_4000, MA_4_20),
        (RAW_PM_4000, V_PM_10),
        (RAW_0_12000, V_1_5),
        (RAW_PM_12000, (-5.0, 5.0)),
        (RAW_0_16000, V_0_10),
        (RAW_PM_16000, (-250.0, 750.0)),
        (RAW_0_32000, MA_0_20),
        (RAW_PM_32000, V_0_5),
        (RAW_0_4000, (300.0, -50.0)),
    ] {
        let lsb = (eng.1 - eng.0).abs() / f64::from(raw_range.1 - raw_range.0);
        for raw in raw_range.0..=raw_range.1 {
            let e = from_raw(raw, raw_range, eng);
            assert_eq!(to_raw(e, eng, raw_range), raw, "{raw_range:?} {eng:?}");
            // Half an LSB either side still converts to the same raw value.
            let back = to_raw(e + 0.49 * lsb, eng, raw_range);
            assert_eq!(back, raw.clamp(raw_range.0, raw_range.1));
        }
        // Engineering → raw → engineering stays within half an LSB.
        for i in 0..=1000 {
            let x = eng.0 + (eng.1 - eng.0) * f64::from(i) / 1000.0;
            let y = from_raw(to_raw(x, eng, raw_range), raw_range, eng);
            assert!((x - y).abs() <= 0.5 * lsb * (1.0 + 1e-9), "{x} → {y}");
        }
    }
}

// ---------------------------------------------------------------- registry

#[test]
fn registry_builds_every_kind() {
    assert_eq!(
        kinds(),
        [
            "fopdt",
            "integrator",
            "second_order",
            "tank",
            "heater",
            "valve",
            "motor",
            "noise",
            "fmu"
        ]
    );
    // The parameters of each built-in kind (an `fmu` needs a file: fmu.rs).
    let params = [
        "gain = 2\ntau = \"30s\"\ndead_time = \"500ms\"\ninitial = 1.5",
        "gain = 0.5\nleak = 0.01\nmin = 0\nmax = 100",
        "gain = 1\nomega = 2.0\nzeta = 0.7",
        "area = 1\nheight = 3\ncv = 0.05\ninitial = 1",
        "capacity = 1e4\npower = 1500\nresistance = 0.1\nambient = 25",
        "travel_time = \"12s\"",
        "accel_time = \"3s\"\ndecel_time = 2\nfeedback_delay = \"200ms\"",
        "seed = 123\nmean = 10\nstddev = 0.1",
    ];
    for (kind, p) in kinds().iter().zip(params) {
        let mut m = build(kind, &table(p)).unwrap_or_else(|e| panic!("{kind}: {e}"));
        let ins = vec![1.0; m.inputs().len()];
        let mut outs = vec![f64::NAN; m.outputs().len()];
        m.outputs_now(&mut outs);
        assert!(outs.iter().all(|x| x.is_finite()), "{kind}: {outs:?}");
        m.step(0.01, &ins, &mut outs);
        assert!(outs.iter().all(|x| x.is_finite()), "{kind}: {outs:?}");
    }
    // The FOPDT table above: y stays at 1.5 through the dead time.
    let mut m = build("fopdt", &table(params[0])).unwrap();
    let ys = run1(m.as_mut(), 0.1, 5, |_| 100.0);
    assert_eq!(ys, [1.5; 5]);
}

#[test]
fn registry_matches_direct_construction() {
    let mut a = build("fopdt", &table("gain = 2\ntau = \"1min\"\ndead_time = 3")).unwrap();
    let mut b = fopdt(2.0, 60.0, 3.0, 0.0);
    let ya = run1(a.as_mut(), 0.1, 500, |i| (i % 37) as f64);
    let yb = run1(&mut b, 0.1, 500, |i| (i % 37) as f64);
    assert_eq!(ya, yb);
}

#[test]
fn registry_errors() {
    let err = |kind: &str, src: &str| build(kind, &table(src)).err().expect("an error");
    assert!(err("pump", "").contains("unknown model type `pump`"));
    assert!(err("fopdt", "tua = 3").contains("unknown parameter `tua`"));
    assert!(err("fopdt", "tau = -1").contains("tau"));
    assert!(err("fopdt", "tau = \"3 parsecs\"").contains("invalid duration"));
    assert!(err("fopdt", "gain = \"big\"").contains("expected a number"));
    assert!(err("second_order", "omega = 1\nperiod = 2").contains("either"));
    assert!(err("second_order", "omega = 0").contains("omega"));
    assert!(err("second_order", "zeta = -0.1").contains("zeta"));
    assert!(err("tank", "area = 1\nheight = 1").contains("`cv`"));
    assert!(err("tank", "area = 0\nheight = 1\ncv = 1").contains("area"));
    assert!(err("heater", "capacity = 1\npower = 1").contains("resistance"));
    assert!(err("integrator", "min = 2\nmax = 1").contains("min"));
    assert!(err("motor", "threshold = 0").contains("threshold"));
    assert!(err("noise", "distribution = \"poisson\"").contains("poisson"));
    assert!(err("noise", "distribution = \"uniform\"\nstddev = 1").contains("amplitude"));
    assert!(err("noise", "stddev = -1").contains("stddev"));
    assert!(err("valve", "travel_time = true").contains("duration"));
}

#[test]
fn non_positive_dt_only_reports() {
    let mut m = fopdt(1.0, 1.0, 0.0, 3.0);
    let mut out = [0.0];
    for dt in [0.0, -1.0, f64::NAN] {
        m.step(dt, &[100.0], &mut out);
        assert_eq!(out[0], 3.0);
    }
    // NaN and infinite analog inputs read as 0.
    m.step(1.0, &[f64::NAN], &mut out);
    assert_rel(out[0], 3.0 * (-1.0f64).exp(), "NaN input");
}

// ---------------------------------------------------------------- properties

/// The configuration of a model of any type (for proptest's Debug output).
#[derive(Clone, Debug)]
enum Spec {
    Fopdt(FopdtConfig),
    Integrator(IntegratorConfig),
    SecondOrder(SecondOrderConfig),
    Tank(TankConfig),
    Heater(HeaterConfig),
    Valve(ValveConfig),
    Motor(MotorConfig),
    Noise(NoiseConfig),
}

impl Spec {
    fn build(self) -> Box<dyn Model> {
        match self {
            Spec::Fopdt(c) => Box::new(Fopdt::new(c).unwrap()),
            Spec::Integrator(c) => Box::new(Integrator::new(c).unwrap()),
            Spec::SecondOrder(c) => Box::new(SecondOrder::new(c).unwrap()),
            Spec::Tank(c) => Box::new(Tank::new(c).unwrap()),
            Spec::Heater(c) => Box::new(Heater::new(c).unwrap()),
            Spec::Valve(c) => Box::new(Valve::new(c).unwrap()),
            Spec::Motor(c) => Box::new(Motor::new(c).unwrap()),
            Spec::Noise(c) => Box::new(Noise::new(c).unwrap()),
        }
    }
}

/// A model of each type with parameters drawn from their documented ranges.
fn any_model() -> impl Strategy<Value = Spec> {
    let dur = || prop_oneof![Just(0.0), 1e-3..100.0f64];
    prop_oneof![
        (-1e3..1e3f64, dur(), dur(), -1e3..1e3f64).prop_map(|(gain, tau, dead_time, initial)| {
            Spec::Fopdt(FopdtConfig {
                gain,
                tau,
                dead_time,
                initial,
            })
        }),
        (
            -1e3..1e3f64,
            prop_oneof![Just(0.0), 1e-4..10.0f64],
            -1e3..1e3f64
        )
            .prop_map(|(gain, leak, initial)| {
                Spec::Integrator(IntegratorConfig {
                    gain,
                    leak,
                    initial,
                    min: -1e9,
                    max: 1e9,
                })
            }),
        (
            -1e3..1e3f64,
            1e-3..100.0f64,
            prop_oneof![Just(0.0), Just(1.0), 0.0..1.0f64, 1.0..50.0f64],
            -1e3..1e3f64
        )
            .prop_map(|(gain, omega, zeta, initial)| {
                Spec::SecondOrder(SecondOrderConfig {
                    gain,
                    omega,
                    zeta,
                    initial,
                })
            }),
        (
            1e-3..100.0f64,
            1e-2..100.0f64,
            0.0..10.0f64,
            prop_oneof![Just(None), (0.0..10.0f64).prop_map(Some)],
            0.0..1.0f64
        )
            .prop_map(|(area, height, cv, qmax, frac)| {
                Spec::Tank(TankConfig {
                    area,
                    height,
                    cv,
                    qmax,
                    initial: frac * height,
                })
            }),
        (
            1e-1..1e7f64,
            0.0..1e5f64,
            prop_oneof![Just(f64::INFINITY), 1e-4..10.0f64],
            -50.0..50.0f64,
            any::<bool>()
        )
            .prop_map(|(capacity, power, resistance, ambient, on_off)| {
                Spec::Heater(HeaterConfig {
                    capacity,
                    power,
                    resistance,
                    ambient,
                    initial: None,
                    on_off,
                })
            }),
        (dur(), dur(), 0.0..100.0f64).prop_map(|(open_time, close_time, initial)| {
            Spec::Valve(ValveConfig {
                open_time,
                close_time,
                initial,
            })
        }),
        (dur(), dur(), 1e-3..100.0f64, dur()).prop_map(
            |(accel_time, decel_time, threshold, feedback_delay)| {
                Spec::Motor(MotorConfig {
                    accel_time,
                    decel_time,
                    threshold,
                    feedback_delay,
                })
            }
        ),
        (
            any::<u64>(),
            -1e3..1e3f64,
            0.0..1e3f64,
            any::<bool>(),
            any::<bool>(),
            prop_oneof![Just(0.0), 1e-2..1.0f64]
        )
            .prop_map(|(seed, mean, width, uniform, input, interval)| {
                let distribution = if uniform {
                    Distribution::Uniform { amplitude: width }
                } else {
                    Distribution::Gaussian { stddev: width }
                };
                Spec::Noise(NoiseConfig {
                    seed,
                    mean,
                    distribution,
                    input,
                    interval,
                })
            }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn models_never_produce_nan_or_inf(
        spec in any_model(),
        steps in prop::collection::vec(
            (
                prop_oneof![Just(10.0), 1e-9..10.0f64],
                prop_oneof![Just(0.0), Just(1.0), Just(100.0), -1e4..1e4f64],
                prop_oneof![Just(0.0), Just(100.0), -10.0..110.0f64],
            ),
            1..100,
        ),
    ) {
        let mut model = spec.build();
        let mut out = vec![0.0; model.outputs().len()];
        model.outputs_now(&mut out);
        prop_assert!(out.iter().all(|x| x.is_finite()), "initial {:?}", out);
        let n_in = model.inputs().len();
        for (dt, a, b) in steps {
            let ins = [a, b];
            model.step(dt, &ins[..n_in], &mut out);
            prop_assert!(out.iter().all(|x| x.is_finite()), "dt={} in={:?} out={:?}", dt, &ins[..n_in], out);
        }
    }
}

proptest! {
    /// The tank's step is exact: one step of `dt` equals 50 steps of `dt/50`
    /// (to 1e-9 of the tank height).
    #[test]
    fn tank_step_splitting(
        area in 1e-2..10.0f64,
        cv in 1e-3..1.0f64,
        frac in 0.0..1.0f64,
        q_in in 0.0..100.0f64,
        valve in 0.0..100.0f64,
        dt in 1e-3..10.0f64,
    ) {
        let cfg = TankConfig { area, height: 4.0, cv, qmax: Some(0.05), initial: frac * 4.0 };
        let mut a = Tank::new(cfg.clone()).unwrap();
        let mut b = Tank::new(cfg).unwrap();
        let mut out = [0.0; 3];
        a.step(dt, &[q_in, valve], &mut out);
        let big = out[0];
        for _ in 0..50 {
            b.step(dt / 50.0, &[q_in, valve], &mut out);
        }
        prop_assert!((out[0] - big).abs() <= 1e-9 * 4.0, "{} vs {}", big, out[0]);
    }
}

// ---------------------------------------------------------------- throughput

/// A small PI temperature loop: heater → FOPDT sensor (lag + dead time) → PI →
/// heater, 10 ms steps, through `Box<dyn Model>` as the scenario runner uses
/// them. Printed, not asserted: run with
/// `cargo test --release -p softplc-sim --test models_registry -- --nocapture throughput`.
#[test]
fn throughput() {
    let steps: usize = if cfg!(debug_assertions) {
        864_000 // 2.4 h in debug builds
    } else {
        8_640_000 // 24 h at 10 ms
    };
    let dt = 0.01;
    let mut heater = build(
        "heater",
        &table("capacity = 5000\npower = 2000\nresistance = 0.05\nambient = 20"),
    )
    .unwrap();
    let mut sensor = build(
        "fopdt",
        &table("tau = \"5s\"\ndead_time = \"2s\"\ninitial = 20"),
    )
    .unwrap();
    let (sp, kp, ti): (f64, f64, f64) = (60.0, 8.0, 120.0);
    let mut integral = 0.0f64;
    let mut t_out = [0.0];
    let mut pv = [20.0];
    let start = Instant::now();
    for _ in 0..steps {
        let e = sp - pv[0];
        let u_unclamped = kp * (e + integral / ti);
        let u = u_unclamped.clamp(0.0, 100.0);
        if u == u_unclamped {
            integral += e * dt;
        }
        heater.step(dt, &[u], &mut t_out);
        sensor.step(dt, &t_out, &mut pv);
    }
    let secs = start.elapsed().as_secs_f64();
    assert!((pv[0] - sp).abs() < 0.5, "the loop settles: pv = {}", pv[0]);
    println!(
        "throughput: {steps} PI-loop steps (heater + fopdt with dead time) in {secs:.3} s = {:.1} M steps/s ({} build), final pv {:.4}",
        steps as f64 / secs / 1e6,
        if cfg!(debug_assertions) { "debug" } else { "release" },
        pv[0]
    );

    // Each model alone, driven by a changing input.
    let n = steps / 8;
    for (kind, params) in [
        ("fopdt", "tau = 5"),
        ("fopdt", "tau = 5\ndead_time = \"2s\""),
        ("fopdt", "tau = 5\ndead_time = \"2.005s\""),
        ("integrator", "leak = 0.1"),
        ("second_order", "omega = 2\nzeta = 0.3"),
        ("tank", "area = 1\nheight = 5\ncv = 0.1\ninitial = 1"),
        ("heater", "capacity = 5000\npower = 2000\nresistance = 0.05"),
        ("valve", "travel_time = 3"),
        ("motor", "accel_time = 3\nfeedback_delay = 0.2"),
        ("noise", "seed = 1\ninput = true"),
    ] {
        let mut m = build(kind, &table(params)).unwrap();
        let mut ins = vec![0.0; m.inputs().len()];
        let mut outs = vec![0.0; m.outputs().len()];
        let start = Instant::now();
        for i in 0..n {
            let x = (i % 1000) as f64 * 0.1;
            ins.iter_mut()
                .for_each(|v| *v = if x > 50.0 { x * 1e-3 } else { x });
            m.step(dt, &ins, &mut outs);
        }
        let secs = start.elapsed().as_secs_f64();
        assert!(outs.iter().all(|v| v.is_finite()));
        println!(
            "throughput: {kind:<12} {:<32} {:>7.1} M steps/s",
            params.replace('\n', ", "),
            n as f64 / secs / 1e6
        );
    }
}
