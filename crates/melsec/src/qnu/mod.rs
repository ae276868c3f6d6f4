//! The instructions the Universal model QCPUs (QnUCPU) have and the
//! QnHCPU has not (MELSEC-Q/L Programming Manual, Common Instruction,
//! SH-080809ENG): the family list the QnU instruction set adds
//! ([`crate::qnu_isa`]) and the other CPUs reject with [`NEEDS_QNU`]. The
//! contacts are lowered with the others in [`crate::ladder`]; the
//! application instructions are here, one file per chapter.

pub mod transfer;

use softplc_lang::isa::Def;

/// The Universal models' families (a new family is one line here).
pub static FAMILIES: &[&[Def]] = &[crate::ladder::QNU_DEFS, transfer::DEFS];

/// Why a CPU other than a Universal model rejects them.
pub const NEEDS_QNU: &str = "a Universal model instruction (QnU): it needs a Universal model \
     CPU ([cpu] model = \"Q04UDEHCPU\" or another QnU model, or --model)";
