//! Golden tests of the plant models against closed-form solutions, the
//! constructor registry, scaling, a no-NaN property test and a throughput check.
//!
//! Tolerances: 1e-9 relative error at every sample point for the closed-form
//! step responses (FOPDT with and without dead time, integrator, second order
//! for ζ = 0.2, 1, 2, heater, tank draining and filling). Where the reference
//! value is exactly 0 (before a dead time, an empty tank) the model must give
//! exactly 0. Where a reference passes through 0 (the rate of an under-damped
//! response) the error is relative to the response's scale.

use std::time::Instant;

use proptest::prelude::*;
use softplc_sim::model::scaling::*;
use softplc_sim::model::*;

const REL: f64 = 1e-9;

#[track_caller]
fn assert_rel(got: f64, want: f64, what: &str) {
    if want == 0.0 {
        assert_eq!(got, 0.0, "{what}: want exactly 0, got {got}");
    } else {
        let err = ((got - want) / want).abs();
        assert!(
            err <= REL,
            "{what}: got {got}, want {want}, relative error {err:e}"
        );
    }
}

#[track_caller]
fn assert_scaled(got: f64, want: f64, scale: f64, what: &str) {
    let err = (got - want).abs() / scale;
    assert!(
        err <= REL,
        "{what}: got {got}, want {want}, error/scale {err:e}"
    );
}

fn table(src: &str) -> toml::Table {
    src.parse::<toml::Table>().expect("test TOML")
}

/// Steps a single-input model `n` times and returns the first output after
/// each step.
fn run1(m: &mut dyn Model, dt: f64, n: usize, u: impl Fn(usize) -> f64) -> Vec<f64> {
    let mut out = vec![0.0; m.outputs().len()];
    (0..n)
        .map(|i| {
            m.step(dt, &[u(i)], &mut out);
            out[0]
        })
        .collect()
}

// ---------------------------------------------------------------- FOPDT

fn fopdt(gain: f64, tau: f64, dead_time: f64, initial: f64) -> Fopdt {
    Fopdt::new(FopdtConfig {
        gain,
        tau,
        dead_time,
        initial,
    })
    .unwrap()
}

/// Step response of K/(τs+1)·e^(−θs) from y0 to a step U at t = 0.
fn fopdt_step(k: f64, tau: f64, theta: f64, y0: f64, u: f64, t: f64) -> f64 {
    if t <= theta {
        y0
    } else {
        y0 + (k * u - y0) * -(-(t - theta) / tau).exp_m1()
    }
}

#[test]
fn fopdt_step_without_dead_time() {
    let (k, tau, u, dt) = (2.5, 7.0, 3.0, 0.01);
    let mut m = fopdt(k, tau, 0.0, 0.0);
    let ys = run1(&mut m, dt, 5000, |_| u);
    for (i, y) in ys.iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        assert_rel(*y, fopdt_step(k, tau, 0.0, 0.0, u, t), &format!("t={t}"));
    }
}

#[test]
fn fopdt_step_with_dead_time_multiple_of_dt() {
    let (k, tau, theta, u, dt) = (-1.7, 4.0, 1.5, 2.0, 0.01);
    let mut m = fopdt(k, tau, theta, 0.0);
    let ys = run1(&mut m, dt, 3000, |_| u);
    for (i, y) in ys.iter().enumerate() {
        let n = i + 1;
        let t = n as f64 * dt;
        let want = if n <= 150 {
            0.0
        } else {
            fopdt_step(k, tau, theta, 0.0, u, t)
        };
        assert_rel(*y, want, &format!("t={t}"));
    }
}

#[test]
fn fopdt_step_with_dead_time_not_multiple_of_dt() {
    // θ = 0.37 s with dt = 0.1 s: the delay is exact, not rounded to steps.
    let (k, tau, theta, u, dt) = (3.0, 2.0, 0.37, 1.25, 0.1);
    let mut m = fopdt(k, tau, theta, 0.0);
    let ys = run1(&mut m, dt, 200, |_| u);
    for (i, y) in ys.iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        let want = if t < theta {
            0.0
        } else {
            fopdt_step(k, tau, theta, 0.0, u, t)
        };
        assert_rel(*y, want, &format!("t={t}"));
    }
}

