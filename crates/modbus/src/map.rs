//! Address maps: which device each protocol address reaches.
//!
//! A [`Map`] is a list of [`Range`]s, each a run of protocol addresses of one
//! [`Table`] mapped onto consecutive device numbers of one [`DeviceKind`], plus
//! the dialect's rules: the function codes it supports, the per-request quantity
//! limits, and whether one request may run from one range into the next.
//!
//! # MELSEC-Q default (contract §3)
//! | table | addresses | devices |
//! |---|---|---|
//! | coils (FC 1, 5, 15) | 0–8191 / 8192–16383 / 16384–24575 / 24576–32767 | Y0–Y1FFF / M0–M8191 / L0–L8191 / B0–B1FFF |
//! | discrete inputs (FC 2) | 0–8191 | X0–X1FFF |
//! | holding registers (FC 3, 6, 16, 22, 23) | 0–12287 / 12288–20479 / 20480–53247 | D0–D12287 / W0–W1FFF / R0–R32767 |
//! | input registers (FC 4) | 0–2047 | SD0–SD2047 |
//!
//! Function codes 1, 2, 3, 4, 5, 6, 8, 15, 16, 22, 23. Limits (Modbus V1.1b3):
//! FC 1/2 1–2000, FC 15 1–1968, FC 3/4 1–125, FC 16 1–123, FC 23 read 1–125 and
//! write 1–121. A request may cross from one range into an adjacent one (coils
//! 8190–8193 are Y1FFE, Y1FFF, M0, M1); any address outside every range is 02.
//!
//! # APLC (seed 002, spec/aplc.md §6.3–§6.5)
//! | table | addresses | devices | notes |
//! |---|---|---|---|
//! | coils | 0–255 | Y0–Y377 (octal; device number = address) | Y200–Y377 read OFF, writes ignored (D2) |
//! | | 1200–1455 | X0–X377 | writes answered normally, ignored; X200–X377 read OFF |
//! | | 2000–3999 | M0–M1999 | |
//! | | 4400–4655 | SM0–SM255 | only the R/W SM of §7.1 are written; others ignored |
//! | | 6000–6991 | S0–S991 | |
//! | | 8000–8255 | T0–T255 contacts (TS) | |
//! | | 9200–9455 | C0–C255 contacts (CS) | |
//! | discrete inputs | 0–255 | X0–X377 | X200–X377 read OFF |
//! | holding registers | 0–7999 | D0–D7999 | |
//! | | 8000–8255 | SD0–SD255 | only the R/W SD of §7.2 are written; others ignored |
//! | | 8500–8515 | Z0–Z15 | |
//! | | 9000–9255 | T0–T255 current values (TN) | |
//! | | 9500–9699 | C0–C199 current values (CN) | |
//! | | 9700–9811 | C200–C255 32-bit values, two registers each, even = high word | FC 3/16 only |
//!
//! Function codes 1, 2, 3, 5, 6, 8, 15, 16 (others: 01). Limits FC 1/2 1–2000,
//! FC 15 1–1968, FC 3 1–125, FC 16 1–120. A request stays inside one range, in
//! this order (§6.5): the start address must be mapped (02); in a 32-bit range
//! the start must be even (02) and the quantity even (03); a quantity larger than
//! the whole range is 03; a range running past its end is 02.
//!
//! The APLC CPU keeps C200+k as the word pair CN(200+2k) (high), CN(201+2k)
//! (low) (crates/aplc/src/devices.rs), so the registers 9700–9811 map one to
//! one onto CN200–CN311 and a pair is a true 32-bit value
//! ([`Range::pair_words`]). A `pairs = true` entry in plc.toml is a pair per
//! 16-bit device (a MELSEC counter): high word 0, writes store the low word.
//!
//! # plc.toml `[modbus]`
//! ```toml
//! [modbus]
//! dialect = "q"                 # "q" (default) or "aplc": the preset map and rules
//! functions = [1, 2, 3, 4, 5, 6, 8, 15, 16]   # optional: restrict the function codes
//! # Each table given replaces that table of the preset entirely.
//! coils = [
//!     { address = 0, device = "Y0", count = 8192 },
//!     { address = 8192, device = "M0", count = 8192 },
//! ]
//! discrete_inputs = [{ address = 0, device = "X0", count = 8192 }]
//! holding_registers = [
//!     { address = 0, device = "D0", count = 12288 },
//!     { address = 20000, device = "CN200", count = 112, pairs = true },
//!     { address = 30000, device = "SD0", count = 256, writable = [[50, 55], [66, 68]] },
//! ]
//! input_registers = [{ address = 0, device = "SD0", count = 2048 }]
//! ```
//! An entry has `address` (0–65535), `device` (a bit device for coils and discrete
//! inputs, a word device for registers; `T`/`C` mean contacts in bit tables and
//! current values in register tables), `count` (protocol addresses, ≥ 1), and
//! optionally `pairs = true` (registers only, even count: each two registers are
//! one 32-bit device value, high word first), `ignore_writes = true` (writes are
//! answered but change nothing) or `writable = [[first, last], …]` (only these
//! device numbers are written; writes to the others are answered and ignored).
//! Ranges of one table must not overlap. The slave keys of the same table
//! (`unit_id`, `read_only`, `tcp_any_unit`) are read by [`crate::Slave::from_toml`].

