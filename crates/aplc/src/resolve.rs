//! Operand resolution against the APLC operand sets (spec aplc.md §4.0, table
//! 3-4 L2066-2090): Bsrc/Bdst bits, 16-bit, 32-bit and REAL sources and
//! destinations, constants fitting their operand, bit groups and indexing.
//! Every failure is a message naming the token.

use softplc_ir::device::{DeviceKind, DeviceMap};
use softplc_ir::ops::{BitArg, Block, Indexed, IndexedKind, WordArg};
use softplc_lang::compile::{Args, Compiler};
use softplc_lang::Token;

use crate::constant::{self, looks_like_constant, Width};
use crate::devices::{is_counter32, parse_device, Dev, DeviceRef};

/// What a bit operand may be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BitUse {
    /// A contact of LD…OR (Bsrc, no index, L2574).
    Contact,
    /// OUT (Y, M, S, LM, SM; no index, L2738).
    Coil,
    /// SET/RST (Bdst with T and C).
    SetRst,
}

/// SM relays the program may not write (Appendix 1 R column, L10696-10978).
fn sm_read_only(n: u32) -> bool {
    matches!(n, 0..=15 | 20..=22 | 71 | 82 | 83 | 114 | 124 | 134 | 190..=193 | 196)
}

/// SD registers the program may not write (Appendix 2 R column).
fn sd_read_only(n: u32) -> bool {
    matches!(n, 0..=12 | 20..=35 | 56 | 57 | 100..=106 | 125..=128 | 139 | 144 | 172 | 174 | 191 | 192)
}

fn device(text: &str) -> Result<DeviceRef, String> {
    let u = text.to_ascii_uppercase();
    match parse_device(&u)? {
        Some(d) => Ok(d),
        None if looks_like_constant(text) => Err(format!(
            "constant `{text}` where the operand table lists none (a device is needed)"
        )),
        None => Err(format!("`{text}` is not a device, constant or variable")),
    }
}

/// A bit operand.
pub fn bit(map: &DeviceMap, text: &str, what: BitUse) -> Result<BitArg, String> {
    let d = device(text)?;
    if d.group.is_some() {
        return Err(format!(
            "`{text}` is a bit group; a bit operand is needed here"
        ));
    }
    if !d.dev.is_bit() {
        return Err(format!(
            "`{text}` is a word device; a bit device is needed here"
        ));
    }
    if d.index.is_some() {
        return Err(format!(
            "`{text}`: this operand cannot be indexed (APLC programming manual §5.1.1, §5.1.7)"
        ));
    }
    let ok = match what {
        BitUse::Contact => true,
        BitUse::Coil => matches!(d.dev, Dev::Y | Dev::M | Dev::S | Dev::LM | Dev::SM),
        BitUse::SetRst => d.dev != Dev::X,
    };
    if !ok || d.dev == Dev::X && what != BitUse::Contact {
        return Err(format!(
            "`{text}` cannot be written by this instruction{}",
            if d.dev == Dev::X {
                " (X is read-only, APLC programming manual §3.1.3)"
            } else {
                ""
            }
        ));
    }
    if what != BitUse::Contact && d.dev == Dev::SM && sm_read_only(d.n) {
        return Err(format!(
            "`{text}` is a read-only special relay (APLC programming manual §3.1.9)"
        ));
    }
    let (k, n) = d
        .dev
        .bit_storage(d.n)
        .ok_or_else(|| format!("`{text}` is not a bit device"))?;
    Ok(BitArg::Bit(map.base(k) + n))
}

