//! Second-order process.

use std::f64::consts::TAU;

use super::params::{ctx, Params};
use super::{analog, Model, Port};

/// Parameters of [`SecondOrder`].
#[derive(Clone, Debug, PartialEq)]
pub struct SecondOrderConfig {
    /// Static gain K. Default 1.
    pub gain: f64,
    /// Natural angular frequency ω in rad/s, > 0. Default 1.
    pub omega: f64,
    /// Damping ratio ζ, ≥ 0 (0 undamped, < 1 under-, 1 critically, > 1
    /// over-damped). Default 1.
    pub zeta: f64,
    /// Initial output y(0) (with y'(0) = 0). Default 0.
    pub initial: f64,
}

impl Default for SecondOrderConfig {
    fn default() -> Self {
        SecondOrderConfig {
            gain: 1.0,
            omega: 1.0,
            zeta: 1.0,
            initial: 0.0,
        }
    }
}

/// Second-order process (`second_order`):
///
/// ```text
/// y''(t) + 2ζω·y'(t) + ω²·y(t) = K·ω²·u(t)
/// ```
///
/// Ports: input `u`; outputs `y` and `rate` (= y', units per second).
///
/// TOML parameters: `gain` (K, default 1), `omega` (ω, rad/s) **or** `period`
/// (natural period T = 2π/ω, duration), default ω = 1 rad/s; `zeta` (ζ,
/// default 1); `initial` (y(0), default 0; y'(0) = 0).
///
/// # Discretisation
///
/// Exact zero-order hold of the state x = (y, y'), ẋ = A·x + B·u with
/// A = [[0, 1], [−ω², −2ζω]]. For u constant over the step the equilibrium is
/// x* = (K·u, 0) and
///
/// ```text
/// x ← x* + Φ(dt)·(x − x*),     Φ(h) = e^(A·h)
/// ```
///
/// (this form keeps the equilibrium exact whatever the rounding of Φ). With
/// σ = ζω, Φ(h) = e^(−σh)·[[c + σ·f, f], [−ω²·f, c − σ·f]] where
///
/// - under-damped (ζ < 1), ω_d = ω·√(1−ζ²): c = cos(ω_d·h), f = sin(ω_d·h)/ω_d;
/// - critically damped (ζ = 1): c = 1, f = h;
/// - over-damped (ζ > 1), β = ω·√(ζ²−1): c = cosh(β·h), f = sinh(β·h)/β,
///   evaluated as (e^(s₁h) ± e^(s₂h))/2 with s₁ = −ω²/(σ+β), s₂ = −σ−β when
///   βh ≥ 1 (no overflow for stiff, heavily damped systems).
///
/// Φ is computed once per distinct dt and cached for the last dt.
#[derive(Clone, Debug)]
pub struct SecondOrder {
    gain: f64,
    omega: f64,
    zeta: f64,
    y: f64,
    v: f64,
    cached_dt: f64,
    phi: [f64; 4],
}

impl SecondOrder {
    /// Validates `cfg` and builds the model.
    pub fn new(cfg: SecondOrderConfig) -> Result<Self, String> {
        if !cfg.gain.is_finite() {
            return Err(format!("gain must be finite (got {})", cfg.gain));
        }
        if !(cfg.omega > 0.0 && cfg.omega.is_finite()) {
            return Err(format!("omega must be > 0 rad/s (got {})", cfg.omega));
        }
        if !(cfg.zeta >= 0.0 && cfg.zeta.is_finite()) {
            return Err(format!("zeta must be ≥ 0 (got {})", cfg.zeta));
        }
        if !cfg.initial.is_finite() {
            return Err(format!("initial must be finite (got {})", cfg.initial));
        }
        Ok(SecondOrder {
            gain: cfg.gain,
            omega: cfg.omega,
            zeta: cfg.zeta,
            y: cfg.initial,
            v: 0.0,
            cached_dt: f64::NAN,
            phi: [1.0, 0.0, 0.0, 1.0],
        })
    }

    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, String> {
        const K: &str = "second_order";
        let p = Params::new(K, t, &["gain", "omega", "period", "zeta", "initial"])?;
        let d = SecondOrderConfig::default();
        let omega = match (p.num("omega")?, p.dur("period")?) {
            (Some(_), Some(_)) => {
                return Err(format!("{K}: give either `omega` or `period`, not both"))
            }
            (Some(w), None) => w,
            (None, Some(t)) if t > 0.0 => TAU / t,
            (None, Some(_)) => return Err(format!("{K}: parameter `period`: must be > 0")),
            (None, None) => d.omega,
        };
        let cfg = SecondOrderConfig {
            gain: p.num_or("gain", d.gain)?,
            omega,
            zeta: p.num_or("zeta", d.zeta)?,
            initial: p.num_or("initial", d.initial)?,
        };
        ctx(K, Self::new(cfg))
    }

    /// The state transition matrix Φ(h) = e^(A·h), row-major.
    pub fn transition(&self, h: f64) -> [f64; 4] {
        let w = self.omega;
        let sigma = self.zeta * w;
        let (ec, ef) = if self.zeta < 1.0 {
            let wd = w * (1.0 - self.zeta * self.zeta).sqrt();
            let (s, c) = (wd * h).sin_cos();
            let e = (-sigma * h).exp();
            (e * c, e * s / wd)
        } else if self.zeta == 1.0 {
            let e = (-w * h).exp();
            (e, e * h)
        } else {
            let beta = w * (self.zeta * self.zeta - 1.0).sqrt();
            let bh = beta * h;
            if bh < 1.0 {
                let e = (-sigma * h).exp();
                (e * bh.cosh(), e * bh.sinh() / beta)
            } else {
                let s1 = -w * w / (sigma + beta);
                let s2 = -sigma - beta;
                let e1 = (s1 * h).exp();
                let e2 = (s2 * h).exp();
                (0.5 * (e1 + e2), 0.5 * (e1 - e2) / beta)
            }
        };
        [ec + sigma * ef, ef, -w * w * ef, ec - sigma * ef]
    }
}

const INPUTS: &[Port] = &[Port::Borrowed("u")];
const OUTPUTS: &[Port] = &[Port::Borrowed("y"), Port::Borrowed("rate")];

impl Model for SecondOrder {
    fn inputs(&self) -> &[Port] {
        INPUTS
    }

    fn outputs(&self) -> &[Port] {
        OUTPUTS
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        let u = analog(inputs[0]);
        if dt > 0.0 {
            if dt != self.cached_dt {
                self.phi = self.transition(dt);
                self.cached_dt = dt;
            }
            let [p11, p12, p21, p22] = self.phi;
            let ys = self.gain * u;
            let e = self.y - ys;
            let v = self.v;
            self.y = ys + p11 * e + p12 * v;
            self.v = p21 * e + p22 * v;
        }
        outputs[0] = self.y;
        outputs[1] = self.v;
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[0] = self.y;
        outputs[1] = self.v;
    }
}
