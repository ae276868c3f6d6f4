//! Process-control instructions of the QnPH/QnPRH process CPU, seed 000
//! (Programming Manual, Process Control Instructions, SH(NA)-080449CHN-B;
//! "000 §x" below). Behaviour the manual leaves open follows
//! `shared/spec/process-control.md` and its decisions DEC-1 … DEC-36, each a
//! named setting ([`settings::ProcessSettings`], plc.toml `[process]`).
//!
//! The instructions exist only on the process CPU models (Q02PHCPU …
//! Q25PHCPU): [`crate::process_dialect`] has them, [`crate::dialect`] rejects
//! them at load naming the models.
//!
//! Modules: `settings` (the decisions), `tag` (the 128-word loop tag, MODE,
//! ALM/INH/ALM2 bits), `common` (operand areas, ΔT and the system devices,
//! float checks, the error path with SD1502/SD1503, the period counter of
//! spec §1.3.1), and one module per chapter of the manual.

pub mod arithmetic;
pub mod autotune;
pub mod common;
pub mod comparison;
pub mod compensation;
pub mod dynamics;
pub mod io;
pub mod limiters;
pub mod manual;
pub mod pgs;
pub mod phpl;
pub mod pid;
pub mod sel;
pub mod selectors;
pub mod settings;
pub mod tag;

use softplc_lang::isa::Def;

/// The process-control families (a new family is one line here).
pub static FAMILIES: &[&[Def]] = &[
    io::DEFS,
    pid::DEFS,
    phpl::DEFS,
    sel::DEFS,
    pgs::DEFS,
    dynamics::DEFS,
    selectors::DEFS,
    limiters::DEFS,
    manual::DEFS,
    compensation::DEFS,
    arithmetic::DEFS,
    comparison::DEFS,
    autotune::DEFS,
];

/// Why a non-process CPU rejects them.
pub const NEEDS_PROCESS_CPU: &str = "a process-control instruction (QnPHCPU/QnPRHCPU Programming \
     Manual (Process Control Instructions)): it needs a process CPU \
     ([cpu] model = \"Q02PHCPU\", \"Q06PHCPU\", \"Q12PHCPU\", \"Q25PHCPU\", \"Q12PRHCPU\" or \"Q25PRHCPU\", \
     or --model)";
