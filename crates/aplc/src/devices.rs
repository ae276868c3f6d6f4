//! APLC-TCP devices (002 table 3-2, L1514-1553; spec aplc.md §2): names,
//! octal X/Y, bit groups `K<n>`, the index suffix `Z<k>`, and where each
//! device lives in softplc's flat device memory.
//!
//! Storage (the engine's memory is organised by `DeviceKind`; the APLC names
//! map onto kinds the MELSEC layout already has):
//! X, Y, M, S, SM, SD, D, Z on the kinds of the same name; T on TS (contact)
//! and TN (value); C on CS (contact) and CN (value), where C0-C199 take CN0-CN199
//! and the 32-bit C200+k take the pair CN(200+2k) (high word), CN(201+2k)
//! (low word); LM on B, V on W; the timers' hidden timing bits and
//! remainders on STS/STN; the EEPROM that EROMWR writes on ZR (kept through
//! power-on like file registers, no APLC name reaches it): ZR0-ZR999 the
//! image of D6000-D6999, ZR1000-ZR1999 1 where EROMWR wrote that word;
//! the communication mailboxes of PORT1/PORT2 on SW (`comm::mailbox`).
//! Eight hidden bits of kind V hold the MC
//! levels' state, then the FOR gate, the CALL flow, the SFC step gate and the
//! interrupt dispatch.

use softplc_ir::device::{DeviceConfig, DeviceKind};

/// An APLC device letter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dev {
    X,
    Y,
    M,
    S,
    T,
    C,
    D,
    V,
    LM,
    Z,
    SM,
    SD,
}

impl Dev {
    pub const ALL: [Dev; 12] = [
        Dev::X,
        Dev::Y,
        Dev::M,
        Dev::S,
        Dev::T,
        Dev::C,
        Dev::D,
        Dev::V,
        Dev::LM,
        Dev::Z,
        Dev::SM,
        Dev::SD,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Dev::X => "X",
            Dev::Y => "Y",
            Dev::M => "M",
            Dev::S => "S",
            Dev::T => "T",
            Dev::C => "C",
            Dev::D => "D",
            Dev::V => "V",
            Dev::LM => "LM",
            Dev::Z => "Z",
            Dev::SM => "SM",
            Dev::SD => "SD",
        }
    }

    /// Number of points (table 3-2).
    pub fn points(self) -> u32 {
        match self {
            Dev::X | Dev::Y => 128,
            Dev::M => 2048,
            Dev::S => 1024,
            Dev::T | Dev::C | Dev::SM | Dev::SD => 256,
            Dev::D => 8000,
            Dev::V | Dev::LM => 64,
            Dev::Z => 16,
        }
    }

    /// X and Y are numbered in octal (L892, L1521).
    pub fn radix(self) -> u32 {
        match self {
            Dev::X | Dev::Y => 8,
            _ => 10,
        }
    }

    /// Has a bit (contact/coil) meaning.
    pub fn is_bit(self) -> bool {
        matches!(
            self,
            Dev::X | Dev::Y | Dev::M | Dev::S | Dev::T | Dev::C | Dev::LM | Dev::SM
        )
    }

    /// Has a word meaning.
    pub fn is_word(self) -> bool {
        matches!(self, Dev::T | Dev::C | Dev::D | Dev::V | Dev::Z | Dev::SD)
    }

    /// The storage kind and number of bit `n`.
    pub fn bit_storage(self, n: u32) -> Option<(DeviceKind, u32)> {
        let k = match self {
            Dev::X => DeviceKind::X,
            Dev::Y => DeviceKind::Y,
            Dev::M => DeviceKind::M,
            Dev::S => DeviceKind::S,
            Dev::T => DeviceKind::TS,
            Dev::C => DeviceKind::CS,
            Dev::LM => DeviceKind::B,
            Dev::SM => DeviceKind::SM,
            _ => return None,
        };
        Some((k, n))
    }

    /// The storage kind and number of word `n` (the first word of C200-C255's
    /// pair).
    pub fn word_storage(self, n: u32) -> Option<(DeviceKind, u32)> {
        Some(match self {
            Dev::T => (DeviceKind::TN, n),
            Dev::C => (DeviceKind::CN, counter_word(n)),
            Dev::D => (DeviceKind::D, n),
            Dev::V => (DeviceKind::W, n),
            Dev::Z => (DeviceKind::Z, n),
            Dev::SD => (DeviceKind::SD, n),
            _ => return None,
        })
    }

    /// Formats device number `n` as the APLC writes it (`X17`, `D100`).
    pub fn format(self, n: u32) -> String {
        match self.radix() {
            8 => format!("{}{:o}", self.name(), n),
            _ => format!("{}{}", self.name(), n),
        }
    }
}

/// C200-C255 are 32-bit counters (L1732-1740).
pub fn is_counter32(n: u32) -> bool {
    (200..256).contains(&n)
}

