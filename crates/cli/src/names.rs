//! The `--dialect` option; device names are `softplc_core::names::DevName`.

use softplc_core::profile::{self, Profile};

/// `--dialect`: a family by name (`melsec`, `aplc`, `MELSEC-QnPH`, any
/// case), as its first model.
pub fn parse_family(text: &str) -> Result<&'static Profile, String> {
    profile::of_family(text).ok_or_else(|| {
        format!(
            "unknown dialect `{}` (expected melsec, aplc or a family: {})",
            text.trim(),
            profile::families().join(", ")
        )
    })
}
