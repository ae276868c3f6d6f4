//! Ladder layout (issue #15; the page is contract §3.1's `/`): the source
//! instructions of a program file (`.il`, `.csv`) become rungs of contacts in
//! series and parallel, with coils and application-instruction boxes on the
//! right.
//!
//! - [`build`] turns a program's listing (`Program::listing`: each
//!   instruction with the ladder role its definition declares) into rung
//!   trees: loads, ANDs and ORs and the block joins make series/parallel
//!   [`Net`]s, the branch stack and outputs followed by more contacts make
//!   branches ([`Fan`]). Nothing is recognised by its mnemonic.
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

use softplc_core::access::ValueType;
use softplc_core::profile::{Profile, SourceFormat};
use softplc_core::program::{Dialect, Program, Source};
use softplc_ir::listing::{Listing, LoopUse, Role, Test};
use softplc_ir::ops::Num;

pub use build::{build, Fan, Item, Net, Rung, RungBody};

/// Whose device names a program's operands are (the names the page shows,
/// subscribes to and writes, contract §3.1 "in the program's dialect"): the
/// CPU model's naming (MELSEC's hexadecimal X/Y, the APLC's octal X/Y and
/// LM/V locals).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Names {
    profile: &'static Profile,
    /// Program locals (the APLC's LM and V) are read live: only in MAIN,
    /// whose frame is the one device memory holds at END (a subroutine's or
    /// interrupt routine's locals are gone then).
    locals: bool,
}

impl Default for Names {
    /// The default model's names (MELSEC-Q).
    fn default() -> Names {
        Names::new(softplc_core::profile::default_profile(), false)
    }
}

impl Names {
    /// The names of `profile`'s programs; `locals`: whether program locals
    /// are live devices here.
    pub fn new(profile: &'static Profile, locals: bool) -> Names {
        Names { profile, locals }
    }

    /// The value type of a device name, `None` for a constant or anything
    /// that is no device of this dialect.
    pub fn device_type(self, name: &str) -> Option<ValueType> {
        let naming = self.profile.naming;
        if !self.locals && naming.is_local(name) {
            return None;
        }
        naming.parse(name).ok().map(|n| n.ty)
    }

