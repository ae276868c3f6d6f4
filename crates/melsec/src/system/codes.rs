//! MELSEC-Q error codes (004 §7.20 self-diagnostics; the codes and messages
//! of the QCPU User's Manual (Hardware Design, Maintenance and Inspection)):
//! the number of each [`Fault`], its message and what it does to the CPU.

use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::system::Severity;

/// BATTERY ERROR (softplc: the state directory was found damaged).
pub const BATTERY: ErrorCode = ErrorCode(1600);
/// FILE OPE. ERROR: the program named by PSCAN/PSTOP/POFF/PLOW does not exist.
pub const NO_PROGRAM: ErrorCode = ErrorCode(2410);
/// SP.UNIT ERROR: buffer memory of a slot with no intelligent function
/// module accessed (FROM/TO, `U\\G`; 004 L4952, L8997).
pub const SP_UNIT: ErrorCode = ErrorCode(2110);
/// OPERATION ERROR: data the instruction cannot process.
pub const OPERATION: ErrorCode = ErrorCode(4100);
/// OPERATION ERROR: device range exceeded.
pub const RANGE: ErrorCode = ErrorCode(4101);
/// WDT ERROR.
pub const WDT: ErrorCode = ErrorCode(5000);
/// PRG.TIME OVER: scan longer than the constant scan.
pub const PRG_TIME_OVER: ErrorCode = ErrorCode(5010);
/// F****: an annunciator turned ON.
pub const ANNUNCIATOR: ErrorCode = ErrorCode(9000);

/// The MELSEC number of `fault`.
pub fn code(fault: Fault) -> ErrorCode {
    match fault {
        Fault::Operation => OPERATION,
        Fault::Range => RANGE,
        Fault::NoModule => SP_UNIT,
        Fault::ForWithoutNext => ErrorCode(4200),
        Fault::NextWithoutFor => ErrorCode(4201),
        Fault::ForNesting => ErrorCode(4202),
        Fault::BreakWithoutFor => ErrorCode(4203),
        Fault::NoRet => ErrorCode(4211),
        Fault::RetInMain => ErrorCode(4212),
        Fault::CallNesting => ErrorCode(4213),
        Fault::NoIret => ErrorCode(4221),
        Fault::IretInMain => ErrorCode(4223),
        Fault::NoProgram => NO_PROGRAM,
        Fault::PointerTwice => ErrorCode(4021),
        Fault::Watchdog => WDT,
        Fault::ScanOverrun => PRG_TIME_OVER,
        Fault::Battery => BATTERY,
        Fault::Annunciator => ANNUNCIATOR,
        Fault::Family(c) => c,
    }
}

/// The CPU's message for error `code`.
pub fn message(code: ErrorCode) -> &'static str {
    match code.0 {
        1600 => "BATTERY ERROR: battery-backed data lost (damaged state file)",
        2110 => {
            "SP.UNIT ERROR: buffer memory of a slot with no intelligent function module accessed"
        }
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
        5010 => "PRG.TIME OVER: scan time exceeded the constant scan",
        9000 => "F****: annunciator ON",
        _ => "error",
    }
}

/// Operation errors (41xx) follow the "operation error" parameter; BATTERY
/// ERROR, PRG.TIME OVER and annunciators keep the CPU running; everything
/// else stops it.
pub fn severity(code: ErrorCode) -> Severity {
    match code.0 {
        4100..=4199 => Severity::Operation,
        1600 | 5010 | 9000 => Severity::Continue,
        _ => Severity::Stop,
    }
}