/// The CN word holding counter `n`'s value (its high word for C200-C255).
pub fn counter_word(n: u32) -> u32 {
    if n < 200 {
        n
    } else {
        200 + 2 * (n - 200)
    }
}

/// CN words: 200 16-bit values and 56 pairs.
const CN_WORDS: u32 = 200 + 2 * 56;
/// Hidden bits (kind V) holding the state of MC levels 0-7.
pub const MC_BITS: u32 = 8;
/// The hidden bit (kind V) of the FOR gate, after the MC bits.
pub const FOR_BIT: u32 = MC_BITS;
/// The hidden bit (kind V) giving a rung its power flow back after CALL.
pub const CALL_BIT: u32 = MC_BITS + 1;
/// Hidden bits (kind V) of SFC steps: the skip of a step body, its MC state.
pub const STEP_SKIP_BIT: u32 = MC_BITS + 2;
pub const STEP_MC_BIT: u32 = MC_BITS + 3;
/// Hidden bits (kind V) of interrupts: the global enable (EI), "an event was
/// taken", and one bit per interrupt routine.
pub const EI_BIT: u32 = MC_BITS + 4;
pub const INT_ANY_BIT: u32 = MC_BITS + 5;
pub const INT_BITS: u32 = MC_BITS + 6;
/// Interrupt routines a program can have: 16 edge, 3 timed, 8 serial events.
pub const MAX_INT: u32 = 32;

/// The hidden word (kind SW, after the ports' mailboxes) where each scan
/// start leaves the changes of X0-X7 in the input image since the previous
/// one: rises in the low byte, falls in the high byte (the edge interrupts).
pub const INPUT_EDGES: u32 = 2 * crate::comm::mailbox::SIZE;

/// The EROMWR area D6000-D6999 (L985-991): its first register and size. Its
/// EEPROM image is ZR0-ZR999, the "saved" marks ZR1000-ZR1999.
pub const EEPROM_FIRST: u32 = 6000;
pub const EEPROM_WORDS: u32 = 1000;

/// The device points of an APLC-TCP CPU in softplc's memory layout.
pub fn device_config() -> DeviceConfig {
    let mut c = DeviceConfig::default();
    for k in DeviceKind::ALL {
        c.set_points(k, 0);
    }
    for (k, n) in [
        (DeviceKind::X, 128),
        (DeviceKind::Y, 128),
        (DeviceKind::M, 2048),
        (DeviceKind::S, 1024),
        (DeviceKind::B, 64),
        (DeviceKind::SM, 256),
        (DeviceKind::D, 8000),
        (DeviceKind::W, 64),
        (DeviceKind::Z, 16),
        (DeviceKind::SD, 256),
        (DeviceKind::V, INT_BITS + MAX_INT),
        (DeviceKind::TS, 256),
        // Hidden: the timers' "timing" bits and sub-unit remainders.
        (DeviceKind::STS, 256),
        (DeviceKind::CS, CN_WORDS),
        // Hidden: the EEPROM image of D6000-D6999 and its "saved" marks.
        (DeviceKind::ZR, 2 * EEPROM_WORDS),
        // Hidden: the ports' mailboxes (comm::mailbox), the input edges.
        (DeviceKind::SW, INPUT_EDGES + 1),
    ] {
        c.set_points(k, n);
    }
    c
}

/// A device operand as written: `M10`, `X17`, `D10Z1`, `K4M0`, `K1X0Z10`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceRef {
    pub dev: Dev,
    pub n: u32,
    /// `K<n>` bit group (1-8).
    pub group: Option<u8>,
    /// Index register `Z<k>`.
    pub index: Option<u8>,
}

impl DeviceRef {
    /// The name as the APLC writes it.
    pub fn text(&self) -> String {
        let mut s = String::new();
        if let Some(k) = self.group {
            s += &format!("K{k}");
        }
        s += &self.dev.format(self.n);
        if let Some(z) = self.index {
            s += &format!("Z{z}");
        }
        s
    }
}

/// Splits a device letter off the start of `t` (upper case).
fn letter(t: &str) -> Option<(Dev, &str)> {
    for (p, d) in [("LM", Dev::LM), ("SM", Dev::SM), ("SD", Dev::SD)] {
        if let Some(rest) = t.strip_prefix(p) {
            if rest.starts_with(|c: char| c.is_ascii_digit()) {
                return Some((d, rest));
            }
        }
    }
    let d = match t.as_bytes().first()? {
        b'X' => Dev::X,
        b'Y' => Dev::Y,
        b'M' => Dev::M,
        b'S' => Dev::S,
        b'T' => Dev::T,
        b'C' => Dev::C,
        b'D' => Dev::D,
        b'V' => Dev::V,
        b'Z' => Dev::Z,
        _ => return None,
    };
    let rest = &t[1..];
    rest.starts_with(|c: char| c.is_ascii_digit())
        .then_some((d, rest))
}

