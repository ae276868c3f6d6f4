//! What a compiled program tells the tools that show it (the web monitor's
//! ladder and faceplates, OPC UA): each source instruction with its ladder
//! role, as written, and the control loops its instructions own. The
//! compiler records it from the instruction definitions, so no tool has to
//! recognise an instruction by its mnemonic.

use crate::layout::Field;
use crate::ops::{Join, Num};

/// What an instruction is on the ladder (PM §3: contacts, connection
/// instructions, outputs and instructions written on the bus bar alone).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Reads a condition: starts a rung or block (`Join::Load`) or joins it.
    Contact { join: Join, test: Test },
    /// Works on the operation result or the stacks.
    Link(Link),
    /// A coil driven by the rung's condition.
    Coil(CoilRole),
    /// An application instruction driven by the rung's condition (a box).
    Box,
    /// Written on the bus bar alone (END, FEND, MCR, NEXT, RET, labels …).
    Standalone,
    /// Opens an SFC step (APLC `STL`): the rungs after it are the step's
    /// body; consecutive steps are one merge.
    Step,
    /// Ends the SFC section (APLC `RET` in MAIN): the rungs after it are
    /// on the plain rail again.
    StepsEnd,
}

/// What a contact tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Test {
    /// A bit, normally open / normally closed.
    Open,
    Closed,
    /// The rising / falling edge of a bit.
    Rising,
    Falling,
    /// ON except on the rising / falling edge of a bit (the QnU's LDPI,
    /// LDFI …).
    NotRising,
    NotFalling,
    /// Bit S2 of word S1 (APLC `BLD D0 5`), normally open or closed.
    WordBit {
        closed: bool,
    },
    /// Two numbers of this type compared (`LD= D0 K5`, `LDD>`, `LDE<`).
    Compare(Num),
    /// A condition an instruction computes (`LD$=` string comparison).
    Computed,
}

/// What a connection instruction does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// ANB / ORB: the block opened by the last load joins the one before it.
    BlockAnd,
    BlockOr,
    /// MPS / MRD / MPP: push, read and pop the branch stack.
    Push,
    Read,
    Pop,
    /// INV: inverts the operation result.
    Invert,
    /// MEP, EGP, EU / MEF, EGF, ED: the rising / falling edge of the result.
    Rising,
    Falling,
    /// NOP written inside a rung: the result passes unchanged.
    Nothing,
}

/// What a coil does to its bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoilRole {
    Out,
    Set,
    Reset,
    /// PLS, PLF, FF: a pulse or toggle on an edge of the condition.
    Pulse,
}

/// One source instruction as compiled.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Listed {
    pub role: Role,
    /// The mnemonic as written (for display only: the role says what it is).
    pub mnemonic: String,
    /// The operands as written.
    pub operands: Vec<String>,
    /// Its source line (in [`crate::ops::Program::sources`]' numbering).
    pub line: u32,
    /// The hidden state the compiler gave it (see [`Held`]).
    pub held: Held,
}

/// Where an instruction's hidden state is in its program: its edge
/// memories and state words (`Program::edge_slots`, `Program::state_words`)
/// and its steps. What writing during RUN carries over from an unchanged
/// instruction (`crate::online`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Held {
    pub edges: std::ops::Range<u32>,
    pub words: std::ops::Range<u32>,
    pub steps: std::ops::Range<u32>,
}

/// A line of the listing: a pointer label or an instruction.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Entry {
    Label { text: String, line: u32 },
    Instr(Listed),
}

/// Control-loop memory an instruction owns: a declared layout over the
/// device words at one of its operands, for one loop or a run of loops.
#[derive(Debug)]
pub struct LoopMemory {
    /// What the block is (`PID I/O data`, `loop tag`).
    pub name: &'static str,
    /// The fields of one loop (a `layout!`'s `FIELDS`).
    pub fields: &'static [Field],
    /// Words from the operand to loop 1's fields.
    pub first: u32,
    /// Words from one loop's fields to the next's; 0 for a single loop.
    pub stride: u32,
    /// The word of the block that holds the number of loops, when the
    /// block says it (PIDINIT's +0).
    pub count: Option<u32>,
    /// The memory that holds these loops' settings: the block of the last
    /// instruction before this one that owns that memory (PIDCONT's loops
    /// take their control data from the PIDINIT before it).
    pub settings: Option<&'static LoopMemory>,
}

impl LoopMemory {
    /// Word offset of `field` of loop `k` (0-based) from the block's start.
    pub fn offset(&self, k: u32, field: &Field) -> u64 {
        self.first as u64 + k as u64 * self.stride as u64 + field.offset as u64
    }

    /// The field named `name`.
    pub fn field(&self, name: &str) -> Option<&'static Field> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// The same declaration (memories are statics: compared by address).
    pub fn is(&self, other: &LoopMemory) -> bool {
        std::ptr::eq(self, other)
    }
}

/// One instruction's loop memory in a program.
#[derive(Clone, Debug)]
pub struct LoopUse {
    /// The instruction's mnemonic as written.
    pub mnemonic: String,
    /// The block's first device, as written (`D600`, `R1000`).
    pub block: String,
    pub line: u32,
    pub memory: &'static LoopMemory,
}

/// A program's listing: its instructions and labels in source order, and
/// the loop memories its instructions own, in the same order.
#[derive(Clone, Debug, Default)]
pub struct Listing {
    pub entries: Vec<Entry>,
    pub loops: Vec<LoopUse>,
}

impl Listing {
    /// Ends each instruction's [`Held`] ranges where the next one's begin
    /// (the compiler records where they begin), the last at the program's
    /// totals.
    pub fn close_held(&mut self, edges: u32, words: u32, steps: u32) {
        let mut end = (edges, words, steps);
        for e in self.entries.iter_mut().rev() {
            if let Entry::Instr(i) = e {
                let h = &mut i.held;
                h.edges.end = end.0.max(h.edges.start);
                h.words.end = end.1.max(h.words.start);
                h.steps.end = end.2.max(h.steps.start);
                end = (h.edges.start, h.words.start, h.steps.start);
            }
        }
    }
}
