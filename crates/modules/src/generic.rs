//! `generic`: an intelligent function module that is buffer memory and
//! nothing else — N words (`buffer_words`, default 4096) that the program
//! reads and writes with FROM/TO and `U\G`, and that a plant model or a
//! scenario drives from outside. The base for a user's own module.

use softplc_ir::rack::{Module, ModuleIo, ModuleProfile, Slot, SlotType};

/// Words of a generic module's buffer memory when the slot does not say.
pub const DEFAULT_WORDS: u32 = 4096;

pub static GENERIC: ModuleProfile = ModuleProfile {
    name: "generic",
    kind: SlotType::Intelligent,
    points: 16,
    buffer_words: 0,
    pointers: None,
    causes: 16,
    manual: "no manual: plain buffer memory (QCPU User's Manual (Function Explanation, Program Fundamentals), ch. 8)",
    new,
    switches: None,
};

fn new(_slot: &Slot) -> Box<dyn Module> {
    Box::new(Generic)
}

/// No behaviour: the words keep what was written, from either side.
#[derive(Debug)]
struct Generic;

impl Module for Generic {
    fn power_on(&mut self, _io: &mut ModuleIo<'_>) {}
    fn end(&mut self, _io: &mut ModuleIo<'_>, _now_us: u64) {}
}
