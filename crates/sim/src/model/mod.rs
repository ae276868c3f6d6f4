//! Plant models. A model is a small continuous-time process advanced in steps of
//! virtual time; it knows nothing of devices (binding and scaling to X/Y/D are the
//! scenario runner's job).
//!
//! # Models
//!
//! | type name | struct | inputs | outputs |
//! |---|---|---|---|
//! | `fopdt` | [`Fopdt`] | `u` | `y` |
//! | `integrator` | [`Integrator`] | `u` | `y` |
//! | `second_order` | [`SecondOrder`] | `u` | `y`, `rate` |
//! | `tank` | [`Tank`] | `q_in`, `valve` | `level`, `overflow`, `q_out` |
//! | `heater` | [`Heater`] | `u` | `temperature` |
//! | `valve` | [`Valve`] | `open` | `position`, `opened`, `closed` |
//! | `motor` | [`Motor`] | `run` | `speed`, `running` |
//! | `noise` | [`Noise`] | none, or `u` with `input = true` | `y` |
//! | `fmu` | [`Fmu`] | the FMU's `input` variables | its `output` variables |
//!
//! Each model is built either directly (`Fopdt::new(FopdtConfig { .. })`) or by
//! type name from a TOML table with [`build`] (the scenario runner's entry
//! point). The struct documentation of each model gives its differential
//! equation, the exact discretisation used by [`Model::step`], its parameters
//! with units and defaults, and its ports.
//!
//! # Common rules
//!
//! - **Time.** `dt` is in seconds. A step with `dt <= 0` (or NaN) leaves the
//!   state unchanged and only writes the outputs. Any `dt > 0` is allowed; every
//!   model is exact for inputs held constant over the step (zero-order hold), so
//!   the result does not depend on how a time span is cut into steps (up to
//!   rounding), except where a model's documentation says otherwise.
//! - **Inputs.** `inputs` must hold (at least) `inputs().len()` values in the
//!   order of [`Model::inputs`]; `outputs` at least `outputs().len()`. A NaN or
//!   infinite analog input is read as 0. Binary inputs (`open`, `run`, on/off
//!   heater) are true when `> 0.5`. Binary outputs are 0.0 or 1.0.
//! - **Cost.** `step` does not allocate (the `fopdt` dead-time line reserves its
//!   ring buffer on the first step and only grows if the step size shrinks) and
//!   is O(1), except the `fopdt` delay line (O(number of input changes leaving
//!   the line in the step)) and `noise` with an `interval` shorter than `dt`.
//!   Transcendental functions of `dt` are cached for the last `dt`. An
//!   `fmu` step costs what the FMU's `fmi3DoStep` costs (softplc itself
//!   allocates nothing in it).
//!
//! # Parameters in TOML
//!
//! Numbers may be TOML integers or floats. Durations (`tau`, `dead_time`,
//! `travel_time`, ...) are either numbers in seconds or strings with units:
//! `"30s"`, `"500ms"`, `"2min"`, `"1h30min"`, `"250us"` (see [`parse_duration`]).
//! Unknown keys are errors (so a typo does not silently fall back to a default).

mod fmu;
mod fopdt;
mod heater;
mod integrator;
mod motor;
mod noise;
mod params;
pub mod scaling;
mod second_order;
mod tank;
mod valve;

pub use fmu::Fmu;
pub use fopdt::{Fopdt, FopdtConfig};
pub use heater::{Heater, HeaterConfig};
pub use integrator::{Integrator, IntegratorConfig};
pub use motor::{Motor, MotorConfig};
pub use noise::{Distribution, Noise, NoiseConfig};
pub use params::parse_duration;
pub use scaling::{from_raw, from_raw_clamped, to_raw};
pub use second_order::{SecondOrder, SecondOrderConfig};
pub use tank::{Tank, TankConfig};
pub use valve::{Valve, ValveConfig};

/// The name of a model port: static for the built-in models, from the
/// model description for an FMU.
pub type Port = std::borrow::Cow<'static, str>;

/// A plant model.
pub trait Model: Send {
    /// Names of the inputs it reads (actuators driven by the PLC), in order.
    fn inputs(&self) -> &[Port];
    /// Names of the outputs it produces (sensors read by the PLC), in order.
    fn outputs(&self) -> &[Port];
    /// Advances the model by `dt` seconds with `inputs` held constant over the
    /// step, then writes the outputs at the end of the step.
    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]);
    /// The outputs in the current state, without advancing.
    fn outputs_now(&self, outputs: &mut [f64]);
    /// Why the model cannot go on (an FMU call failed): it then holds its
    /// outputs and the scenario stops with this error. The built-in models
    /// never fail.
    fn fault(&self) -> Option<&str> {
        None
    }
}

/// The type names accepted by [`build`].
const KINDS: &[&str] = &[
    "fopdt",
    "integrator",
    "second_order",
    "tank",
    "heater",
    "valve",
    "motor",
    "noise",
    "fmu",
];

/// The model type names [`build`] knows, in documentation order.
pub fn kinds() -> &'static [&'static str] {
    KINDS
}

