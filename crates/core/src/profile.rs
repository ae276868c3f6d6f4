//! The CPU models softplc runs: every dialect's [`Profile`]s in one list,
//! found by model name or family, each with the instruction set and
//! language dialect its programs compile in.

pub use softplc_ir::profile::{Capacity, Doors, NamedDevice, Naming, Profile};

use crate::engine::CpuConfig;
use crate::program::{Dialect, ProcessSettings};

/// Every model: MELSEC's, then the APLC-TCP.
pub fn all() -> impl Iterator<Item = &'static Profile> {
    softplc_melsec::profiles::PROFILES
        .iter()
        .chain([&softplc_aplc::profile::PROFILE])
}

/// The profile of a model name (any case).
pub fn find(model: &str) -> Result<&'static Profile, String> {
    let up = model.trim().to_ascii_uppercase();
    all().find(|p| p.model == up).ok_or_else(|| {
        let list: Vec<&str> = all().map(|p| p.model).collect();
        let (last, rest) = list.split_last().expect("models");
        format!(
            "unknown CPU model \"{}\" (expected {}, or {last})",
            model.trim(),
            rest.join(", ")
        )
    })
}

/// The model a project or program gets when none is named: the Q06HCPU.
pub fn default_profile() -> &'static Profile {
    softplc_melsec::profiles::default_profile()
}

/// The APLC-TCP.
pub fn aplc() -> &'static Profile {
    &softplc_aplc::profile::PROFILE
}

/// The families (`MELSEC-Q`, `MELSEC-QnPH`, `MELSEC-QnU`, `APLC`), each once, in the
/// order of [`all`].
pub fn families() -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for p in all() {
        if !out.contains(&p.family) {
            out.push(p.family);
        }
    }
    out
}

/// The first model of a family given by name (`melsec`/`MELSEC-Q`, `aplc`):
/// what `--dialect` selects for a single program file.
pub fn of_family(name: &str) -> Option<&'static Profile> {
    let want = name.trim();
    let want = if want.eq_ignore_ascii_case("melsec") {
        softplc_melsec::profiles::FAMILY_Q
    } else {
        want
    };
    if want.eq_ignore_ascii_case(default_profile().family) {
        return Some(default_profile());
    }
    all().find(|p| p.family.eq_ignore_ascii_case(want))
}

/// Whether programs of `profile` are `.apl` files (the APLC's language)
/// rather than MELSEC instruction lists.
pub fn is_aplc(profile: &Profile) -> bool {
    profile.family == softplc_aplc::profile::FAMILY
}

/// How a model's program files are written, for the tools that read them
/// (the loaders of single files and the ladder view).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SourceFormat {
    /// Instruction lists: `.il` text or a GX Works2 `.csv` export (MELSEC).
    InstructionList,
    /// POU text: `.apl` files of POUs with their variable tables (the APLC).
    Pou,
}

impl SourceFormat {
    /// The format a program file is read in by default: by its name,
    /// `.apl` (any case) is POU text.
    pub fn of_file(path: &std::path::Path) -> SourceFormat {
        if crate::aplc::is_apl(path) {
            SourceFormat::Pou
        } else {
            SourceFormat::InstructionList
        }
    }

    /// The model a file of this format runs on when none is named.
    pub fn default_profile(self) -> &'static Profile {
        match self {
            SourceFormat::InstructionList => default_profile(),
            SourceFormat::Pou => aplc(),
        }
    }
}

/// The format of `profile`'s program files.
pub fn source_format(profile: &Profile) -> SourceFormat {
    if is_aplc(profile) {
        SourceFormat::Pou
    } else {
        SourceFormat::InstructionList
    }
}

/// The language dialect `.il`/`.csv` programs of a MELSEC model compile in:
/// the process CPU's or the redundant CPU's (with the project's `[process]`
/// decisions), the Universal models' or MELSEC-Q's. (An APLC-TCP compiles `.apl` files:
/// [`crate::aplc`].)
pub fn dialect(profile: &Profile, process: ProcessSettings) -> Dialect {
    use softplc_melsec::profiles::{FAMILY_QNPH, FAMILY_QNU};
    match profile.family {
        FAMILY_QNPH if softplc_melsec::is_redundant_model(profile.model) => {
            softplc_melsec::redundant_dialect(process)
        }
        FAMILY_QNPH => softplc_melsec::process_dialect(process),
        FAMILY_QNU => softplc_melsec::qnu_dialect().clone(),
        _ => softplc_melsec::dialect().clone(),
    }
}

/// The settings' defaults for a CPU of `profile`.
pub fn config(profile: &'static Profile) -> CpuConfig {
    CpuConfig::new(profile)
}

/// A Q06HCPU's defaults: the CPU of a project without `[cpu] model`.
pub fn default_config() -> CpuConfig {
    CpuConfig::new(default_profile())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn models_are_found_by_name_in_any_case() {
        assert_eq!(find("q25phcpu").unwrap().family, "MELSEC-QnPH");
        assert_eq!(find(" APLC-TCP ").unwrap(), aplc());
        let e = find("Q99CPU").unwrap_err();
        assert!(
            e.starts_with("unknown CPU model \"Q99CPU\" (expected Q02CPU, "),
            "{e}"
        );
        assert_eq!(of_family("aplc").unwrap(), aplc());
        assert_eq!(of_family("melsec").unwrap().model, "Q06HCPU");
        assert_eq!(
            families(),
            ["MELSEC-Q", "MELSEC-QnPH", "MELSEC-QnU", "APLC"]
        );
    }
}
