//! MC protocol device codes for the Q/L CPU device set (subcommands 0000/0001:
//! 1-byte binary code with a 3-byte device number; 2-character ASCII code with a
//! 6-character device number).
//!
//! | device | binary | ASCII | ASCII number | unit | softplc storage |
//! |---|---|---|---|---|---|
//! | input X | `9C` | `X*` | hex | bit | `X` (writes go to the input image) |
//! | output Y | `9D` | `Y*` | hex | bit | `Y` |
//! | internal relay M | `90` | `M*` | dec | bit | `M` |
//! | latch relay L | `92` | `L*` | dec | bit | `L` |
//! | annunciator F | `93` | `F*` | dec | bit | `F` |
//! | edge relay V | `94` | `V*` | dec | bit | `V` |
//! | link relay B | `A0` | `B*` | hex | bit | `B` |
//! | link special relay SB | `A1` | `SB` | hex | bit | `SB` |
//! | step relay S | `98` | `S*` | dec | bit | `S` |
//! | special relay SM | `91` | `SM` | dec | bit | `SM` |
//! | timer contact TS | `C1` | `TS` | dec | bit | `TS` |
//! | timer coil TC | `C0` | `TC` | dec | bit | `TC` |
//! | timer current value TN | `C2` | `TN` | dec | word | `TN` |
//! | retentive timer contact SS | `C7` | `SS` | dec | bit | `STS` |
//! | retentive timer coil SC | `C6` | `SC` | dec | bit | `STC` |
//! | retentive timer current value SN | `C8` | `SN` | dec | word | `STN` |
//! | counter contact CS | `C4` | `CS` | dec | bit | `CS` |
//! | counter coil CC | `C3` | `CC` | dec | bit | `CC` |
//! | counter current value CN | `C5` | `CN` | dec | word | `CN` |
//! | data register D | `A8` | `D*` | dec | word | `D` |
//! | link register W | `B4` | `W*` | hex | word | `W` |
//! | link special register SW | `B5` | `SW` | hex | word | `SW` |
//! | special register SD | `A9` | `SD` | dec | word | `SD` |
//! | index register Z | `CC` | `Z*` | dec | word | `Z` |
//! | file register R | `AF` | `R*` | dec | word | `R` (the block SD648 selects) |
//! | file register ZR | `B0` | `ZR` | hex | word | `ZR` |
//! | direct input DX | `A2` | `DX` | hex | bit | `X` (no separate direct access in softplc) |
//! | direct output DY | `A3` | `DY` | hex | bit | `Y` |
//!
//! In ASCII the second character of a one-letter code may be `*` or a space. The
//! binary device number is always binary; the ASCII number is written in the
//! device's own numbering (hexadecimal for X, Y, B, W, SB, SW, DX, DY and ZR).
//!
//! Buffer memory of an intelligent function module, `U<n>\G<addr>` (module
//! access device G, binary `AB`, ASCII `G*`, decimal), is reached only through
//! the device extension specification (subcommands 0080/0081, see
//! [`crate::command`]): its unit number travels in the extension
//! specification. [`Device::ALL`] lists the devices of the plain
//! specification; G is not among them and answers `C05B` there.

use softplc_core::device::DeviceKind;
use std::fmt;

/// A device as the MC protocol names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Device {
    X,
    Y,
    M,
    L,
    F,
    V,
    B,
    SB,
    S,
    SM,
    TS,
    TC,
    TN,
    SS,
    SC,
    SN,
    CS,
    CC,
    CN,
    D,
    W,
    SW,
    SD,
    Z,
    R,
    ZR,
    DX,
    DY,
    /// Module access device: buffer memory of the intelligent function module
    /// a [`DeviceRef::unit`] names (extension specification only).
    G,
}

impl Device {
    pub const ALL: [Device; 28] = {
        use Device::*;
        [
            X, Y, M, L, F, V, B, SB, S, SM, TS, TC, TN, SS, SC, SN, CS, CC, CN, D, W, SW, SD, Z, R,
            ZR, DX, DY,
        ]
    };

    /// The 1-byte binary device code.
    pub fn binary_code(self) -> u8 {
        use Device::*;
        match self {
            X => 0x9C,
            Y => 0x9D,
            M => 0x90,
            L => 0x92,
            F => 0x93,
            V => 0x94,
            B => 0xA0,
            SB => 0xA1,
            S => 0x98,
            SM => 0x91,
            TS => 0xC1,
            TC => 0xC0,
            TN => 0xC2,
            SS => 0xC7,
            SC => 0xC6,
            SN => 0xC8,
            CS => 0xC4,
            CC => 0xC3,
            CN => 0xC5,
            D => 0xA8,
            W => 0xB4,
            SW => 0xB5,
            SD => 0xA9,
            Z => 0xCC,
            R => 0xAF,
            ZR => 0xB0,
            DX => 0xA2,
            DY => 0xA3,
            G => 0xAB,
        }
    }

    /// The 2-character ASCII device code (`*` pads one-letter names).
    pub fn ascii_code(self) -> [u8; 2] {
        let n = self.name().as_bytes();
        if n.len() == 1 {
            [n[0], b'*']
        } else {
            [n[0], n[1]]
        }
    }

    pub fn from_binary(code: u8) -> Option<Device> {
        Device::ALL.into_iter().find(|d| d.binary_code() == code)
    }