#[test]
fn fopdt_exact_with_varying_dt() {
    let (k, tau, theta, u) = (1.5, 3.0, 0.8, 2.0);
    let mut m = fopdt(k, tau, theta, 0.0);
    let mut out = [0.0];
    let dts = [0.013, 0.1, 0.05, 0.31, 0.002, 0.7, 0.25, 1.3, 0.01, 2.0];
    let mut t = 0.0;
    for i in 0..300 {
        let dt = dts[i % dts.len()];
        m.step(dt, &[u], &mut out);
        t += dt;
        let want = if t <= theta {
            0.0
        } else {
            fopdt_step(k, tau, theta, 0.0, u, t)
        };
        assert_rel(out[0], want, &format!("step {i} t={t}"));
    }
}

#[test]
fn fopdt_initial_value_holds_through_dead_time() {
    let (k, tau, theta, y0, u, dt) = (2.0, 5.0, 2.0, 10.0, 8.0, 0.05);
    let mut m = fopdt(k, tau, theta, y0);
    let mut out = [0.0];
    m.outputs_now(&mut out);
    assert_eq!(out[0], y0);
    let ys = run1(&mut m, dt, 1000, |_| u);
    for (i, y) in ys.iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        assert_rel(*y, fopdt_step(k, tau, theta, y0, u, t), &format!("t={t}"));
    }
}

#[test]
fn fopdt_pulse_is_superposition_of_delayed_steps() {
    // u = 1 on [0, 1 s), then 0: y = K·[s(t−θ) − s(t−θ−1)] with
    // s(t) = 1 − e^(−t/τ) for t > 0.
    let (k, tau, theta, dt) = (4.0, 1.5, 0.75, 0.05);
    let mut m = fopdt(k, tau, theta, 0.0);
    let ys = run1(&mut m, dt, 200, |i| if i < 20 { 1.0 } else { 0.0 });
    let s = |t: f64| if t > 0.0 { -(-t / tau).exp_m1() } else { 0.0 };
    for (i, y) in ys.iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        let want = k * (s(t - theta) - s(t - theta - 1.0));
        if t <= theta + 1e-9 {
            assert_eq!(*y, 0.0, "t={t}");
        } else {
            // Past the pulse the response is a difference of two exponentials
            // of similar size: compare relative to the peak.
            assert_scaled(*y, want, k, &format!("t={t}"));
        }
    }
}

#[test]
fn fopdt_zero_tau_is_a_pure_delay() {
    let (k, theta, dt) = (2.0, 0.3, 0.1);
    let mut m = fopdt(k, 0.0, theta, 0.0);
    let u = |i: usize| (i as f64 * 0.7).sin();
    let ys = run1(&mut m, dt, 100, u);
    for (i, y) in ys.iter().enumerate() {
        // Just before the end of step i, (i+1)·dt, the lag sees the input
        // applied just before (i+1)·dt − θ = (i−2)·dt, i.e. in step i − 3.
        let want = if i >= 3 { k * u(i - 3) } else { 0.0 };
        assert_eq!(*y, want, "step {i}");
    }
}

// ---------------------------------------------------------------- integrator

#[test]
fn integrator_ramp() {
    let (k, y0, u, dt) = (0.4, -3.0, 2.5, 0.01);
    let mut m = Integrator::new(IntegratorConfig {
        gain: k,
        initial: y0,
        ..Default::default()
    })
    .unwrap();
    let ys = run1(&mut m, dt, 10_000, |_| u);
    for (i, y) in ys.iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        let want = y0 + k * u * t;
        if want.abs() > 1e-6 {
            assert_rel(*y, want, &format!("t={t}"));
        } else {
            // The ramp crosses zero at t = 3 s.
            assert_scaled(*y, want, y0.abs(), &format!("t={t}"));
        }
    }
}

#[test]
fn integrator_clamps_and_leaks() {
    let mut m = Integrator::new(IntegratorConfig {
        gain: 2.0,
        min: -1.0,
        max: 5.0,
        ..Default::default()
    })
    .unwrap();
    let ys = run1(&mut m, 0.1, 100, |_| 10.0);
    assert_rel(ys[0], 2.0, "first step");
    assert_eq!(ys[1], 4.0);
    assert!(ys[2..].iter().all(|&y| y == 5.0));
    let ys = run1(&mut m, 0.1, 100, |_| -10.0);
    assert_eq!(*ys.last().unwrap(), -1.0);

    // y' = K·u − λ·y: y = y∞ + (y0 − y∞)·e^(−λt), y∞ = K·u/λ.
    let (k, leak, y0, u, dt) = (3.0, 0.2, 1.0, 2.0, 0.05);
    let mut m = Integrator::new(IntegratorConfig {
        gain: k,
        leak,
        initial: y0,
        ..Default::default()
    })
    .unwrap();
    let ys = run1(&mut m, dt, 2000, |_| u);
    let y_inf = k * u / leak;
    for (i, y) in ys.iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        assert_rel(
            *y,
            y_inf + (y0 - y_inf) * (-leak * t).exp(),
            &format!("t={t}"),
        );
    }
}

