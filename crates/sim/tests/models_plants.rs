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
//! This file: the plant and actuator models (heater, tank, valve, motor) and noise.

use softplc_sim::model::*;

mod common;
use common::{assert_rel, assert_scaled, run1, table};

// ---------------------------------------------------------------- heater

#[test]
fn heater_step_to_steady_state() {
    let (c, p, r, ta, u) = (5000.0, 2000.0, 0.05, 20.0, 60.0);
    let mut m = Heater::new(HeaterConfig {
        capacity: c,
        power: p,
        resistance: r,
        ambient: ta,
        initial: None,
        on_off: false,
    })
    .unwrap();
    let t_inf = u / 100.0 * p * r + ta; // 80 °C
    let tau = r * c; // 250 s
    let dt = 0.5;
    let ts = run1(&mut m, dt, 20_000, |_| u);
    for (i, temp) in ts.iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        assert_rel(
            *temp,
            t_inf + (ta - t_inf) * (-t / tau).exp(),
            &format!("t={t}"),
        );
    }
    assert_rel(*ts.last().unwrap(), t_inf, "steady state K·P·R + Ta");
    // Cooling back to ambient with the heater off.
    let ts = run1(&mut m, 2.0, 5000, |_| 0.0);
    assert_rel(*ts.last().unwrap(), ta, "cooled to ambient");
}

#[test]
fn heater_on_off_and_insulated() {
    let mut m = build(
        "heater",
        &table("capacity = 100\npower = 50\nresistance = 2\nambient = 10\non_off = true"),
    )
    .unwrap();
    let ts = run1(m.as_mut(), 1.0, 2000, |_| 1.0);
    for (i, temp) in ts.iter().enumerate() {
        // τ = R·C = 200 s, T∞ = Ta + P·R = 110 °C.
        let t = (i + 1) as f64;
        assert_rel(
            *temp,
            110.0 - 100.0 * (-t / 200.0).exp(),
            &format!("on t={t}"),
        );
    }
    let mut m = build(
        "heater",
        &table("capacity = 100\npower = 50\nresistance = inf\ninitial = 15"),
    )
    .unwrap();
    let ts = run1(m.as_mut(), 0.1, 100, |_| 50.0);
    // Insulated: T = T0 + P·u·t/C = 15 + 25·10/100.
    assert_rel(*ts.last().unwrap(), 17.5, "insulated ramp");
}

// ---------------------------------------------------------------- tank

#[test]
fn tank_draining_matches_torricelli() {
    // √h(t) = √h0 − Cv·t/(2A); empty at t = 2A√h0/Cv = 160 s.
    let (area, cv, h0, dt) = (2.0, 0.05, 4.0, 0.1);
    let mut m = Tank::new(TankConfig {
        area,
        height: 5.0,
        cv,
        qmax: None,
        initial: h0,
    })
    .unwrap();
    let mut out = [0.0; 3];
    for i in 0..2000 {
        m.step(dt, &[0.0, 100.0], &mut out);
        let t = (i + 1) as f64 * dt;
        let s = (h0.sqrt() - cv * t / (2.0 * area)).max(0.0);
        if s > 0.0 {
            assert_rel(out[0], s * s, &format!("level t={t}"));
            assert_rel(out[2], cv * s, &format!("q_out t={t}"));
        } else {
            // At the instant it empties (t = 160 s) rounding leaves ~1e-27 m.
            assert_scaled(out[0], 0.0, h0, &format!("level t={t}"));
        }
        assert_eq!(out[1], 0.0);
    }
    assert_eq!(out[0], 0.0);
}

