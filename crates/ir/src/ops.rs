//! The compiled program: a flat array of pre-resolved operations.
//!
//! Every device operand is resolved at load time to an index into the flat bit or
//! word array of [`crate::device::DeviceMemory`]. The common cases (plain contacts
//! and coils, word-to-word MOV) are small inline variants; everything else sits
//! behind a `Box` so that `Op` stays 16 bytes and the program stays cache-dense.

/// Width and type of the numbers an instruction works on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Num {
    /// 16-bit signed BIN.
    I16,
    /// 32-bit signed BIN, low word first (`D` instructions).
    I32,
    /// IEEE-754 single precision in two words (`E` instructions).
    F32,
}

impl Num {
    pub fn words(self) -> u32 {
        match self {
            Num::I16 => 1,
            Num::I32 | Num::F32 => 2,
        }
    }
}

/// How an index-modified operand is addressed (`D0Z1`, `K4M0Z2`, `X0Z1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IndexedKind {
    /// Word device.
    Word,
    /// Bit device read as `n` 4-bit digits.
    Digits(u8),
    /// Single bit device.
    Bit,
    /// Bit `b` of a word device.
    WordBit(u8),
}

/// An operand whose device number is computed when it executes: index
/// modification (`D0Z1`) and file registers `R`, which address the block
/// selected by RSET (004 §10.7).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Indexed {
    pub kind: IndexedKind,
    /// Flat index of device number 0 of this kind (ZR for `R`).
    pub base: u32,
    /// Device number as written.
    pub number: u32,
    /// Points of this device kind: the effective number must stay below it.
    pub points: u32,
    /// Flat word index of the index register `Zn`, or [`Indexed::NONE`].
    pub z: u32,
    /// What the number is relative to: the device, the selected
    /// file-register block, or a module that is not there.
    pub window: Window,
}

impl Indexed {
    pub const NONE: u32 = u32::MAX;
}

/// What an [`Indexed`] operand's number is relative to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Window {
    /// Device number 0 of its kind.
    Device,
    /// `R`: the file-register block the CPU's selector word holds.
    SelectedBlock,
    /// `ZR`: file registers numbered from ZR0.
    FileRegister,
    /// `U<n>\\G<addr>` of a slot with no intelligent function module: every
    /// access is [`crate::fault::Fault::NoModule`] naming its unit (004 ch. 8).
    NoModule(u16),
    /// Memory the operand may not reach in its role: every access is the
    /// fault (a multi-CPU system's own shared memory through `U3En\\G`,
    /// another CPU's shared memory or a module another CPU controls as a
    /// destination; 004 L8985-8998, L9199-9205).
    Refused(crate::fault::Fault),
}

/// A resolved word operand; 16-bit instructions use the low word of a constant.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WordArg {
    /// Word device at a flat word index.
    Word(u32),
    /// Constant, raw bits (K/H as two's complement, E as f32 bits).
    Const(u32),
    /// Digit specification: `n` digits (4·n bits) from a flat bit index.
    Digits {
        bit: u32,
        n: u8,
    },
    Indexed(Box<Indexed>),
}

/// A resolved bit operand.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BitArg {
    /// Bit device at a flat bit index.
    Bit(u32),
    /// Bit `bit` of the word at a flat word index (`D0.F`).
    WordBit {
        word: u32,
        bit: u8,
    },
    Indexed(Box<Indexed>),
}

/// Where a contact puts its result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Join {
    /// Start of a rung or block (LD): the result replaces the accumulator.
    Load,
    And,
    Or,
}

/// Edge detection of a contact (LDP/LDF, ANDP …).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    None,
    Rising,
    Falling,
}

/// A contact on a general bit operand, or an edge contact.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contact {
    pub join: Join,
    pub negate: bool,
    pub edge: Edge,
    /// Hidden edge memory slot (edge contacts only).
    pub slot: u32,
    pub src: BitArg,
}

/// Comparison operators of the comparison contacts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CmpOp {
    Eq,
    Ne,
    Gt,
    Le,
    Lt,
    Ge,
}

/// `LD= S1 S2` and friends, 16/32-bit and real.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Compare {
    pub join: Join,
    pub op: CmpOp,
    pub num: Num,
    pub a: WordArg,
    pub b: WordArg,
}

/// A contact whose value an instruction computes (`LD$= S1 S2` and friends).
pub trait Condition: std::fmt::Debug + Send + Sync {
    fn eval(&self, mem: &crate::device::DeviceMemory) -> Result<bool, crate::fault::Fault>;
}

/// A [`Condition`] contact with its join.
#[derive(Debug)]
pub struct CondOp {
    pub join: Join,
    pub cond: Box<dyn Condition>,
}

/// A coil-type instruction on a general bit operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoilKind {
    Out,
    Set,
    Rst,
    /// PLS/PLF/FF with their hidden edge slot.
    Pls(u32),
    Plf(u32),
    Ff(u32),
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Coil {
    pub kind: CoilKind,
    pub dst: BitArg,
}