    /// Accepts `*` or a space as the pad of a one-letter code.
    pub fn from_ascii(code: [u8; 2]) -> Option<Device> {
        let code = if code[1] == b' ' {
            [code[0], b'*']
        } else {
            code
        };
        Device::ALL.into_iter().find(|d| d.ascii_code() == code)
    }

    /// The MC protocol name (`SS`, not softplc's `STS`).
    pub fn name(self) -> &'static str {
        use Device::*;
        match self {
            X => "X",
            Y => "Y",
            M => "M",
            L => "L",
            F => "F",
            V => "V",
            B => "B",
            SB => "SB",
            S => "S",
            SM => "SM",
            TS => "TS",
            TC => "TC",
            TN => "TN",
            SS => "SS",
            SC => "SC",
            SN => "SN",
            CS => "CS",
            CC => "CC",
            CN => "CN",
            D => "D",
            W => "W",
            SW => "SW",
            SD => "SD",
            Z => "Z",
            R => "R",
            ZR => "ZR",
            DX => "DX",
            DY => "DY",
            G => "G",
        }
    }

    /// Device numbers are hexadecimal in ASCII frames (and in names).
    pub fn is_hex(self) -> bool {
        use Device::*;
        matches!(self, X | Y | B | SB | W | SW | ZR | DX | DY)
    }

    /// Where softplc keeps the device.
    pub fn kind(self) -> DeviceKind {
        use Device::*;
        match self {
            X | DX => DeviceKind::X,
            Y | DY => DeviceKind::Y,
            M => DeviceKind::M,
            L => DeviceKind::L,
            F => DeviceKind::F,
            V => DeviceKind::V,
            B => DeviceKind::B,
            SB => DeviceKind::SB,
            S => DeviceKind::S,
            SM => DeviceKind::SM,
            TS => DeviceKind::TS,
            TC => DeviceKind::TC,
            TN => DeviceKind::TN,
            SS => DeviceKind::STS,
            SC => DeviceKind::STC,
            SN => DeviceKind::STN,
            CS => DeviceKind::CS,
            CC => DeviceKind::CC,
            CN => DeviceKind::CN,
            D => DeviceKind::D,
            W => DeviceKind::W,
            SW => DeviceKind::SW,
            SD => DeviceKind::SD,
            Z => DeviceKind::Z,
            R => DeviceKind::R,
            ZR => DeviceKind::ZR,
            G => DeviceKind::G,
        }
    }

    /// Bit devices (the others are word devices).
    pub fn is_bit(self) -> bool {
        self.kind().is_bit()
    }
}

impl fmt::Display for Device {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The largest device number a Q-format device specification carries (3 bytes).
pub const MAX_NUMBER: u32 = 0xFF_FFFF;

/// A device and a device number, e.g. `D100`, `X1F` or `U3\G1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DeviceRef {
    pub device: Device,
    /// At most [`MAX_NUMBER`]; in ASCII frames a decimal device's number is at most 999999.
    pub number: u32,
    /// Buffer memory `U<unit>\G<number>`: the module's start I/O number
    /// divided by 16 (device [`Device::G`]); `None` for the CPU's devices.
    pub unit: Option<u16>,
}

impl DeviceRef {
    pub fn new(device: Device, number: u32) -> DeviceRef {
        DeviceRef {
            device,
            number,
            unit: None,
        }
    }

    /// Word `address` of the buffer memory of the module whose start I/O
    /// number is `unit` × 16: `U<unit>\G<address>`.
    pub fn module(unit: u16, address: u32) -> DeviceRef {
        DeviceRef {
            device: Device::G,
            number: address,
            unit: Some(unit),
        }
    }

    /// Parses a device name as a client writes it: `D100`, `X1F`, `ZR10`, `SN3`,
    /// `U3\G1`. Numbers are hexadecimal for the hexadecimal devices and the unit.
    pub fn parse(s: &str) -> Option<DeviceRef> {
        let s = s.trim();
        let upper = s.to_ascii_uppercase();
        if let Some((u, g)) = upper.strip_prefix('U').and_then(|r| r.split_once('\\')) {
            let unit = u16::from_str_radix(u, 16).ok().filter(|_| u.len() <= 3)?;
            let address = g.strip_prefix('G')?;
            if address.is_empty() || !address.bytes().all(|c| c.is_ascii_digit()) {
                return None;
            }
            let number = address.parse::<u32>().ok().filter(|n| *n <= MAX_NUMBER)?;
            return Some(DeviceRef::module(unit, number));
        }
        let split = s.find(|c: char| c.is_ascii_digit()).unwrap_or(s.len());
        // Hexadecimal numbers may start with a letter (XFF): try the longest
        // device name first, then shorter ones.
        for cut in (1..=split.min(2)).rev() {
            let (name, num) = upper.split_at(cut);
            let Some(device) = Device::ALL.into_iter().find(|d| d.name() == name) else {
                continue;
            };
            let radix = if device.is_hex() { 16 } else { 10 };
            if num.is_empty() || !num.chars().all(|c| c.is_digit(radix)) {
                continue;
            }
            let number = u32::from_str_radix(num, radix).ok()?;
            if number > MAX_NUMBER {
                return None;
            }
            return Some(DeviceRef::new(device, number));
        }
        None
    }
}

impl fmt::Display for DeviceRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(u) = self.unit {
            write!(f, "U{u:X}\\{}{}", self.device, self.number)
        } else if self.device.is_hex() {
            write!(f, "{}{:X}", self.device, self.number)
        } else {
            write!(f, "{}{}", self.device, self.number)
        }
    }
}
