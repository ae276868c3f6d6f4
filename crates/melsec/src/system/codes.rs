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
/// SP.UNIT ERROR: a program's `U\\G` or FROM on its own CPU shared memory
/// (004 L8985-8998).
pub const OWN_SHARED: ErrorCode = ErrorCode(2114);
/// SP.UNIT ERROR: a write to another CPU's shared memory.
pub const OTHER_SHARED: ErrorCode = ErrorCode(2115);
/// SP.UNIT ERROR: a write to a module another CPU controls (004 L9199-9205).
pub const NOT_CONTROLLED: ErrorCode = ErrorCode(2116);
/// PARAMETER ERROR: the number of CPUs set is not the number installed
/// (004 L8411-8520).
pub const CPU_COUNT: ErrorCode = ErrorCode(3010);
/// PARAMETER ERROR: the multi-CPU parameters differ from CPU 1's.
pub const MULTI_CPU_PARAMETER: ErrorCode = ErrorCode(3012);
/// OPERATION ERROR: more than 32 inter-CPU instructions pending (004 L9020-9024).
pub const TOO_MANY_PENDING: ErrorCode = ErrorCode(4107);
/// MULTI CPU DOWN: another CPU's stop error stops this one (004 L8521-8598).
pub const MULTI_CPU_DOWN: ErrorCode = ErrorCode(7000);
/// MULTI EXE. ERROR: another CPU stopped; this one goes on.
pub const MULTI_EXE: ErrorCode = ErrorCode(7010);
/// OPERATION ERROR: data the instruction cannot process.
pub const OPERATION: ErrorCode = ErrorCode(4100);
/// OPERATION ERROR: device range exceeded.
pub const RANGE: ErrorCode = ErrorCode(4101);
/// WDT ERROR.
pub const WDT: ErrorCode = ErrorCode(5000);
/// PRG.TIME OVER: scan longer than the constant scan.
pub const PRG_TIME_OVER: ErrorCode = ErrorCode(5010);
/// PRG.TIME OVER: low-speed scan longer than the low-speed execution
/// monitor time (004 §4.2.3 (7), §7.19.2 factor 5).
pub const LOW_SPEED_TIME_OVER: ErrorCode = ErrorCode(5011);
/// F****: an annunciator turned ON.
pub const ANNUNCIATOR: ErrorCode = ErrorCode(9000);

/// The MELSEC number of `fault`.
pub fn code(fault: Fault) -> ErrorCode {
    match fault {
        Fault::Operation => OPERATION,
        Fault::Range => RANGE,
        Fault::NoModule { .. } => SP_UNIT,
        Fault::OwnSharedMemory { .. } => OWN_SHARED,
        Fault::OtherSharedMemory { .. } => OTHER_SHARED,
        Fault::NotControlled { .. } => NOT_CONTROLLED,
        Fault::TooManyPending => TOO_MANY_PENDING,
        Fault::MultiCpuDown => MULTI_CPU_DOWN,
        Fault::MultiCpuError => MULTI_EXE,
        Fault::CpuCount => CPU_COUNT,
        Fault::MultiCpuParameter => MULTI_CPU_PARAMETER,
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
        Fault::LowSpeedOverrun => LOW_SPEED_TIME_OVER,
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
        2114 => "SP.UNIT ERROR: the program accessed its own CPU shared memory as another CPU's",
        2115 => "SP.UNIT ERROR: the program wrote another CPU's shared memory",
        2116 => "SP.UNIT ERROR: the program wrote to a module another CPU controls",
        3010 => "PARAMETER ERROR: the number of CPUs set differs from the CPUs installed",
        3012 => "PARAMETER ERROR: the multi-CPU parameters differ from CPU 1's",
        4107 => "OPERATION ERROR: more than 32 inter-CPU instructions pending",
        7000 => "MULTI CPU DOWN: another CPU's stop error stopped this CPU",
        7010 => "MULTI EXE. ERROR: another CPU stopped with an error",
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
        5011 => "PRG.TIME OVER: low-speed scan time exceeded the low-speed execution monitor time",
        9000 => "F****: annunciator ON",
        _ => "error",
    }
}

