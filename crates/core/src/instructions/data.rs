//! Programming manual (common instructions): data processing (SER, SUM, DECO, ENCO, SEG, DIS, UNI, WTOB, BTOW, MAX, MIN, SORT, WSUM, MEAN).
//!
//! Not implemented yet: every mnemonic of this family is rejected at load as an
//! unsupported instruction.

use super::CompileFn;

/// The compile function for a mnemonic of this family (pulse suffix removed).
pub fn lookup(m: &str) -> Option<CompileFn> {
    let _ = m;
    None
}
