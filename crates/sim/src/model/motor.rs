//! Motor with speed ramp and a running feedback contact.

use super::params::{ctx, Params};
use super::{binary, bit, ramp, Model, Port};

/// Parameters of [`Motor`].
#[derive(Clone, Debug, PartialEq)]
pub struct MotorConfig {
    /// Time to accelerate from 0 to 100 % speed, in s (0 = instantaneous).
    /// Default 0.
    pub accel_time: f64,
    /// Time to decelerate from 100 % to 0, in s (0 = instantaneous). Default 0.
    pub decel_time: f64,
    /// Speed in % at or above which the running condition holds, in (0, 100].
    /// Default 50.
    pub threshold: f64,
    /// Time the running condition must hold (or be absent) before the
    /// `running` contact follows it, in s. Default 0.
    pub feedback_delay: f64,
}

impl Default for MotorConfig {
    fn default() -> Self {
        MotorConfig {
            accel_time: 0.0,
            decel_time: 0.0,
            threshold: 50.0,
            feedback_delay: 0.0,
        }
    }
}

/// Motor (`motor`) with linear acceleration/deceleration and a running
/// feedback contact (speed monitor or contactor auxiliary contact):
///
/// ```text
/// speed'(t) = +100/accel_time   while run = 1 and speed < 100
///           = −100/decel_time   while run = 0 and speed > 0
/// cond(t)   = speed(t) ≥ threshold
/// running   follows cond once cond has kept its new value for feedback_delay
/// ```
///
/// Ports: input `run` (0/1); outputs `speed` (0–100 %) and `running` (0/1).
///
/// TOML parameters: `accel_time`, `decel_time` (durations, default 0),
/// `threshold` (%, default 50), `feedback_delay` (duration, default 0).
///
/// The delay applies to both edges and is a debounce (on- and off-delay
/// timer), not a transport delay: a condition change shorter than
/// `feedback_delay` never reaches the contact. The motor starts stopped.
///
/// # Discretisation
///
/// Exact in virtual time. The speed is a linear ramp clamped at 0/100 (end
/// positions snapped as for [`Valve`](super::Valve)). Within a step the speed
/// is monotonic, so the condition changes at most once; the model computes the
/// instant the speed crosses the threshold inside the step and counts the
/// feedback delay from that instant, not from the step boundary. The contact
/// changes at the first step boundary at or after crossing + delay (with a
/// tolerance of 1e-6·dt for rounding).
#[derive(Clone, Debug)]
pub struct Motor {
    accel_rate: f64,
    decel_rate: f64,
    threshold: f64,
    delay: f64,
    speed: f64,
    cond: bool,
    /// Time the condition has held its current value.
    since: f64,
    running: bool,
}

impl Motor {
    /// Validates `cfg` and builds the model.
    pub fn new(cfg: MotorConfig) -> Result<Self, String> {
        for (name, v) in [
            ("accel_time", cfg.accel_time),
            ("decel_time", cfg.decel_time),
            ("feedback_delay", cfg.feedback_delay),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(format!("{name} must be a finite time ≥ 0 s (got {v})"));
            }
        }
        if !(cfg.threshold > 0.0 && cfg.threshold <= 100.0) {
            return Err(format!(
                "threshold must be in (0, 100] % (got {})",
                cfg.threshold
            ));
        }
        Ok(Motor {
            accel_rate: 100.0 / cfg.accel_time,
            decel_rate: 100.0 / cfg.decel_time,
            threshold: cfg.threshold,
            delay: cfg.feedback_delay,
            speed: 0.0,
            cond: false,
            since: f64::INFINITY,
            running: false,
        })
    }

    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, String> {
        const K: &str = "motor";
        let p = Params::new(
            K,
            t,
            &["accel_time", "decel_time", "threshold", "feedback_delay"],
        )?;
        let d = MotorConfig::default();
        let cfg = MotorConfig {
            accel_time: p.dur_or("accel_time", d.accel_time)?,
            decel_time: p.dur_or("decel_time", d.decel_time)?,
            threshold: p.num_or("threshold", d.threshold)?,
            feedback_delay: p.dur_or("feedback_delay", d.feedback_delay)?,
        };
        ctx(K, Self::new(cfg))
    }

    /// The speed in %.
    pub fn speed(&self) -> f64 {
        self.speed
    }
}

const INPUTS: &[Port] = &[Port::Borrowed("run")];
const OUTPUTS: &[Port] = &[Port::Borrowed("speed"), Port::Borrowed("running")];

impl Model for Motor {
    fn inputs(&self) -> &[Port] {
        INPUTS
    }

    fn outputs(&self) -> &[Port] {
        OUTPUTS
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        if dt > 0.0 {
            let s0 = self.speed;
            let (target, rate) = if binary(inputs[0]) {
                (100.0, self.accel_rate)
            } else {
                (0.0, self.decel_rate)
            };
            let s1 = ramp(s0, target, rate, dt);
            self.speed = s1;
            let cond = s1 >= self.threshold;
            if cond != self.cond {
                // Crossing instant inside the step (0 for a jump).
                let at = if rate.is_finite() {
                    ((self.threshold - s0).abs() / rate).clamp(0.0, dt)
                } else {
                    0.0
                };
                self.cond = cond;
                self.since = dt - at;
            } else {
                self.since += dt;
            }
            if self.running != cond && self.since >= self.delay - 1e-6 * dt {
                self.running = cond;
            }
        }
        self.outputs_now(outputs);
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[0] = self.speed;
        outputs[1] = bit(self.running);
    }
}
