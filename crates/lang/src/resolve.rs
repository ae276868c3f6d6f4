//! Operand resolution: device names, constants, digit specification, word
//! bits, index modification and pointers, checked against the configured device
//! points and turned into pre-resolved [`WordArg`]/[`BitArg`] (004 §10).

use super::compile::Compiler;
use super::source::Token;
use softplc_ir::device::{
    parse_operand_in, Constant, DeviceKind, DeviceMap, DeviceName, Operand, Reach, UnitAccess,
};
use softplc_ir::ops::*;

impl Compiler<'_> {
    // --- operands ---

    pub fn parse(&mut self, tok: &Token) -> Option<Operand> {
        match parse_operand_in(self.dialect.devices, &tok.text) {
            Ok(o) => Some(o),
            Err(e) => {
                let t = Token {
                    col: tok.col + e.offset as u32,
                    ..tok.clone()
                };
                self.err(&t, e.message);
                None
            }
        }
    }

    pub fn range_err(&mut self, tok: &Token, kind: DeviceKind, number: u32, text: &str) {
        let points = self.map.points(kind);
        let _ = number;
        let name = display_kind(kind);
        let msg = if points == 0 {
            format!("`{text}`: device {name} has 0 points in this CPU configuration")
        } else {
            let last = kind.format(points - 1);
            let last = last.trim_start_matches(kind.name());
            format!("`{text}` is out of range ({name}0-{name}{last})")
        };
        // A constant beyond the file registers is refused here; an indexed
        // one runs with the CPU's rule (no error, reads 0: 004 §10.7.5 (1)).
        let msg = if matches!(kind, DeviceKind::R | DeviceKind::ZR) {
            format!("{msg}: beyond the registered file registers ([devices] file_register); a CPU would read 0 there with no error (QCPU manual §10.7.5), so softplc refuses the device number at load")
        } else {
            msg
        };
        self.err(tok, msg);
    }

    pub fn indexed(
        &mut self,
        kind: IndexedKind,
        dk: DeviceKind,
        number: u32,
        z: u8,
    ) -> Box<Indexed> {
        self.computed(kind, dk, number, Some(z))
    }

    /// An operand resolved at run time: index-modified, or a file register `R`,
    /// which addresses the block selected by RSET (ZR = block × 32768 + n).
    pub fn computed(
        &self,
        kind: IndexedKind,
        dk: DeviceKind,
        number: u32,
        z: Option<u8>,
    ) -> Box<Indexed> {
        let z = z.map_or(Indexed::NONE, |z| self.map.base(DeviceKind::Z) + z as u32);
        let (base, points, window) = if dk == DeviceKind::R {
            let zr = DeviceKind::ZR;
            (
                self.map.base(zr),
                self.map.points(zr),
                Window::SelectedBlock,
            )
        } else if dk == DeviceKind::ZR {
            (self.map.base(dk), self.map.points(dk), Window::FileRegister)
        } else {
            (self.map.base(dk), self.map.points(dk), Window::Device)
        };
        Box::new(Indexed {
            kind,
            base,
            number,
            points,
            z,
            window,
        })
    }

    /// `U<unit>\\G<number>` resolved for `access`: a plain word when the
    /// module is there, may be reached that way and `span` words from
    /// `number` are in its buffer memory, else an operand checked when it
    /// runs — past the end OPERATION ERROR, no module SP.UNIT ERROR, memory
    /// the unit's owner refuses (a multi-CPU system's shared memories, a
    /// module another CPU controls) that error, as the CPU does (004 ch. 8,
    /// L8985-8998, L9199-9205).
    fn unit_operand(
        &self,
        kind: IndexedKind,
        unit: u32,
        number: u32,
        z: Option<u8>,
        span: u32,
        access: UnitAccess,
    ) -> Result<u32, Box<Indexed>> {
        let (base, points, window) = match self.map.unit(unit) {
            Some(w) => (
                self.map.base(DeviceKind::G) + w.first,
                w.words,
                w.owner
                    .refuses(access)
                    .map_or(Window::Device, Window::Refused),
            ),
            None => (0, 0, Window::NoModule),
        };
        if z.is_none() && window == Window::Device && number as u64 + span as u64 <= points as u64 {
            return Ok(base + number);
        }
        let z = z.map_or(Indexed::NONE, |z| self.map.base(DeviceKind::Z) + z as u32);
        Err(Box::new(Indexed {
            kind,
            base,
            number,
            points,
            z,
            window,
        }))
    }

    /// A bit operand read (contacts, sources).
    pub fn bit_operand(&mut self, tok: &Token) -> Option<BitArg> {
        self.bit_device(tok, UnitAccess::Read)
    }

    /// A bit operand read or, with [`UnitAccess::Write`], written.
    fn bit_device(&mut self, tok: &Token, access: UnitAccess) -> Option<BitArg> {
        let op = self.parse(tok)?;
        match op {
            Operand::Device { dev, .. } if dev.reach == Reach::Direct => {
                self.err(
                    tok,
                    format!("`{}`: direct access is for contacts (DX: LD, AND, OR and their forms) and coils (DY: OUT, SET, RST, PLS, PLF, FF)", tok.text),
                );
                None
            }
            Operand::Device {
                dev,
                digits: None,
                bit: Some(b),
                index,
            } if matches!(dev.reach, Reach::Unit(_)) => {
                let Reach::Unit(unit) = dev.reach else {
                    return None;
                };
                if index.is_none() {
                    self.note_use(tok, DeviceUse::Bit);
                }
                Some(
                    match self.unit_operand(
                        IndexedKind::WordBit(b),
                        unit,
                        dev.number,
                        index,
                        1,
                        access,
                    ) {
                        Ok(word) => BitArg::WordBit { word, bit: b },
                        Err(ix) => BitArg::Indexed(ix),
                    },
                )
            }
            Operand::Device {
                dev,
                digits: None,
                bit: None,
                index,
            } if dev.kind.is_bit() => {
                if dev.number >= self.map.points(dev.kind) {
                    self.range_err(tok, dev.kind, dev.number, &tok.text);
                    return None;
                }
                if index.is_none() {
                    self.note_use(tok, DeviceUse::Bit);
                }
                Some(match index {
                    None => BitArg::Bit(self.map.base(dev.kind) + dev.number),
                    Some(z) => {
                        BitArg::Indexed(self.indexed(IndexedKind::Bit, dev.kind, dev.number, z))
                    }
                })
            }
            Operand::Device {
                dev,
                digits: None,
                bit: Some(b),
                index,
            } => {
                if dev.number >= self.map.points(dev.kind) {
                    self.range_err(tok, dev.kind, dev.number, &tok.text);
                    return None;
                }
                if index.is_none() {
                    self.note_use(tok, DeviceUse::Bit);
                }
                Some(match index {
                    None if dev.kind == DeviceKind::R => BitArg::Indexed(self.computed(
                        IndexedKind::WordBit(b),
                        dev.kind,
                        dev.number,
                        None,
                    )),
                    None => BitArg::WordBit {
                        word: self.map.word_at(dev.kind, dev.number),
                        bit: b,
                    },
                    Some(z) => BitArg::Indexed(self.indexed(
                        IndexedKind::WordBit(b),
                        dev.kind,
                        dev.number,
                        z,
                    )),
                })
            }
            Operand::Device {
                dev, digits: None, ..
            } => {
                self.err(
                    tok,
                    format!("`{}` is a word device; a bit operand needs a bit device or a word bit such as `{}.0`", tok.text, tok.text),
                );
                let _ = dev;
                None
            }
            Operand::Device { .. } => {
                self.err(
                    tok,
                    format!(
                        "`{}` is a digit-specified word; a bit operand is needed here",
                        tok.text
                    ),
                );
                None
            }
            Operand::Const(_) => {
                self.err(
                    tok,
                    format!(
                        "constant `{}` cannot be a bit operand; a bit device is needed",
                        tok.text
                    ),
                );
                None
            }
            _ => {
                self.err(
                    tok,
                    format!(
                        "`{}` cannot be a bit operand; a bit device is needed",
                        tok.text
                    ),
                );
                None
            }
        }
    }

    pub fn bit_dest(&mut self, tok: &Token) -> Option<BitArg> {
        if let Ok(Operand::Device { dev, .. }) = parse_operand_in(self.dialect.devices, &tok.text) {
            if matches!(
                dev.kind,
                DeviceKind::TS
                    | DeviceKind::TC
                    | DeviceKind::STS
                    | DeviceKind::STC
                    | DeviceKind::CS
                    | DeviceKind::CC
            ) {
                self.err(tok, format!("`{}`: timer and counter contacts and coils are driven by `OUT {}` with a set value", tok.text, tok.text));
                return None;
            }
        }
        // `DY<n>`: the output module and Y<n> at once (004 L6134-6150). The
        // simulated output module is Y's device memory, so the coil writes Y.
        self.direct(tok, DeviceKind::Y)
            .unwrap_or_else(|| self.bit_device(tok, UnitAccess::Write))
    }

    /// A contact's operand: a bit operand, or a direct input `DX<n>` (then
    /// `true`), which reads X<n> after `Op::DirectIn` has refreshed it.
    pub fn contact_operand(&mut self, tok: &Token) -> Option<(BitArg, bool)> {
        match self.direct(tok, DeviceKind::X) {
            Some(direct) => direct.map(|b| (b, true)),
            None => self.bit_operand(tok).map(|b| (b, false)),
        }
    }

    /// `tok` as direct access to `kind` (`DX<n>`, `DY<n>`): `None` when it
    /// is not, else the X/Y bit (`Some(None)` after an error).
    fn direct(&mut self, tok: &Token, kind: DeviceKind) -> Option<Option<BitArg>> {
        // Most operands are not: tell by their first letters, not a parse.
        let t = tok.text.as_bytes();
        let letter = kind.name().as_bytes()[0];
        if !(t.len() > 2 && t[0].eq_ignore_ascii_case(&b'D') && t[1].eq_ignore_ascii_case(&letter))
        {
            return None;
        }
        let Ok(Operand::Device { dev, .. }) = parse_operand_in(self.dialect.devices, &tok.text)
        else {
            return None;
        };
        if dev.reach != Reach::Direct || dev.kind != kind {
            return None;
        }
        if dev.number >= self.map.points(kind) {
            self.range_err(tok, kind, dev.number, &tok.text);
            return Some(None);
        }
        self.note_use(tok, DeviceUse::Bit);
        Some(Some(BitArg::Bit(self.map.base(kind) + dev.number)))
    }

    pub fn edge_relay(&mut self, tok: &Token) -> Option<u32> {
        match self.bit_operand(tok)? {
            BitArg::Bit(b)
                if (self.map.base(DeviceKind::V)
                    ..self.map.base(DeviceKind::V) + self.map.points(DeviceKind::V))
                    .contains(&b) =>
            {
                Some(b)
            }
            _ => {
                self.err(
                    tok,
                    format!("`{}`: EGP/EGF need an edge relay V without index", tok.text),
                );
                None
            }
        }
    }

    /// A word operand read as `num`.
    pub fn word_src(&mut self, tok: &Token, num: Num) -> Option<WordArg> {
        let op = self.parse(tok)?;
        if let Operand::Const(c) = &op {
            return self.constant(tok, c, num);
        }
        self.word_device(tok, op, num, num.words(), UnitAccess::Read)
    }

    /// A word operand written as `num`, occupying `words` words.
    pub fn word_dest(&mut self, tok: &Token, num: Num, words: u32) -> Option<WordArg> {
        let op = self.parse(tok)?;
        if let Operand::Const(_) = op {
            self.err(
                tok,
                format!("constant `{}` cannot be a destination", tok.text),
            );
            return None;
        }
        self.word_device(tok, op, num, words, UnitAccess::Write)
    }

    pub fn constant(&mut self, tok: &Token, c: &Constant, num: Num) -> Option<WordArg> {
        match (c, num) {
            (Constant::Int { value, hex }, Num::I16) => {
                let ok = if *hex {
                    (0..=0xFFFF).contains(value)
                } else {
                    (-32768..=32767).contains(value)
                };
                if !ok {
                    let range = if *hex {
                        "H0-HFFFF"
                    } else {
                        "K-32768 to K32767"
                    };
                    self.err(
                        tok,
                        format!(
                            "constant `{}` does not fit a 16-bit operand ({range})",
                            tok.text
                        ),
                    );
                    return None;
                }
                Some(WordArg::Const(*value as i32 as u32 & 0xFFFF))
            }
            (Constant::Int { value, hex }, Num::I32) => {
                let ok = if *hex {
                    (0..=0xFFFF_FFFF).contains(value)
                } else {
                    (i32::MIN as i64..=i32::MAX as i64).contains(value)
                };
                if !ok {
                    self.err(
                        tok,
                        format!("constant `{}` does not fit a 32-bit operand", tok.text),
                    );
                    return None;
                }
                Some(WordArg::Const(*value as u32))
            }
            (Constant::Real(v), Num::F32) => {
                let f = *v as f32;
                if f.is_infinite() || (*v != 0.0 && f.abs() < f32::MIN_POSITIVE) {
                    self.err(
                        tok,
                        format!(
                            "real constant `{}` is outside the single-precision range",
                            tok.text
                        ),
                    );
                    return None;
                }
                Some(WordArg::Const(f.to_bits()))
            }
            (Constant::Int { .. }, Num::F32) => {
                self.err(
                    tok,
                    format!(
                        "`{}`: a real operand needs an E constant, e.g. E1.5",
                        tok.text
                    ),
                );
                None
            }
            (Constant::Real(_), _) => {
                self.err(
                    tok,
                    format!(
                        "real constant `{}` where a BIN value (K or H) is needed",
                        tok.text
                    ),
                );
                None
            }
            (Constant::Str(_), _) => {
                self.err(
                    tok,
                    format!("string `{}` where a numeric operand is needed", tok.text),
                );
                None
            }
        }
    }

    /// A word device operand (no constant) of `words` words, read or, with
    /// [`UnitAccess::Write`], written.
    pub fn word_device(
        &mut self,
        tok: &Token,
        op: Operand,
        num: Num,
        words: u32,
        access: UnitAccess,
    ) -> Option<WordArg> {
        let Operand::Device {
            dev,
            digits,
            bit,
            index,
        } = op
        else {
            self.err(tok, format!("`{}` cannot be a word operand", tok.text));
            return None;
        };
        if dev.reach == Reach::Direct {
            self.err(
                tok,
                format!("`{}`: direct access is for contacts and OUT; a word operand takes X or Y with a digit specification", tok.text),
            );
            return None;
        }
        if let (Reach::Unit(unit), None, None) = (dev.reach, digits, bit) {
            if index.is_none() {
                self.note_use(tok, DeviceUse::Word(num));
            }
            return Some(
                match self.unit_operand(IndexedKind::Word, unit, dev.number, index, words, access) {
                    Ok(w) => WordArg::Word(w),
                    Err(ix) => WordArg::Indexed(ix),
                },
            );
        }
        if bit.is_some() {
            self.err(
                tok,
                format!("`{}` is a bit; a word operand is needed here", tok.text),
            );
            return None;
        }
        if let Some(n) = digits {
            if num == Num::F32 {
                self.err(
                    tok,
                    format!(
                        "`{}`: digit specification cannot hold a real number",
                        tok.text
                    ),
                );
                return None;
            }
            let max = if num == Num::I16 { 4 } else { 8 };
            if n > max {
                self.err(
                    tok,
                    format!(
                        "`{}`: K{n} needs a 32-bit instruction (K1-K{max} here)",
                        tok.text
                    ),
                );
                return None;
            }
            let need = dev.number as u64 + 4 * n as u64;
            if dev.number >= self.map.points(dev.kind) || need > self.map.points(dev.kind) as u64 {
                self.range_err(tok, dev.kind, dev.number, &tok.text);
                return None;
            }
            return Some(match index {
                None => WordArg::Digits {
                    bit: self.map.base(dev.kind) + dev.number,
                    n,
                },
                Some(z) => {
                    WordArg::Indexed(self.indexed(IndexedKind::Digits(n), dev.kind, dev.number, z))
                }
            });
        }
        let kind = dev.word_kind();
        if kind.is_bit() {
            self.err(
                tok,
                format!("`{}` is a bit device; a word operand needs a digit specification such as `K4{}`", tok.text, tok.text),
            );
            return None;
        }
        let points = self.map.points(kind);
        if dev.number >= points {
            self.range_err(tok, kind, dev.number, &tok.text);
            return None;
        }
        // FD: 4 words a point, an operand within its point, no index
        // modification (004 §10.3.1 (2)(c)).
        if kind == DeviceKind::FD {
            if index.is_some() {
                self.err(
                    tok,
                    format!(
                        "`{}`: a function register FD cannot be index-modified",
                        tok.text
                    ),
                );
                return None;
            }
            if words > 4 {
                self.err(
                    tok,
                    format!(
                        "`{}`: this operand uses {words} words; a function register holds 4",
                        tok.text
                    ),
                );
                return None;
            }
        } else if index.is_none() && dev.number as u64 + words as u64 > points as u64 {
            let last = name_of(&dev, kind, dev.number + words - 1);
            self.err(
                tok,
                format!(
                    "`{}`: this operand uses {words} words, up to `{last}`, beyond the last device",
                    tok.text
                ),
            );
            return None;
        }
        if index.is_none() {
            self.note_use(tok, DeviceUse::Word(num));
        }
        Some(match index {
            None if kind == DeviceKind::R => {
                WordArg::Indexed(self.computed(IndexedKind::Word, kind, dev.number, None))
            }
            None => WordArg::Word(self.map.word_at(kind, dev.number)),
            Some(z) => WordArg::Indexed(self.indexed(IndexedKind::Word, kind, dev.number, z)),
        })
    }

    /// Records a resolved device operand for `Program::used_devices`.
    fn note_use(&mut self, tok: &Token, how: DeviceUse) {
        self.used_devices.push((tok.text.to_uppercase(), how));
    }

    pub fn pointer(&mut self, tok: &Token) -> Option<u32> {
        match self.parse(tok)? {
            Operand::Pointer(p) if p <= 4095 => Some(p),
            Operand::Pointer(_) => {
                self.err(
                    tok,
                    format!("pointer `{}` is out of range (P0-P4095)", tok.text),
                );
                None
            }
            _ => {
                self.err(
                    tok,
                    format!("`{}`: a pointer P0-P4095 is needed here", tok.text),
                );
                None
            }
        }
    }

    pub fn nesting(&mut self, tok: &Token) -> Option<u32> {
        match self.parse(tok)? {
            Operand::Nesting(n) if n <= 14 => Some(n),
            _ => {
                self.err(
                    tok,
                    format!("`{}`: a nesting number N0-N14 is needed here", tok.text),
                );
                None
            }
        }
    }
}

/// Remainder slot of timer `n`: T first, then ST.
pub fn timer_slot(map: &DeviceMap, retentive: bool, n: u32) -> u32 {
    if retentive {
        map.points(DeviceKind::TS) + n
    } else {
        n
    }
}

fn display_kind(k: DeviceKind) -> &'static str {
    match k {
        DeviceKind::TS | DeviceKind::TN => "T",
        DeviceKind::STS | DeviceKind::STN => "ST",
        DeviceKind::CS | DeviceKind::CN => "C",
        k => k.name(),
    }
}

fn name_of(dev: &DeviceName, kind: DeviceKind, n: u32) -> String {
    if dev.generic {
        format!("{}{}", display_kind(kind), n)
    } else {
        kind.format(n)
    }
}
