//! An `.apl` file as written, for tools that show it (the web monitor's
//! ladder): its POUs before `#NAME` and global names are substituted, its
//! comments, and each instruction as the compiler lists it (ladder role,
//! operands as devices) with how the source wrote its operands and, for a
//! CALL, the callee's parameter names.

use softplc_ir::listing::{Listed, LoopUse};
use softplc_lang::{Diagnostics, SourceInstr};

use crate::pou::{self, Pou, Unit};
use crate::text;

/// An `.apl` file as written.
#[derive(Clone, Debug)]
pub struct Outline {
    pub unit: Unit,
    pub comments: Vec<text::Comment>,
    /// Lines holding tokens (the comments of other lines stand alone).
    pub token_lines: Vec<u32>,
}

/// One instruction as a tool shows it.
#[derive(Clone, Debug)]
pub struct Shown {
    /// As the compiler lists it (`Program::listing`), operands as devices.
    pub listed: Listed,
    /// The loop memory it owns.
    pub owned: Option<LoopUse>,
    /// Per operand, the name the source wrote where it differs from the
    /// device (`#RUNOK` for LM0, a global's name); empty otherwise.
    pub aliases: Vec<String>,
    /// A CALL's parameter names, in operand order from its second operand:
    /// the callee's IN, IN_OUT and OUT variables in table order (TEMP is not
    /// passed, L2458-2462).
    pub params: Vec<String>,
}

/// Reads `.apl` bytes into an [`Outline`]; the same text and structure
/// errors as [`crate::load_bytes`], without compiling.
pub fn outline(name: &str, bytes: &[u8]) -> Result<Outline, Diagnostics> {
    let text = text::decode(bytes);
    let (lines, comments) =
        text::lines_and_comments(name, &text).map_err(|d| Diagnostics(vec![d]))?;
    let unit = pou::parse_as_written(name, &lines, &crate::is_mnemonic).map_err(Diagnostics)?;
    Ok(Outline {
        unit,
        comments,
        token_lines: lines.iter().map(|l| l[0].line).collect(),
    })
}

impl Outline {
    /// The instructions of `pou` (one of [`Unit::pous`]) as shown. An
    /// operand naming an unknown local is shown as written (the compiler
    /// reports it).
    pub fn shown(&self, pou: &Pou) -> Vec<Shown> {
        pou.body.iter().map(|i| self.show(pou, i)).collect()
    }

    fn show(&self, pou: &Pou, i: &SourceInstr) -> Shown {
        let mut aliases = Vec::new();
        let mut resolved = i.clone();
        for t in &mut resolved.operands {
            let dev = self.unit.device_of(pou, &t.text).unwrap_or(&t.text);
            if dev == t.text {
                aliases.push(String::new());
            } else {
                let dev = dev.to_string();
                aliases.push(std::mem::replace(&mut t.text, dev));
            }
        }
        let (listed, owned) = softplc_lang::compile::listed(crate::isa(), &resolved);
        Shown {
            params: self.params(&resolved),
            listed,
            owned,
            aliases,
        }
    }

    /// A CALL's parameter names (see [`Shown::params`]); none for any
    /// other instruction.
    fn params(&self, i: &SourceInstr) -> Vec<String> {
        if !i.mnemonic.text.eq_ignore_ascii_case("CALL") {
            return Vec::new();
        }
        let callee = i.operands.first().map(|t| t.text.to_ascii_uppercase());
        self.unit
            .pous
            .iter()
            .find(|p| Some(p.name()) == callee)
            .map(|sbr| {
                sbr.vars
                    .iter()
                    .filter(|v| v.kind != "TEMP")
                    .map(|v| v.name.clone())
                    .collect()
            })
            .unwrap_or_default()
    }
}
