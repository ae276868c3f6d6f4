//! One program file run on its own, not in a project (`softplc run`,
//! `check` and `serve` of a file, a scenario's `program`): the CPU model it
//! runs on and the powered-on CPU. Which language the file is written in
//! (MELSEC instruction lists, APLC POU text) is decided here and in
//! [`crate::profile::source_format`], so that no command branches on a
//! dialect.

use std::fmt;
use std::path::Path;

use crate::engine::calendar::DateTime;
use crate::engine::{Clock, Cpu, CpuConfig};
use crate::profile::{self, Profile, SourceFormat};
use crate::program::{self, Diagnostics};

/// The model a single program file runs on: `model` (`--model`, a
/// scenario's `cpu`) if given, else the first model of `family`
/// (`--dialect`), else the default model of the file's format by its name
/// (`.apl`: the APLC-TCP; anything else: the Q06HCPU). A given model must
/// read the file's format (`family`'s, else the file name's).
pub fn profile_for(
    path: &Path,
    model: Option<&'static Profile>,
    family: Option<&'static Profile>,
) -> Result<&'static Profile, String> {
    let format = family.map_or_else(|| SourceFormat::of_file(path), profile::source_format);
    match model {
        Some(m) if profile::source_format(m) != format => Err(format!(
            "{} does not run {} (the APLC-TCP runs .apl programs, a MELSEC model .il/.csv)",
            m.model,
            path.display()
        )),
        Some(m) => Ok(m),
        None => Ok(family.unwrap_or_else(|| format.default_profile())),
    }
}

/// What a single file's CPU takes besides its model's defaults.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The calendar at power-on (`--clock`).
    pub clock_start: Option<DateTime>,
    /// The serial ports' settings of a model that has them (a scenario's
    /// `[port1]`/`[port2]`).
    pub ports: Vec<crate::aplc::PortConfig>,
    /// The model was given (`--model`, a scenario's `cpu`): a model the
    /// file names itself (a GX Works2 export's PLC Information row) does
    /// not replace it. Otherwise the file's model outranks the default.
    pub explicit_model: bool,
}

/// Why a single file does not run.
#[derive(Debug)]
pub enum LoadError {
    /// The program does not compile or does not fit the model.
    Program(Diagnostics),
    /// The CPU refuses the program (e.g. an APLC file without `POU MAIN`).
    Cpu(String),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::Program(d) => d.fmt(f),
            LoadError::Cpu(e) => f.write_str(e),
        }
    }
}

/// Loads `path` as the one program of a `profile` CPU (see [`profile_for`])
/// with the model's default settings and powers it on.
pub fn load(
    path: &Path,
    profile: &'static Profile,
    options: Options,
    clock: Box<dyn Clock>,
) -> Result<Cpu, LoadError> {
    match profile::source_format(profile) {
        SourceFormat::InstructionList => {
            // Compiled against the model's own devices (its file registers).
            let (profile, program) =
                program::load_single_or(path, options.explicit_model.then_some(profile), profile)
                    .map_err(LoadError::Program)?;
            let mut cfg = CpuConfig::new(profile);
            if let Some(t) = options.clock_start {
                cfg.clock_start = t;
            }
            Ok(Cpu::new(program, cfg, clock))
        }
        SourceFormat::Pou => {
            let program = crate::aplc::load_file(path).map_err(LoadError::Program)?;
            let mut cfg = crate::aplc::cpu_config_with_ports(
                crate::aplc::cpu_config().watchdog,
                None,
                options.ports,
            );
            cfg.profile = profile;
            if let Some(t) = options.clock_start {
                cfg.clock_start = t;
            }
            crate::aplc::single_cpu(program, cfg, clock).map_err(LoadError::Cpu)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_model_follows_the_option_the_family_or_the_file_name() {
        let (q06, aplc) = (profile::default_profile(), profile::aplc());
        let q25ph = profile::find("Q25PHCPU").unwrap();
        let il = Path::new("a.il");
        let apl = Path::new("b.APL");
        assert_eq!(profile_for(il, None, None), Ok(q06));
        assert_eq!(profile_for(apl, None, None), Ok(aplc));
        assert_eq!(profile_for(il, None, Some(aplc)), Ok(aplc));
        assert_eq!(profile_for(apl, None, Some(q06)), Ok(q06));
        assert_eq!(profile_for(il, Some(q25ph), None), Ok(q25ph));
        assert_eq!(profile_for(apl, Some(q25ph), Some(q06)), Ok(q25ph));
        let e = profile_for(il, Some(aplc), None).unwrap_err();
        assert!(e.starts_with("APLC-TCP does not run a.il"), "{e}");
        let e = profile_for(apl, Some(q06), None).unwrap_err();
        assert!(e.starts_with("Q06HCPU does not run b.APL"), "{e}");
        let e = profile_for(il, Some(q06), Some(aplc)).unwrap_err();
        assert!(e.starts_with("Q06HCPU does not run a.il"), "{e}");
    }
}