use serde::Deserialize;
use softplc_core::device::{parse_operand, DeviceConfig, DeviceKind, Operand};

use crate::pdu::Exception;

/// The four Modbus data tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Table {
    /// FC 1, 5, 15 (0xxxx).
    Coils,
    /// FC 2 (1xxxx), read-only.
    DiscreteInputs,
    /// FC 3, 6, 16, 22, 23 (4xxxx).
    HoldingRegisters,
    /// FC 4 (3xxxx), read-only.
    InputRegisters,
}

impl Table {
    pub const ALL: [Table; 4] = [
        Table::Coils,
        Table::DiscreteInputs,
        Table::HoldingRegisters,
        Table::InputRegisters,
    ];

    /// Bit table (coils, discrete inputs) or register table.
    pub fn is_bit(self) -> bool {
        matches!(self, Table::Coils | Table::DiscreteInputs)
    }

    /// The `[modbus]` key of the table.
    pub fn key(self) -> &'static str {
        match self {
            Table::Coils => "coils",
            Table::DiscreteInputs => "discrete_inputs",
            Table::HoldingRegisters => "holding_registers",
            Table::InputRegisters => "input_registers",
        }
    }
}

/// A run of protocol addresses mapped onto consecutive devices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Range {
    pub table: Table,
    /// First protocol address (0-based).
    pub address: u16,
    /// Number of protocol addresses (1..=65536 − address).
    pub count: u32,
    pub kind: DeviceKind,
    /// Device number at `address`.
    pub first: u32,
    /// Registers come in pairs, each pair one 32-bit device value, high word at the
    /// even offset (spec/aplc.md §6.4 C200–C255). Pairs are read and written only
    /// whole: FC 6 and 22 are refused (02).
    pub pairs: bool,
    /// With `pairs`: the device keeps each 32-bit value in two consecutive
    /// words, high word first (the APLC's C200+k in CN(200+2k), CN(201+2k),
    /// crates/aplc/src/devices.rs), so registers map one to one onto its
    /// words. Without: each pair is one 16-bit device, read zero-extended
    /// (high word 0) and written from the low word (a MELSEC counter).
    pub pair_words: bool,
    /// `None`: every device is written. `Some(list)`: only device numbers in these
    /// inclusive ranges are written; writes to others are answered and ignored.
    pub writable: Option<Vec<(u32, u32)>>,
    /// `Some(n)`: only device numbers below `n` exist; the rest of the range
    /// reads OFF/0 and takes writes without effect (the APLC's 256-point X/Y
    /// tables over X0-X177/Y0-Y177, spec/aplc.md §11 D2).
    pub limit: Option<u32>,
}

impl Range {
    pub fn new(table: Table, address: u16, count: u32, kind: DeviceKind, first: u32) -> Range {
        Range {
            table,
            address,
            count,
            kind,
            first,
            pairs: false,
            pair_words: false,
            writable: None,
            limit: None,
        }
    }

    pub fn with_pairs(mut self) -> Range {
        self.pairs = true;
        self
    }

    /// Pairs over a device that stores each value in two words, high first.
    pub fn with_pair_words(mut self) -> Range {
        self.pairs = true;
        self.pair_words = true;
        self
    }

    /// Devices from number `n` on do not exist (read OFF/0, writes ignored).
    pub fn with_limit(mut self, n: u32) -> Range {
        self.limit = Some(n);
        self
    }

    pub fn with_writable(mut self, writable: &[(u32, u32)]) -> Range {
        self.writable = Some(writable.to_vec());
        self
    }

    /// One past the last address.
    pub fn end(&self) -> u32 {
        self.address as u32 + self.count
    }

