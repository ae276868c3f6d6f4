//! softplc-aplc: the APLC-TCP dialect (seed 002, spec aplc.md, contract
//! §1.1): the `.apl` loader ([`text`], [`pou`]), the devices with octal X/Y
//! ([`devices`]), constants ([`constant`]), operand resolution ([`resolve`]),
//! the instruction set (one chapter file each with its `DEFS`, and
//! [`rejected`]), the system devices ([`system`]) and the CLI's device names
//! ([`names`]). It runs on the shared engine; nothing is translated to
//! MELSEC text.

#![forbid(unsafe_code)]

pub mod arith;
pub mod ascii;
pub mod basic;
pub mod bits;
pub mod bitword;
pub mod blockshift;
pub mod calc;
pub mod call;
pub mod checksum;
pub mod comm;
pub mod compare;
pub mod compile;
pub mod constant;
pub mod convert;
pub mod counters;
pub mod devices;
pub mod eeprom;
pub mod files;
pub mod flow;
pub mod interrupt;
pub mod logic;
pub mod names;
pub mod num;
mod outline;
pub mod pid;
pub mod pou;
pub mod profile;
pub mod ramp;
pub mod real;
pub mod rejected;
pub mod resolve;
pub mod sfc;
pub mod stack;
pub mod system;
pub mod text;
pub mod timers;
pub mod transfer;

use std::path::Path;
use std::sync::{Arc, OnceLock};

use softplc_ir::device::{DeviceDef, DeviceKind, DeviceTable, Numbering};
use softplc_ir::ops::Program;
use softplc_lang::dialect::{Dialect, Flag, WordOrder};
use softplc_lang::isa::{Def, Found, Isa};
use softplc_lang::Diagnostics;

pub use devices::device_config;
pub use outline::{outline, Outline, Shown};

/// Every definition, by chapter.
pub static DEFS: &[&[Def]] = &[
    basic::DEFS,
    sfc::DEFS,
    timers::DEFS,
    counters::DEFS,
    flow::DEFS,
    call::DEFS,
    interrupt::DEFS,
    arith::DEFS,
    transfer::DEFS,
    bits::DEFS,
    logic::DEFS,
    logic::SHIFTS,
    real::DEFS,
    convert::DEFS,
    convert::FUNCS,
    bitword::DEFS,
    checksum::DEFS,
    stack::DEFS,
    blockshift::DEFS,
    ramp::DEFS,
    ascii::DEFS,
    eeprom::DEFS,
    comm::modbus::DEFS,
    comm::freeport::DEFS,
    comm::inverter::DEFS,
    pid::DEFS,
    compare::DEFS,
    rejected::DEFS,
];

/// The APLC-TCP instruction set.
pub fn isa() -> &'static Isa {
    static ISA: OnceLock<Isa> = OnceLock::new();
    ISA.get_or_init(|| Isa::new(DEFS))
}

const fn d(name: &'static str, kind: DeviceKind, generic: bool, numbering: Numbering) -> DeviceDef {
    DeviceDef {
        name,
        kind,
        generic,
        numbering,
    }
}

/// The APLC names over softplc's storage kinds (see [`devices`]). The
/// `.apl` loader resolves operands with [`devices::parse_device`]; this table
/// describes the same names for the dialect seam.
pub static DEVICES: DeviceTable = DeviceTable {
    modules: false,
    defs: &[
        d("LM", DeviceKind::B, false, Numbering::Dec),
        d("SM", DeviceKind::SM, false, Numbering::Dec),
        d("SD", DeviceKind::SD, false, Numbering::Dec),
        d("X", DeviceKind::X, false, Numbering::Oct),
        d("Y", DeviceKind::Y, false, Numbering::Oct),
        d("M", DeviceKind::M, false, Numbering::Dec),
        d("S", DeviceKind::S, false, Numbering::Dec),
        d("T", DeviceKind::TS, true, Numbering::Dec),
        d("C", DeviceKind::CS, true, Numbering::Dec),
        d("D", DeviceKind::D, false, Numbering::Dec),
        d("V", DeviceKind::W, false, Numbering::Dec),
        d("Z", DeviceKind::Z, false, Numbering::Dec),
    ],
};

/// The APLC-TCP dialect.
pub fn dialect() -> &'static Dialect {
    static D: OnceLock<Dialect> = OnceLock::new();
    D.get_or_init(|| Dialect {
        name: "APLC-TCP",
        isa: isa(),
        devices: &DEVICES,
        word_order: WordOrder::HighFirst,
        flags: &[(Flag::Carry, DeviceKind::SM, 181)],
        settings: softplc_lang::settings::Settings::new(),
    })
}

/// The system devices for the engine (`CpuConfig::system`), watchdog 200 ms,
/// no constant scan.
pub fn system() -> Arc<dyn softplc_ir::system::System> {
    system_with(200, 0)
}

/// The system devices with the watchdog and constant-scan settings (ms) that
/// SD34, SD33 and SM8 show.
pub fn system_with(watchdog_ms: u16, constant_scan_ms: u16) -> Arc<dyn softplc_ir::system::System> {
    system_with_ports(watchdog_ms, constant_scan_ms, Vec::new())
}

/// [`system_with`] and the settings of PORT1/PORT2 that SD120-SD154 show.
pub fn system_with_ports(
    watchdog_ms: u16,
    constant_scan_ms: u16,
    ports: Vec<comm::PortConfig>,
) -> Arc<dyn softplc_ir::system::System> {
    system_with_run_input(watchdog_ms, constant_scan_ms, ports, None)
}

/// [`system_with_ports`] and the system block's run input (index 0-15 of
/// X0-X17) that SM9 and SD9 show.
pub fn system_with_run_input(
    watchdog_ms: u16,
    constant_scan_ms: u16,
    ports: Vec<comm::PortConfig>,
    run_input: Option<u8>,
) -> Arc<dyn softplc_ir::system::System> {
    Arc::new(system::Aplc {
        watchdog_ms,
        constant_scan_ms,
        run_input,
        ports,
    })
}

/// True for a mnemonic of the APLC instruction set (implemented or not).
pub fn is_mnemonic(m: &str) -> bool {
    matches!(isa().lookup(&m.to_ascii_uppercase()), Found::Def(_, false))
}

/// Loads `.apl` text already in memory (any bytes: UTF-8 or GB18030).
pub fn load_bytes(name: &str, bytes: &[u8]) -> Result<Program, Diagnostics> {
    let text = text::decode(bytes);
    let lines = text::lines(name, &text).map_err(|d| Diagnostics(vec![d]))?;
    let unit = pou::parse(name, &lines, &is_mnemonic).map_err(Diagnostics)?;
    let mut program = compile::compile(name, &unit)?;
    program.globals = globals_of(&unit);
    Ok(program)
}

/// The global table of a parsed unit as (name, device), sorted by name: the
/// program's [`Program::globals`].
pub(crate) fn globals_of(unit: &pou::Unit) -> Vec<(String, String)> {
    let mut g: Vec<(String, String)> = unit
        .globals
        .iter()
        .map(|(n, d)| (n.clone(), d.clone()))
        .collect();
    g.sort();
    g
}

/// Loads an `.apl` file.
pub fn load_file(path: &Path) -> Result<Program, Diagnostics> {
    let name = path.display().to_string();
    let bytes = softplc_lang::read_limited(path, softplc_lang::MAX_IL_BYTES, "a program file")
        .map_err(|e| compile::file_error(&name, e))?;
    load_bytes(&name, &bytes)
}