// ---------------------------------------------------------------- second order

/// Step response y(t) and rate y'(t) of K·ω²/(s² + 2ζωs + ω²) to a step U from
/// rest, from the textbook forms (independent of the model's Φ).
fn second_order_step(k: f64, w: f64, z: f64, u: f64, t: f64) -> (f64, f64) {
    let ku = k * u;
    if z < 1.0 {
        let wd = w * (1.0 - z * z).sqrt();
        let s = z * w;
        let e = (-s * t).exp();
        (
            ku * (1.0 - e * ((wd * t).cos() + s / wd * (wd * t).sin())),
            ku * w * w / wd * e * (wd * t).sin(),
        )
    } else if z == 1.0 {
        let e = (-w * t).exp();
        (ku * (1.0 - e * (1.0 + w * t)), ku * w * w * t * e)
    } else {
        let r = w * (z * z - 1.0).sqrt();
        let s1 = -z * w + r;
        let s2 = -z * w - r;
        let (e1, e2) = ((s1 * t).exp(), (s2 * t).exp());
        (
            ku * (1.0 + (s2 * e1 - s1 * e2) / (s1 - s2)),
            ku * w * w * (e1 - e2) / (s1 - s2),
        )
    }
}

fn check_second_order(zeta: f64, dt: f64, steps: usize) {
    let (k, w, u) = (2.0, 1.3, 1.5);
    let mut m = SecondOrder::new(SecondOrderConfig {
        gain: k,
        omega: w,
        zeta,
        initial: 0.0,
    })
    .unwrap();
    let mut out = [0.0; 2];
    for i in 0..steps {
        m.step(dt, &[u], &mut out);
        let t = (i + 1) as f64 * dt;
        let (y, v) = second_order_step(k, w, zeta, u, t);
        assert_rel(out[0], y, &format!("ζ={zeta} y t={t}"));
        // The rate passes through zero: compare relative to its scale K·U·ω.
        assert_scaled(out[1], v, k * u * w, &format!("ζ={zeta} rate t={t}"));
    }
}

#[test]
fn second_order_step_underdamped() {
    check_second_order(0.2, 0.01, 3000);
    check_second_order(0.2, 0.37, 100);
}

#[test]
fn second_order_step_critically_damped() {
    check_second_order(1.0, 0.01, 3000);
    check_second_order(1.0, 0.37, 100);
}

#[test]
fn second_order_step_overdamped() {
    check_second_order(2.0, 0.01, 3000);
    check_second_order(2.0, 0.37, 100);
    check_second_order(2.0, 1.3, 40);
}

#[test]
fn second_order_continuous_across_critical_damping() {
    let run = |zeta: f64| {
        let mut m = SecondOrder::new(SecondOrderConfig {
            zeta,
            ..Default::default()
        })
        .unwrap();
        run1(&mut m, 0.05, 200, |_| 1.0)
    };
    let crit = run(1.0);
    for z in [1.0 - 1e-9, 1.0 + 1e-9, 1.0 - 1e-6, 1.0 + 1e-6] {
        for (a, b) in run(z).iter().zip(&crit) {
            assert!((a - b).abs() < 1e-5, "ζ={z}: {a} vs {b}");
        }
    }
}

#[test]
fn second_order_period_parameter() {
    let m = build("second_order", &table("period = \"2s\"\nzeta = 0.0")).unwrap();
    let mut m = m;
    let mut out = [0.0; 2];
    // Undamped, ω = π: y = 1 − cos(πt); after one period (2 s) back to 0.
    for _ in 0..200 {
        m.step(0.01, &[1.0], &mut out);
    }
    assert!(out[0].abs() < 1e-12, "{}", out[0]);
    for _ in 0..100 {
        m.step(0.01, &[1.0], &mut out);
    }
    assert!((out[0] - 2.0).abs() < 1e-12, "{}", out[0]);
}

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
            "noise"
        ]
    );
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
/// `cargo test --release -p softplc-sim --test models -- --nocapture throughput`.
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