#[test]
fn tank_filling_against_implicit_solution() {
    // q > 0, c > 0: (s0 − s) + s*·ln((s* − s0)/(s* − s)) = c·t/(2A), s = √h.
    let (area, cv, valve, q, dt) = (1.5, 0.08, 50.0, 0.06, 0.25);
    let c = cv * valve / 100.0;
    let ss = q / c; // √h∞ = 1.5 m^½ → h∞ = 2.25 m
    for h0 in [0.0, 0.5, 4.0] {
        let mut m = Tank::new(TankConfig {
            area,
            height: 10.0,
            cv,
            qmax: None,
            initial: h0,
        })
        .unwrap();
        let s0 = f64::sqrt(h0);
        let mut out = [0.0; 3];
        for i in 0..2000 {
            m.step(dt, &[q, valve], &mut out);
            let t = (i + 1) as f64 * dt;
            let s = out[0].sqrt();
            if ((ss - s) / ss).abs() < 1e-6 {
                // Near equilibrium the implicit form is ill-conditioned.
                break;
            }
            let lhs = (s0 - s) + ss * ((ss - s0) / (ss - s)).ln();
            let rhs = c * t / (2.0 * area);
            assert_rel(lhs, rhs, &format!("h0={h0} t={t} h={}", out[0]));
        }
        // And it settles at (q/c)².
        for _ in 0..20_000 {
            m.step(dt, &[q, valve], &mut out);
        }
        assert_rel(out[0], ss * ss, &format!("h0={h0} equilibrium"));
        assert_rel(out[2], q, &format!("h0={h0} outflow = inflow"));
    }
}

#[test]
fn tank_is_independent_of_step_size() {
    // (initial level, q_in % of qmax, valve %): filling from low, filling from
    // empty, draining towards a low equilibrium, draining with no inflow.
    for (initial, q_in, valve) in [
        (0.2, 70.0, 35.0),
        (0.0, 70.0, 35.0),
        (2.5, 5.0, 100.0),
        (2.5, 0.0, 10.0),
    ] {
        let cfg = TankConfig {
            area: 0.7,
            height: 3.0,
            cv: 0.02,
            qmax: Some(0.01),
            initial,
        };
        let mut a = Tank::new(cfg.clone()).unwrap();
        let mut b = Tank::new(cfg).unwrap();
        let mut out = [0.0; 3];
        for big_step in [40.0, 400.0] {
            a.step(big_step, &[q_in, valve], &mut out);
            let big = out[0];
            for _ in 0..(big_step * 100.0) as usize {
                b.step(0.01, &[q_in, valve], &mut out);
            }
            assert_rel(
                out[0],
                big,
                &format!("h0={initial} q={q_in} v={valve}: one {big_step} s step vs 10 ms steps"),
            );
        }
    }
}

#[test]
fn tank_overflow_and_qmax() {
    // Valve shut, 40 % of qmax = 0.02 m³/s into 0.5 m²: 0.04 m/s, full (2 m)
    // after 50 s.
    let mut m = build(
        "tank",
        &table("area = 0.5\nheight = 2\ncv = 0.1\nqmax = 0.05"),
    )
    .unwrap();
    let mut out = [0.0; 3];
    for i in 0..600 {
        m.step(0.1, &[40.0, 0.0], &mut out);
        let t = (i + 1) as f64 * 0.1;
        if t < 50.0 - 1e-9 {
            assert_rel(out[0], 0.04 * t, &format!("t={t}"));
            assert_eq!(out[1], 0.0, "t={t}");
        } else if t > 50.0 + 1e-9 {
            assert_eq!(out[0], 2.0);
            assert_eq!(out[1], 1.0, "spilling at t={t}");
        }
    }
    // Open the valve: c·√2 = 0.1414 > 0.02, no more spilling.
    m.step(0.1, &[40.0, 100.0], &mut out);
    assert_eq!(out[1], 0.0);
    assert!(out[0] < 2.0);
}

// ---------------------------------------------------------------- valve, motor

