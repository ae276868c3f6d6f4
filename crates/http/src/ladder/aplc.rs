//! The ladder of an APLC-TCP `.apl` file (contract §1.1, spec aplc.md §3):
//! the file is read by the APLC dialect's own reader
//! ([`softplc_aplc::outline`]: the tokens, POUs and variable tables the
//! compiler uses, before `#NAME` and global names are substituted) and laid
//! out by the same rung builder as MELSEC files, with the APLC instruction
//! classes ([`softplc_aplc::dialect`]) and APLC device names
//! (the APLC-TCP's [`Names`]: octal X/Y, LM/V, TN/CN).
//!
//! - One [`Section`] per POU (MAIN, `SBR_<n>`, `INT_<n> EVENT <e>`) with its
//!   variable table; comment lines above a rung are its comment.
//! - An operand written as `#NAME` or a global's name is drawn `NAME=DEVICE`
//!   and the device is what the page reads and writes; a CALL's arguments
//!   carry the callee's parameter names (`IN1:=3`), all as the dialect's
//!   outline shows them ([`softplc_aplc::Shown`]).
//! - SFC (002 §5.2 L3019-3101): a run of SFC steps draws as one step box on
//!   a rung of its own, and the step's body rungs take their rail power
//!   from the step(s) (up to the end of the SFC section or of the POU, as
//!   the compiler scopes them); `SET Sn`/`OUT Sn` transitions draw as coils.
//! - Labels and jumps are instructions in this dialect: LBL a rung of its
//!   own, CJ a box (L3601-3666).

use std::path::Path;

use softplc_aplc::pou::{Pou, PouKind};

use super::build::{Builder, Notes};
use super::{LadderProgram, Names, Section, Wide};

/// Reads and lays out an `.apl` file (any file name).
pub fn from_file(path: &Path) -> Result<LadderProgram, String> {
    from_file_wide(path, Wide::default())
}

/// [`from_file`] showing the operands of `wide` (the compiled program's
/// 32-bit and real devices) as whole values.
pub fn from_file_wide(path: &Path, wide: Wide) -> Result<LadderProgram, String> {
    let name = path.display().to_string();
    let bytes = softplc_core::program::read_limited(
        path,
        softplc_core::program::MAX_IL_BYTES,
        "a program file",
    )?;
    layout(&name, &bytes, wide)
}

/// Lays out `.apl` text (UTF-8 or GB18030 bytes) read from `name`.
pub fn from_bytes(name: &str, bytes: &[u8]) -> Result<LadderProgram, String> {
    layout(name, bytes, Wide::default())
}

fn layout(name: &str, bytes: &[u8], wide: Wide) -> Result<LadderProgram, String> {
    let outline = softplc_aplc::outline(name, bytes).map_err(|d| {
        d.0.first()
            .map_or_else(|| "cannot parse".to_string(), |d| d.to_string())
    })?;
    let unit = &outline.unit;
    let mut b = Builder::new(Names::new(softplc_core::profile::aplc(), true)).with_wide(wide);
    let mut sections = Vec::new();
    let mut loops = Vec::new();
    for pou in &unit.pous {
        b.set_names(Names::new(
            softplc_core::profile::aplc(),
            pou.kind == PouKind::Main,
        ));
        b.end_step();
        sections.push(Section {
            title: title(pou),
            vars: pou
                .vars
                .iter()
                .map(|v| format!("{} {} {} = {}", v.name, v.kind, v.ty, v.addr))
                .collect(),
            first: b.count(),
        });
        for shown in outline.shown(pou) {
            loops.extend(shown.owned);
            let notes = Notes {
                aliases: shown.aliases,
                params: shown.params,
            };
            b.item(&shown.listed, notes);
        }
    }
    let mut rungs = b.finish();
    // Comment lines (lines without tokens) between a rung's first line and
    // the line with tokens before it are the rung's comment.
    let lines = &outline.token_lines;
    for r in &mut rungs {
        let before = lines.partition_point(|&l| l < r.line);
        let from = before.checked_sub(1).map_or(0, |p| lines[p]);
        r.comment = outline
            .comments
            .iter()
            .filter(|c| c.line > from && c.line < r.line)
            .map(|c| c.text.clone())
            .collect();
    }
    let first = lines.first().copied().unwrap_or(u32::MAX);
    Ok(LadderProgram {
        file: name.to_string(),
        rungs,
        sections,
        comment: outline
            .comments
            .iter()
            .filter(|c| c.line < first)
            .map(|c| c.text.clone())
            .collect(),
        loops,
        unreadable: Vec::new(),
        local: Vec::new(),
    })
}

/// `MAIN`, `SBR_1`, `INT_1 EVENT 26`.
fn title(pou: &Pou) -> String {
    match pou.kind {
        PouKind::Int { event, .. } => format!("{} EVENT {event}", pou.name()),
        _ => pou.name(),
    }
}
