//! MELSEC error codes raised by the engine (004 §7.20 self-diagnostics; codes as
//! listed in the QCPU User's Manual (Hardware Design, Maintenance and Inspection)).

use std::fmt;

/// A self-diagnostic error code as it appears in SD0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ErrorCode(pub u16);

impl ErrorCode {
    /// FILE OPE. ERROR: the program named by PSCAN/PSTOP/POFF/PLOW does not exist.
    pub const NO_PROGRAM: ErrorCode = ErrorCode(2410);
    /// OPERATION ERROR: data the instruction cannot process (division by 0,
    /// invalid real number, out-of-range conversion).
    pub const OPERATION: ErrorCode = ErrorCode(4100);
    /// OPERATION ERROR: device range exceeded (index modification, block length).
    pub const RANGE: ErrorCode = ErrorCode(4101);
    /// FOR NEXT ERROR: FOR without NEXT reached END.
    pub const FOR_WITHOUT_NEXT: ErrorCode = ErrorCode(4200);
    /// FOR NEXT ERROR: NEXT executed without FOR.
    pub const NEXT_WITHOUT_FOR: ErrorCode = ErrorCode(4201);
    /// FOR NEXT ERROR: more than 16 nesting levels.
    pub const FOR_NESTING: ErrorCode = ErrorCode(4202);
    /// FOR NEXT ERROR: BREAK executed without FOR.
    pub const BREAK_WITHOUT_FOR: ErrorCode = ErrorCode(4203);
    /// CAN'T EXECUTE(P): the subroutine did not end with RET.
    pub const NO_RET: ErrorCode = ErrorCode(4211);
    /// CAN'T EXECUTE(P): RET executed in the main program.
    pub const RET_IN_MAIN: ErrorCode = ErrorCode(4212);
    /// CAN'T EXECUTE(P): more than 16 CALL nesting levels.
    pub const CALL_NESTING: ErrorCode = ErrorCode(4213);
    /// CAN'T EXECUTE(I): the interrupt program did not end with IRET.
    pub const NO_IRET: ErrorCode = ErrorCode(4221);
    /// CAN'T EXECUTE(I): IRET executed outside an interrupt program.
    pub const IRET_IN_MAIN: ErrorCode = ErrorCode(4223);
    /// BATTERY ERROR: battery-backed data was lost (softplc: the state directory
    /// was found damaged at power-on; COMPATIBILITY.md "Decisions").
    pub const BATTERY: ErrorCode = ErrorCode(1600);
    /// F****: an annunciator turned ON (continuation error).
    pub const ANNUNCIATOR: ErrorCode = ErrorCode(9000);
    /// WDT ERROR: scan exceeded the watchdog time.
    pub const WDT: ErrorCode = ErrorCode(5000);
    /// PRG.TIME OVER: scan exceeded the constant-scan setting.
    pub const PRG_TIME_OVER: ErrorCode = ErrorCode(5010);

    /// The CPU's error message for this code.
    pub fn message(self) -> &'static str {
        match self.0 {
            1600 => "BATTERY ERROR: battery-backed data lost (damaged state file)",
            2410 => "FILE OPE. ERROR: the specified program does not exist",
            4100 => "OPERATION ERROR: the instruction cannot process this data",
            4101 => "OPERATION ERROR: device range exceeded",
            4200 => "FOR NEXT ERROR: FOR without NEXT",
            4201 => "FOR NEXT ERROR: NEXT without FOR",
            4202 => "FOR NEXT ERROR: more than 16 FOR nesting levels",
            4203 => "FOR NEXT ERROR: BREAK without FOR",
            4211 => "CAN'T EXECUTE(P): no RET in the executed subroutine",
            4212 => "CAN'T EXECUTE(P): RET executed in the main program",
            4213 => "CAN'T EXECUTE(P): more than 16 CALL nesting levels",
            4221 => "CAN'T EXECUTE(I): no IRET in the executed interrupt program",
            4223 => "CAN'T EXECUTE(I): IRET executed outside an interrupt program",
            5000 => "WDT ERROR: scan time exceeded the watchdog",
            9000 => "F****: annunciator ON",
            5010 => "PRG.TIME OVER: scan time exceeded the constant scan",
            // APLC-TCP execution errors (seed 002 Appendix 6, L11266-11289);
            // the numbers do not overlap MELSEC's.
            60 => "program compile error",
            61 => "user program timeout (watchdog)",
            62 => "illegal instruction",
            63 => "illegal operand device type",
            64 => "illegal operand value",
            65 => "operand device number out of range",
            66 => "subroutine stack overflow",
            67 => "interrupt request queue overflow",
            68 => "illegal jump label or subroutine call",
            69 => "divide by zero",
            70 => "illegal stack definition",
            72 => "undefined subroutine or interrupt routine",
            73 => "special module address invalid",
            74 => "special module access error",
            75 => "I/O immediate refresh error",
            _ => "error",
        }
    }

    /// Operation errors follow the "operation error: stop/continue" parameter;
    /// everything else stops the CPU.
    pub fn is_operation_error(self) -> bool {
        (4100..4200).contains(&self.0)
    }

    /// Errors after which the CPU keeps running: BATTERY ERROR, PRG.TIME OVER and annunciators
    /// (operation errors continue only when the parameter says so).
    pub fn is_continuation(self) -> bool {
        matches!(self.0, 1600 | 5010 | 9000)
    }
}

impl fmt::Display for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.0, self.message())
    }
}

/// A runtime fault raised by an instruction.
pub type Fault = ErrorCode;

/// The latest self-diagnostic error, with where it happened.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CpuError {
    pub code: ErrorCode,
    /// Step number of the failing instruction, if an instruction failed.
    pub step: Option<u32>,
    /// Source file and line of that instruction.
    pub file: Option<String>,
    pub line: Option<u32>,
}

/// One entry of the error history (004 §7.20.2): the latest 16 are kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HistoryEntry {
    pub code: ErrorCode,
    /// Calendar time of detection, seconds since 1970.
    pub time: i64,
    /// Step of the failing instruction, or the annunciator number for 9000.
    pub detail: Option<u32>,
}