/// `OUT T`, `OUTH T`, `OUT ST`, `OUTH ST` (004 §10.2.10).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Timer {
    pub coil: u32,
    pub contact: u32,
    /// Current value word.
    pub value: u32,
    /// Index into the engine's per-timer sub-count remainders.
    pub slot: u32,
    pub set: WordArg,
    pub high_speed: bool,
    pub retentive: bool,
}

/// `OUT C` (004 §10.2.11).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Counter {
    pub coil: u32,
    pub contact: u32,
    pub value: u32,
    pub set: WordArg,
}

/// Timer or counter cleared by `RST`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResetTc {
    pub contact: u32,
    pub value: u32,
    /// Timer remainder slot, `u32::MAX` for counters.
    pub slot: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArithOp {
    Add,
    Sub,
    Mul,
    Div,
}

/// `MC n dev` (master control).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MasterControl {
    pub level: u8,
    pub dst: BitArg,
}

/// One compiled operation. `Op` is 16 bytes.
#[derive(Debug)]
pub enum Op {
    // --- contacts on plain bit devices (004 sequence instructions) ---
    Ld(u32),
    Ldi(u32),
    And(u32),
    Ani(u32),
    Or(u32),
    Ori(u32),
    Contact(Box<Contact>),
    /// Direct input `DX<n>` (004 §10.2, L6054-6083): X`n` takes the input
    /// module's value now (the contact that follows reads it), so a later
    /// X sees what the DX read.
    DirectIn(u32),
    Compare(Box<Compare>),
    /// A contact computed by an instruction (string comparison `LD$=` …).
    Cond(Box<CondOp>),
    /// Opens a new block inside a rung: pushes the accumulator for ANB/ORB.
    Push,
    Anb,
    Orb,
    Mps,
    Mrd,
    Mpp,
    Inv,
    /// MEP/MEF with their hidden edge slot.
    Mep(u32),
    Mef(u32),
    /// EGP/EGF: edge of the operation result, remembered in edge relay V.
    EdgeRelay {
        rising: bool,
        v: u32,
    },
    // --- coils ---
    Out(u32),
    Set(u32),
    Rst(u32),
    Coil(Box<Coil>),
    Timer(Box<Timer>),
    Counter(Box<Counter>),
    Mc(Box<MasterControl>),
    Mcr(u8),
    // --- application instructions ---
    /// Pulse (P) form gate: runs the next op only on the condition's rising edge.
    Pulse(u32),
    /// `MOV K s D` with the constant pre-truncated to 16 bits.
    MovK {
        k: u16,
        d: u32,
    },
    /// `MOV S D` between plain word devices.
    MovW {
        s: u32,
        d: u32,
    },
    /// `DMOV S D` between plain word devices (two words, low first).
    MovD {
        s: u32,
        d: u32,
    },
    /// `DMOV K s D` / `EMOV E s D` into a plain word pair, low word first.
    MovDK {
        k: u32,
        d: u32,
    },
    /// An instruction of a family module: index into [`Program::ext`]; runs
    /// while the condition is ON.
    Ext(u32),
    /// A family instruction of `Drive::Always`: `exec`
    /// while the condition is ON, `off` while it is OFF.
    ExtAlways(u32),
    // --- program control ---
    /// CJ (conditional) and JMP (unconditional) to an op index.
    Cj {
        target: u32,
        always: bool,
    },
    /// SCJ: jumps while the condition was already on at the previous execution.
    Scj {
        target: u32,
        slot: u32,
    },
    GoEnd,
    Call(u32),
    /// CALL of a common pointer defined in another file, before linking.
    CallCommon(u32),
    /// CALL into program `slot` at op `pc` (a linked common pointer).
    CallFar {
        slot: u16,
        pc: u32,
    },
    Ret,
    /// A subroutine call with arguments (FX/FY/FD), an FCALL or an ECALL:
    /// a nested pass over the subroutine (see [`CallArgs`]).
    CallArgs(Box<CallArgs>),
    For(Box<WordArg>),
    Next,
    Break(Box<(WordArg, u32)>),
    Fend,
    End,
    Stop,
    /// STOP that stops the program at once: the rest of the scan (END
    /// processing included) does not run (the APLC's STOP, 002 §6.1.10).
    StopNow,
    Nop,
    /// End of an interrupt program.
    Iret,
}

/// `CALL`/`FCALL`/`ECALL`/`EFCALL` with up to 5 arguments (004 §10.3.1,
/// §10.9.1, L1171-1200): argument n is passed through FXn (a bit read by the
/// subroutine), FYn (a bit it returns) or FDn (4 words, in and out).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CallArgs {
    pub callee: Callee,
    pub args: Box<[FnArg]>,
    /// FCALL/EFCALL: with the condition OFF the subroutine still runs, with
    /// every condition inside it OFF (its non-execution processing).
    pub fcall: bool,
    /// The pulse form's edge slot (…P: runs on the rising edge).
    pub pulse: Option<u32>,
}

