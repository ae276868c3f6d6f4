//! Deterministic measurement noise.

use std::f64::consts::TAU;

use super::params::{ctx, Params};
use super::{analog, Model, Port};

/// The distribution of [`Noise`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distribution {
    /// Normal with the given standard deviation.
    Gaussian {
        /// Standard deviation σ, ≥ 0.
        stddev: f64,
    },
    /// Uniform on [−amplitude, +amplitude].
    Uniform {
        /// Half-width, ≥ 0.
        amplitude: f64,
    },
}

/// Parameters of [`Noise`].
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseConfig {
    /// PRNG seed; equal seeds give equal sequences. Default 0.
    pub seed: u64,
    /// Mean added to every sample. Default 0.
    pub mean: f64,
    /// Distribution. Default Gaussian with σ = 1.
    pub distribution: Distribution,
    /// Whether the model has an input `u` added to the output.
    pub input: bool,
    /// Sample-and-hold interval in s: a new sample is drawn every `interval`
    /// of virtual time, so the sequence does not depend on the step size.
    /// 0 = a new sample at every step. Default 0.
    pub interval: f64,
}

impl Default for NoiseConfig {
    fn default() -> Self {
        NoiseConfig {
            seed: 0,
            mean: 0.0,
            distribution: Distribution::Gaussian { stddev: 1.0 },
            input: false,
            interval: 0.0,
        }
    }
}

/// Noise source (`noise`):
///
/// ```text
/// y = mean + n_k (+ u)
/// ```
///
/// where n_k is the current sample of a deterministic pseudo-random sequence.
///
/// Ports: no inputs (or input `u` with `input = true`); output `y`.
///
/// TOML parameters: `seed` (integer, default 0), `mean` (default 0),
/// `distribution` (`"gaussian"` (default) or `"uniform"`), `stddev` (σ of the
/// gaussian, default 1), `amplitude` (half-width of the uniform, default 1),
/// `input` (bool, default false), `interval` (duration, default 0).
///
/// # Generator
///
/// xorshift64* (Vigna; shifts 12, 25, 27, multiplier 0x2545F4914F6CDD1D)
/// seeded through splitmix64 (so any seed, including 0, is valid). A uniform
/// u ∈ (0, 1) is `((x >> 11) + 0.5)·2⁻⁵³`; gaussian samples come in pairs from
/// Box–Muller: `√(−2 ln u₁)·(cos 2πu₂, sin 2πu₂)`. The first sample is drawn at
/// construction (what [`Model::outputs_now`] reports before the first step);
/// each step with `interval = 0` draws the next one. With `interval > 0`, the
/// sample in force at virtual time t is sample number ⌊t/interval⌋ (a step
/// draws as many as intervals ended within it).
#[derive(Clone, Debug)]
pub struct Noise {
    state: u64,
    spare: Option<f64>,
    mean: f64,
    distribution: Distribution,
    has_input: bool,
    interval: f64,
    /// Time since the current sample was drawn (with `interval > 0`).
    age: f64,
    sample: f64,
    u: f64,
}

fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Noise {
    /// Validates `cfg` and builds the model.
    pub fn new(cfg: NoiseConfig) -> Result<Self, String> {
        match cfg.distribution {
            Distribution::Gaussian { stddev: s } if !(s >= 0.0 && s.is_finite()) => {
                return Err(format!("stddev must be ≥ 0 (got {s})"))
            }
            Distribution::Uniform { amplitude: a } if !(a >= 0.0 && a.is_finite()) => {
                return Err(format!("amplitude must be ≥ 0 (got {a})"))
            }
            _ => {}
        }
        if !cfg.mean.is_finite() {
            return Err(format!("mean must be finite (got {})", cfg.mean));
        }
        if !(cfg.interval >= 0.0 && cfg.interval.is_finite()) {
            return Err(format!(
                "interval must be a finite time ≥ 0 s (got {})",
                cfg.interval
            ));
        }
        let mut state = splitmix64(cfg.seed);
        if state == 0 {
            state = 0x9E37_79B9_7F4A_7C15;
        }
        let mut n = Noise {
            state,
            spare: None,
            mean: cfg.mean,
            distribution: cfg.distribution,
            has_input: cfg.input,
            interval: cfg.interval,
            age: 0.0,
            sample: 0.0,
            u: 0.0,
        };
        n.sample = n.draw();
        Ok(n)
    }

    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, String> {
        const K: &str = "noise";
        let p = Params::new(
            K,
            t,
            &[
                "seed",
                "mean",
                "distribution",
                "stddev",
                "amplitude",
                "input",
                "interval",
            ],
        )?;
        let d = NoiseConfig::default();
        let distribution = match p.str("distribution")?.unwrap_or("gaussian") {
            "gaussian" | "normal" => {
                if p.has("amplitude") {
                    return Err(format!(
                        "{K}: `amplitude` is for the uniform distribution; use `stddev`"
                    ));
                }
                Distribution::Gaussian {
                    stddev: p.num_or("stddev", 1.0)?,
                }
            }
            "uniform" => {
                if p.has("stddev") {
                    return Err(format!(
                        "{K}: `stddev` is for the gaussian distribution; use `amplitude`"
                    ));
                }
                Distribution::Uniform {
                    amplitude: p.num_or("amplitude", 1.0)?,
                }
            }
            other => {
                return Err(format!(
                    "{K}: parameter `distribution`: `{other}` is not \"gaussian\" or \"uniform\""
                ))
            }
        };
        let cfg = NoiseConfig {
            seed: p.u64_or("seed", d.seed)?,
            mean: p.num_or("mean", d.mean)?,
            distribution,
            input: p.bool_or("input", d.input)?,
            interval: p.dur_or("interval", d.interval)?,
        };
        ctx(K, Self::new(cfg))
    }

    /// Next raw 64-bit value of xorshift64*.
    #[inline]
    fn next_u64(&mut self) -> u64 {
        let mut x = self.state;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.state = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in the open interval (0, 1).
    #[inline]
    fn next_open01(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
    }

    /// The next noise sample (without the mean).
    fn draw(&mut self) -> f64 {
        match self.distribution {
            Distribution::Uniform { amplitude } => amplitude * (2.0 * self.next_open01() - 1.0),
            Distribution::Gaussian { stddev } => {
                if let Some(z) = self.spare.take() {
                    return stddev * z;
                }
                let u1 = self.next_open01();
                let u2 = self.next_open01();
                let r = (-2.0 * u1.ln()).sqrt();
                let (s, c) = (TAU * u2).sin_cos();
                self.spare = Some(r * s);
                stddev * r * c
            }
        }
    }
}

const NO_INPUTS: &[Port] = &[];
const INPUTS: &[Port] = &[Port::Borrowed("u")];
const OUTPUTS: &[Port] = &[Port::Borrowed("y")];

impl Model for Noise {
    fn inputs(&self) -> &[Port] {
        if self.has_input {
            INPUTS
        } else {
            NO_INPUTS
        }
    }

    fn outputs(&self) -> &[Port] {
        OUTPUTS
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        if self.has_input {
            self.u = analog(inputs[0]);
        }
        if dt > 0.0 {
            if self.interval > 0.0 {
                self.age += dt;
                let tol = 1e-6 * dt.min(self.interval);
                while self.age >= self.interval - tol {
                    self.age -= self.interval;
                    self.sample = self.draw();
                }
            } else {
                self.sample = self.draw();
            }
        }
        self.outputs_now(outputs);
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[0] = self.mean + self.sample + self.u;
    }
}
