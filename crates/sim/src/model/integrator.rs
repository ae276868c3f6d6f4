//! Integrating process.

use super::params::{ctx, Params};
use super::{analog, approach, ExpCache, Model, Port};

/// Parameters of [`Integrator`].
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorConfig {
    /// Gain K: output units per second per input unit. Default 1.
    pub gain: f64,
    /// Leak rate λ in 1/s, ≥ 0 (0 = pure integrator). Default 0.
    pub leak: f64,
    /// Initial output y(0) (clamped to [min, max]). Default 0.
    pub initial: f64,
    /// Lower clamp. Default −∞.
    pub min: f64,
    /// Upper clamp. Default +∞.
    pub max: f64,
}

impl Default for IntegratorConfig {
    fn default() -> Self {
        IntegratorConfig {
            gain: 1.0,
            leak: 0.0,
            initial: 0.0,
            min: f64::NEG_INFINITY,
            max: f64::INFINITY,
        }
    }
}

/// Integrating process (`integrator`), optionally leaky, with clamps:
///
/// ```text
/// y'(t) = K·u(t) − λ·y(t),      min ≤ y ≤ max
/// ```
///
/// Ports: input `u`, output `y`.
///
/// TOML parameters: `gain` (K, 1/s, default 1), `leak` (λ, 1/s, default 0),
/// `initial` (default 0), `min`, `max` (default unbounded).
///
/// # Discretisation
///
/// Exact for u constant over the step:
///
/// ```text
/// λ = 0:  y ← y + K·u·dt
/// λ > 0:  y ← y·e^(−λ·dt) + (K·u/λ)·(1 − e^(−λ·dt))
/// then    y ← clamp(y, min, max)
/// ```
///
/// (the leaky form evaluated as `y + (K·u/λ − y)·(1 − e^(−λ·dt))`, with
/// `expm1`).
///
/// Clamping at the end of the step is exact too: with constant input the
/// unclamped trajectory is monotonic within a step, so if it leaves the band it
/// stays out until the step's end, where the clamped process sits on the limit.
#[derive(Clone, Debug)]
pub struct Integrator {
    gain: f64,
    leak: f64,
    min: f64,
    max: f64,
    y: f64,
    cache: ExpCache,
}

impl Integrator {
    /// Validates `cfg` and builds the model.
    pub fn new(cfg: IntegratorConfig) -> Result<Self, String> {
        if !cfg.gain.is_finite() {
            return Err(format!("gain must be finite (got {})", cfg.gain));
        }
        if !(cfg.leak >= 0.0 && cfg.leak.is_finite()) {
            return Err(format!(
                "leak must be a finite rate ≥ 0 1/s (got {})",
                cfg.leak
            ));
        }
        if cfg.min.is_nan() || cfg.max.is_nan() || cfg.min > cfg.max {
            return Err(format!(
                "min ({}) must not be greater than max ({})",
                cfg.min, cfg.max
            ));
        }
        if !cfg.initial.is_finite() {
            return Err(format!("initial must be finite (got {})", cfg.initial));
        }
        let tau = if cfg.leak > 0.0 {
            1.0 / cfg.leak
        } else {
            f64::INFINITY
        };
        Ok(Integrator {
            gain: cfg.gain,
            leak: cfg.leak,
            min: cfg.min,
            max: cfg.max,
            y: cfg.initial.clamp(cfg.min, cfg.max),
            cache: ExpCache::new(tau),
        })
    }

    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, String> {
        const K: &str = "integrator";
        let p = Params::new(K, t, &["gain", "leak", "initial", "min", "max"])?;
        let d = IntegratorConfig::default();
        let cfg = IntegratorConfig {
            gain: p.num_or("gain", d.gain)?,
            leak: p.num_or("leak", d.leak)?,
            initial: p.num_or("initial", d.initial)?,
            min: p.num_or("min", d.min)?,
            max: p.num_or("max", d.max)?,
        };
        ctx(K, Self::new(cfg))
    }
}

const INPUTS: &[Port] = &[Port::Borrowed("u")];
const OUTPUTS: &[Port] = &[Port::Borrowed("y")];

impl Model for Integrator {
    fn inputs(&self) -> &[Port] {
        INPUTS
    }

    fn outputs(&self) -> &[Port] {
        OUTPUTS
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        let u = analog(inputs[0]);
        if dt > 0.0 {
            let y = if self.leak == 0.0 {
                self.y + self.gain * u * dt
            } else {
                let b = self.cache.at(dt);
                approach(self.y, self.gain * u / self.leak, b)
            };
            self.y = y.clamp(self.min, self.max);
        }
        outputs[0] = self.y;
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[0] = self.y;
    }
}