/// A word operand of `width`; `dest` for destinations; `sd_dest` lets a
/// destination be SD (MOV, DMOV: "Wdst +SD").
pub fn word(
    map: &DeviceMap,
    text: &str,
    width: Width,
    dest: bool,
    sd_dest: bool,
) -> Result<WordArg, String> {
    if looks_like_constant(text) {
        if dest {
            return Err(format!("constant `{text}` cannot be a destination"));
        }
        return constant::parse(text, width).map(WordArg::Const);
    }
    let d = device(text)?;
    if let Some(k) = d.group {
        let (lo, hi) = match width {
            Width::W16 => (1, 4),
            Width::W32 => (5, 8),
            Width::Real => {
                return Err(format!(
                    "`{text}`: a REAL operand is D or V (APLC programming manual §3.3.2)"
                ))
            }
        };
        if !(lo..=hi).contains(&k) {
            return Err(format!(
                "`{text}`: a {}-bit operand takes K{lo}-K{hi} (APLC programming manual §3.3.2)",
                if width == Width::W16 { 16 } else { 32 }
            ));
        }
        if dest && matches!(d.dev, Dev::X | Dev::SM) {
            return Err(format!(
                "`{text}` cannot be a destination (K<n>Y, M, S or LM)"
            ));
        }
        let (kind, n) = d
            .dev
            .bit_storage(d.n)
            .ok_or_else(|| format!("`{text}` is not a bit device"))?;
        return Ok(match d.index {
            None => WordArg::Digits {
                bit: map.base(kind) + n,
                n: k,
            },
            Some(z) => WordArg::Indexed(indexed(
                map,
                IndexedKind::Digits(k),
                kind,
                n,
                map.points(kind),
                z,
            )),
        });
    }
    if !d.dev.is_word() {
        return Err(format!(
            "`{text}` is a bit device; a word operand needs a bit group such as K4{text}"
        ));
    }
    let ok = match width {
        Width::W16 => d.dev != Dev::C || !is_counter32(d.n),
        Width::W32 => match d.dev {
            Dev::C => is_counter32(d.n),
            Dev::D | Dev::SD | Dev::V => true,
            _ => false,
        },
        Width::Real => matches!(d.dev, Dev::D | Dev::V),
    };
    if !ok {
        let why = match (width, d.dev) {
            (Width::W16, Dev::C) => "C200-C255 are 32-bit counters".to_string(),
            (Width::W32, Dev::C) => "a 32-bit operand takes C200-C255".to_string(),
            (Width::Real, _) => {
                "a REAL operand is D or V (APLC programming manual §3.3.2)".to_string()
            }
            _ => format!(
                "{} is not a 32-bit operand (APLC programming manual §3.3.2)",
                d.dev.name()
            ),
        };
        return Err(format!("`{text}`: {why}"));
    }
    if dest && d.dev == Dev::SD && (!sd_dest || sd_read_only(d.n)) {
        return Err(format!(
            "`{text}` cannot be a destination here (read-only or not in the operand table)"
        ));
    }
    let words = if width == Width::W16 || d.dev == Dev::C {
        1
    } else {
        2
    };
    if d.n + words > d.dev.points() && d.index.is_none() {
        return Err(format!(
            "`{text}`: a 32-bit operand needs {} too, past the last device",
            d.dev.format(d.n + 1)
        ));
    }
    let (kind, n) = d
        .dev
        .word_storage(d.n)
        .ok_or_else(|| format!("`{text}` is not a word device"))?;
    Ok(match d.index {
        None => WordArg::Word(map.base(kind) + n),
        Some(z) => {
            if d.dev == Dev::C && is_counter32(d.n) {
                return Err(format!(
                    "`{text}`: indexing C200-C255 is not implemented yet in softplc"
                ));
            }
            let points = if d.dev == Dev::C { 200 } else { d.dev.points() };
            WordArg::Indexed(indexed(map, IndexedKind::Word, kind, n, points, z))
        }
    })
}

fn indexed(
    map: &DeviceMap,
    kind: IndexedKind,
    dk: DeviceKind,
    number: u32,
    points: u32,
    z: u8,
) -> Box<Indexed> {
    Box::new(Indexed {
        kind,
        base: map.base(dk),
        number,
        points,
        z: map.base(DeviceKind::Z) + z as u32,
        window: softplc_ir::ops::Window::Device,
    })
}

