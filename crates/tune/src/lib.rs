//! softplc-tune: offline loop tuning in virtual time (issue 12, item 5).
//!
//! On a scenario (a program and its plant models, `docs/scenarios.md`) the
//! [`driver`] makes an open-loop step test on a process-control loop tag,
//! fits a first-order-plus-dead-time model to the response ([`fit`]), lists
//! the settings of the classic tuning rules in the units of S.PID
//! ([`rules`]), compares them with what S.AT1 would identify on the same
//! record ([`at1`]) and verifies one rule in closed loop with the step
//! response metrics ([`metrics`]) and an SVG trend. [`csv_fit`] fits a
//! recorded step test from a CSV file. `softplc tune` is the command line.
//!
//! ```no_run
//! use softplc_sim::scenario::Scenario;
//! use softplc_tune::driver::{tune_scenario, Options};
//!
//! let sc = Scenario::load("examples/process/fopdt_loop.toml".as_ref()).unwrap();
//! let report = tune_scenario(&sc, &Options::new("R1000")).unwrap();
//! print!("{}", report.text());
//! ```

#![forbid(unsafe_code)]

pub mod at1;
pub mod csv_fit;
pub mod driver;
pub mod fit;
pub mod loop_tag;
pub mod metrics;
pub mod report;
pub mod rules;
pub mod session;