    /// The name of a timer's or counter's current value (`T0` → `TN0`,
    /// `C3` → `CN3`; MELSEC also `ST1` → `STN1`).
    pub fn current_value(self, dev: &str) -> Option<String> {
        self.profile.naming.current_value(dev)
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
    /// The pulse-NOT contacts: ON except on the rising / falling edge.
    RiseNot,
    FallNot,
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
            Kind::RiseNot => "risenot",
            Kind::FallNot => "fallnot",
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
    /// What its definition says it is on the ladder.
    pub role: Role,
    /// The mnemonic as written, upper case (shown, never interpreted).
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
    /// Per operand, its width when the program uses that device only as a
    /// 32-bit or real value ([`Wide`]); `None` for a word, a bit, a constant.
    pub wide: Vec<Option<Num>>,
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
        match self.role {
            Role::Contact {
                test: Test::WordBit { .. },
                ..
            } => self.operands.get(1).map(String::as_str),
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
        let wide = match self.wide.get(k).copied().flatten() {
            Some(Num::I32) => Some("i32"),
            Some(Num::F32) => Some("f32"),
            _ => None,
        };
        Some(match self.compare_type().or(wide) {
            Some(t) if !name.contains(':') => format!("{name}:{t}"),
            _ => name,
        })
    }

    /// `i32` or `f32` for a 32-bit or real comparison contact.
    fn compare_type(&self) -> Option<&'static str> {
        match self.role {
            Role::Contact {
                test: Test::Compare(Num::I32),
                ..
            } => Some("i32"),
            Role::Contact {
                test: Test::Compare(Num::F32),
                ..
            } => Some("f32"),
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

/// The devices a program uses as one 32-bit or real value
/// (`Program::used_devices`, recorded as the compiler resolved each operand:
/// EMOV's D0 is a real, DMOV's an integer of two words), so that a box shows
/// the whole value rather than its first word. A device the program also
/// uses with another width is left out: which one an instruction means is not
/// recorded per instruction.
#[derive(Clone, Debug, Default)]
pub struct Wide(Vec<(String, Num)>);

impl Wide {
    pub fn of(p: &Program) -> Wide {
        let mut wide: Vec<(String, Num)> = Vec::new();
        let mut mixed: Vec<&str> = Vec::new();
        for (name, how) in &p.used_devices {
            let num = match how {
                softplc_ir::ops::DeviceUse::Word(n) => Some(*n),
                softplc_ir::ops::DeviceUse::Bit => None,
            };
            match (num, wide.iter().position(|(d, _)| d == name)) {
                (Some(n @ (Num::I32 | Num::F32)), None) if !mixed.contains(&name.as_str()) => {
                    wide.push((name.clone(), n))
                }
                (Some(n), Some(i)) if wide[i].1 == n => {}
                (_, Some(i)) => {
                    wide.swap_remove(i);
                    mixed.push(name);
                }
                (_, None) => mixed.push(name),
            }
        }
        Wide(wide)
    }

    /// The width of operand `name`, if the program uses it only that way.
    pub fn get(&self, name: &str) -> Option<Num> {
        self.0
            .iter()
            .find(|(d, _)| d.eq_ignore_ascii_case(name))
            .map(|(_, n)| *n)
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
    /// The control-loop memories its instructions own, in program order
    /// (the faceplates' loops).
    pub loops: Vec<LoopUse>,
    /// Operand names the CPU cannot read (`U9\\G0` of a unit with no
    /// module: the program stops with SP.UNIT ERROR when it gets there),
    /// drawn but not watched, so the page's other names stay live.
    pub unreadable: Vec<String>,
    /// Operand names of which this program has its own copy (local
    /// devices): the page watches them as `NAME@FILE`, this program's.
    pub local: Vec<String>,
}

impl LadderProgram {
    /// Lays out a compiled program from its listing.
    pub fn from_program(p: &Program) -> LadderProgram {
        LadderProgram {
            file: p.file.to_string(),
            rungs: build::build_wide(&p.listing.entries, Wide::of(p)),
            loops: p.listing.loops.clone(),
            ..LadderProgram::default()
        }
    }

    /// Lays out a listing (MELSEC names) read from `file`.
    pub fn from_listing(file: &str, listing: &Listing) -> LadderProgram {
        LadderProgram {
            file: file.to_string(),
            rungs: build(&listing.entries),
            loops: listing.loops.clone(),
            ..LadderProgram::default()
        }
    }

    /// Lays out a parsed file (MELSEC-Q instruction roles) as the compiler
    /// would list it, whether or not it compiles: an unknown mnemonic
    /// draws as a box.
    pub fn from_source(src: &Source) -> LadderProgram {
        LadderProgram::from_source_in(src, softplc_core::instructions::dialect())
    }

    /// Lays out a parsed file with the instruction roles of `dialect`.
    pub fn from_source_in(src: &Source, dialect: &Dialect) -> LadderProgram {
        let listing = softplc_core::program::compile::listing(src, dialect);
        LadderProgram::from_listing(&src.file, &listing)
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

/// The ladder of every program of `cpu`: a MELSEC program's from its
/// listing; an APLC-TCP program's from its `.apl` file read again (its
/// comments and names as written are not in the listing; a file that
/// cannot be read shows as a note).
pub fn load_programs(cpu: &softplc_core::engine::Cpu) -> Vec<LadderProgram> {
    let mut programs = programs_of(cpu);
    for (slot, p) in programs.iter_mut().enumerate() {
        let mut names: Vec<String> = Vec::new();
        for r in &p.rungs {
            r.for_each(&mut |e| names.extend(e.watched()));
        }
        names.sort();
        names.dedup();
        let parsed = |n: &String| softplc_core::names::DevName::parse_for(n, cpu);
        p.local = names
            .iter()
            .filter(|n| {
                parsed(n).is_ok_and(|d| {
                    d.spec()
                        .device()
                        .is_some_and(|(kind, at)| cpu.is_local_to(slot, kind, at))
                })
            })
            .cloned()
            .collect();
        p.unreadable = names
            .into_iter()
            .filter(|n| parsed(n).and_then(|d| d.read(cpu)).is_err())
            .collect();
    }
    programs
}

/// The ladder of every program of `cpu`.
fn programs_of(cpu: &softplc_core::engine::Cpu) -> Vec<LadderProgram> {
    let format = softplc_core::profile::source_format(cpu.profile());
    (0..cpu.program_count())
        .map(|i| {
            let p = cpu.program_at(i);
            if format == SourceFormat::InstructionList {
                return LadderProgram::from_program(p);
            }
            aplc::from_file_wide(Path::new(&p.file), Wide::of(p)).unwrap_or_else(|e| {
                eprintln!("softplc: --http: no ladder for {}: {e}", p.file);
                LadderProgram {
                    file: p.file.clone(),
                    ..LadderProgram::default()
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests;
