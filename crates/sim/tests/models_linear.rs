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
//! This file: the linear models against their closed-form step responses (FOPDT,
//! integrator, second order).

use softplc_sim::model::*;

mod common;
use common::{assert_rel, assert_scaled, fopdt, run1, table};

// ---------------------------------------------------------------- FOPDT

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
