//! First-order lag plus dead time.

use std::collections::VecDeque;

use super::params::{ctx, Params};
use super::{analog, approach, lag_fraction, ExpCache, Model, Port};

/// Parameters of [`Fopdt`].
#[derive(Clone, Debug, PartialEq)]
pub struct FopdtConfig {
    /// Static gain K (output units per input unit). Default 1.
    pub gain: f64,
    /// Time constant τ in seconds, ≥ 0 (0 = pure gain with dead time). Default 1 s.
    pub tau: f64,
    /// Dead time θ in seconds, ≥ 0. Default 0.
    pub dead_time: f64,
    /// Initial output y(0). Default 0.
    pub initial: f64,
}

impl Default for FopdtConfig {
    fn default() -> Self {
        FopdtConfig {
            gain: 1.0,
            tau: 1.0,
            dead_time: 0.0,
            initial: 0.0,
        }
    }
}

/// First-order plus dead time (`fopdt`):
///
/// ```text
/// τ·y'(t) = K·u(t − θ) − y(t)
/// ```
///
/// Ports: input `u`, output `y`.
///
/// TOML parameters: `gain` (K, default 1), `tau` (τ, duration, default 1 s),
/// `dead_time` (θ, duration, default 0), `initial` (y(0), default 0).
///
/// # Discretisation
///
/// Exact zero-order hold. Over an interval of length h on which the delayed
/// input u(t − θ) is constant (= u_d):
///
/// ```text
/// y ← y·e^(−h/τ) + K·u_d·(1 − e^(−h/τ))
/// ```
///
/// evaluated as `y ← y + (K·u_d − y)·(1 − e^(−h/τ))` with `1 − e^(−h/τ)` from
/// `expm1`: accurate for small h/τ and for small y, and the steady state K·u_d
/// is a fixed point exactly (no rounding drift while the input is constant).
///
/// With θ = 0 the step is one such interval (h = dt, the exponentials cached for
/// the last dt). With θ > 0 the model keeps the input history as a delay line of
/// (time, value) change points in virtual time; an input applied over
/// `[t, t + dt]` reaches the lag over `[t + θ, t + dt + θ]`. A step splits at
/// every change point that becomes due inside it, so the delay is **exact for
/// any θ**, whether or not it is a multiple of dt, and with varying dt: the
/// output is the exact continuous-time response of the lag to the delayed
/// piecewise-constant input. Change points that fall within `1e-6·dt` of a
/// step boundary are snapped to the boundary (this absorbs the rounding of the
/// accumulated virtual time, so with θ a multiple of dt each step is a single
/// interval). A step response sampled at step boundaries therefore equals
/// `y(t) = y0 + (K·U − y0)·(1 − e^(−(t−θ)/τ))` for t ≥ θ (and y0 before), up to
/// rounding.
///
/// Before t = 0 the input is taken as the steady-state value `y0/K` (0 if
/// K = 0), so the output stays at y0 during the first θ. Consecutive equal
/// inputs are stored once; the line holds at most about θ/dt + 2 entries.
#[derive(Clone, Debug)]
pub struct Fopdt {
    gain: f64,
    dead_time: f64,
    tau: f64,
    y: f64,
    cache: ExpCache,
    /// Virtual time of the start of the next step.
    now: f64,
    /// The delayed input in force at `now`.
    u_d: f64,
    /// Pending input changes: (time applied, value); due at time + θ.
    line: VecDeque<(f64, f64)>,
}

impl Fopdt {
    /// Validates `cfg` and builds the model.
    pub fn new(cfg: FopdtConfig) -> Result<Self, String> {
        if !cfg.gain.is_finite() {
            return Err(format!("gain must be finite (got {})", cfg.gain));
        }
        if !(cfg.tau >= 0.0 && cfg.tau.is_finite()) {
            return Err(format!("tau must be a finite time ≥ 0 s (got {})", cfg.tau));
        }
        if !(cfg.dead_time >= 0.0 && cfg.dead_time.is_finite()) {
            return Err(format!(
                "dead_time must be a finite time ≥ 0 s (got {})",
                cfg.dead_time
            ));
        }
        if !cfg.initial.is_finite() {
            return Err(format!("initial must be finite (got {})", cfg.initial));
        }
        let u_d = if cfg.gain != 0.0 {
            cfg.initial / cfg.gain
        } else {
            0.0
        };
        Ok(Fopdt {
            gain: cfg.gain,
            dead_time: cfg.dead_time,
            tau: cfg.tau,
            y: cfg.initial,
            cache: ExpCache::new(cfg.tau),
            now: 0.0,
            u_d,
            line: VecDeque::new(),
        })
    }

    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, String> {
        const K: &str = "fopdt";
        let p = Params::new(K, t, &["gain", "tau", "dead_time", "initial"])?;
        let d = FopdtConfig::default();
        let cfg = FopdtConfig {
            gain: p.num_or("gain", d.gain)?,
            tau: p.dur_or("tau", d.tau)?,
            dead_time: p.dur_or("dead_time", d.dead_time)?,
            initial: p.num_or("initial", d.initial)?,
        };
        ctx(K, Self::new(cfg))
    }

    /// The current output.
    pub fn y(&self) -> f64 {
        self.y
    }

    /// Advances the lag by a sub-interval of length `h` with the delayed input
    /// `u_d` (uncached exponential).
    #[inline]
    fn advance_part(&mut self, h: f64) {
        let b = lag_fraction(h, self.tau);
        self.y = approach(self.y, self.gain * self.u_d, b);
    }

    fn step_delayed(&mut self, dt: f64, u: f64) {
        if self.line.capacity() == 0 {
            self.line
                .reserve((self.dead_time / dt).ceil().min(65536.0) as usize + 2);
        }
        let last = self.line.back().map_or(self.u_d, |e| e.1);
        if u != last {
            self.line.push_back((self.now, u));
        }
        let start = self.now;
        let end = start + dt;
        let eps = 1e-6 * dt;
        let mut t = start;
        while let Some(&(at, v)) = self.line.front() {
            let due = at + self.dead_time;
            if due >= end - eps {
                break;
            }
            if due > t + eps {
                self.advance_part(due - t);
                t = due;
            }
            self.u_d = v;
            self.line.pop_front();
        }
        if t == start {
            let b = self.cache.at(dt);
            self.y = approach(self.y, self.gain * self.u_d, b);
        } else {
            self.advance_part(end - t);
        }
        self.now = end;
    }
}

const INPUTS: &[Port] = &[Port::Borrowed("u")];
const OUTPUTS: &[Port] = &[Port::Borrowed("y")];

impl Model for Fopdt {
    fn inputs(&self) -> &[Port] {
        INPUTS
    }

    fn outputs(&self) -> &[Port] {
        OUTPUTS
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        let u = analog(inputs[0]);
        if dt > 0.0 {
            if self.dead_time > 0.0 {
                self.step_delayed(dt, u);
            } else {
                let b = self.cache.at(dt);
                self.y = approach(self.y, self.gain * u, b);
            }
        }
        outputs[0] = self.y;
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[0] = self.y;
    }
}