/// The first word of a 16-bit block (BMOV, FMOV: D, SD as a source, C0-C199,
/// T, V) and the end of its device.
pub fn block(map: &DeviceMap, text: &str, dest: bool) -> Result<Block, String> {
    let d = device(text)?;
    if d.group.is_some() {
        return Err(format!(
            "`{text}`: blocks of bit groups are not implemented yet in softplc"
        ));
    }
    if !matches!(d.dev, Dev::D | Dev::SD | Dev::C | Dev::T | Dev::V) {
        return Err(format!("`{text}`: a block is D, SD, C, T or V"));
    }
    let start = word(map, text, Width::W16, dest, false)?;
    let (kind, _) = d
        .dev
        .word_storage(0)
        .ok_or_else(|| format!("`{text}` is not a word device"))?;
    let points = if d.dev == Dev::C { 200 } else { d.dev.points() };
    Ok(Block {
        start,
        limit: map.base(kind) + points,
    })
}

/// The first pair of a 32-bit destination block (DFMOV: D, V, C200-C255).
pub fn block32(map: &DeviceMap, text: &str) -> Result<Block, String> {
    let d = device(text)?;
    if d.group.is_some() || d.dev == Dev::SD {
        return Err(format!("`{text}`: a 32-bit block is D, V or C200-C255"));
    }
    let start = word(map, text, Width::W32, true, false)?;
    let (kind, first) = d
        .dev
        .word_storage(0)
        .ok_or_else(|| format!("`{text}` is not a word device"))?;
    let points = if d.dev == Dev::C {
        crate::devices::counter_word(255) + 2
    } else {
        d.dev.points() + first
    };
    Ok(Block {
        start,
        limit: map.base(kind) + points,
    })
}

/// A timer or counter operand (`T5`, `C200`): its number.
pub fn tc(text: &str, dev: Dev) -> Result<u32, String> {
    let d = device(text)?;
    if d.dev != dev || d.group.is_some() || d.index.is_some() {
        return Err(format!("`{text}`: a {} device is needed here", dev.name()));
    }
    Ok(d.n)
}

/// A constant operand fixed at load in `lo..=hi` (LBL, CJ, MC numbers).
pub fn number(text: &str, lo: u32, hi: u32) -> Result<u32, String> {
    match text.parse::<u32>() {
        Ok(n) if (lo..=hi).contains(&n) => Ok(n),
        _ => Err(format!("`{text}`: a constant {lo}-{hi} is needed here")),
    }
}

/// Resolution through [`Args`] with the diagnostic at operand `k`.
pub trait ArgsExt {
    fn word_at(&mut self, k: usize, width: Width, dest: bool) -> Option<WordArg>;
    fn sd_dest_at(&mut self, k: usize, width: Width) -> Option<WordArg>;
    fn bit_at(&mut self, k: usize, what: BitUse) -> Option<BitArg>;
    fn check<T>(&mut self, k: usize, r: Result<T, String>) -> Option<T>;
    fn flags(&self) -> Flags;
}

impl ArgsExt for Args<'_, '_> {
    fn word_at(&mut self, k: usize, width: Width, dest: bool) -> Option<WordArg> {
        let r = word(self.map(), self.text(k), width, dest, false);
        self.check(k, r)
    }
    fn sd_dest_at(&mut self, k: usize, width: Width) -> Option<WordArg> {
        let r = word(self.map(), self.text(k), width, true, true);
        self.check(k, r)
    }
    fn bit_at(&mut self, k: usize, what: BitUse) -> Option<BitArg> {
        let r = bit(self.map(), self.text(k), what);
        self.check(k, r)
    }
    fn check<T>(&mut self, k: usize, r: Result<T, String>) -> Option<T> {
        r.map_err(|e| self.error(k, e)).ok()
    }
    fn flags(&self) -> Flags {
        Flags::of(self.map())
    }
}

/// Resolution for lowerings, with the diagnostic at the token.
pub fn at<T>(c: &mut Compiler<'_>, tok: &Token, r: Result<T, String>) -> Option<T> {
    r.map_err(|e| c.err(tok, e)).ok()
}

/// The flat bit indices of the flags SM180 (zero), SM181 (carry), SM182
/// (borrow) (L2486-2500).
#[derive(Clone, Copy, Debug)]
pub struct Flags {
    pub zero: u32,
    pub carry: u32,
    pub borrow: u32,
}

impl Flags {
    pub fn of(map: &DeviceMap) -> Flags {
        let sm = map.base(DeviceKind::SM);
        Flags {
            zero: sm + 180,
            carry: sm + 181,
            borrow: sm + 182,
        }
    }
}
