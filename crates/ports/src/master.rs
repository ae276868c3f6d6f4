//! The Modbus master of a port (002 §6.10.1 L8065-8134, Appendix 4
//! L11206-11223; spec aplc.md §6.8, §7.6, D26): the request a `Modbus`
//! instruction left in the mailbox is sent at the next END with its CRC or
//! ASCII framing; the reply is checked and written to S3, or the error code
//! goes to SD139/SD144.
//!
//! Error codes: no reply within the timeout (SD136/SD141 ms, 0 = 1000)
//! after every retry (SD137/SD142) → 0x10; a reply cut short or malformed
//! (shorter than its function's length when the line goes silent or the
//! timeout runs out; ASCII without `:`…CR LF or with a non-hex character)
//! → 0x11; a bad CRC or LRC →
//! 0x1A; another station's address → 0x16; another function code → 0x17; an
//! echo with another start address → 0x18; a length or byte count that does
//! not fit the request → 0x19; an exception reply → its exception code (01,
//! 02, 03, …), the reply written to S3 as received. Only a missing, cut or
//! corrupted reply (0x10, 0x11, 0x1A) is retried. A broadcast (station 0,
//! FC 05/06/15/16) is done once sent.

use softplc_aplc::comm::modbus::reply_len;
use softplc_aplc::comm::Mode;
use softplc_modbus::{crc16, lrc};

pub const E_TIMEOUT: u16 = 0x10;
pub const E_FRAME: u16 = 0x11;
pub const E_STATION: u16 = 0x16;
pub const E_FUNCTION: u16 = 0x17;
pub const E_START: u16 = 0x18;
pub const E_LENGTH: u16 = 0x19;
pub const E_CHECKSUM: u16 = 0x1A;

/// The bytes on the wire for a request (RTU bytes without CRC).
pub fn encode(mode: Mode, req: &[u8]) -> Vec<u8> {
    match mode {
        Mode::Rtu => {
            let mut out = req.to_vec();
            out.extend(crc16(req).to_le_bytes());
            out
        }
        Mode::Ascii => {
            let mut out = vec![b':'];
            let hex = |b: u8| b"0123456789ABCDEF"[b as usize];
            for b in req.iter().copied().chain([lrc(req)]) {
                out.push(hex(b >> 4));
                out.push(hex(b & 15));
            }
            out.extend(b"\r\n");
            out
        }
    }
}

/// The length of a complete RTU reply at the front of `buf`, as far as its
/// function code tells; `None` while more bytes are needed.
fn rtu_len(buf: &[u8]) -> Option<usize> {
    let fc = *buf.get(1)?;
    let n = match fc {
        f if f & 0x80 != 0 => 5,
        1..=4 => 5 + *buf.get(2)? as usize,
        _ => 8,
    };
    (buf.len() >= n).then_some(n)
}

/// Whether `buf` holds a whole reply (RTU by its length, ASCII up to LF).
pub fn complete(mode: Mode, buf: &[u8]) -> Option<usize> {
    match mode {
        Mode::Rtu => rtu_len(buf),
        Mode::Ascii => buf.iter().position(|b| *b == b'\n').map(|i| i + 1),
    }
}

/// A reply's bytes without checksum (address, function, data), or the
/// Appendix 4 code of what is wrong with the frame.
pub fn unframe(mode: Mode, raw: &[u8]) -> Result<Vec<u8>, u16> {
    match mode {
        Mode::Rtu => {
            if raw.len() < 4 {
                return Err(E_FRAME);
            }
            let n = raw.len() - 2;
            if crc16(&raw[..n]) != u16::from_le_bytes([raw[n], raw[n + 1]]) {
                return Err(E_CHECKSUM);
            }
            Ok(raw[..n].to_vec())
        }
        Mode::Ascii => {
            let start = raw.iter().position(|b| *b == b':').ok_or(E_FRAME)?;
            let body = &raw[start + 1..];
            let body = body.strip_suffix(b"\r\n").ok_or(E_FRAME)?;
            if body.len() % 2 != 0 || body.len() < 6 {
                return Err(E_FRAME);
            }
            let digit = |c: u8| (c as char).to_digit(16).map(|d| d as u8).ok_or(E_FRAME);
            let mut bytes = Vec::with_capacity(body.len() / 2);
            for pair in body.chunks(2) {
                bytes.push(digit(pair[0])? << 4 | digit(pair[1])?);
            }
            let sum = bytes.pop().unwrap_or(0);
            if lrc(&bytes) != sum {
                return Err(E_CHECKSUM);
            }
            Ok(bytes)
        }
    }
}

