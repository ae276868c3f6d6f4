//! Free port `XMT S1 S2 S3` and `RCV S1 D S2` (002 §6.10.10-11 L8433-8542,
//! §10.3 L10361-10428; spec aplc.md §6.9, §3.5).
//!
//! Both run while their power flow is ON and start only when the port is
//! not already doing it: XMT when its TX enable (SM120/SM130) is OFF, RCV
//! when its RX enable (SM121/SM131) is OFF, so with power flow always ON
//! they repeat once the previous one completed (L8500: "use an edge or SM1
//! to receive once"). XMT sets TX enable and clears TX done; RCV sets RX
//! enable, clears RX done, the completion code SD125 and the count SD127.
//! Both turn the idle flag OFF. The communication phase after END sends
//! and receives, sets TX done/RX done, clears the enables, fills SD125-SD128
//! and queues the serial interrupt events (PORT1: 34-37). One byte per word
//! (the low byte), or two with SD120/SD150 bit 12, low byte first (the
//! packing of the ASCII instructions, §4.8). The port must be set to free
//! port and the count must be 1-512 (XMT) or 1 and up (RCV) within D, else
//! run error 64 and nothing starts.

use softplc_ir::device::DeviceKind;
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{Block, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use super::{
    channel, d_buffer, mailbox, Regs, IDLE, RX_DONE, RX_ENABLE, SD_CODE, SD_COUNT, TX_DONE,
    TX_ENABLE,
};
use crate::constant::Width;
use crate::num::{self, E_VALUE};
use crate::resolve::{self, ArgsExt};

static DOC: Doc = Doc {
    family: "communication",
    cite: "002 §6.10.10-11 L8433-8542, §10.3 L10361-10428",
    notes: "free port only; S1 = 1 (PORT1) or 2 (PORT2); starts when TX/RX enable is OFF (SM120/SM121, SM130/SM131), done in the communication phase after END: SM122/SM123 done, SD125 completion bits, SD126 last character, SD127 count, SD128 TX character; start/end characters and timeouts from SD120-SD124; RCV's buffer is D; events 34-37 on PORT1",
};

pub static DEFS: &[Def] = &[
    // 002 §6.10.10 L8433 XMT (7 steps).
    Def::app("XMT", &DOC, xmt).no_pulse().steps(Steps::Fixed(7)),
    // 002 §6.10.11 L8480 RCV (7 steps).
    Def::app("RCV", &DOC, rcv).no_pulse().steps(Steps::Fixed(7)),
];

/// What both instructions address.
#[derive(Debug)]
struct Port {
    port: u8,
    sm: usize,
    sd: usize,
    mailbox: usize,
}

impl Port {
    fn of(a: &Args<'_, '_>, port: u8) -> Port {
        let map = a.map();
        Port {
            port,
            sm: map.base(DeviceKind::SM) as usize,
            sd: map.base(DeviceKind::SD) as usize,
            mailbox: (map.base(DeviceKind::SW) + mailbox::base(port)) as usize,
        }
    }

    fn sm(&self, off: u32) -> usize {
        self.sm + (Regs::of(self.port).sm_free + off) as usize
    }

    fn sd(&self, off: u32) -> usize {
        self.sd + (Regs::of(self.port).sd_free + off) as usize
    }

    fn mb(&self, off: u32) -> usize {
        self.mailbox + off as usize
    }

    fn packed(&self, words: &[u16]) -> bool {
        words[self.sd(0)] & 1 << 12 != 0
    }

    fn is_free(&self, words: &[u16]) -> bool {
        words[self.mb(mailbox::PROTOCOL)] == mailbox::FREE
    }
}

#[derive(Debug)]
struct Xmt {
    port: Port,
    data: Block,
    count: WordArg,
}

#[derive(Debug)]
struct Rcv {
    port: Port,
    /// D's number.
    dest: u32,
    max: WordArg,
}

fn xmt(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let port = channel(a, 0);
    let data = {
        use crate::devices::{parse_device, Dev};
        let dv = matches!(parse_device(&a.text(1).to_ascii_uppercase()), Ok(Some(d)) if d.group.is_none() && matches!(d.dev, Dev::D | Dev::V));
        if !dv {
            let t = a.text(1).to_string();
            a.error(
                1,
                format!("`{t}`: XMT sends from D or V (APLC programming manual §6.12.11)"),
            );
            None
        } else {
            let r = resolve::block(a.map(), a.text(1), false);
            a.check(1, r)
        }
    };
    let count = a.word_at(2, Width::W16, false);
    let port = Port::of(a, port?);
    Some(Box::new(Xmt {
        port,
        data: data?,
        count: count?,
    }))
}

fn rcv(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let port = channel(a, 0);
    let dest = d_buffer(a, 1, "APLC programming manual §6.12.12");
    let max = a.word_at(2, Width::W16, false);
    let port = Port::of(a, port?);
    Some(Box::new(Rcv {
        port,
        dest: dest?,
        max: max?,
    }))
}

impl Instr for Xmt {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let p = &self.port;
        let mem = &mut *cx.mem;
        if !p.is_free(&mem.words) {
            return Err(E_VALUE);
        }
        if mem.bits[p.sm(TX_ENABLE)] {
            return Ok(()); // still sending
        }
        let n = num::read16(mem, &self.count)?;
        if !(1..=mailbox::TX_MAX as i16).contains(&n) {
            return Err(E_VALUE);
        }
        let n = n as usize;
        let packed = p.packed(&mem.words);
        let words = if packed { n.div_ceil(2) } else { n };
        let s = mem.block_start(&self.data, words as u32)?;
        let out = p.mb(mailbox::TX_BYTES);
        for k in 0..n {
            let w = if packed {
                mem.words[s + k / 2] >> (8 * (k % 2))
            } else {
                mem.words[s + k]
            };
            mem.words[out + k] = w & 0xFF;
        }
        mem.words[p.mb(mailbox::TX_LEN)] = n as u16;
        mem.words[p.mb(mailbox::TX_REQ)] = 1;
        mem.bits[p.sm(TX_ENABLE)] = true;
        mem.bits[p.sm(TX_DONE)] = false;
        mem.bits[p.sm(IDLE)] = false;
        Ok(())
    }
}

impl Instr for Rcv {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let p = &self.port;
        let now_ms = cx.now_us / 1000;
        let mem = &mut *cx.mem;
        if !p.is_free(&mem.words) {
            return Err(E_VALUE);
        }
        if mem.bits[p.sm(RX_ENABLE)] {
            return Ok(()); // still receiving
        }
        let n = num::read16(mem, &self.max)?;
        let words = if p.packed(&mem.words) {
            (n.max(0) as u32).div_ceil(2)
        } else {
            n.max(0) as u32
        };
        if n < 1 || self.dest + words > 8000 {
            return Err(E_VALUE);
        }
        mem.words[p.mb(mailbox::RX_DEST)] = self.dest as u16;
        mem.words[p.mb(mailbox::RX_MAX)] = n as u16;
        mem.words[p.mb(mailbox::RX_T0)] = now_ms as u16;
        mem.words[p.mb(mailbox::RX_T0 + 1)] = (now_ms >> 16) as u16;
        mem.words[p.mb(mailbox::RX_ARM)] = 1;
        mem.words[p.sd(SD_CODE)] = 0;
        mem.words[p.sd(SD_COUNT)] = 0;
        mem.bits[p.sm(RX_ENABLE)] = true;
        mem.bits[p.sm(RX_DONE)] = false;
        mem.bits[p.sm(IDLE)] = false;
        Ok(())
    }
}