/// What an error does (004 §7.15 (3), L4911-4922, and the self-diagnostics
/// list L4932-4995): operation errors (41xx) follow the "operation error"
/// parameter, SP.UNIT ERROR (21xx) the "intelligent module program
/// execution error" parameter, FILE OPE. ERROR (24xx) the "file access
/// error" parameter (L4957); BATTERY ERROR, PRG.TIME OVER, MULTI EXE.
/// ERROR and annunciators keep the CPU running; everything else stops it.
pub fn severity(code: ErrorCode) -> Severity {
    match code.0 {
        4100..=4199 => Severity::Operation,
        2110..=2119 => Severity::ModuleAccess,
        2410..=2419 => Severity::FileAccess,
        1600 | 5010 | 5011 | 7010 | 9000 => Severity::Continue,
        _ => Severity::Stop,
    }
}

/// The kinds of common error information SD5-SD15 holds, numbered as SD4's
/// low byte (004 App. 2 SD4, L10153-10180).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Common {
    None = 0,
    /// Slot (or CPU) number and I/O number.
    Module = 1,
    /// Drive and file name.
    File = 2,
    /// The time set.
    Time = 3,
    /// Program file name and step.
    Program = 4,
}

/// The kinds of individual error information SD16-SD26 holds, numbered as
/// SD4's high byte (L10153-10180). Parameter numbers (5) and CHK failure
/// numbers (7) are not listed: softplc raises no error that carries one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Individual {
    None = 0,
    /// The time measured.
    Time = 3,
    /// Program file name and step.
    Program = 4,
    /// The annunciator number.
    Annunciator = 6,
}

/// The information an error with `code` carries, one table for every error
/// softplc raises (App. 2 SD4-SD26 describe the layouts; which error
/// carries which follows the QCPU error-code list):
/// - SP.UNIT ERROR names the module (its slot and I/O number) and the
///   program location of the access;
/// - PARAMETER ERROR the parameter file (drive 0, PARAM.QPA);
/// - WDT ERROR and PRG.TIME OVER the time set and the time measured;
/// - an annunciator its number (the instruction location is not recorded);
/// - MULTI CPU DOWN / MULTI EXE. ERROR the CPU that caused it (SD5 its
///   number, SD6 its I/O number, App. 2 SD5 *1);
/// - BATTERY ERROR nothing (softplc's battery is a state directory, no
///   drive);
/// - every other error the program location where an instruction raised it.
pub fn information(code: ErrorCode) -> (Common, Individual) {
    match code.0 {
        2110..=2119 => (Common::Module, Individual::Program),
        3000..=3999 => (Common::File, Individual::None),
        5000 | 5001 | 5010 | 5011 => (Common::Time, Individual::Time),
        9000 => (Common::None, Individual::Annunciator),
        7000 | 7010 => (Common::Module, Individual::None),
        1600 => (Common::None, Individual::None),
        _ => (Common::Program, Individual::None),
    }
}

/// The LED display cause number of error `code` (004 §7.19.2, L5392-5406):
/// 2 SP.UNIT ERROR, 3 OPERATION ERROR, 4 FILE OPE. ERROR, 5 PRG.TIME OVER,
/// 6 CHK, 7 annunciator, 9 BATTERY ERROR; `None` for a cause the table
/// does not list (stop errors always show).
pub fn led_cause(code: ErrorCode) -> Option<u8> {
    Some(match code.0 {
        2110..=2119 => 2,
        4100..=4199 => 3,
        2410..=2419 => 4,
        5010 | 5011 => 5,
        9010 => 6,
        9000 => 7,
        1600 => 9,
        _ => return None,
    })
}
