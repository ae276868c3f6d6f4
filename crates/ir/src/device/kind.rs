//! Device kinds and their numbering (004 Table 10.1, L5894-5950).

use std::fmt;

/// Every device kind with its own storage.
///
/// Timers, retentive timers and counters are split into contact (`TS`), coil (`TC`)
/// and current value (`TN`), the way the MC protocol names them. In a program `T0`
/// means the contact in a bit operand and the current value in a word operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum DeviceKind {
    // bit devices
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
    STS,
    STC,
    CS,
    CC,
    FX,
    FY,
    // word devices
    D,
    W,
    SW,
    SD,
    Z,
    TN,
    STN,
    CN,
    FD,
    R,
    ZR,
    /// Buffer memory of the rack's intelligent function modules, every
    /// module's words one after another (004 ch. 8). Programs name it
    /// `U<n>\\G<addr>`; the map's unit windows say where each module's are.
    G,
}

/// How a dialect writes a device's numbers: decimal, hexadecimal (MELSEC
/// X/Y/B/W) or octal (APLC X/Y).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbering {
    Dec,
    Hex,
    Oct,
}

impl Numbering {
    pub const fn radix(self) -> u32 {
        match self {
            Numbering::Dec => 10,
            Numbering::Hex => 16,
            Numbering::Oct => 8,
        }
    }

    /// True when `c` (upper case) is a digit of this numbering.
    pub fn is_digit(self, c: u8) -> bool {
        (c as char).is_digit(self.radix())
    }
}

impl DeviceKind {
    pub const COUNT: usize = 30;
    pub const ALL: [DeviceKind; Self::COUNT] = {
        use DeviceKind::*;
        [
            X, Y, M, L, F, V, B, SB, S, SM, TS, TC, STS, STC, CS, CC, FX, FY, D, W, SW, SD, Z, TN,
            STN, CN, FD, R, ZR, G,
        ]
    };

    /// Buffer memory of the modules: the modules' own memory, not the
    /// CPU's, so no device clear, latch or initial value of the CPU touches it.
    pub fn is_module(self) -> bool {
        self == DeviceKind::G
    }

    /// The system's relays and registers (SM, SD): kept through a device
    /// clear.
    pub fn is_system(self) -> bool {
        matches!(self, DeviceKind::SM | DeviceKind::SD)
    }

    /// The contact, coil and current-value kinds of a timer, retentive
    /// timer or counter point, whichever of them `self` is (TS, TC, TN for
    /// TC): they are sized, latched and made local together. `None` for
    /// every other kind.
    pub fn timer_parts(self) -> Option<&'static [DeviceKind; 3]> {
        use DeviceKind::*;
        match self {
            TS | TC | TN => Some(&[TS, TC, TN]),
            STS | STC | STN => Some(&[STS, STC, STN]),
            CS | CC | CN => Some(&[CS, CC, CN]),
            _ => None,
        }
    }

    /// The kind that names a range of this kind's points: the contact
    /// (TS, STS, CS) for any part of a timer, retentive timer or counter
    /// ([`Self::timer_parts`]), else `self`.
    pub fn range_kind(self) -> DeviceKind {
        self.timer_parts().map_or(self, |p| p[0])
    }

    /// Words each point occupies: 4 for the function registers FD (004
    /// §10.3.1 (2)(c): "1 point occupies 4 words", for 16-, 32- and 64-bit
    /// arguments), 1 for every other word device.
    #[inline]
    pub fn words_per_point(self) -> u32 {
        if self == DeviceKind::FD {
            4
        } else {
            1
        }
    }

    #[inline]
    pub fn is_bit(self) -> bool {
        (self as u8) <= (DeviceKind::FY as u8)
    }

    /// The MELSEC-Q numbering of this kind (the numbering a dialect writes is
    /// in its [`super::DeviceTable`]).
    pub fn numbering(self) -> Numbering {
        self.melsec_numbering()
    }

    pub(crate) const fn melsec_numbering(self) -> Numbering {
        use DeviceKind::*;
        match self {
            X | Y | B | SB | W | SW | FX | FY => Numbering::Hex,
            _ => Numbering::Dec,
        }
    }

    /// The name as written in programs and on the command line.
    pub fn name(self) -> &'static str {
        use DeviceKind::*;
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
            STS => "STS",
            STC => "STC",
            CS => "CS",
            CC => "CC",
            FX => "FX",
            FY => "FY",
            D => "D",
            W => "W",
            SW => "SW",
            SD => "SD",
            Z => "Z",
            TN => "TN",
            STN => "STN",
            CN => "CN",
            FD => "FD",
            R => "R",
            ZR => "ZR",
            G => "G",
        }
    }

    /// Formats device number `n` in this kind's numbering (`X1F`, `D100`).
    pub fn format(self, n: u32) -> String {
        match self.numbering() {
            Numbering::Hex => format!("{}{:X}", self.name(), n),
            Numbering::Dec => format!("{}{}", self.name(), n),
            Numbering::Oct => format!("{}{:o}", self.name(), n),
        }
    }
}

impl fmt::Display for DeviceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
