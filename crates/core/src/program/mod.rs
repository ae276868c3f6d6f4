//! Program loading: file formats → [`Source`] → compiled [`Program`].

mod args;
pub mod compile;
pub mod csv;
pub mod il;
pub mod isa;
pub mod ops;
pub(crate) mod resolve;
mod rung;
mod source;

use std::path::Path;

pub use compile::compile;
pub use ops::Program;
pub use source::{is_label, Diagnostic, Diagnostics, Source, SourceInstr, SourceItem, Token};

use crate::device::DeviceConfig;

/// Loads a program file: `.csv` is a GX Works2 export, anything else an `.il` list.
/// Every diagnostic of the file is returned on failure.
pub fn load_file(path: &Path, devices: &DeviceConfig) -> Result<Program, Diagnostics> {
    load_file_with(path, devices, None)
}

/// [`load_file`] with the "common pointer" parameter of a project
/// (see [`compile::compile_with`]).
pub fn load_file_with(
    path: &Path,
    devices: &DeviceConfig,
    common_from: Option<u32>,
) -> Result<Program, Diagnostics> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        Diagnostics(vec![Diagnostic {
            file: name.clone(),
            line: 0,
            col: 0,
            message: format!("cannot read file: {e}"),
        }])
    })?;
    load_bytes_with(&name, &bytes, devices, common_from)
}

/// Loads program text already in memory; the format follows the file name.
pub fn load_bytes(
    name: &str,
    bytes: &[u8],
    devices: &DeviceConfig,
) -> Result<Program, Diagnostics> {
    load_bytes_with(name, bytes, devices, None)
}

fn load_bytes_with(
    name: &str,
    bytes: &[u8],
    devices: &DeviceConfig,
    common_from: Option<u32>,
) -> Result<Program, Diagnostics> {
    let is_csv = Path::new(name)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let src = if is_csv {
        csv::parse_csv(name, bytes)
    } else if name.to_ascii_lowercase().ends_with(".apl") {
        Err(vec![Diagnostic {
            file: name.to_string(),
            line: 1,
            col: 1,
            message: "unsupported: the APLC dialect (.apl) is not implemented yet".into(),
        }])
    } else {
        match std::str::from_utf8(bytes) {
            Ok(text) => il::parse_il(name, text),
            Err(e) => Err(vec![Diagnostic {
                file: name.to_string(),
                line: 1 + bytes[..e.valid_up_to()]
                    .iter()
                    .filter(|b| **b == b'\n')
                    .count() as u32,
                col: 1,
                message: "the file is not UTF-8 text".into(),
            }]),
        }
    };
    let src = src.map_err(Diagnostics)?;
    compile::compile_with(&src, devices, common_from)
}

/// Compiles `.il` text (for tests and tools).
pub fn compile_il(name: &str, text: &str, devices: &DeviceConfig) -> Result<Program, Diagnostics> {
    load_bytes(name, text.as_bytes(), devices)
}