/// Where a [`CallArgs`] goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Callee {
    /// A pointer of this file: op index (after the compiler's fix-up).
    Here(u32),
    /// A common pointer of another file, before linking.
    Common(u32),
    /// ECALL: pointer `pointer` of program `file` (upper-case name without
    /// extension), before linking.
    File { file: Box<str>, pointer: u32 },
    /// Linked: op `pc` of program `slot`.
    Far { slot: u16, pc: u32 },
}

/// One argument of a [`CallArgs`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FnArg {
    /// A bit device: read into FXn and FYn at the call; FYn written back
    /// at the return when `back` (not for X and contacts).
    Bit { dev: BitArg, back: bool },
    /// A word device: its 4 words read into FDn at the call and written back at
    /// the return when `back`.
    Word { dev: Block, back: bool },
    /// A constant: FDn's 4 words (sign-extended), nothing written back.
    Const([u16; 4]),
}

/// FOR/NEXT and CALL nesting (programming manual: 16 levels).
pub const MAX_NESTING: usize = 16;

/// A word-device block operand whose length is known only at run time (BMOV,
/// FMOV, SUM …): the first word and the flat index one past the device's last
/// point, which a block may not cross (`Fault::Range`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    pub start: WordArg,
    /// Flat index one past the last point of the device kind; for an index-modified
    /// start the range is in its [`Indexed`].
    pub limit: u32,
}

/// A bit-device block operand whose length is known only at run time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BitBlock {
    pub start: BitArg,
    /// Flat bit index one past the last point of the device kind.
    pub limit: u32,
}

/// How a program uses a device operand written without index or digit
/// specification: as a bit, or as a word operand of a width (a `D`
/// instruction's 32-bit pair, an `E` instruction's real). Servers that show
/// the devices a program uses (OPC UA, contract §3.2) read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DeviceUse {
    Bit,
    Word(Num),
}

/// A compiled program with the source map needed for error reports.
#[derive(Debug)]
pub struct Program {
    /// File name as given.
    pub file: String,
    pub ops: Vec<Op>,
    /// For each op, the step number of its instruction.
    pub op_step: Vec<u32>,
    /// For each op, the source line of its instruction.
    pub op_line: Vec<u32>,
    /// Hidden edge memories (LDP, PLS, pulse forms …).
    pub edge_slots: u32,
    /// Hidden state words of family instructions.
    pub state_words: u32,
    /// CPU-wide state words ([`crate::instr::ExecCtx::shared`]) its instructions
    /// use; the CPU allocates the largest need of its programs.
    pub shared_words: u32,
    /// Common pointers defined in this file: (Pn, op index).
    pub common_labels: Vec<(u32, u32)>,
    /// Local pointers defined in this file: (Pn, op index), ascending (ECALL
    /// reaches them from other files, 004 §10.9.1).
    pub local_labels: Vec<(u32, u32)>,
    /// Interrupt pointers of this file: (In, op index), ascending.
    pub interrupts: Vec<(u8, u32)>,
    /// Family instructions referenced by [`Op::Ext`].
    pub ext: Vec<Box<dyn crate::instr::Instr>>,
    /// Steps used, END included.
    pub steps: u32,
    /// Sizes of the flat bit and word memories the program was compiled for;
    /// every resolved index is below them (checked when a CPU is built).
    pub bit_len: u32,
    pub word_len: u32,
    /// A program combined from several source files (the `[[program]]`
    /// files of an APLC-TCP project form one user program): `(first line,
    /// file)` ascending, `op_line` counting the lines of the files one after
    /// the other; empty for a program of one file.
    pub sources: Vec<(u32, String)>,
    /// Names the source gives devices, for device names from outside the
    /// program: the APLC's global variables as (upper-case name, device).
    pub globals: Vec<(String, String)>,
    /// The device operands as written (upper case) and how they are used,
    /// sorted, each pair once (see [`DeviceUse`]).
    pub used_devices: Vec<(String, DeviceUse)>,
    /// The source instructions with their ladder roles, and the control
    /// loops they own, for the tools that show the program.
    pub listing: crate::listing::Listing,
    /// An instruction may write X: it names X in an operand other than
    /// a contact's (conservative: a coil, box or CALL argument naming X
    /// counts whatever it does with it). The input refresh copies the
    /// input image only when a program may write X or something else
    /// changed X or the image since the last refresh.
    pub may_write_x: bool,
}

impl Program {
    /// The file and its own line number of op `pc`'s instruction.
    pub fn source_of(&self, pc: usize) -> (&str, Option<u32>) {
        let line = self.op_line.get(pc).copied();
        match line.and_then(|l| file_line(&self.sources, l)) {
            Some((file, own)) => (file, Some(own)),
            None => (&self.file, line),
        }
    }
}

/// The file and its own line of `line` in the numbering of [`Program::sources`]
/// (the files' lines counted one after the other); `None` before the first.
pub fn file_line(sources: &[(u32, String)], line: u32) -> Option<(&str, u32)> {
    sources
        .iter()
        .rev()
        .find(|(first, _)| line >= *first)
        .map(|(first, f)| (f.as_str(), line - first + 1))
}

#[cfg(test)]
mod tests {
    #[test]
    fn op_is_16_bytes() {
        assert_eq!(std::mem::size_of::<super::Op>(), 16);
    }
}
