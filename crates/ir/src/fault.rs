//! Faults in no family's numbers: [`Fault`] says what went wrong; the CPU's
//! family ([`crate::system::System::code`]) turns it into the [`ErrorCode`] it
//! records (SD0, the error history, [`CpuError`]) and gives that code's message.

/// The number a CPU records for an error (SD0 on MELSEC, SD20 on the APLC).
/// Its meaning and message belong to the CPU's family.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ErrorCode(pub u16);

/// What went wrong while a CPU ran its programs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fault {
    /// Data the instruction cannot process (division by 0, an invalid real
    /// number, an out-of-range conversion).
    Operation,
    /// A device range exceeded (index modification, block length, an
    /// address past a module's buffer memory).
    Range,
    /// Buffer memory of a slot with no intelligent function module read or
    /// written (MELSEC: SP.UNIT ERROR). `unit`: the unit number accessed
    /// (the start I/O number without its last hex digit), for the error
    /// information.
    NoModule { unit: u16 },
    /// A program read or wrote its own CPU shared memory through `U3En\G`,
    /// or read it with FROM (multi-CPU system; MELSEC: SP.UNIT ERROR 2114).
    OwnSharedMemory { unit: u16 },
    /// A program wrote another CPU's shared memory (MELSEC: 2115).
    OtherSharedMemory { unit: u16 },
    /// A program wrote the buffer memory of a module another CPU of the
    /// multi-CPU system controls (MELSEC: 2116).
    NotControlled { unit: u16 },
    /// More inter-CPU instructions waiting to complete than the CPU holds
    /// (MELSEC: OPERATION ERROR 4107).
    TooManyPending,
    /// Another CPU of the multi-CPU system stopped and stops this one
    /// (MELSEC: MULTI CPU DOWN 7000).
    MultiCpuDown,
    /// Another CPU of the multi-CPU system stopped; this one goes on
    /// (MELSEC: MULTI EXE. ERROR 7010).
    MultiCpuError,
    /// The number of CPUs set differs from the CPUs installed (MELSEC:
    /// PARAMETER ERROR 3010).
    CpuCount,
    /// The multi-CPU parameters differ from CPU 1's (MELSEC: PARAMETER
    /// ERROR 3012).
    MultiCpuParameter,
    /// FOR without NEXT reached END.
    ForWithoutNext,
    /// NEXT executed without FOR.
    NextWithoutFor,
    /// More FOR nesting levels than the CPU has.
    ForNesting,
    /// BREAK executed without FOR.
    BreakWithoutFor,
    /// A subroutine did not end with RET.
    NoRet,
    /// RET executed in the main program.
    RetInMain,
    /// More CALL nesting levels than the CPU has.
    CallNesting,
    /// An interrupt program did not end with IRET.
    NoIret,
    /// IRET executed outside an interrupt program.
    IretInMain,
    /// A program named by an instruction does not exist.
    NoProgram,
    /// A common pointer is defined in two program files (found when the
    /// CPU is built).
    PointerTwice,
    /// The scan exceeded the watchdog time.
    Watchdog,
    /// The scan exceeded the constant-scan period.
    ScanOverrun,
    /// A low-speed scan exceeded the low-speed execution monitor time.
    LowSpeedOverrun,
    /// Battery-backed data was lost (softplc: the state directory was found
    /// damaged at power-on).
    Battery,
    /// An annunciator turned ON.
    Annunciator,
    /// A family's own error, for the few instructions that raise a number
    /// of their family (the MELSEC PID's 4103, the APLC's 67, 69, 70, 73).
    Family(ErrorCode),
}

impl Fault {
    /// The unit number a module-access fault names, `None` for the others.
    pub fn unit(self) -> Option<u32> {
        match self {
            Fault::NoModule { unit }
            | Fault::OwnSharedMemory { unit }
            | Fault::OtherSharedMemory { unit }
            | Fault::NotControlled { unit } => Some(unit as u32),
            _ => None,
        }
    }
}

/// The latest self-diagnostic error, with where it happened.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CpuError {
    pub code: ErrorCode,
    /// Step number of the failing instruction, if an instruction failed.
    pub step: Option<u32>,
    /// Source file and line of that instruction.
    pub file: Option<String>,
    pub line: Option<u32>,
}

/// One entry of the error history (004 §7.20.2): the latest 16 are kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HistoryEntry {
    pub code: ErrorCode,
    /// Calendar time of detection, seconds since 1970.
    pub time: i64,
    /// Step of the failing instruction, or the annunciator number.
    pub detail: Option<u32>,
}
