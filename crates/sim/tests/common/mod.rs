//! Helpers shared by the `models_*` tests: relative-error assertions, TOML
//! tables, stepping a single-input model and a FOPDT constructor.
#![allow(dead_code)]

use softplc_sim::model::{Fopdt, FopdtConfig, Model};

pub const REL: f64 = 1e-9;

#[track_caller]
pub fn assert_rel(got: f64, want: f64, what: &str) {
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
pub fn assert_scaled(got: f64, want: f64, scale: f64, what: &str) {
    let err = (got - want).abs() / scale;
    assert!(
        err <= REL,
        "{what}: got {got}, want {want}, error/scale {err:e}"
    );
}

pub fn table(src: &str) -> toml::Table {
    src.parse::<toml::Table>().expect("test TOML")
}

/// Steps a single-input model `n` times and returns the first output after
/// each step.
pub fn run1(m: &mut dyn Model, dt: f64, n: usize, u: impl Fn(usize) -> f64) -> Vec<f64> {
    let mut out = vec![0.0; m.outputs().len()];
    (0..n)
        .map(|i| {
            m.step(dt, &[u(i)], &mut out);
            out[0]
        })
        .collect()
}

pub fn fopdt(gain: f64, tau: f64, dead_time: f64, initial: f64) -> Fopdt {
    Fopdt::new(FopdtConfig {
        gain,
        tau,
        dead_time,
        initial,
    })
    .unwrap()
}
