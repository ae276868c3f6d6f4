//! `Modbus S1 S2 S3`, the Modbus master instruction (002 §6.10.1
//! L8065-8134, §10.4.13 L10655-10659, Appendix 4 L11206-11223; spec aplc.md
//! §6.8, §7.6, decision D26).
//!
//! On the rising edge of its power flow: S1 the channel (1 = PORT1, 2 =
//! PORT2), S2 (D or V) the request in RTU form, one byte per word (slave
//! address, function code, then the request's bytes: 4 for FC 01-06; for FC
//! 15/16 address, quantity, byte count and the data), S3 (D) the reply
//! buffer. The instruction checks the parameters (error codes 0x12, 0x13,
//! 0x14, 0x1C, 0x1E land in SD139/SD144 with SM136/SM138 at once), clears
//! the port's done and error flags and its error code, turns its idle flag
//! (SM124/SM134) OFF and leaves the request in the port's mailbox; the
//! communication phase after END sends it, with the CRC or the ASCII
//! framing, and writes the reply. A rising edge while the port is busy
//! (idle OFF) sends nothing and is run error 64.

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::Block;
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use super::{channel, d_buffer, mailbox, Regs, IDLE};
use crate::num::E_VALUE;
use crate::resolve;

static DOC: Doc = Doc {
    family: "communication",
    cite: "002 §6.10.1 L8065-8134, Appendix 4 L11206-11223",
    notes: "rising edge; S1 = 1 (PORT1) or 2 (PORT2), S2 (D/V) the RTU request one byte per word (FC 01-06: 6 words; FC 15/16: 7 + byte count), S3 (D) the reply without CRC (D26); sent and answered in the communication phase after END; SM135/SM136 (SM137/SM138) done/error, SD139 (SD144) the Appendix 4 code; timeout SD136 (0 = 1000 ms), retries SD137; a rising edge while busy is error 64",
};

pub static DEFS: &[Def] = &[
    // 002 §6.10.1 L8065 Modbus (8 steps).
    Def::app("MODBUS", &DOC, compile)
        .on_rise()
        .steps(Steps::Fixed(8)),
];

/// Appendix 4 codes the instruction itself sets (the others come with the
/// reply, see `softplc-ports`).
pub const E_PARAMETER: u16 = 0x12;
pub const E_OWN_STATION: u16 = 0x13;
pub const E_ADDRESS_OVERFLOW: u16 = 0x14;
pub const E_FUNCTION: u16 = 0x1C;
pub const E_COUNT: u16 = 0x1E;

/// The function codes the master sends (D26; FC 08 and the others are not
/// listed for the instruction).
pub const FUNCTIONS: [u8; 8] = [1, 2, 3, 4, 5, 6, 15, 16];

/// Words of S2 a request with function `fc` takes, given S2+6 (the byte
/// count of FC 15/16); `None` for a function the master does not send.
pub fn request_words(fc: u8, byte_count: u16) -> Option<usize> {
    match fc {
        1..=6 => Some(6),
        15 | 16 => Some(7 + byte_count as usize),
        _ => None,
    }
}

/// Checks a request (RTU bytes without CRC) as the instruction does; the
/// Appendix 4 code of the first problem. `own` is the port's station.
pub fn check_request(req: &[u8], own: u16) -> Result<(), u16> {
    let (addr, fc) = (req[0], req[1]);
    if !FUNCTIONS.contains(&fc) {
        return Err(E_FUNCTION);
    }
    let broadcast_ok = matches!(fc, 5 | 6 | 15 | 16);
    if addr > 247 || (addr == 0 && !broadcast_ok) {
        return Err(E_PARAMETER);
    }
    if addr as u16 == own {
        return Err(E_OWN_STATION);
    }
    let be = |k: usize| u16::from_be_bytes([req[k], req[k + 1]]);
    let q = be(4);
    let ok = match fc {
        1 | 2 => (1..=2000).contains(&q),
        3 | 4 => (1..=125).contains(&q),
        15 => (1..=1968).contains(&q) && req[6] as usize == (q as usize).div_ceil(8),
        16 => (1..=123).contains(&q) && req[6] as usize == 2 * q as usize,
        _ => true,
    };
    if ok {
        Ok(())
    } else {
        Err(E_COUNT)
    }
}

/// Bytes of the normal reply to `req` without CRC (address, function, data).
pub fn reply_len(req: &[u8]) -> usize {
    let q = u16::from_be_bytes([req[4], req[5]]) as usize;
    match req[1] {
        1 | 2 => 3 + q.div_ceil(8),
        3 | 4 => 3 + 2 * q,
        _ => 6,
    }
}

/// A port's Modbus master as the instructions that start a request see it:
/// its flags, error code and mailbox (flat indices).
#[derive(Debug)]
pub(crate) struct Master {
    port: u8,
    sm: usize,
    sd: usize,
    mailbox: usize,
}

impl Master {
    pub(crate) fn of(a: &Args<'_, '_>, port: u8) -> Master {
        let map = a.map();
        Master {
            port,
            sm: map.base(DeviceKind::SM) as usize,
            sd: map.base(DeviceKind::SD) as usize,
            mailbox: (map.base(DeviceKind::SW) + mailbox::base(port)) as usize,
        }
    }

