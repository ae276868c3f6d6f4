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
    pub use softplc_lang::compile::{Args, BitBlock, Block, Compiler, MAX_NESTING};

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
