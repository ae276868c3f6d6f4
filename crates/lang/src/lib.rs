//! softplc-lang: the language front end. File formats ([`il`], [`csv`]) →
//! [`Source`] (tokens with file:line:column) → the compiler ([`compile`]:
//! instruction lookup in a [`dialect::Dialect`]'s instruction set, operand resolution, rung
//! checks, every diagnostic of a file) → a [`Program`] of pre-resolved ops.
//! It knows no instruction set: a dialect crate passes its `Dialect`.

mod args;
pub mod compile;
pub mod csv;
pub mod dialect;
pub mod il;
pub mod isa;
pub mod resolve;
mod rung;
mod source;

use std::path::Path;

pub use compile::compile;
pub use softplc_ir::ops::Program;
pub use source::{is_label, Diagnostic, Diagnostics, Source, SourceInstr, SourceItem, Token};

use dialect::Dialect;
use softplc_ir::device::DeviceConfig;

/// Loads a program file: `.csv` is a GX Works2 export, anything else an `.il`
/// list, compiled for `dialect` with the "common pointer" parameter of a
/// project (see [`compile::compile`]). Every diagnostic of the file is returned
/// on failure.
pub fn load_file(
    path: &Path,
    devices: &DeviceConfig,
    dialect: &Dialect,
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
    load_bytes(&name, &bytes, devices, dialect, common_from)
}

/// Loads program text already in memory; the format follows the file name.
pub fn load_bytes(
    name: &str,
    bytes: &[u8],
    devices: &DeviceConfig,
    dialect: &Dialect,
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
    compile::compile(&src, devices, dialect, common_from)
}