/// Checks a reply (without checksum) against its request; `Err((code,
/// write))`: the Appendix 4 code and whether the reply still goes to S3 (an
/// exception reply does).
pub fn check(req: &[u8], reply: &[u8]) -> Result<(), (u16, bool)> {
    if reply.len() < 2 {
        return Err((E_FRAME, false));
    }
    if reply[0] != req[0] {
        return Err((E_STATION, false));
    }
    if reply[1] == req[1] | 0x80 {
        return match reply.get(2) {
            Some(code) if reply.len() == 3 => Err((*code as u16, true)),
            _ => Err((E_LENGTH, false)),
        };
    }
    if reply[1] != req[1] {
        return Err((E_FUNCTION, false));
    }
    match req[1] {
        1..=4 => {
            if reply.len() != reply_len(req) || reply[2] as usize != reply.len() - 3 {
                return Err((E_LENGTH, false));
            }
        }
        _ => {
            if reply.len() != 6 {
                return Err((E_LENGTH, false));
            }
            if reply[2..4] != req[2..4] {
                return Err((E_START, false));
            }
            if reply[4..6] != req[4..6] {
                return Err((E_LENGTH, false));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_and_checks() {
        // spec §6.5: 01 01 00 00 01 00 has the CRC 3D 9A on the wire.
        assert_eq!(
            encode(Mode::Rtu, &[1, 1, 0, 0, 1, 0]),
            [1, 1, 0, 0, 1, 0, 0x3D, 0x9A]
        );
        // Modbus over serial line, ASCII example: 11 03 00 6B 00 03 → LRC 7E.
        assert_eq!(
            encode(Mode::Ascii, &[0x11, 3, 0, 0x6B, 0, 3]),
            b":1103006B00037E\r\n"
        );
        // The exception reply of spec §6.5: 01 84 01 82 C0.
        let raw = [0x01, 0x84, 0x01, 0x82, 0xC0];
        assert_eq!(complete(Mode::Rtu, &raw), Some(5));
        let reply = unframe(Mode::Rtu, &raw).unwrap();
        assert_eq!(check(&[1, 4, 0, 2, 0, 10], &reply), Err((1, true)));
        let mut bad = raw;
        bad[4] ^= 1;
        assert_eq!(unframe(Mode::Rtu, &bad), Err(E_CHECKSUM));
        assert_eq!(unframe(Mode::Ascii, b":0103\r\n"), Err(E_FRAME));
        assert_eq!(
            unframe(Mode::Ascii, b":1103006B00037F\r\n"),
            Err(E_CHECKSUM)
        );
        assert_eq!(unframe(Mode::Ascii, b":11G3006B00037E\r\n"), Err(E_FRAME));
        // FC 03 of 2 registers: 4 data bytes expected.
        let req = [1, 3, 0, 0, 0, 2];
        assert_eq!(check(&req, &[1, 3, 4, 0, 1, 0, 2]), Ok(()));
        assert_eq!(check(&req, &[1, 3, 2, 0, 1]), Err((E_LENGTH, false)));
        assert_eq!(check(&req, &[2, 3, 4, 0, 1, 0, 2]), Err((E_STATION, false)));
        assert_eq!(
            check(&req, &[1, 4, 4, 0, 1, 0, 2]),
            Err((E_FUNCTION, false))
        );
        assert_eq!(
            check(&[1, 6, 0, 5, 0, 9], &[1, 6, 0, 6, 0, 9]),
            Err((E_START, false))
        );
    }
}
