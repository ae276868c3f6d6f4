//! softplc-modules: the simulated modules a rack's slots can hold
//! (`module = "…"` in a `[[slot]]` of plc.toml). Each profile is one file
//! with its buffer-memory map and the manual it follows; docs/modules.md
//! lists them. A module runs at END in the CPU's time
//! ([`softplc_ir::rack::Module`]).

#![forbid(unsafe_code)]

pub mod analog;
pub mod generic;
mod q64ad;
mod qda;
mod qi60;

use softplc_ir::rack::ModuleProfile;

pub use generic::GENERIC;
pub use q64ad::Q64AD;
pub use qda::{Q62DA, Q64DA};
pub use qi60::QI60;

/// Every module profile, by the name `plc.toml` writes.
pub static PROFILES: &[&ModuleProfile] = &[&GENERIC, &QI60, &Q64AD, &Q62DA, &Q64DA];

/// The profile named `name` (case-insensitive).
pub fn find(name: &str) -> Option<&'static ModuleProfile> {
    PROFILES
        .iter()
        .copied()
        .find(|p| p.name.eq_ignore_ascii_case(name))
}

/// The intelligent function module switch setting of a slot holding
/// `profile`, from plc.toml's `range` (range names, CH1 first) and
/// `switches` (switches 1-5), checked against what the module simulates.
/// A module without analog ranges takes any switches and no `range`.
pub fn switch_setting(
    profile: &ModuleProfile,
    range: Option<&[&str]>,
    switches: Option<[u16; 5]>,
) -> Result<[u16; 5], String> {
    match (profile.switches, range) {
        (Some(check), _) => check(range, switches),
        (None, Some(_)) => Err(format!("the {} module has no analog ranges", profile.name)),
        (None, None) => Ok(switches.unwrap_or_default()),
    }
}
