//! The base units (004 §5.1; App. 1 SM250; App. 2 SD240-SD244, SD250).
//! softplc's rack is a list of up to 64 slots (`[[slot]]`), taken as 8-slot
//! Q bases in automatic mode: slots 0-7 are the main base, 8-15 extension
//! base 1, … 56-63 extension base 7 (004 L2402-2413: one main base, seven
//! extension bases, 64 slots).

use softplc_ir::device::DeviceMemory;
use softplc_ir::rack::{Rack, SlotType};

use super::devices::{sd, sm_get};

/// Slots of each base.
pub const SLOTS_PER_BASE: u32 = 8;

/// What the rack tells the base registers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Bases {
    /// SD241: the last extension base a slot is on (0: the main base only).
    pub extension_bases: u16,
    /// SD250: the last I/O number of the loaded modules, its top two hex
    /// digits plus 1 (0x2FF → 0x30); 0 without modules.
    pub max_io: u16,
}

impl Bases {
    pub fn of(rack: &Rack) -> Bases {
        let last_slot = rack.slots.iter().map(|s| s.index).max();
        let max_io = rack
            .slots
            .iter()
            .filter(|s| s.kind != SlotType::Empty && s.points > 0)
            .map(|s| ((s.start + s.points - 1) >> 4) + 1)
            .max()
            .unwrap_or(0);
        Bases {
            extension_bases: last_slot.map_or(0, |i| (i / SLOTS_PER_BASE).min(7)) as u16,
            max_io: max_io.min(u16::MAX as u32) as u16,
        }
    }

    /// Power-on: SD240 automatic mode (0), SD241 the last extension base,
    /// SD242 one bit per base present, each a Q base (1: Q mode), SD243/SD244
    /// the slots of each base present, a nibble each (main base in SD243
    /// bits 0-3, extension base 7 in SD244 bits 12-15).
    pub(crate) fn power_on(&self, mem: &mut DeviceMemory) {
        let bases = self.extension_bases as u32 + 1;
        let mut slots = 0u32;
        for b in 0..bases {
            slots |= SLOTS_PER_BASE << (4 * b);
        }
        sd(mem, 240, 0);
        sd(mem, 241, self.extension_bases);
        sd(mem, 242, ((1u32 << bases) - 1) as u16);
        sd(mem, 243, slots as u16);
        sd(mem, 244, (slots >> 16) as u16);
    }

    /// END: SM250 turned ON since the last END loads SD250 (App. 2 "S
    /// (request/END)"). Returns SM250 for the next edge.
    pub(crate) fn end(&self, mem: &mut DeviceMemory, before: bool) -> bool {
        let now = sm_get(mem, 250);
        if now && !before {
            sd(mem, 250, self.max_io);
        }
        now
    }
}
