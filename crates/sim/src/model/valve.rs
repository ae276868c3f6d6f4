//! On/off valve with travel time.

use super::params::{ctx, Params};
use super::{binary, bit, ramp, Model, Port};

/// Parameters of [`Valve`].
#[derive(Clone, Debug, PartialEq)]
pub struct ValveConfig {
    /// Time for a full stroke from closed to open, in s (0 = instantaneous).
    /// Default 0.
    pub open_time: f64,
    /// Time for a full stroke from open to closed, in s (0 = instantaneous).
    /// Default 0.
    pub close_time: f64,
    /// Initial position in % (0 = closed), clamped to 0–100. Default 0.
    pub initial: f64,
}

impl Default for ValveConfig {
    fn default() -> Self {
        ValveConfig {
            open_time: 0.0,
            close_time: 0.0,
            initial: 0.0,
        }
    }
}

/// On/off actuator with travel time (`valve`), e.g. a motorised or pneumatic
/// valve with limit switches:
///
/// ```text
/// position'(t) = +100/open_time    while open = 1 and position < 100
///              = −100/close_time   while open = 0 and position > 0
/// ```
///
/// Ports: input `open` (1 = drive open, 0 = drive closed); outputs `position`
/// (0–100 %), `opened` (1 when fully open, the open limit switch) and `closed`
/// (1 when fully closed).
///
/// TOML parameters: `travel_time` (duration, sets both directions), or
/// `open_time` / `close_time` (durations; each defaults to `travel_time`,
/// else 0 = instantaneous); `initial` (%, default 0).
///
/// # Discretisation
///
/// Exact (linear travel, clamped at the ends). Arrival at an end is snapped
/// when the remaining travel is within 1e-6 of a step's travel, so after
/// exactly `open_time` (at a step boundary) the valve reads `opened` despite
/// rounding of the accumulated position.
#[derive(Clone, Debug)]
pub struct Valve {
    open_rate: f64,
    close_rate: f64,
    pos: f64,
}

impl Valve {
    /// Validates `cfg` and builds the model.
    pub fn new(cfg: ValveConfig) -> Result<Self, String> {
        for (name, v) in [("open_time", cfg.open_time), ("close_time", cfg.close_time)] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(format!("{name} must be a finite time ≥ 0 s (got {v})"));
            }
        }
        if !cfg.initial.is_finite() {
            return Err(format!("initial must be finite (got {})", cfg.initial));
        }
        Ok(Valve {
            open_rate: 100.0 / cfg.open_time,
            close_rate: 100.0 / cfg.close_time,
            pos: cfg.initial.clamp(0.0, 100.0),
        })
    }

    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, String> {
        const K: &str = "valve";
        let p = Params::new(K, t, &["travel_time", "open_time", "close_time", "initial"])?;
        let travel = p.dur_or("travel_time", 0.0)?;
        let cfg = ValveConfig {
            open_time: p.dur_or("open_time", travel)?,
            close_time: p.dur_or("close_time", travel)?,
            initial: p.num_or("initial", 0.0)?,
        };
        ctx(K, Self::new(cfg))
    }

    /// The position in %.
    pub fn position(&self) -> f64 {
        self.pos
    }
}

const INPUTS: &[Port] = &[Port::Borrowed("open")];
const OUTPUTS: &[Port] = &[
    Port::Borrowed("position"),
    Port::Borrowed("opened"),
    Port::Borrowed("closed"),
];

impl Model for Valve {
    fn inputs(&self) -> &[Port] {
        INPUTS
    }

    fn outputs(&self) -> &[Port] {
        OUTPUTS
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        if dt > 0.0 {
            self.pos = if binary(inputs[0]) {
                ramp(self.pos, 100.0, self.open_rate, dt)
            } else {
                ramp(self.pos, 0.0, self.close_rate, dt)
            };
        }
        self.outputs_now(outputs);
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[0] = self.pos;
        outputs[1] = bit(self.pos >= 100.0);
        outputs[2] = bit(self.pos <= 0.0);
    }
}
