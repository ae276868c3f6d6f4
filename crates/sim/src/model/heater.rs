//! Heater with loss to ambient.

use super::params::{ctx, Params};
use super::{analog, approach, binary, ExpCache, Model, Port};

/// Parameters of [`Heater`].
#[derive(Clone, Debug, PartialEq)]
pub struct HeaterConfig {
    /// Thermal mass (heat capacity) C in J/K, > 0.
    pub capacity: f64,
    /// Heating power P at 100 % in W, ≥ 0.
    pub power: f64,
    /// Thermal resistance to ambient R in K/W, > 0 (`f64::INFINITY` = perfectly
    /// insulated).
    pub resistance: f64,
    /// Ambient temperature Ta in °C. Default 20.
    pub ambient: f64,
    /// Initial temperature in °C. Default: `ambient`.
    pub initial: Option<f64>,
    /// Input `u` is on/off (`> 0.5` = full power) instead of 0–100 %.
    pub on_off: bool,
}

impl Default for HeaterConfig {
    fn default() -> Self {
        HeaterConfig {
            capacity: 1.0,
            power: 0.0,
            resistance: 1.0,
            ambient: 20.0,
            initial: None,
            on_off: false,
        }
    }
}

/// Heater (`heater`): a lumped thermal mass heated electrically and losing heat
/// to ambient:
///
/// ```text
/// C·T'(t) = P·u(t)/100 − (T(t) − Ta)/R
/// ```
///
/// i.e. a first-order lag with τ = R·C towards T∞ = Ta + P·R·u/100.
///
/// Ports: input `u` (heating 0–100 %, clamped; or on/off with `on_off = true`),
/// output `temperature` (°C).
///
/// TOML parameters: `capacity` (C, J/K, required), `power` (P, W, required),
/// `resistance` (R, K/W, required; `inf` allowed), `ambient` (Ta, °C, default
/// 20), `initial` (°C, default Ta), `on_off` (bool, default false).
///
/// # Discretisation
///
/// Exact zero-order hold:
///
/// ```text
/// T ← T·e^(−dt/τ) + T∞·(1 − e^(−dt/τ))         (R finite)
/// T ← T + P·(u/100)·dt/C                       (R = ∞)
/// ```
///
/// (the first evaluated as `T + (T∞ − T)·(1 − e^(−dt/τ))` with `expm1`, so T∞
/// is an exact fixed point),
///
/// so with u held at U the temperature is
/// `T(t) = T∞ + (T0 − T∞)·e^(−t/(R·C))`, reaching `Ta + P·R·U/100`.
#[derive(Clone, Debug)]
pub struct Heater {
    capacity: f64,
    power: f64,
    resistance: f64,
    ambient: f64,
    on_off: bool,
    t: f64,
    cache: ExpCache,
}

impl Heater {
    /// Validates `cfg` and builds the model.
    pub fn new(cfg: HeaterConfig) -> Result<Self, String> {
        if !(cfg.capacity > 0.0 && cfg.capacity.is_finite()) {
            return Err(format!("capacity must be > 0 J/K (got {})", cfg.capacity));
        }
        if !(cfg.power >= 0.0 && cfg.power.is_finite()) {
            return Err(format!("power must be ≥ 0 W (got {})", cfg.power));
        }
        if cfg.resistance.is_nan() || cfg.resistance <= 0.0 {
            return Err(format!(
                "resistance must be > 0 K/W (got {})",
                cfg.resistance
            ));
        }
        if !cfg.ambient.is_finite() {
            return Err(format!("ambient must be finite (got {})", cfg.ambient));
        }
        let t0 = cfg.initial.unwrap_or(cfg.ambient);
        if !t0.is_finite() {
            return Err(format!("initial must be finite (got {t0})"));
        }
        Ok(Heater {
            capacity: cfg.capacity,
            power: cfg.power,
            resistance: cfg.resistance,
            ambient: cfg.ambient,
            on_off: cfg.on_off,
            t: t0,
            cache: ExpCache::new(cfg.resistance * cfg.capacity),
        })
    }

    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, String> {
        const K: &str = "heater";
        let p = Params::new(
            K,
            t,
            &[
                "capacity",
                "power",
                "resistance",
                "ambient",
                "initial",
                "on_off",
            ],
        )?;
        let d = HeaterConfig::default();
        let cfg = HeaterConfig {
            capacity: p.num_req("capacity")?,
            power: p.num_req("power")?,
            resistance: p.num_req("resistance")?,
            ambient: p.num_or("ambient", d.ambient)?,
            initial: p.num("initial")?,
            on_off: p.bool_or("on_off", d.on_off)?,
        };
        ctx(K, Self::new(cfg))
    }

    /// The temperature in °C.
    pub fn temperature(&self) -> f64 {
        self.t
    }
}

const INPUTS: &[Port] = &[Port::Borrowed("u")];
const OUTPUTS: &[Port] = &[Port::Borrowed("temperature")];

impl Model for Heater {
    fn inputs(&self) -> &[Port] {
        INPUTS
    }

    fn outputs(&self) -> &[Port] {
        OUTPUTS
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        if dt > 0.0 {
            let frac = if self.on_off {
                if binary(inputs[0]) {
                    1.0
                } else {
                    0.0
                }
            } else {
                analog(inputs[0]).clamp(0.0, 100.0) / 100.0
            };
            let heat = self.power * frac;
            if self.resistance.is_finite() {
                let t_inf = self.ambient + heat * self.resistance;
                let b = self.cache.at(dt);
                self.t = approach(self.t, t_inf, b);
            } else {
                self.t += heat * dt / self.capacity;
            }
        }
        outputs[0] = self.t;
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[0] = self.t;
    }
}
