//! softplc-lang: the language front end. File formats ([`il`], [`csv`]) →
//! [`Source`] (tokens with file:line:column) → the compiler ([`compile`]:
//! instruction lookup in a [`dialect::Dialect`]'s instruction set, operand resolution, rung
//! checks, every diagnostic of a file) → a [`Program`] of pre-resolved ops.
//! It knows no instruction set: a dialect crate passes its `Dialect`.

#![forbid(unsafe_code)]

mod args;
pub mod audit;
pub mod compile;
pub mod csv;
pub mod dialect;
pub mod il;
pub mod isa;
pub mod resolve;
pub mod rung;
pub mod settings;
mod source;

use std::path::Path;

pub use compile::compile;
pub use softplc_ir::ops::Program;
pub use source::{is_label, Diagnostic, Diagnostics, Source, SourceInstr, SourceItem, Token};

use dialect::Dialect;
use softplc_ir::device::DeviceConfig;

/// Largest `.il` file read (a Q06HCPU holds 60k steps; a generous ~250
/// bytes a step).
pub const MAX_IL_BYTES: u64 = 16 << 20;
/// Largest `.csv` export read (UTF-16, several cells a row).
pub const MAX_CSV_BYTES: u64 = 64 << 20;

/// Reads a whole file, refusing one larger than `limit` bytes without reading
/// more than `limit + 1` (so `/dev/zero` or a huge file fails fast instead of
/// filling memory). The error says what the limit is for.
pub fn read_limited(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read file: {e}"))?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read file: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(format!(
            "file is larger than {} MiB, the limit for {what}",
            limit >> 20
        ));
    }
    Ok(bytes)
}

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
    let src = parse_file(path)?;
    compile::compile(&src, devices, dialect, common_from)
}

/// Reads and parses a program file (`.csv` a GX Works2 export, anything else
/// an `.il` list) without compiling it.
pub fn parse_file(path: &Path) -> Result<Source, Diagnostics> {
    let name = path.display().to_string();
    let (limit, what) = if is_csv(&name) {
        (MAX_CSV_BYTES, "a CSV export")
    } else {
        (MAX_IL_BYTES, "a program file")
    };
    let bytes = read_limited(path, limit, what).map_err(|message| {
        Diagnostics(vec![Diagnostic {
            file: name.clone(),
            line: 0,
            col: 0,
            message,
        }])
    })?;
    parse_bytes(&name, &bytes)
}

/// Loads program text already in memory; the format follows the file name.
pub fn load_bytes(
    name: &str,
    bytes: &[u8],
    devices: &DeviceConfig,
    dialect: &Dialect,
    common_from: Option<u32>,
) -> Result<Program, Diagnostics> {
    let src = parse_bytes(name, bytes)?;
    compile::compile(&src, devices, dialect, common_from)
}

fn is_csv(name: &str) -> bool {
    Path::new(name)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// Parses program text already in memory; the format follows the file name.
pub fn parse_bytes(name: &str, bytes: &[u8]) -> Result<Source, Diagnostics> {
    let src = if is_csv(name) {
        csv::parse_csv(name, bytes)
    } else if name.to_ascii_lowercase().ends_with(".apl") {
        Err(vec![Diagnostic {
            file: name.to_string(),
            line: 1,
            col: 1,
            message: "an .apl file is an APLC program: it is read by the APLC dialect (softplc-aplc), not as MELSEC text".into(),
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
    src.map_err(Diagnostics)
}
