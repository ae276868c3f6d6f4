//! softplc-melsec: the MELSEC-Q dialect. One module per chapter of the
//! MELSEC-Q/QnA programming manual (common instructions) and of the PID manual
//! (001), each with its `DEFS`: one [`Def`] per instruction (name, pulse form,
//! rung class, drive, steps, manual reference) next to its behaviour. The
//! sequence instructions (`ladder`), program control (`control`) and the
//! built-in compare/arithmetic/MOV (`basic`) are lowered into the ladder
//! machine's ops; every other instruction compiles to an [`Instr`] through
//! [`Args`]. [`DEFS`] lists the families, [`isa`] indexes them, [`dialect`]
//! adds the devices, word order and system flags.

#![forbid(unsafe_code)]

mod annunciator;
pub mod arithmetic;
pub mod basic;
pub mod bits;
pub mod clock;
pub mod comparison;
pub mod control;
pub mod conversion;
pub mod data;
pub mod file_register;
pub mod float;
pub mod ladder;
pub mod limits;
pub mod logic;
pub mod misc;
pub mod module_access;
pub mod multi_cpu;
pub mod pid;
pub mod process;
pub mod profiles;
pub mod qnu;
pub mod rejected;
pub mod rotation;
pub mod strings;
pub mod system;
pub mod table;
pub mod timing;
pub mod transfer;
mod user_clock;

use softplc_ir::device::{DeviceKind, MELSEC_Q};
pub use softplc_ir::instr::{ExecCtx, Instr, LocalSlot, LocalState};
pub use softplc_lang::compile::Args;
use softplc_lang::dialect::{Dialect, Flag, WordOrder};
use softplc_lang::isa::{Def, Isa};
use softplc_lang::settings::Settings;

pub use softplc_lang::isa::CompileFn;

/// The MELSEC-Q instruction set: every family's definitions, then the rejected
/// instructions (see [`softplc_lang::isa`]). A new family is one line here.
pub static DEFS: &[&[Def]] = &[
    ladder::DEFS,
    basic::DEFS,
    control::DEFS,
    conversion::DEFS,
    arithmetic::DEFS,
    strings::DEFS,
    transfer::DEFS,
    logic::DEFS,
    rotation::DEFS,
    bits::DEFS,
    data::DEFS,
    table::DEFS,
    limits::DEFS,
    comparison::DEFS,
    float::DEFS,
    clock::DEFS,
    pid::DEFS,
    file_register::DEFS,
    timing::DEFS,
    misc::DEFS,
    module_access::DEFS,
    multi_cpu::DEFS,
    rejected::DEFS,
];

/// The MELSEC-Q instruction set (QnHCPU), indexed by name; the process
/// CPU's and the Universal models' instructions are rejected naming the
/// models that have them.
pub fn isa() -> &'static Isa {
    static ISA: std::sync::LazyLock<Isa> = std::sync::LazyLock::new(|| {
        Isa::new(DEFS)
            .rejecting(process::FAMILIES, process::NEEDS_PROCESS_CPU)
            .rejecting(qnu::FAMILIES, qnu::NEEDS_QNU)
    });
    &ISA
}

/// The process CPU's instruction set (QnPHCPU, 000 §1): MELSEC-Q's and the
/// process-control instructions, without the PID control instructions (001
/// §1 point: the process CPU does not support them; they are rejected naming
/// the process-control equivalents); the Universal models' are rejected.
pub fn process_isa() -> &'static Isa {
    static ISA: std::sync::LazyLock<Isa> = std::sync::LazyLock::new(|| {
        let families: Vec<&'static [Def]> = DEFS
            .iter()
            // `DEFS` are consts (no single address): the family by its names.
            .filter(|f| {
                !f.iter()
                    .map(|d| d.name)
                    .eq(pid::DEFS.iter().map(|d| d.name))
            })
            .chain(process::FAMILIES)
            .copied()
            .collect();
        Isa::new(&families)
            .rejecting(&[pid::DEFS], pid::NOT_ON_PROCESS_CPU)
            .rejecting(qnu::FAMILIES, qnu::NEEDS_QNU)
    });
    &ISA
}

