//! Instruction families, one module per chapter of the MELSEC-Q/QnA programming
//! manual (common instructions): sequence instructions (contacts, coils, timers,
//! counters, master control) and basic instructions (comparison, arithmetic,
//! conversion, transfer). Program-control instructions (jumps, CALL, FOR/NEXT)
//! live in the engine's interpreter loop because they move the program counter.
//!
//! Further families plug in through [`FAMILIES`]: a family module offers a
//! `lookup` that maps a mnemonic (without its `P` suffix) to a compile function,
//! which reads operands through [`Args`] and returns an [`Instr`] the engine
//! executes when the rung condition is ON. Pulse forms are handled for them.

pub mod arithmetic;
pub mod basic;
pub mod bits;
pub mod clock;
pub mod comparison;
pub mod control;
pub mod conversion;
pub mod data;
pub mod file_register;
pub mod float;
pub mod ladder;
pub mod limits;
pub mod logic;
pub mod misc;
pub mod pid;
pub mod rejected;
pub mod rotation;
pub mod sequence;
pub mod strings;
pub mod table;
pub mod timing;
pub mod transfer;

use std::fmt::Debug;

use crate::device::DeviceMemory;
use crate::engine::Fault;
pub use crate::program::compile::Args;

/// Everything an application instruction may touch while it executes.
pub struct ExecCtx<'a> {
    pub mem: &'a mut DeviceMemory,
    /// Hidden per-instruction state words, allocated with [`Args::state_words`].
    pub state: &'a mut [u32],
    /// PLC clock reading (µs) and the scan time measured at the previous END (µs).
    pub now_us: u64,
    pub scan_us: u32,
    /// CPU-wide state shared by instructions of every program file (what the
    /// CPU keeps outside device memory, e.g. the PID registration), cleared at
    /// power-on and STOP→RUN; see [`SHARED_WORDS`].
    pub shared: &'a mut [u32],
    /// The calendar clock (read with `clock.now(now_us)`, set by DATEWR).
    pub clock: &'a mut crate::engine::calendar::PlcClock,
}

/// A compiled application instruction of a family module.
pub trait Instr: Debug + Send + Sync {
    /// Runs the instruction while its condition is ON (for a pulse form, only
    /// on the rising edge).
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault>;

    /// Runs the instruction while its condition is OFF; called only for
    /// instructions defined with [`crate::program::isa::Drive::Always`].
    fn off(&self, _cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        Ok(())
    }
}

pub use crate::program::isa::CompileFn;

/// Size of [`ExecCtx::shared`]: the PID registrations of both families, then the
/// RND random series (`misc`).
pub const SHARED_WORDS: usize = misc::SHARED_AT + misc::SHARED_WORDS;

/// The MELSEC-Q instruction set: every family's definitions, then the rejected
/// instructions (see [`crate::program::isa`]). A new family is one line here.
pub static DEFS: &[&[crate::program::isa::Def]] = &[
    ladder::DEFS,
    basic::DEFS,
    control::DEFS,
    conversion::DEFS,
    arithmetic::DEFS,
    strings::DEFS,
    transfer::DEFS,
    logic::DEFS,
    rotation::DEFS,
    bits::DEFS,
    data::DEFS,
    table::DEFS,
    limits::DEFS,
    comparison::DEFS,
    float::DEFS,
    clock::DEFS,
    pid::DEFS,
    file_register::DEFS,
    timing::DEFS,
    misc::DEFS,
    rejected::DEFS,
];

/// The state an instruction keeps between executions (the CPU's per-instruction
/// memory: "was the condition ON last time", a sub-unit time remainder), held in
/// the program's hidden state words, which are cleared at power-on and STOP→RUN.
/// Declare it with [`local_state!`]; allocate it with [`Args::local`].
pub trait LocalState: Copy + Default {
    /// State words it occupies.
    const WORDS: u32;
    fn load(words: &[u32]) -> Self;
    fn store(self, words: &mut [u32]);
}

/// Where an instruction's [`LocalState`] lives (typed: no word offsets by hand).
#[derive(Debug)]
pub struct LocalSlot<T> {
    at: u32,
    _state: std::marker::PhantomData<fn() -> T>,
}

impl<T> LocalSlot<T> {
    pub(crate) fn new(at: u32) -> Self {
        LocalSlot {
            at,
            _state: std::marker::PhantomData,
        }
    }
}

impl ExecCtx<'_> {
    /// The instruction's state as last stored.
    #[inline]
    pub fn local<T: LocalState>(&self, slot: &LocalSlot<T>) -> T {
        let at = slot.at as usize;
        T::load(&self.state[at..at + T::WORDS as usize])
    }

    #[inline]
    pub fn set_local<T: LocalState>(&mut self, slot: &LocalSlot<T>, v: T) {
        let at = slot.at as usize;
        v.store(&mut self.state[at..at + T::WORDS as usize]);
    }
}

/// A field type of a [`local_state!`] struct: one state word.
pub trait StateWord: Copy + Default {
    fn to_word(self) -> u32;
    fn from_word(w: u32) -> Self;
}

impl StateWord for bool {
    fn to_word(self) -> u32 {
        self as u32
    }
    fn from_word(w: u32) -> Self {
        w != 0
    }
}

impl StateWord for u32 {
    fn to_word(self) -> u32 {
        self
    }
    fn from_word(w: u32) -> Self {
        w
    }
}

/// Declares a per-instruction state struct whose fields are one state word
/// each (`bool`, `u32`), and implements [`LocalState`] for it.
#[macro_export]
macro_rules! local_state {
    ($(#[$m:meta])* $vis:vis struct $name:ident { $($(#[$fm:meta])* $field:ident: $ty:ty),* $(,)? }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        $vis struct $name { $($(#[$fm])* $field: $ty),* }

        impl $crate::instructions::LocalState for $name {
            const WORDS: u32 = [$(stringify!($field)),*].len() as u32;
            fn load(words: &[u32]) -> Self {
                let mut k = 0;
                $(let $field = <$ty as $crate::instructions::StateWord>::from_word(words[k]); k += 1;)*
                let _ = k;
                $name { $($field),* }
            }
            fn store(self, words: &mut [u32]) {
                let mut k = 0;
                $(words[k] = $crate::instructions::StateWord::to_word(self.$field); k += 1;)*
                let _ = k;
            }
        }
    };
}