/// True when `t` (any case) has the form of a device, with or without a bit
/// group or index: what a variable name may not look like (L1176).
pub fn looks_like_device(t: &str) -> bool {
    let u = t.to_ascii_uppercase();
    let body = group_prefix(&u).map_or(u.as_str(), |(_, r)| r);
    letter(body).is_some_and(|(_, rest)| {
        let (num, idx) = split_index(rest);
        num.bytes().all(|b| b.is_ascii_digit())
            && idx.is_none_or(|z| !z.is_empty() && z.bytes().all(|b| b.is_ascii_digit()))
    })
}

fn group_prefix(u: &str) -> Option<(u8, &str)> {
    let b = u.as_bytes();
    if b.len() >= 3 && b[0] == b'K' && b[1].is_ascii_digit() && b[2].is_ascii_alphabetic() {
        Some((b[1] - b'0', &u[2..]))
    } else {
        None
    }
}

/// Splits `10Z1` into `10` and `Some("1")`.
fn split_index(rest: &str) -> (&str, Option<&str>) {
    match rest.find('Z') {
        Some(p) => (&rest[..p], Some(&rest[p + 1..])),
        None => (rest, None),
    }
}

/// Parses a device operand (upper case). `Ok(None)`: not a device at all
/// (a constant or a name); `Err`: a device with a bad number.
pub fn parse_device(u: &str) -> Result<Option<DeviceRef>, String> {
    let (group, body) = match group_prefix(u) {
        Some((k, r)) => (Some(k), r),
        None => (None, u),
    };
    let Some((dev, rest)) = letter(body) else {
        return Ok(None);
    };
    let (num, idx) = split_index(rest);
    if dev == Dev::Z && idx.is_some() {
        return Err(format!("`{u}`: an index register cannot be indexed"));
    }
    let radix = dev.radix();
    let n = match u32::from_str_radix(num, radix) {
        Ok(n) if num.bytes().all(|b| b.is_ascii_digit()) => n,
        _ if radix == 8 && num.bytes().all(|b| b.is_ascii_digit()) => {
            return Err(format!(
                "`{u}`: {} is numbered in octal (digits 0-7; {}0-{}177)",
                dev.name(),
                dev.name(),
                dev.name()
            ))
        }
        _ => return Err(format!("`{u}` is not a device")),
    };
    if n >= dev.points() {
        return Err(format!(
            "`{u}` is out of range ({}-{})",
            dev.format(0),
            dev.format(dev.points() - 1)
        ));
    }
    let index = match idx {
        None => None,
        Some(z) => match z.parse::<u8>() {
            Ok(z) if z < 16 => Some(z),
            _ => return Err(format!("`{u}`: the index register is Z0-Z15")),
        },
    };
    if let Some(k) = group {
        if !(1..=8).contains(&k) {
            return Err(format!("`{u}`: a bit group is K1-K8"));
        }
        if !dev.is_bit() || matches!(dev, Dev::T | Dev::C) {
            return Err(format!(
                "`{u}`: a bit group needs X, Y, M, S, LM or SM (APLC programming manual §3.2.1)"
            ));
        }
        if n + 4 * k as u32 > dev.points() {
            return Err(format!(
                "`{u}`: K{k} from {} runs past {}",
                dev.format(n),
                dev.format(dev.points() - 1)
            ));
        }
    }
    Ok(Some(DeviceRef {
        dev,
        n,
        group,
        index,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn octal_and_decimal_numbers() {
        let x = parse_device("X10").unwrap().unwrap();
        assert_eq!((x.dev, x.n), (Dev::X, 8));
        assert!(parse_device("X8").unwrap_err().contains("octal"));
        assert!(parse_device("Y18").is_err());
        assert!(parse_device("X200").unwrap_err().contains("out of range"));
        assert_eq!(parse_device("X177").unwrap().unwrap().n, 127);
        let k = parse_device("K1X0Z10").unwrap().unwrap();
        assert_eq!((k.group, k.index, k.n), (Some(1), Some(10), 0));
        assert_eq!(parse_device("LM63").unwrap().unwrap().dev, Dev::LM);
        assert!(parse_device("D8000").is_err());
        assert_eq!(parse_device("ABC").unwrap(), None);
        assert_eq!(parse_device("100").unwrap(), None);
        assert!(looks_like_device("x8"));
        assert!(!looks_like_device("Y0输出控制"));
    }

    #[test]
    fn counter_words() {
        assert_eq!(counter_word(199), 199);
        assert_eq!(counter_word(200), 200);
        assert_eq!(counter_word(255), 310);
        assert_eq!(device_config().points(DeviceKind::CN), CN_WORDS);
    }

    proptest! {
        /// APLC name ↔ index round trip for every device (octal X/Y included).
        #[test]
        fn name_index_round_trip(d in 0usize..12, n in 0u32..8000, z in proptest::option::of(0u8..16)) {
            let dev = Dev::ALL[d];
            let n = n % dev.points();
            let index = if dev == Dev::Z { None } else { z };
            let r = DeviceRef { dev, n, group: None, index };
            let text = r.text();
            prop_assert_eq!(parse_device(&text).unwrap(), Some(r));
        }
    }
}
