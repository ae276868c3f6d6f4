//! Ladder layout (issue #15; the page is contract §3.1's `/`): the source
//! instructions of a program file (`.il`, `.csv`) become rungs of contacts in
//! series and parallel, with coils and application-instruction boxes on the
//! right.
//!
//! - [`build`] turns the instruction list into rung trees: LD/AND/OR and
//!   ANB/ORB make series/parallel [`Net`]s, MPS/MRD/MPP and outputs followed
//!   by more contacts make branches ([`Fan`]). Which instruction is a
//!   contact, a connection, an output or standalone comes from the dialect's
//!   instruction classes; only the structural connection instructions and the
//!   LD/AND/OR prefixes are read by name.
//! - [`grid`] places a rung on a grid of cells;
//! - [`render`] draws the grid as text (the snapshot tests) and as SVG with an
//!   element id per contact and coil and the device names to colour them live.
//!
//! Malformed lists never panic: a connection without its block is drawn as
//! it comes.

pub mod build;
pub mod grid;
pub mod render;

use std::path::Path;

use softplc_core::program::{Dialect, Source, SourceItem};

pub use build::{build, Fan, Item, Net, Rung, RungBody};

/// What an element draws as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Normally open, normally closed, rising and falling edge contacts.
    No,
    Nc,
    Rise,
    Fall,
    /// A comparison contact (`LD= D0 K5`).
    Compare,
    /// INV, MEP, MEF, EGP, EGF: an operation on the result, in series.
    Modifier,
    /// OUT of a bit device (timer and counter coils included).
    Coil,
    /// SET and RST of a bit.
    Set,
    Reset,
    /// An application instruction (and other outputs) as a box.
    Box,
    /// END, FEND, MCR, NEXT, RET …: a rung of its own.
    Standalone,
}

impl Kind {
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::No => "no",
            Kind::Nc => "nc",
            Kind::Rise => "rise",
            Kind::Fall => "fall",
            Kind::Compare => "cmp",
            Kind::Modifier => "mod",
            Kind::Coil => "coil",
            Kind::Set => "set",
            Kind::Reset => "rst",
            Kind::Box => "box",
            Kind::Standalone => "end",
        }
    }
}

/// One instruction as drawn.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Elem {
    /// Index of the element in its program (element id on the page).
    pub id: u32,
    pub kind: Kind,
    pub mnemonic: String,
    pub operands: Vec<String>,
    /// Source line.
    pub line: u32,
}

impl Elem {
    /// Operands that are devices (their `--show` names), constants left out.
    pub fn devices(&self) -> impl Iterator<Item = &str> {
        self.operands
            .iter()
            .map(String::as_str)
            .filter(|o| softplc_core::access::DeviceSpec::parse(o).is_ok())
    }
}

/// A program file as ladder rungs.
#[derive(Clone, Debug, Default)]
pub struct LadderProgram {
    pub file: String,
    pub rungs: Vec<Rung>,
}

impl LadderProgram {
    /// Lays out a parsed file (MELSEC-Q instruction classes).
    pub fn from_source(src: &Source) -> LadderProgram {
        LadderProgram::from_source_in(src, softplc_core::instructions::dialect())
    }

    /// Lays out a parsed file with the instruction classes of `dialect`.
    pub fn from_source_in(src: &Source, dialect: &Dialect) -> LadderProgram {
        LadderProgram {
            file: src.file.clone(),
            rungs: build(src, dialect),
        }
    }

    /// Reads and lays out a program file (`.csv` or `.il`) as MELSEC-Q.
    pub fn from_file(path: &Path) -> Result<LadderProgram, String> {
        LadderProgram::from_file_in(path, softplc_core::instructions::dialect())
    }

    /// Reads and lays out a program file in `dialect`.
    pub fn from_file_in(path: &Path, dialect: &Dialect) -> Result<LadderProgram, String> {
        let name = path.display().to_string();
        let is_csv = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let limit = if is_csv {
            softplc_core::program::MAX_CSV_BYTES
        } else {
            softplc_core::program::MAX_IL_BYTES
        };
        let bytes = softplc_core::program::read_limited(path, limit, "a program file")?;
        let src = if is_csv {
            softplc_core::program::csv::parse_csv(&name, &bytes)
        } else {
            let text = String::from_utf8_lossy(&bytes);
            softplc_core::program::il::parse_il(&name, &text)
        }
        .map_err(|d| {
            d.first()
                .map_or_else(|| "cannot parse".to_string(), |d| d.to_string())
        })?;
        Ok(LadderProgram::from_source_in(&src, dialect))
    }

    /// Every device the program names, once, in order of appearance.
    pub fn devices(&self) -> Vec<String> {
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        for r in &self.rungs {
            r.for_each(&mut |e| {
                for d in e.devices() {
                    if seen.insert(d.to_string()) {
                        out.push(d.to_string());
                    }
                }
            });
        }
        out
    }
}

/// The ladder of every program file of `cpu`, read again from the files it
/// was compiled from (a file that cannot be read shows as a note), with the
/// instruction classes of the CPU model's dialect.
pub fn load_programs(cpu: &softplc_core::engine::Cpu) -> Vec<LadderProgram> {
    let dialect = softplc_core::program::dialect_for(&cpu.config().model, Default::default());
    (0..cpu.program_count())
        .map(|i| {
            let file = &cpu.program_at(i).file;
            LadderProgram::from_file_in(Path::new(file), &dialect).unwrap_or_else(|e| {
                eprintln!("softplc: --http: no ladder for {file}: {e}");
                LadderProgram {
                    file: file.clone(),
                    rungs: Vec::new(),
                }
            })
        })
        .collect()
}

/// Items of a source as (label before it, instruction).
pub(crate) fn items(src: &Source) -> impl Iterator<Item = &SourceItem> {
    src.items.iter()
}

#[cfg(test)]
mod tests;