/// Builds a model from its type name and parameters (TOML table, durations as
/// strings like "30s", "500ms" or numbers in seconds).
///
/// The parameters of each type are documented on its struct ([`Fopdt`],
/// [`Integrator`], [`SecondOrder`], [`Tank`], [`Heater`], [`Valve`], [`Motor`],
/// [`Noise`], [`Fmu`]). Errors name the model type and the parameter.
pub fn build(kind: &str, params: &toml::Table) -> Result<Box<dyn Model>, String> {
    Ok(match kind {
        "fopdt" => Box::new(Fopdt::from_table(params)?),
        "integrator" => Box::new(Integrator::from_table(params)?),
        "second_order" => Box::new(SecondOrder::from_table(params)?),
        "tank" => Box::new(Tank::from_table(params)?),
        "heater" => Box::new(Heater::from_table(params)?),
        "valve" => Box::new(Valve::from_table(params)?),
        "motor" => Box::new(Motor::from_table(params)?),
        "noise" => Box::new(Noise::from_table(params)?),
        "fmu" => Box::new(Fmu::from_table(params)?),
        _ => {
            return Err(format!(
                "unknown model type `{kind}` (known: {})",
                KINDS.join(", ")
            ))
        }
    })
}

/// The input and output ports of a model, checking its parameters: an FMU's
/// from its model description only (it is not loaded), a built-in model's
/// by building it.
pub fn ports(kind: &str, params: &toml::Table) -> Result<(Vec<Port>, Vec<Port>), String> {
    if kind == "fmu" {
        return fmu::ports(params);
    }
    let m = build(kind, params)?;
    Ok((m.inputs().to_vec(), m.outputs().to_vec()))
}

/// An analog input as the models read it: NaN and ±inf become 0.
#[inline]
pub(crate) fn analog(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}

/// A binary input: true when `> 0.5` (false for NaN).
#[inline]
pub(crate) fn binary(x: f64) -> bool {
    x > 0.5
}

/// 1.0 for true, 0.0 for false.
#[inline]
pub(crate) fn bit(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// `1 − e^(−dt/τ)` (via `expm1`, accurate for small `dt/τ`), cached for the
/// last `dt`: the fraction of the way to its target a first-order lag covers
/// in `dt`. `τ = 0` gives 1; `τ = ∞` gives 0.
#[derive(Clone, Debug)]
pub(crate) struct ExpCache {
    tau: f64,
    dt: f64,
    b: f64,
}

impl ExpCache {
    pub(crate) fn new(tau: f64) -> Self {
        ExpCache {
            tau,
            dt: f64::NAN,
            b: 0.0,
        }
    }

    /// `1 − e^(−dt/τ)` for `dt > 0`.
    #[inline]
    pub(crate) fn at(&mut self, dt: f64) -> f64 {
        if dt != self.dt {
            self.b = lag_fraction(dt, self.tau);
            self.dt = dt;
        }
        self.b
    }
}

/// `1 − e^(−h/τ)` for `h > 0`, uncached.
#[inline]
pub(crate) fn lag_fraction(h: f64, tau: f64) -> f64 {
    if tau <= 0.0 {
        1.0
    } else {
        -(-h / tau).exp_m1()
    }
}

/// First-order approach of `y` to `target` by the fraction `b` (from
/// [`lag_fraction`]): `y + (target − y)·b`, exactly `target` when `b = 1`.
#[inline]
pub(crate) fn approach(y: f64, target: f64, b: f64) -> f64 {
    if b == 1.0 {
        target
    } else {
        y + (target - y) * b
    }
}

/// Moves `pos` towards `target` at `rate` units per second for `dt` seconds
/// (linear travel, `rate = inf` is instantaneous). Arrival is snapped: when the
/// remaining distance is within `1e-6` of a step's travel (plus `1e-9` units)
/// the position lands exactly on `target`, so an end position is reached at the
/// step boundary where the exact travel time elapses despite rounding.
#[inline]
pub(crate) fn ramp(pos: f64, target: f64, rate: f64, dt: f64) -> f64 {
    let travel = rate * dt;
    let rest = target - pos;
    if rest.abs() <= travel * (1.0 + 1e-6) + 1e-9 {
        target
    } else if rest > 0.0 {
        pos + travel
    } else {
        pos - travel
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_builds_with_defaults_or_reports_missing() {
        for kind in kinds() {
            let mut t = toml::Table::new();
            // The minimal parameters each type requires.
            match *kind {
                "fopdt" | "second_order" | "integrator" | "noise" | "valve" | "motor" => {}
                "tank" => {
                    t.insert("area".into(), 1.0.into());
                    t.insert("height".into(), 2.0.into());
                    t.insert("cv".into(), 0.1.into());
                }
                "heater" => {
                    t.insert("capacity".into(), 1000.0.into());
                    t.insert("power".into(), 100.0.into());
                    t.insert("resistance".into(), 0.5.into());
                }
                "fmu" => {
                    let err = build(kind, &t).err().unwrap();
                    assert_eq!(err, "fmu: parameter `file`: required (the .fmu file)");
                    continue;
                }
                _ => unreachable!(),
            }
            let m = build(kind, &t).unwrap_or_else(|e| panic!("{kind}: {e}"));
            assert!(!m.outputs().is_empty());
        }
        assert!(build("nope", &toml::Table::new()).is_err());
    }
}