    pub fn contains(&self, address: u32) -> bool {
        (self.address as u32..self.end()).contains(&address)
    }

    /// Device number of the address at `offset` from the start.
    pub fn device(&self, offset: u32) -> u32 {
        self.first
            + if self.pairs && !self.pair_words {
                offset / 2
            } else {
                offset
            }
    }

    /// Whether a write to device number `n` takes effect.
    pub fn is_writable(&self, n: u32) -> bool {
        match &self.writable {
            None => true,
            Some(list) => list.iter().any(|&(a, b)| (a..=b).contains(&n)),
        }
    }

    /// `8192-16383 → M0-M8191`.
    pub fn describe(&self) -> String {
        format!(
            "{}-{} → {}-{}",
            self.address,
            self.end() - 1,
            self.kind.format(self.first),
            self.kind.format(self.device(self.count - 1)),
        )
    }
}

/// Per-request quantity limits (exception 03 outside them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// FC 1, 2.
    pub read_bits: u16,
    /// FC 15.
    pub write_bits: u16,
    /// FC 3, 4.
    pub read_registers: u16,
    /// FC 16.
    pub write_registers: u16,
    /// FC 23, read part.
    pub rw_read_registers: u16,
    /// FC 23, write part.
    pub rw_write_registers: u16,
}

impl Limits {
    /// Modbus application protocol V1.1b3.
    pub const STANDARD: Limits = Limits {
        read_bits: 2000,
        write_bits: 1968,
        read_registers: 125,
        write_registers: 123,
        rw_read_registers: 125,
        rw_write_registers: 121,
    };
    /// Seed 002 (spec/aplc.md §6.3, §6.5): at most 120 registers per write.
    pub const APLC: Limits = Limits {
        write_registers: 120,
        ..Limits::STANDARD
    };
}

/// A preset: the map and rules a dialect's slave starts from, by name (a
/// CPU profile's `doors.modbus`, the `[modbus] dialect` key).
#[derive(Debug)]
pub struct Preset {
    /// The names `[modbus] dialect` selects it by (any case); the first is
    /// its own, the one profiles give.
    pub names: &'static [&'static str],
    /// The function codes it answers; a `functions` list chooses among them.
    pub functions: &'static [u8],
    pub limits: Limits,
    /// See [`Map::span`].
    pub span: bool,
    /// Its address ranges.
    pub ranges: fn() -> Vec<Range>,
}

impl PartialEq for Preset {
    /// Presets are static values, one per name.
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for Preset {}

/// The MELSEC-Q map of contract §3 (module docs).
pub static Q_PRESET: Preset = Preset {
    names: &["q", "melsec", "melsec-q"],
    functions: &Q_FUNCTIONS,
    limits: Limits::STANDARD,
    span: true,
    ranges: q_ranges,
};

/// The APLC map of seed 002 (spec/aplc.md §6.4): one range per request.
pub static APLC_PRESET: Preset = Preset {
    names: &["aplc"],
    functions: &APLC_FUNCTIONS,
    limits: Limits::APLC,
    span: false,
    ranges: aplc_ranges,
};

/// Every preset; the first is the default of [`Map::from_toml`].
pub static PRESETS: [&Preset; 2] = [&Q_PRESET, &APLC_PRESET];

impl Preset {
    /// Its own name (`q`, `aplc`).
    pub fn name(&self) -> &'static str {
        self.names[0]
    }

    /// The preset called `name` (any case, surrounding blanks ignored).
    pub fn find(name: &str) -> Option<&'static Preset> {
        let name = name.trim();
        PRESETS
            .into_iter()
            .find(|p| p.names.iter().any(|n| n.eq_ignore_ascii_case(name)))
    }

    /// The map as the preset gives it.
    pub fn map(&'static self) -> Map {
        Map {
            preset: self,
            functions: self.functions.to_vec(),
            limits: self.limits,
            span: self.span,
            ranges: (self.ranges)(),
        }
    }
}

/// An address map with its dialect rules.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Map {
    /// The preset it started from (its function codes bound `functions`).
    pub preset: &'static Preset,
    /// Supported function codes; others get exception 01.
    pub functions: Vec<u8>,
    pub limits: Limits,
    /// `true`: a request may run across adjacent ranges of its table. `false`: it
    /// must stay inside one range, with seed 002's exception order (module docs).
    pub span: bool,
    pub ranges: Vec<Range>,
}

