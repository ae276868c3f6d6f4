//! PID control instructions (seed 001): S.PIDINIT/S.PIDCONT family and
//! PIDINIT/PIDCONT family.
//!
//! Not implemented yet: every mnemonic of this family is rejected at load as an
//! unsupported instruction.

use super::CompileFn;

/// The compile function for a mnemonic of this family (pulse suffix removed).
pub fn lookup(m: &str) -> Option<CompileFn> {
    let _ = m;
    None
}
