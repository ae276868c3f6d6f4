//! Checksums CCITT, CRC16, LRC (002 §6.16 L8548-8667; spec aplc.md §4.16,
//! decision D19): `OP S1 S2 D`, S1 the data (D or V, one byte per word: the
//! low byte), S2 the count (≥ 0, else error 64), D (D or V) both the initial
//! value and the result, so checksums chain.

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{Block, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::devices::{parse_device, Dev};
use crate::num::E_VALUE;
use crate::resolve::{self, ArgsExt};

static DOC: Doc = Doc {
    family: "checksums",
    cite: "002 §6.16 L8548-8667",
    notes: "low byte of each word; D is the initial value (chaining); CRC16 the reflected 16#A001 register as a number (D19: 01 01 00 00 01 00 from 16#FFFF give 16#9A3D, sent 3D 9A); CCITT 16#1021 MSB first; LRC two's complement of the byte sum in D's low byte",
};

pub static DEFS: &[Def] = &[
    // 002 §6.16.1 L8550 CCITT
    Def::app("CCITT", &DOC, |a| compile(a, Kind::Ccitt))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.16.2 L8584 CRC16
    Def::app("CRC16", &DOC, |a| compile(a, Kind::Crc16))
        .no_pulse()
        .steps(Steps::Fixed(7)),
    // 002 §6.16.3 L8619 LRC
    Def::app("LRC", &DOC, |a| compile(a, Kind::Lrc))
        .no_pulse()
        .steps(Steps::Fixed(7)),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Ccitt,
    Crc16,
    Lrc,
}

#[derive(Debug)]
struct Sum {
    kind: Kind,
    data: Block,
    n: WordArg,
    d: WordArg,
}

fn dv(a: &mut Args<'_, '_>, k: usize) -> bool {
    let ok = matches!(parse_device(&a.text(k).to_ascii_uppercase()), Ok(Some(d)) if d.group.is_none() && matches!(d.dev, Dev::D | Dev::V));
    if !ok {
        a.error(
            k,
            format!(
                "`{}`: D or V is needed here (APLC programming manual §6.13)",
                a.text(k)
            ),
        );
    }
    ok
}

fn compile(a: &mut Args<'_, '_>, kind: Kind) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) || !dv(a, 0) || !dv(a, 2) {
        return None;
    }
    let r = resolve::block(a.map(), a.text(0), false);
    let data = a.check(0, r);
    let n = a.word_at(1, Width::W16, false);
    let d = a.word_at(2, Width::W16, true)?;
    Some(Box::new(Sum {
        kind,
        data: data?,
        n: n?,
        d,
    }))
}

/// The CRC-16 (Modbus) register after `bytes`, from `crc`.
pub fn crc16(mut crc: u16, bytes: impl Iterator<Item = u8>) -> u16 {
    for b in bytes {
        crc ^= b as u16;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                crc >> 1 ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    crc
}

fn ccitt(mut crc: u16, bytes: impl Iterator<Item = u8>) -> u16 {
    for b in bytes {
        crc ^= (b as u16) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                crc << 1 ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}

impl Instr for Sum {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let n = cx.mem.read16(&self.n)? as i16;
        if n < 0 {
            return Err(E_VALUE);
        }
        let s = cx.mem.block_start(&self.data, n as u32)?;
        let init = cx.mem.read16(&self.d)?;
        let bytes = cx.mem.words[s..s + n as usize].iter().map(|w| *w as u8);
        let v = match self.kind {
            Kind::Crc16 => crc16(init, bytes),
            Kind::Ccitt => ccitt(init, bytes),
            Kind::Lrc => (bytes.fold(init as u8, |a, b| a.wrapping_sub(b))) as u16,
        };
        cx.mem.write16(&self.d, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors() {
        // D19: the Modbus request 01 01 00 00 01 00 (L10533), and chained.
        let frame = [1u8, 1, 0, 0, 1, 0];
        assert_eq!(crc16(0xFFFF, frame.iter().copied()), 0x9A3D);
        let half = crc16(0xFFFF, frame[..3].iter().copied());
        assert_eq!(crc16(half, frame[3..].iter().copied()), 0x9A3D);
        // CRC-16/XMODEM check value of "123456789".
        assert_eq!(ccitt(0, b"123456789".iter().copied()), 0x31C3);
    }
}