/// Function codes of the Q dialect.
pub const Q_FUNCTIONS: [u8; 11] = [1, 2, 3, 4, 5, 6, 8, 15, 16, 22, 23];
/// Function codes of the APLC dialect (spec/aplc.md §6.3).
pub const APLC_FUNCTIONS: [u8; 8] = [1, 2, 3, 5, 6, 8, 15, 16];

/// X and Y points of an APLC-TCP (X0-X177, Y0-Y177, table 3-2 L1520).
pub const APLC_IO_POINTS: u32 = 128;

/// SM writable over Modbus on APLC: the R/W rows of spec/aplc.md §7.1.
pub const APLC_WRITABLE_SM: [(u32, u32); 15] = [
    (40, 56),
    (63, 68),
    (70, 70),
    (80, 81),
    (84, 87),
    (90, 97),
    (110, 113),
    (120, 123),
    (130, 133),
    (135, 138),
    (172, 175),
    (178, 178),
    (180, 182),
    (185, 186),
    (200, 255),
];

/// SD writable over Modbus on APLC: the R/W rows of spec/aplc.md §7.2.
pub const APLC_WRITABLE_SD: [(u32, u32); 12] = [
    (50, 55),
    (66, 68),
    (80, 89),
    (120, 124),
    (135, 138),
    (140, 142),
    (150, 154),
    (173, 173),
    (175, 175),
    (178, 178),
    (180, 184),
    (200, 219),
];

/// The presets' own names as the `dialect` error lists them: `"q" or "aplc"`.
fn preset_names() -> String {
    let names: Vec<String> = PRESETS
        .iter()
        .map(|p| format!("\"{}\"", p.name()))
        .collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => names.concat(),
    }
}

/// The ranges of the MELSEC-Q map (module docs).
fn q_ranges() -> Vec<Range> {
    use DeviceKind::*;
    use Table::*;
    vec![
        Range::new(Coils, 0, 8192, Y, 0),
        Range::new(Coils, 8192, 8192, M, 0),
        Range::new(Coils, 16384, 8192, L, 0),
        Range::new(Coils, 24576, 8192, B, 0),
        Range::new(DiscreteInputs, 0, 8192, X, 0),
        Range::new(HoldingRegisters, 0, 12288, D, 0),
        Range::new(HoldingRegisters, 12288, 8192, W, 0),
        Range::new(HoldingRegisters, 20480, 32768, R, 0),
        Range::new(InputRegisters, 0, 2048, SD, 0),
    ]
}

/// The ranges of the APLC map (module docs).
fn aplc_ranges() -> Vec<Range> {
    use DeviceKind::*;
    use Table::*;
    vec![
        // 256 addresses over Y0-Y177 / X0-X177 (decision D2).
        Range::new(Coils, 0, 256, Y, 0).with_limit(APLC_IO_POINTS),
        Range::new(Coils, 1200, 256, X, 0)
            .with_writable(&[])
            .with_limit(APLC_IO_POINTS),
        Range::new(Coils, 2000, 2000, M, 0),
        Range::new(Coils, 4400, 256, SM, 0).with_writable(&APLC_WRITABLE_SM),
        Range::new(Coils, 6000, 992, S, 0),
        Range::new(Coils, 8000, 256, TS, 0),
        Range::new(Coils, 9200, 256, CS, 0),
        Range::new(DiscreteInputs, 0, 256, X, 0).with_limit(APLC_IO_POINTS),
        Range::new(HoldingRegisters, 0, 8000, D, 0),
        Range::new(HoldingRegisters, 8000, 256, SD, 0).with_writable(&APLC_WRITABLE_SD),
        Range::new(HoldingRegisters, 8500, 16, Z, 0),
        Range::new(HoldingRegisters, 9000, 256, TN, 0),
        Range::new(HoldingRegisters, 9500, 200, CN, 0),
        // C200+k in CN(200+2k) (high), CN(201+2k) (low).
        Range::new(HoldingRegisters, 9700, 112, CN, 200).with_pair_words(),
    ]
}

/// One piece of a request: `len` addresses of `range` from `offset`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Chunk<'a> {
    pub range: &'a Range,
    pub offset: u32,
    pub len: u32,
}

/// Keys of `[modbus]` read by [`Map::from_toml`].
pub const MAP_KEYS: [&str; 6] = [
    "dialect",
    "functions",
    "coils",
    "discrete_inputs",
    "holding_registers",
    "input_registers",
];

impl Default for Map {
    fn default() -> Self {
        Map::q_default()
    }
}

impl Map {
    /// The MELSEC-Q default map of contract §3.
    pub fn q_default() -> Map {
        Q_PRESET.map()
    }

