//! Programming manual (common instructions): character strings and ASCII conversion ($MOV, $+, STR, VAL, ESTR, EVAL, ASC, HEX, DABIN, BINDA, LEN, RIGHT, LEFT, MIDR, MIDW, INSTR).
//!
//! Not implemented yet: every mnemonic of this family is rejected at load as an
//! unsupported instruction.

use super::CompileFn;

/// The compile function for a mnemonic of this family (pulse suffix removed).
pub fn lookup(m: &str) -> Option<CompileFn> {
    let _ = m;
    None
}