#[test]
fn valve_travel_times() {
    let mut v = Valve::new(ValveConfig {
        open_time: 5.0,
        close_time: 8.0,
        initial: 0.0,
    })
    .unwrap();
    let mut out = [0.0; 3];
    v.outputs_now(&mut out);
    assert_eq!(out, [0.0, 0.0, 1.0]);
    let dt = 0.01;
    for n in 1..=600 {
        v.step(dt, &[1.0], &mut out);
        let want = (n as f64 * 0.2).min(100.0);
        assert_rel(out[0], want, &format!("opening step {n}"));
        assert_eq!(
            out[1],
            if n >= 500 { 1.0 } else { 0.0 },
            "opened at step {n}"
        );
        assert_eq!(out[2], 0.0);
    }
    for n in 1..=900 {
        v.step(dt, &[0.0], &mut out);
        let want = (100.0 - n as f64 * 12.5 * dt).max(0.0);
        if want > 0.0 {
            assert_rel(out[0], want, &format!("closing step {n}"));
        }
        assert_eq!(out[1], 0.0);
        assert_eq!(
            out[2],
            if n >= 800 { 1.0 } else { 0.0 },
            "closed at step {n}"
        );
    }
    // A step size that does not divide the travel time: opened at the first
    // boundary at or after 5 s.
    let mut v = build("valve", &table("travel_time = \"5s\"")).unwrap();
    let dt = 0.03;
    let first = (1..1000)
        .find(|_| {
            v.step(dt, &[1.0], &mut out);
            out[1] == 1.0
        })
        .unwrap();
    assert_eq!(first, 167); // 5.01 s
                            // Reversal mid-stroke: open 2 s (40 %), close 1 s (−20 %).
    let mut v = build("valve", &table("open_time = 5\nclose_time = \"5000ms\"")).unwrap();
    for _ in 0..200 {
        v.step(0.01, &[1.0], &mut out);
    }
    for _ in 0..100 {
        v.step(0.01, &[0.0], &mut out);
    }
    assert_rel(out[0], 20.0, "reversal");
    // Instantaneous by default.
    let mut v = build("valve", &toml::Table::new()).unwrap();
    v.step(0.01, &[1.0], &mut out);
    assert_eq!(out, [100.0, 1.0, 0.0]);
}

/// Steps until `running` equals `want`; returns the step count.
fn steps_until(m: &mut dyn Model, dt: f64, run: f64, want: f64, limit: usize) -> usize {
    let mut out = [0.0; 2];
    for n in 1..=limit {
        m.step(dt, &[run], &mut out);
        if out[1] == want {
            return n;
        }
    }
    panic!("running never became {want}");
}

#[test]
fn motor_ramp_and_feedback_delay() {
    let cfg = MotorConfig {
        accel_time: 10.0,
        decel_time: 4.0,
        threshold: 50.0,
        feedback_delay: 0.5,
    };
    let mut m = Motor::new(cfg.clone()).unwrap();
    let dt = 0.01;
    // Speed reaches 50 % at 5 s; the contact closes 0.5 s later.
    assert_eq!(steps_until(&mut m, dt, 1.0, 1.0, 2000), 550);
    assert_rel(m.speed(), 55.0, "speed at 5.5 s");
    let mut out = [0.0; 2];
    for _ in 0..450 {
        m.step(dt, &[1.0], &mut out);
    }
    assert_eq!(out, [100.0, 1.0]);
    // Stop: 25 %/s, below 50 % after 2 s, contact opens 0.5 s later.
    assert_eq!(steps_until(&mut m, dt, 0.0, 0.0, 2000), 250);
    assert_rel(m.speed(), 37.5, "speed at 2.5 s after stop");

    // The delay is counted from the crossing instant inside a step: with
    // dt = 0.3 s the speed crosses 50 % at 5 s (inside step 17, which ends at
    // 5.1 s) and the contact closes at the first boundary ≥ 5.5 s: 5.7 s.
    let mut m = Motor::new(cfg.clone()).unwrap();
    assert_eq!(steps_until(&mut m, 0.3, 1.0, 1.0, 100), 19);

    // A run pulse shorter than the delay (threshold crossed for 0.3 s) never
    // reaches the contact.
    let mut m = Motor::new(MotorConfig {
        accel_time: 0.0,
        decel_time: 0.0,
        ..cfg
    })
    .unwrap();
    for n in 0..100 {
        m.step(dt, &[if n < 30 { 1.0 } else { 0.0 }], &mut out);
        assert_eq!(out[1], 0.0, "step {n}");
    }
    assert_eq!(out[0], 0.0);
}

#[test]
fn motor_from_table_defaults() {
    let mut m = build("motor", &table("accel_time = \"2s\"\nthreshold = 90")).unwrap();
    assert_eq!(m.inputs(), ["run"]);
    assert_eq!(m.outputs(), ["speed", "running"]);
    // No feedback delay: contact at 90 % = 1.8 s.
    assert_eq!(steps_until(m.as_mut(), 0.1, 1.0, 1.0, 100), 18);
}

// ---------------------------------------------------------------- noise