    /// The APLC map of seed 002 (spec/aplc.md §6.4).
    pub fn aplc() -> Map {
        APLC_PRESET.map()
    }

    /// Reads the `[modbus]` table of plc.toml (schema in the module docs); without
    /// `dialect` the Q preset is the base. Keys not in [`MAP_KEYS`] are left to
    /// other readers.
    pub fn from_toml(table: &toml::Table) -> Result<Map, String> {
        Map::from_toml_with(table, PRESETS[0])
    }

    /// As [`Map::from_toml`], with `default` as the preset when `dialect` is
    /// absent (the CPU profile's, `Preset::find(profile.doors.modbus)`).
    pub fn from_toml_with(table: &toml::Table, default: &'static Preset) -> Result<Map, String> {
        let preset = match table.get("dialect") {
            None => default,
            Some(toml::Value::String(s)) => Preset::find(s).ok_or_else(|| {
                format!(
                    "[modbus] dialect: unknown dialect \"{s}\" (expected {})",
                    preset_names()
                )
            })?,
            Some(v) => {
                return Err(format!(
                    "[modbus] dialect: expected a string, found {}",
                    v.type_str()
                ))
            }
        };
        let mut map = preset.map();
        if let Some(v) = table.get("functions") {
            let list: Vec<i64> = v
                .clone()
                .try_into()
                .map_err(|_| "[modbus] functions: expected a list of function codes".to_string())?;
            let supported = preset.functions;
            let mut functions = Vec::new();
            for fc in list {
                match u8::try_from(fc) {
                    Ok(fc) if supported.contains(&fc) => functions.push(fc),
                    _ => {
                        return Err(format!(
                            "[modbus] functions: function code {fc} is not supported by this dialect (supported: {supported:?})"
                        ))
                    }
                }
            }
            map.functions = functions;
        }
        for t in Table::ALL {
            let Some(v) = table.get(t.key()) else {
                continue;
            };
            let entries: Vec<EntrySpec> = v
                .clone()
                .try_into()
                .map_err(|e: toml::de::Error| format!("[modbus] {}: {}", t.key(), e.message()))?;
            map.ranges.retain(|r| r.table != t);
            for (i, e) in entries.iter().enumerate() {
                let r = e
                    .to_range(t)
                    .map_err(|m| format!("[modbus] {}[{i}]: {m}", t.key()))?;
                map.ranges.push(r);
            }
        }
        map.validate()?;
        Ok(map)
    }

    /// Checks the ranges: sizes, device kinds, pairs, overlaps.
    pub fn validate(&self) -> Result<(), String> {
        for r in &self.ranges {
            if r.count == 0 || r.end() > 65536 {
                return Err(format!(
                    "{} range at {}: count {} does not fit the 0-65535 address space",
                    r.table.key(),
                    r.address,
                    r.count
                ));
            }
            if r.kind.is_bit() != r.table.is_bit() {
                return Err(format!(
                    "{} range at {}: {} is a {} device",
                    r.table.key(),
                    r.address,
                    r.kind,
                    if r.kind.is_bit() { "bit" } else { "word" }
                ));
            }
            if r.pairs && (r.table.is_bit() || !r.count.is_multiple_of(2)) {
                return Err(format!(
                    "{} range at {}: pairs need a register table and an even count",
                    r.table.key(),
                    r.address
                ));
            }
            if let Some(list) = &r.writable {
                if let Some((a, b)) = list.iter().find(|(a, b)| a > b) {
                    return Err(format!(
                        "{} range at {}: writable range [{a}, {b}] is reversed",
                        r.table.key(),
                        r.address
                    ));
                }
            }
        }
        for (i, a) in self.ranges.iter().enumerate() {
            for b in &self.ranges[i + 1..] {
                if a.table == b.table
                    && (a.address as u32) < b.end()
                    && (b.address as u32) < a.end()
                {
                    return Err(format!(
                        "{}: ranges {} and {} overlap",
                        a.table.key(),
                        a.describe(),
                        b.describe()
                    ));
                }
            }
        }
        Ok(())
    }

    /// Ranges that reach past the device points of `cfg` (requests there get
    /// exception 04), as messages for a start-up warning.
    pub fn check_devices(&self, cfg: &DeviceConfig) -> Vec<String> {
        self.ranges
            .iter()
            .filter(|r| {
                r.device(r.count - 1).min(r.limit.unwrap_or(u32::MAX) - 1) >= cfg.points(r.kind)
            })
            .map(|r| {
                format!(
                    "{} {}: the CPU has {} {} points",
                    r.table.key(),
                    r.describe(),
                    cfg.points(r.kind),
                    r.kind
                )
            })
            .collect()
    }

