//! Program loading for the MELSEC-Q CPU: the language front end
//! (softplc-lang) bound to the MELSEC-Q instruction set (softplc-melsec).

use std::path::Path;

pub use softplc_ir::ops;
pub use softplc_ir::ops::Program;
pub use softplc_lang::{
    csv, il, is_label, isa, read_limited, Diagnostic, Diagnostics, Source, SourceInstr, SourceItem,
    Token, MAX_CSV_BYTES, MAX_IL_BYTES,
};

use crate::device::DeviceConfig;

/// The compiler, bound to the MELSEC-Q instruction set.
pub mod compile {
    pub use softplc_lang::compile::{listing, Args, BitBlock, Block, Compiler, MAX_NESTING};

    use super::{DeviceConfig, Diagnostics, Program, Source};

    /// Compiles with the "common pointer" parameter: pointers from
    /// `common_from` up to P4095 are common (004 §10.9.2).
    pub fn compile_with(
        src: &Source,
        devices: &DeviceConfig,
        common_from: Option<u32>,
    ) -> Result<Program, Diagnostics> {
        softplc_lang::compile::compile(src, devices, softplc_melsec::dialect(), common_from)
    }
}

/// Compiles a parsed file for a CPU with the given device points.
pub fn compile(src: &Source, devices: &DeviceConfig) -> Result<Program, Diagnostics> {
    compile::compile_with(src, devices, None)
}

/// Loads a program file: `.csv` is a GX Works2 export, anything else an `.il` list.
/// Every diagnostic of the file is returned on failure.
pub fn load_file(path: &Path, devices: &DeviceConfig) -> Result<Program, Diagnostics> {
    load_file_with(path, devices, None)
}

/// [`load_file`] with the "common pointer" parameter of a project.
pub fn load_file_with(
    path: &Path,
    devices: &DeviceConfig,
    common_from: Option<u32>,
) -> Result<Program, Diagnostics> {
    softplc_lang::load_file(path, devices, softplc_melsec::dialect(), common_from)
}

/// Loads program text already in memory; the format follows the file name.
pub fn load_bytes(
    name: &str,
    bytes: &[u8],
    devices: &DeviceConfig,
) -> Result<Program, Diagnostics> {
    softplc_lang::load_bytes(name, bytes, devices, softplc_melsec::dialect(), None)
}

/// Compiles `.il` text (for tests and tools).
pub fn compile_il(name: &str, text: &str, devices: &DeviceConfig) -> Result<Program, Diagnostics> {
    load_bytes(name, text.as_bytes(), devices)
}

pub use softplc_lang::dialect::Dialect;
pub use softplc_melsec::process::settings::ProcessSettings;

/// The dialect a CPU model compiles in (see [`crate::profile::dialect`]).
pub fn dialect_for(profile: &crate::profile::Profile, process: ProcessSettings) -> Dialect {
    crate::profile::dialect(profile, process)
}

/// [`load_file_with`] in a given dialect (see [`dialect_for`]).
pub fn load_file_in(
    path: &Path,
    devices: &DeviceConfig,
    dialect: &Dialect,
    common_from: Option<u32>,
) -> Result<Program, Diagnostics> {
    softplc_lang::load_file(path, devices, dialect, common_from)
}

/// [`compile_il`] in a given dialect (see [`dialect_for`]).
pub fn compile_il_in(
    name: &str,
    text: &str,
    devices: &DeviceConfig,
    dialect: &Dialect,
) -> Result<Program, Diagnostics> {
    softplc_lang::load_bytes(name, text.as_bytes(), devices, dialect, None)
}

/// Loads a single MELSEC program file (`softplc run`/`check` of an `.il` or
/// `.csv`) for the model it runs on: `model` (`--model`) when given, else the
/// model a GX Works2 export names in its `PLC Information` row, else the
/// Q06HCPU. `--model` takes precedence over the file's row (to run an export
/// on another CPU). The program compiles in the model's dialect, against its
/// default devices, and must fit its program memory.
pub fn load_single(
    path: &Path,
    model: Option<&'static crate::profile::Profile>,
) -> Result<(&'static crate::profile::Profile, Program), Diagnostics> {
    load_single_or(path, model, crate::profile::default_profile())
}

/// [`load_single`] with `fallback` (a `--dialect` family's model) instead
/// of the Q06HCPU when neither `model` nor the file names one.
pub fn load_single_or(
    path: &Path,
    model: Option<&'static crate::profile::Profile>,
    fallback: &'static crate::profile::Profile,
) -> Result<(&'static crate::profile::Profile, Program), Diagnostics> {
    let src = softplc_lang::parse_file(path)?;
    let profile = match (model, &src.model) {
        (Some(p), _) => p,
        (None, Some(named)) => named_model(&src.file, named)?,
        (None, None) => fallback,
    };
    let devices = (profile.default_devices)();
    let dialect = dialect_for(profile, ProcessSettings::default());
    let program = softplc_lang::compile(&src, &devices, &dialect, None)?;
    crate::project::check_capacity(profile, &[(program.file.as_str(), program.steps)])
        .map_err(|d| Diagnostics(vec![d]))?;
    let mut broken = Vec::new();
    crate::project::step_relays(&program, &mut broken);
    if !broken.is_empty() {
        return Err(Diagnostics(broken));
    }
    Ok((profile, program))
}

/// The MELSEC model a file names (`Q04UDEH` or `Q04UDEHCPU`, any case).
fn named_model(file: &str, named: &Token) -> Result<&'static crate::profile::Profile, Diagnostics> {
    let text = named.text.as_str();
    crate::profile::find(text)
        .or_else(|_| crate::profile::find(&format!("{text}CPU")))
        .ok()
        .filter(|p| !crate::profile::is_aplc(p))
        .ok_or_else(|| {
            Diagnostics(vec![Diagnostic::at(
                file,
                named,
                format!(
                    "the PLC Information row names the CPU model `{text}`, which softplc does \
                     not run (a MELSEC-Q, QnPH or Universal QnU model); give --model to run \
                     the program on one"
                ),
            )])
        })
}