fn noise_seq(src: &str, n: usize) -> Vec<f64> {
    let mut m = build("noise", &table(src)).unwrap();
    assert!(m.inputs().is_empty());
    let mut out = [0.0];
    (0..n)
        .map(|_| {
            m.step(0.01, &[], &mut out);
            out[0]
        })
        .collect()
}

fn mean_var(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, var)
}

#[test]
fn noise_is_deterministic() {
    let a = noise_seq("seed = 42\nstddev = 0.5", 10_000);
    let b = noise_seq("seed = 42\nstddev = 0.5", 10_000);
    let c = noise_seq("seed = 43\nstddev = 0.5", 10_000);
    assert_eq!(a, b);
    assert_ne!(a, c);
    assert!(a.iter().zip(&c).filter(|(x, y)| x == y).count() < 10);
    let u1 = noise_seq("seed = 7\ndistribution = \"uniform\"", 1000);
    let u2 = noise_seq("seed = 7\ndistribution = \"uniform\"", 1000);
    assert_eq!(u1, u2);
    assert_ne!(u1, noise_seq("distribution = \"uniform\"", 1000));
    // Seed 0 is valid and not degenerate.
    let z = noise_seq("seed = 0", 1000);
    assert!(z.iter().all(|x| x.is_finite()));
    assert!(mean_var(&z).1 > 0.5);
}

#[test]
fn noise_statistics() {
    const N: usize = 100_000;
    // Gaussian, mean 5, σ = 2: sample mean within 5·σ/√N ≈ 0.032, sample
    // variance within 5·σ²·√(2/N) ≈ 0.089.
    let g = noise_seq("seed = 1\nmean = 5.0\nstddev = 2.0", N);
    let (m, v) = mean_var(&g);
    assert!((m - 5.0).abs() < 0.032, "gaussian mean {m}");
    assert!((v - 4.0).abs() < 0.089, "gaussian variance {v}");
    // Gaussian tails: ~4.55 % outside ±2σ.
    let out2 = g.iter().filter(|x| (*x - 5.0).abs() > 4.0).count() as f64 / N as f64;
    assert!((out2 - 0.0455).abs() < 0.004, "P(|z| > 2) = {out2}");
    // Uniform on [−3, 3]: mean 0, variance a²/3 = 3, all within ±3.
    let u = noise_seq("seed = 2\ndistribution = \"uniform\"\namplitude = 3", N);
    let (m, v) = mean_var(&u);
    assert!(
        m.abs() < 5.0 * (3.0f64 / N as f64).sqrt(),
        "uniform mean {m}"
    );
    // Var of the sample variance of a uniform: (μ4 − σ⁴)/N = (9·9/5 − 9)/N.
    assert!(
        (v - 3.0).abs() < 5.0 * (7.2f64 / N as f64).sqrt(),
        "uniform variance {v}"
    );
    assert!(u.iter().all(|x| x.abs() <= 3.0));
}

#[test]
fn noise_input_and_interval() {
    let mut m = build("noise", &table("input = true\nstddev = 0\nmean = 1")).unwrap();
    assert_eq!(m.inputs(), ["u"]);
    let mut out = [0.0];
    m.step(0.01, &[41.0], &mut out);
    assert_eq!(out[0], 42.0);
    // With an interval the sequence depends on virtual time, not on dt.
    let sample_at = |dt: f64, steps: usize| {
        let mut m = build("noise", &table("seed = 9\ninterval = \"100ms\"")).unwrap();
        let mut out = [0.0];
        (0..steps)
            .map(|_| {
                m.step(dt, &[], &mut out);
                out[0]
            })
            .collect::<Vec<_>>()
    };
    let fine = sample_at(0.01, 1000); // 10 s
    let coarse = sample_at(0.05, 200);
    for (j, c) in coarse.iter().enumerate() {
        assert_eq!(*c, fine[5 * j + 4], "t={}", (j + 1) as f64 * 0.05);
    }
    // Held for 10 steps of 10 ms: sample 1 on [0.1 s, 0.2 s), reported after
    // steps 9..=18 (ending at 0.10..0.19 s).
    assert_ne!(fine[8], fine[9]);
    assert!(fine[9..19].iter().all(|x| *x == fine[9]));
    assert_ne!(fine[18], fine[19]);
}
