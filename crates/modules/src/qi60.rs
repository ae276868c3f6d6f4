//! `QI60`: the 16-point interrupt module. Its inputs are X like any input
//! module's; a rising edge of input k (seen at the input refresh) raises
//! interrupt pointer I<k> (QCPU User's Manual (Function Explanation,
//! Program Fundamentals), App. 3: I0-I15; QI60 Interrupt Module User's
//! Manual, SH-080029). One per CPU. The edges are the engine's: the module
//! has no buffer memory and no behaviour of its own.

use softplc_ir::rack::{Module, ModuleIo, ModuleProfile, Slot, SlotType};

pub static QI60: ModuleProfile = ModuleProfile {
    name: "QI60",
    kind: SlotType::Interrupt,
    points: 16,
    buffer_words: 0,
    pointers: Some(0..16),
    causes: 0,
    manual: "QI60 Interrupt Module User's Manual (SH-080029)",
    new,
    switches: None,
};

fn new(_slot: &Slot) -> Box<dyn Module> {
    Box::new(Qi60)
}

#[derive(Debug)]
struct Qi60;

impl Module for Qi60 {
    fn power_on(&mut self, _io: &mut ModuleIo<'_>) {}
    fn end(&mut self, _io: &mut ModuleIo<'_>, _now_us: u64) {}
}
