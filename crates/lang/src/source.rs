//! Source-level program: what the parsers of every file format produce and the
//! compiler consumes. Positions are kept so every diagnostic names file:line:column.

use std::fmt;

/// A word of source text with its position (1-based line and character column).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Token {
    pub text: String,
    pub line: u32,
    pub col: u32,
}

/// One instruction as written: mnemonic and operand tokens.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceInstr {
    pub mnemonic: Token,
    pub operands: Vec<Token>,
    /// The step number stated by the file (GX Works2 CSV export); `None` for `.il`,
    /// where the compiler counts steps itself.
    pub step: Option<u32>,
}

/// A line of a program: a pointer label (`P10`, `I28`) or an instruction.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SourceItem {
    Label(Token),
    Instr(SourceInstr),
}

/// A parsed program file.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Source {
    /// File name as shown in diagnostics.
    pub file: String,
    pub items: Vec<SourceItem>,
    /// The CPU model the file was written for, as the file names it (the
    /// `PLC Information` row of a GX Works2 export: `Q04UDEH` of
    /// `QCPU (Q mode) Q04UDEH`); `None` when it names none.
    pub model: Option<Token>,
}

/// A load-time error (or warning) at a place in a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    pub file: String,
    pub line: u32,
    pub col: u32,
    pub message: String,
}

impl Diagnostic {
    pub fn at(file: &str, tok: &Token, message: impl Into<String>) -> Self {
        Diagnostic {
            file: file.to_string(),
            line: tok.line,
            col: tok.col,
            message: message.into(),
        }
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.file, self.line, self.col, self.message
        )
    }
}

/// Every diagnostic of a file that failed to load.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{d}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostics {}

/// True for a token that is a pointer label on its own line: `P0`-`P4095`, `I0`-`I255`.
pub fn is_label(text: &str) -> bool {
    let b = text.as_bytes();
    b.len() >= 2
        && matches!(b[0], b'P' | b'p' | b'I' | b'i')
        && b[1..].iter().all(u8::is_ascii_digit)
}
