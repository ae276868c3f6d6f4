//! The instruction trait the interpreter calls ([`Instr`]), what an instruction
//! sees while it runs ([`ExecCtx`]), and its typed per-instruction state
//! ([`LocalState`], declared with [`local_state!`](crate::local_state)).

use std::fmt::Debug;

use crate::calendar::PlcClock;
use crate::cpu::CpuServices;
use crate::device::DeviceMemory;
use crate::fault::Fault;

/// Everything an application instruction may touch while it executes.
pub struct ExecCtx<'a> {
    pub mem: &'a mut DeviceMemory,
    /// Hidden per-instruction state words, allocated by the compiler (`Args::local`).
    pub state: &'a mut [u32],
    /// PLC clock reading (µs) and the scan time measured at the previous END (µs).
    pub now_us: u64,
    pub scan_us: u32,
    /// CPU-wide state shared by instructions of every program file (what the
    /// CPU keeps outside device memory, e.g. the PID registration), cleared at
    /// power-on and STOP→RUN; sized by [`crate::ops::Program::shared_words`]; each
    /// family's part is a [`CpuSlot`].
    pub shared: &'a mut [u32],
    /// The calendar clock (read with `clock.now(now_us)`, set by DATEWR).
    pub clock: &'a mut PlcClock,
    /// What the engine does for CPU-function instructions (watchdog,
    /// interrupts, execution types, trace, timers, error reports).
    pub cpu: &'a mut CpuServices,
}

/// A compiled application instruction of a family module.
pub trait Instr: Debug + Send + Sync {
    /// Runs the instruction while its condition is ON (for a pulse form, only
    /// on the rising edge).
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault>;

    /// Runs the instruction while its condition is OFF; called only for
    /// instructions defined to run on every execution (`Drive::Always`).
    fn off(&self, _cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        Ok(())
    }

    /// Resolves what the instruction names in other program files when the
    /// CPU is built: `programs` are the CPU's program names (file names
    /// without extension, upper case) in slot order.
    fn link(&mut self, _programs: &[String]) {}

    /// What `exec` does, for a native tier to do inline, when the
    /// instruction is one of the few it knows ([`crate::word_op`]).
    fn word_op(&self) -> Option<crate::word_op::WordOp<'_>> {
        None
    }
}

/// The state an instruction keeps between executions (the CPU's per-instruction
/// memory: "was the condition ON last time", a sub-unit time remainder), held in
/// the program's hidden state words, which are cleared at power-on and STOP→RUN.
/// Declare it with [`local_state!`](crate::local_state); the compiler allocates it
/// (`Args::local`).
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
    pub fn new(at: u32) -> Self {
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

        impl $crate::instr::LocalState for $name {
            const WORDS: u32 = [$(stringify!($field)),*].len() as u32;
            fn load(words: &[u32]) -> Self {
                let mut k = 0;
                $(let $field = <$ty as $crate::instr::StateWord>::from_word(words[k]); k += 1;)*
                let _ = k;
                $name { $($field),* }
            }
            fn store(self, words: &mut [u32]) {
                let mut k = 0;
                $(words[k] = $crate::instr::StateWord::to_word(self.$field); k += 1;)*
                let _ = k;
            }
        }
    };
}

/// CPU-wide state of an instruction family (the PID registration, the RND
/// series): words of [`ExecCtx::shared`], shared by the instructions of every
/// program file and cleared at power-on and STOP→RUN. Each type gets its own
/// words the first time it is used, so no family computes offsets by hand.
/// Declare one with [`cpu_state!`](crate::cpu_state).
pub trait CpuState {
    /// Words it occupies.
    const WORDS: u32;
    /// Its first word in the shared state (assigned once per process).
    fn offset() -> u32;
}

/// Reserves `words` shared-state words for a new [`CpuState`] type.
pub fn allocate_cpu_words(words: u32) -> u32 {
    static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    NEXT.fetch_add(words, std::sync::atomic::Ordering::Relaxed)
}

/// Where a [`CpuState`] lives (from `Args::cpu`).
#[derive(Debug)]
pub struct CpuSlot<T> {
    at: u32,
    _state: std::marker::PhantomData<fn() -> T>,
}

impl<T> Clone for CpuSlot<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for CpuSlot<T> {}

impl<T: CpuState> CpuSlot<T> {
    pub fn new() -> Self {
        CpuSlot {
            at: T::offset(),
            _state: std::marker::PhantomData,
        }
    }

    /// Words one past the state: the shared words a program using it needs.
    pub fn end(&self) -> u32 {
        self.at + T::WORDS
    }

    /// The state's words in the shared state (`cx.shared`, borrowed alone so
    /// that `cx.mem` stays usable).
    #[inline]
    pub fn words<'a>(&self, shared: &'a mut [u32]) -> &'a mut [u32] {
        let at = self.at as usize;
        &mut shared[at..at + T::WORDS as usize]
    }
}

impl<T: CpuState> Default for CpuSlot<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// Declares a [`CpuState`] type of `WORDS` shared words.
#[macro_export]
macro_rules! cpu_state {
    ($(#[$m:meta])* $vis:vis struct $name:ident[$words:expr];) => {
        $(#[$m])*
        #[derive(Debug)]
        $vis struct $name;

        impl $crate::instr::CpuState for $name {
            const WORDS: u32 = $words as u32;
            fn offset() -> u32 {
                static AT: std::sync::OnceLock<u32> = std::sync::OnceLock::new();
                *AT.get_or_init(|| $crate::instr::allocate_cpu_words(Self::WORDS))
            }
        }
    };
}