    /// Whether the map answers function code `fc`.
    pub fn supports(&self, fc: u8) -> bool {
        self.functions.contains(&fc)
    }

    /// The range of `table` holding `address`.
    pub fn find(&self, table: Table, address: u32) -> Option<&Range> {
        self.ranges
            .iter()
            .find(|r| r.table == table && r.contains(address))
    }

    /// The device at one protocol address (for tools and tests): kind and number;
    /// in a pairs range, the 32-bit device.
    pub fn device_at(&self, table: Table, address: u16) -> Option<(DeviceKind, u32)> {
        let r = self.find(table, address as u32)?;
        Some((r.kind, r.device(address as u32 - r.address as u32)))
    }

    /// Splits `quantity` addresses from `address` into range pieces, or the
    /// exception the dialect gives (02 or 03). `single`: FC 5, 6 or 22, which may
    /// not address a pairs range (02). The quantity limits of the function code are
    /// checked before this.
    pub fn resolve(
        &self,
        table: Table,
        address: u16,
        quantity: u16,
        single: bool,
    ) -> Result<Vec<Chunk<'_>>, Exception> {
        use Exception::{IllegalDataAddress as Addr, IllegalDataValue as Value};
        let start = address as u32;
        let quantity = quantity as u32;
        let mut chunks = Vec::new();
        if !self.span {
            // Seed 002 order (spec/aplc.md §6.5).
            let r = self.find(table, start).ok_or(Addr)?;
            let offset = start - r.address as u32;
            if r.pairs {
                if single || !offset.is_multiple_of(2) {
                    return Err(Addr);
                }
                if !quantity.is_multiple_of(2) {
                    return Err(Value);
                }
            }
            if quantity > r.count {
                return Err(Value);
            }
            if start + quantity > r.end() {
                return Err(Addr);
            }
            chunks.push(Chunk {
                range: r,
                offset,
                len: quantity,
            });
            return Ok(chunks);
        }
        let (mut at, end) = (start, start + quantity);
        while at < end {
            let r = self.find(table, at).ok_or(Addr)?;
            let len = end.min(r.end()) - at;
            chunks.push(Chunk {
                range: r,
                offset: at - r.address as u32,
                len,
            });
            at += len;
        }
        for c in &chunks {
            if c.range.pairs {
                if single || !c.offset.is_multiple_of(2) {
                    return Err(Addr);
                }
                if !c.len.is_multiple_of(2) {
                    return Err(Value);
                }
            }
        }
        Ok(chunks)
    }
}

/// One `[modbus]` table entry as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EntrySpec {
    address: u32,
    device: String,
    count: u32,
    #[serde(default)]
    pairs: bool,
    #[serde(default)]
    ignore_writes: bool,
    writable: Option<Vec<[u32; 2]>>,
}

impl EntrySpec {
    fn to_range(&self, table: Table) -> Result<Range, String> {
        if self.address > 65535 {
            return Err(format!("address {} is over 65535", self.address));
        }
        if self.count == 0 || self.address + self.count > 65536 {
            return Err(format!(
                "count {} does not fit the 0-65535 address space from {}",
                self.count, self.address
            ));
        }
        let dev = match parse_operand(&self.device) {
            Ok(Operand::Device {
                dev,
                digits: None,
                bit: None,
                index: None,
            }) => dev,
            _ => return Err(format!("device \"{}\" is not a device name", self.device)),
        };
        let kind = if table.is_bit() {
            dev.kind
        } else {
            dev.word_kind()
        };
        if kind.is_bit() != table.is_bit() {
            return Err(format!(
                "device \"{}\" is a {} device; {} need {} devices",
                self.device,
                if kind.is_bit() { "bit" } else { "word" },
                table.key(),
                if table.is_bit() { "bit" } else { "word" }
            ));
        }
        if self.ignore_writes && self.writable.is_some() {
            return Err("give either ignore_writes or writable, not both".into());
        }
        let mut r = Range::new(table, self.address as u16, self.count, kind, dev.number);
        r.pairs = self.pairs;
        if self.ignore_writes {
            r.writable = Some(Vec::new());
        }
        if let Some(list) = &self.writable {
            r.writable = Some(list.iter().map(|[a, b]| (*a, *b)).collect());
        }
        Ok(r)
    }
}
