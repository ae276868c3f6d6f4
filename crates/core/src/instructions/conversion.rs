//! Programming manual (common instructions): BCD/BIN conversion and other BIN/real conversions (BCD, BIN, GRY, GBIN, NEG, DBL, WORD, RAD, DEG, BKBCD, BKBIN).
//!
//! Not implemented yet: every mnemonic of this family is rejected at load as an
//! unsupported instruction.

use super::CompileFn;

/// The compile function for a mnemonic of this family (pulse suffix removed).
pub fn lookup(m: &str) -> Option<CompileFn> {
    let _ = m;
    None
}