/// The redundant CPU's instruction set (QnPRHCPU): MELSEC-Q's, the PID
/// control instructions and the process-control instructions (001 §1 point:
/// the redundant CPU can use both); the Universal models' are rejected.
pub fn redundant_isa() -> &'static Isa {
    static ISA: std::sync::LazyLock<Isa> = std::sync::LazyLock::new(|| {
        let families: Vec<&'static [Def]> = DEFS.iter().chain(process::FAMILIES).copied().collect();
        Isa::new(&families).rejecting(qnu::FAMILIES, qnu::NEEDS_QNU)
    });
    &ISA
}

/// The Universal models' instruction set (QnUCPU): MELSEC-Q's and the
/// instructions the Universal models add ([`qnu`]); the process-control
/// instructions are rejected.
pub fn qnu_isa() -> &'static Isa {
    static ISA: std::sync::LazyLock<Isa> = std::sync::LazyLock::new(|| {
        let families: Vec<&'static [Def]> = DEFS.iter().chain(qnu::FAMILIES).copied().collect();
        Isa::new(&families).rejecting(process::FAMILIES, process::NEEDS_PROCESS_CPU)
    });
    &ISA
}

/// System flags of the instructions (SM700 …).
const FLAGS: &[(Flag, DeviceKind, u32)] = &[
    (Flag::Carry, DeviceKind::SM, 700),
    (Flag::NoNul, DeviceKind::SM, 701),
    (Flag::BinarySearch, DeviceKind::SM, 702),
    (Flag::SortDescending, DeviceKind::SM, 703),
    (Flag::AllTrue, DeviceKind::SM, 704),
];

/// The MELSEC-Q dialect: its instruction set, devices (hex X/Y/B/W), low word
/// first, and the SM70x flags of the instructions.
pub fn dialect() -> &'static Dialect {
    static DIALECT: std::sync::LazyLock<Dialect> = std::sync::LazyLock::new(|| Dialect {
        name: "MELSEC-Q",
        isa: isa(),
        devices: &MELSEC_Q,
        word_order: WordOrder::LowFirst,
        flags: FLAGS,
        settings: Settings::new(),
    });
    &DIALECT
}

/// The dialect of the process CPU models (Q02PHCPU … Q25PHCPU) with the
/// project's decisions (plc.toml `[process]`).
pub fn process_dialect(settings: process::settings::ProcessSettings) -> Dialect {
    Dialect {
        name: "MELSEC-QnPH",
        isa: process_isa(),
        settings: Settings::new().with(settings),
        ..dialect().clone()
    }
}

/// The dialect of the redundant CPU models (Q12PRHCPU, Q25PRHCPU): the
/// process CPU's with the PID control instructions, and the project's
/// decisions (plc.toml `[process]`).
pub fn redundant_dialect(settings: process::settings::ProcessSettings) -> Dialect {
    Dialect {
        isa: redundant_isa(),
        ..process_dialect(settings)
    }
}

/// The dialect of the Universal models (Q00UJCPU … Q26UDVCPU): MELSEC-Q's
/// with the Universal models' instruction set.
pub fn qnu_dialect() -> &'static Dialect {
    static DIALECT: std::sync::LazyLock<Dialect> = std::sync::LazyLock::new(|| Dialect {
        name: "MELSEC-QnU",
        isa: qnu_isa(),
        ..dialect().clone()
    });
    &DIALECT
}

/// Whether `model` is a redundant CPU (QnPRHCPU): a process CPU that also
/// has the PID control instructions.
pub fn is_redundant_model(model: &str) -> bool {
    is_process_model(model) && model.contains("PRH")
}

/// Whether `model` is a process CPU (QnPHCPU or QnPRHCPU).
pub fn is_process_model(model: &str) -> bool {
    profiles::PROFILES
        .iter()
        .any(|p| p.model == model && p.family == profiles::FAMILY_QNPH)
}
