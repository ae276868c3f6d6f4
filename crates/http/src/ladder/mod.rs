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
//! - [`aplc`] lays out an APLC `.apl` file the same way: one section per
//!   POU, operands shown as written and as their devices, SFC steps.
//!
//! Malformed lists never panic: a connection without its block is drawn as
//! it comes.

pub mod aplc;
pub mod build;
pub mod grid;
pub mod render;

use std::path::Path;

use softplc_core::access::{DeviceSpec, ValueType};
use softplc_core::program::{Dialect, Source, SourceItem};

pub use build::{build, Fan, Item, Net, Rung, RungBody};

/// Whose device names a program's operands are (the names the page shows,
/// subscribes to and writes, contract §3.1 "in the program's dialect").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Names {
    /// MELSEC-Q (`--show` names, hexadecimal X/Y).
    #[default]
    Melsec,
    /// APLC-TCP (`softplc_aplc::names`, octal X/Y). `locals`: LM and V are
    /// read live; only in MAIN, whose frame is the one device memory holds
    /// at END (a subroutine's or interrupt routine's locals are gone then).
    Aplc { locals: bool },
}

impl Names {
    /// The value type of a device name, `None` for a constant or anything
    /// that is no device of this dialect.
    pub fn device_type(self, name: &str) -> Option<ValueType> {
        match self {
            Names::Melsec => DeviceSpec::parse(name).ok().map(|d| d.ty),
            Names::Aplc { locals } => {
                let u = name.to_ascii_uppercase();
                if !locals && (u.starts_with('V') || u.contains("LM")) {
                    return None;
                }
                softplc_aplc::names::Name::parse(name).ok().map(|n| n.ty)
            }
        }
    }

    /// The name of a timer's or counter's current value (`T0` → `TN0`,
    /// `C3` → `CN3`; MELSEC also `ST1` → `STN1`).
    pub fn current_value(self, dev: &str) -> Option<String> {
        let u = dev.to_ascii_uppercase();
        let kinds: &[(&str, &str)] = match self {
            Names::Melsec => &[("ST", "STN"), ("T", "TN"), ("C", "CN")],
            Names::Aplc { .. } => &[("T", "TN"), ("C", "CN")],
        };
        for (p, n) in kinds {
            if let Some(rest) = u.strip_prefix(p) {
                if !rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit()) {
                    return Some(format!("{n}{rest}"));
                }
            }
        }
        None
    }
}

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
    /// An SFC step (APLC `STL Sn`, a run of STLs for a merge): a box on the
    /// rail, active while all its steps are ON.
    Step,
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
            Kind::Step => "step",
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
    /// Whose names the operands are.
    pub names: Names,
    /// Per operand, how the source wrote it where that differs from the
    /// device (`#RUNOK` for LM0, a global's name); empty otherwise.
    pub aliases: Vec<String>,
    /// A CALL's parameter names, in operand order from the second operand.
    pub params: Vec<String>,
}

impl Elem {
    /// Operands that are devices (their `--show` names), constants left out.
    pub fn devices(&self) -> impl Iterator<Item = &str> {
        self.operands
            .iter()
            .map(String::as_str)
            .filter(|o| self.names.device_type(o).is_some())
    }

    /// Operand `k` as shown: `NAME=DEVICE` where the source wrote a name,
    /// `PARAM=ARG` for a CALL's arguments.
    pub fn label(&self, k: usize) -> String {
        let op = self.operands.get(k).map_or("", String::as_str);
        let shown = match self.aliases.get(k).filter(|a| !a.is_empty()) {
            Some(a) => format!("{a}={op}"),
            None => op.to_string(),
        };
        match k.checked_sub(1).and_then(|p| self.params.get(p)) {
            Some(p) => format!("{p}:={shown}"),
            None => shown,
        }
    }