    fn fail(&self, mem: &mut DeviceMemory, code: u16) {
        let r = Regs::of(self.port);
        mem.bits[self.sm + r.sm_error as usize] = true;
        mem.words[self.sd + r.sd_error as usize] = code;
    }

    /// Starts a transaction: run error 64 while the port is busy; clears
    /// the previous outcome (D26); `Ok(false)` (0x12 set) when the port is
    /// not a Modbus master.
    pub(crate) fn begin(&self, mem: &mut DeviceMemory) -> Result<bool, Fault> {
        let r = Regs::of(self.port);
        if !mem.bits[self.sm + (r.sm_free + IDLE) as usize] {
            return Err(E_VALUE);
        }
        mem.bits[self.sm + r.sm_done as usize] = false;
        mem.bits[self.sm + r.sm_error as usize] = false;
        mem.words[self.sd + r.sd_error as usize] = 0;
        if mem.words[self.mailbox + mailbox::PROTOCOL as usize] != mailbox::MASTER {
            self.fail(mem, E_PARAMETER);
            return Ok(false);
        }
        Ok(true)
    }

    /// Checks `req` and leaves it for the communication phase: the reply
    /// to D`dest`.., and for a read of one register its value to
    /// D`value` too (EVRD).
    pub(crate) fn submit(&self, mem: &mut DeviceMemory, req: &[u8], dest: u32, value: Option<u32>) {
        let r = Regs::of(self.port);
        let own = mem.words[self.sd + r.sd_station as usize];
        if let Err(code) = check_request(req, own) {
            return self.fail(mem, code);
        }
        if dest as usize + reply_len(req) > 8000 {
            return self.fail(mem, E_ADDRESS_OVERFLOW);
        }
        let mb = self.mailbox;
        for (k, b) in req.iter().enumerate() {
            mem.words[mb + mailbox::MB_BYTES as usize + k] = *b as u16;
        }
        mem.words[mb + mailbox::MB_LEN as usize] = req.len() as u16;
        mem.words[mb + mailbox::MB_DEST as usize] = dest as u16;
        mem.words[mb + mailbox::MB_VALUE as usize] = value.map_or(0, |d| d as u16 + 1);
        mem.words[mb + mailbox::MB_REQ as usize] = 1;
        mem.bits[self.sm + (r.sm_free + IDLE) as usize] = false;
    }
}

#[derive(Debug)]
struct ModbusInstr {
    master: Master,
    tx: Block,
    /// S3's D number.
    rx: u32,
}

fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let port = channel(a, 0);
    let tx = {
        use crate::devices::{parse_device, Dev};
        let dv = matches!(parse_device(&a.text(1).to_ascii_uppercase()), Ok(Some(d)) if d.group.is_none() && matches!(d.dev, Dev::D | Dev::V));
        if !dv {
            let t = a.text(1).to_string();
            a.error(
                1,
                format!("`{t}`: the request buffer S2 is D or V (APLC programming manual §6.12.1)"),
            );
            None
        } else {
            let r = resolve::block(a.map(), a.text(1), false);
            resolve::ArgsExt::check(a, 1, r)
        }
    };
    let rx = d_buffer(a, 2, "APLC programming manual §6.12.1");
    let master = Master::of(a, port?);
    Some(Box::new(ModbusInstr {
        master,
        tx: tx?,
        rx: rx?,
    }))
}

impl Instr for ModbusInstr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        if !self.master.begin(mem)? {
            return Ok(());
        }
        let s = mem.block_start(&self.tx, 2)?;
        let fc = mem.words[s + 1] as u8;
        let count = mem.words.get(s + 6).copied().unwrap_or(0) & 0xFF;
        let Some(n) = request_words(fc, count) else {
            self.master.fail(mem, E_FUNCTION);
            return Ok(());
        };
        let s = mem.block_start(&self.tx, n as u32)?;
        let mut req = [0u8; 256];
        for (k, w) in mem.words[s..s + n].iter().enumerate() {
            req[k] = *w as u8;
        }
        self.master.submit(mem, &req[..n], self.rx, None);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_and_replies() {
        // D26's corrected example: slave 3, FC 01, start 10, 5 coils.
        let req = [3, 1, 0, 10, 0, 5];
        assert_eq!(check_request(&req, 1), Ok(()));
        assert_eq!(reply_len(&req), 4); // 03 01 01 xx
        assert_eq!(reply_len(&[1, 3, 0, 0, 0, 10]), 23);
        assert_eq!(reply_len(&[1, 16, 0, 0, 0, 2, 4, 0, 1, 0, 2]), 6);
        assert_eq!(check_request(&[1, 7, 0, 0, 0, 1], 2), Err(E_FUNCTION));
        assert_eq!(check_request(&[1, 3, 0, 0, 0, 1], 1), Err(E_OWN_STATION));
        assert_eq!(check_request(&[0, 3, 0, 0, 0, 1], 1), Err(E_PARAMETER));
        assert_eq!(check_request(&[0, 6, 0, 0, 0, 1], 1), Ok(()));
        assert_eq!(check_request(&[1, 3, 0, 0, 0, 126], 2), Err(E_COUNT));
        // FC 16 with 2 registers needs byte count 4.
        assert_eq!(
            check_request(&[1, 16, 0, 0, 0, 2, 3, 0, 1, 0], 2),
            Err(E_COUNT)
        );
        assert_eq!(request_words(16, 4), Some(11));
        assert_eq!(request_words(8, 0), None);
    }
}
