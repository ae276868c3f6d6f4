//! softplc-modules: the simulated modules a rack's slots can hold
//! (`module = "…"` in a `[[slot]]` of plc.toml). Each profile is one file
//! with its buffer-memory map and the manual it follows; docs/modules.md
//! lists them. A module runs at END in the CPU's time
//! ([`softplc_ir::rack::Module`]).

#![forbid(unsafe_code)]

pub mod generic;
mod qi60;

use softplc_ir::rack::ModuleProfile;

pub use generic::GENERIC;
pub use qi60::QI60;

/// Every module profile, by the name `plc.toml` writes.
pub static PROFILES: &[&ModuleProfile] = &[&GENERIC, &QI60];

/// The profile named `name` (case-insensitive).
pub fn find(name: &str) -> Option<&'static ModuleProfile> {
    PROFILES
        .iter()
        .copied()
        .find(|p| p.name.eq_ignore_ascii_case(name))
}