    /// The bit number of a word-bit contact (APLC `BLD D0 5`: bit 5 of D0).
    pub fn word_bit(&self) -> Option<&str> {
        match self.kind {
            Kind::No | Kind::Nc if self.operands.len() == 2 => Some(&self.operands[1]),
            _ => None,
        }
    }

    /// All operands as shown, separated by blanks.
    pub fn labels(&self) -> String {
        (0..self.operands.len())
            .map(|k| self.label(k))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The word values a box, comparison or timer coil shows.
    pub fn values(&self) -> Vec<String> {
        (0..self.operands.len())
            .filter_map(|k| self.word_value(k))
            .collect()
    }

    /// Operand `k` read as a word, `None` for a constant: a word device, a
    /// timer's or counter's current value for T/C, and in a 32-bit or REAL
    /// comparison (`LDD>=`, `LDR<`, MELSEC `LDD=`, `LDE>`) the typed name
    /// (`D20:i32`), as the page's script compares them.
    pub fn word_value(&self, k: usize) -> Option<String> {
        let d = self.operands.get(k)?;
        let name = match self.names.device_type(d)? {
            ValueType::Bit => self.names.current_value(d)?,
            _ => d.clone(),
        };
        Some(match self.compare_type() {
            Some(t) if !name.contains(':') => format!("{name}:{t}"),
            _ => name,
        })
    }

    /// `i32` or `f32` for a 32-bit or real comparison contact.
    fn compare_type(&self) -> Option<&'static str> {
        if self.kind != Kind::Compare {
            return None;
        }
        let m = &self.mnemonic;
        let rest = ["LD", "AND", "OR"].iter().find_map(|p| m.strip_prefix(p))?;
        match rest.chars().next()? {
            'D' => Some("i32"),
            'E' | 'R' => Some("f32"),
            _ => None,
        }
    }

    /// The names the page subscribes to for this element: its devices, and
    /// the values it shows.
    pub fn watched(&self) -> Vec<String> {
        let mut v: Vec<String> = self.devices().map(str::to_string).collect();
        if matches!(self.kind, Kind::Coil | Kind::Box | Kind::Compare) {
            v.extend(self.values());
        }
        v
    }
}

/// A POU of an APLC program: its rungs from `first` to the next section.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Section {
    /// `MAIN`, `SBR_1`, `INT_1 EVENT 26`.
    pub title: String,
    /// Its local variables, `NAME KIND TYPE = ADDRESS` each.
    pub vars: Vec<String>,
    /// Index of its first rung.
    pub first: usize,
}

/// A program file as ladder rungs.
#[derive(Clone, Debug, Default)]
pub struct LadderProgram {
    pub file: String,
    pub rungs: Vec<Rung>,
    /// The POUs (APLC), empty for MELSEC files.
    pub sections: Vec<Section>,
    /// Comment lines before the file's first instruction or declaration.
    pub comment: Vec<String>,
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
            ..LadderProgram::default()
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
            for d in &r.bus {
                if seen.insert(d.clone()) {
                    out.push(d.clone());
                }
            }
        }
        out
    }
}

/// The ladder of every program file of `cpu`, read again from the files it
/// was compiled from (a file that cannot be read shows as a note), with the
/// instruction classes of the CPU model's dialect: an APLC-TCP CPU's files
/// as `.apl`.
pub fn load_programs(cpu: &softplc_core::engine::Cpu) -> Vec<LadderProgram> {
    let profile = cpu.profile();
    let dialect = softplc_core::profile::dialect(profile, Default::default());
    (0..cpu.program_count())
        .map(|i| {
            let file = &cpu.program_at(i).file;
            let path = Path::new(file);
            let ladder = if softplc_core::profile::is_aplc(profile) {
                aplc::from_file(path)
            } else {
                LadderProgram::from_file_in(path, &dialect)
            };
            ladder.unwrap_or_else(|e| {
                eprintln!("softplc: --http: no ladder for {file}: {e}");
                LadderProgram {
                    file: file.clone(),
                    ..LadderProgram::default()
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
