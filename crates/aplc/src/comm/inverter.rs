//! `EVWRT` and `EVRD`, the inverter's single-register write and read over
//! the Modbus master of PORT1 (002 §6.10.8-9 L8380-8432, Appendix 3
//! L11200-11201, Appendix 5 L11225-11237; spec aplc.md §4.15, §7.3-§7.4).
//!
//! On the rising edge: `EVWRT S1 S2 S3 S4` writes S4 into register S3 of
//! the inverter at station S2 (FC 06; station 0 broadcasts); `EVRD S1 S2 S3
//! D1` reads register S3 (FC 03, one register) into D1. S1 is the channel,
//! 1 only (L8140). The request goes through the port's Modbus master like
//! `Modbus`'s: the request bytes are also left in the inverter TX buffer
//! D7940.. and the reply lands in the RX buffer D7970.. (one byte a word,
//! Appendix 3); SM135 done, SM136 error with the code in SD139 (an
//! inverter's exception code is its Appendix 5 error: 0x1-0x6, 0x18,
//! 0x20-0x22). The other inverter instructions stay rejected: the manual
//! gives no register for their actions (`rejected.rs`).

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::WordArg;
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use super::d_buffer;
use super::modbus::Master;
use crate::constant::Width;
use crate::num;
use crate::resolve::ArgsExt;

static DOC: Doc = Doc {
    family: "inverter",
    cite: "002 §6.10.8-9 L8380-8432, Appendix 3 L11200-11201, Appendix 5 L11225-11237",
    notes: "rising edge; S1 = 1 (PORT1 only), S2 the station (EVWRT 0-247, 0 broadcast; EVRD 1-247), S3 the register; EVWRT sends FC 06 with S4, EVRD FC 03 of one register into D1; request bytes in D7940.., reply in D7970..; SM135/SM136 and SD139 as `Modbus` (an exception is the inverter's Appendix 5 code)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.10.8 L8380 EVWRT (10 steps).
    Def::app("EVWRT", &DOC, |a| compile(a, false))
        .on_rise()
        .steps(Steps::Fixed(10)),
    // 002 §6.10.9 L8403 EVRD ("EV RD"; 10 steps).
    Def::app("EVRD", &DOC, |a| compile(a, true))
        .on_rise()
        .steps(Steps::Fixed(10)),
];

/// The inverter TX and RX buffers (Appendix 3).
const TX_BUFFER: usize = 7940;
const RX_BUFFER: u32 = 7970;

#[derive(Debug)]
struct Inverter {
    master: Master,
    station: WordArg,
    register: WordArg,
    /// EVWRT: the value; EVRD: `None`.
    value: Option<WordArg>,
    /// EVRD: D1's number.
    dest: Option<u32>,
    /// D7940's flat index.
    tx: usize,
}

/// EVRD (`read`) or EVWRT.
fn compile(a: &mut Args<'_, '_>, read: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let port = if a.text(0).trim() == "1" {
        Some(1)
    } else {
        let t = a.text(0).to_string();
        a.error(
            0,
            format!("`{t}`: the inverter instructions use channel 1 (PORT1) only (APLC programming manual §6.12.2)"),
        );
        None
    };
    let station = a.word_at(1, Width::W16, false);
    let register = a.word_at(2, Width::W16, false);
    let (value, dest) = if read {
        (
            Some(None),
            d_buffer(a, 3, "APLC programming manual §6.12.10").map(Some),
        )
    } else {
        (a.word_at(3, Width::W16, false).map(Some), Some(None))
    };
    let master = Master::of(a, port?);
    let tx = (a.map().base(softplc_ir::device::DeviceKind::D) as usize) + TX_BUFFER;
    Some(Box::new(Inverter {
        master,
        station: station?,
        register: register?,
        value: value?,
        dest: dest?,
        tx,
    }))
}

impl Instr for Inverter {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        if !self.master.begin(mem)? {
            return Ok(());
        }
        let station = num::read16(mem, &self.station)? as u16;
        let register = num::read16(mem, &self.register)? as u16;
        let station = station.min(255) as u8;
        let [rh, rl] = register.to_be_bytes();
        let req = match &self.value {
            Some(v) => {
                let [vh, vl] = (num::read16(mem, v)? as u16).to_be_bytes();
                [station, 6, rh, rl, vh, vl]
            }
            None => [station, 3, rh, rl, 0, 1],
        };
        for (k, b) in req.iter().enumerate() {
            mem.words[self.tx + k] = *b as u16;
        }
        self.master.submit(mem, &req, RX_BUFFER, self.dest);
        Ok(())
    }
}
