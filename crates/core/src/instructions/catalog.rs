//! The instruction catalogue: which mnemonics exist, which softplc implements, and
//! how many steps each takes. COMPATIBILITY.md is the human-readable form of this.

use crate::program::ops::{ArithOp, Num};
use crate::program::Token;

/// Application instructions compiled by [`crate::program::compile`]; each also
/// has a pulse form with a trailing `P`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum App {
    Mov(Num),
    Arith(ArithOp, Num),
    Step(Num, i32),
    Flt(Num),
    Int(Num),
}

/// Looks up an implemented application instruction (without its `P` suffix).
pub fn application(m: &str) -> Option<App> {
    use ArithOp::*;
    use Num::*;
    Some(match m {
        "MOV" => App::Mov(I16),
        "DMOV" => App::Mov(I32),
        "EMOV" => App::Mov(F32),
        "+" => App::Arith(Add, I16),
        "-" => App::Arith(Sub, I16),
        "*" => App::Arith(Mul, I16),
        "/" => App::Arith(Div, I16),
        "D+" => App::Arith(Add, I32),
        "D-" => App::Arith(Sub, I32),
        "D*" => App::Arith(Mul, I32),
        "D/" => App::Arith(Div, I32),
        "E+" => App::Arith(Add, F32),
        "E-" => App::Arith(Sub, F32),
        "E*" => App::Arith(Mul, F32),
        "E/" => App::Arith(Div, F32),
        "INC" => App::Step(I16, 1),
        "DEC" => App::Step(I16, -1),
        "DINC" => App::Step(I32, 1),
        "DDEC" => App::Step(I32, -1),
        "FLT" => App::Flt(I16),
        "DFLT" => App::Flt(I32),
        "INT" => App::Int(I16),
        "DINT" => App::Int(I32),
        _ => return None,
    })
}

/// MELSEC-Q instructions that softplc knows of but does not implement yet: they are
/// rejected as "unsupported" rather than "unknown".
const KNOWN: &[&str] = &[
    // sequence / program control not yet implemented
    "IRET",
    "EI",
    "DI",
    "IMASK",
    "FCALL",
    "ECALL",
    "EFCALL",
    "XCALL",
    "COM",
    "PSCAN",
    "PSTOP",
    "POFF",
    "PLOW",
    "SFT",
    "SFTP",
    "ZPUSH",
    "ZPOP",
    "CHK",
    "CHKEND",
    "CHKST",
    "CHKCIR",
    "CHKEND",
    "QDRSET",
    "RSET",
    "PLOAD",
    "PUNLOAD",
    "PSWAP",
    "TIMCHK",
    "STMR",
    "ROTC",
    "RAMP",
    "SPD",
    "PLSY",
    "PWM",
    "MTR",
    "UDCNT1",
    "UDCNT2",
    "TTMR",
    "IX",
    "IXEND",
    "IXDEV",
    "IXSET",
    // comparison / arithmetic / conversion
    "BKCMP=",
    "BKCMP<>",
    "BKCMP>",
    "BKCMP<=",
    "BKCMP<",
    "BKCMP>=",
    "DBKCMP=",
    "CMP",
    "DCMP",
    "ECMP",
    "ZCP",
    "DZCP",
    "B+",
    "B-",
    "B*",
    "B/",
    "DB+",
    "DB-",
    "DB*",
    "DB/",
    "$+",
    "BK+",
    "BK-",
    "BCD",
    "DBCD",
    "BIN",
    "DBIN",
    "DBL",
    "WORD",
    "GRY",
    "DGRY",
    "GBIN",
    "DGBIN",
    "NEG",
    "DNEG",
    "ENEG",
    "BKBCD",
    "BKBIN",
    "ESTR",
    "EVAL",
    "STR",
    "DSTR",
    "VAL",
    "DVAL",
    "ASC",
    "HEX",
    "DABIN",
    "DDABIN",
    "BINDA",
    "DBINDA",
    "BINHA",
    "DBINHA",
    "BCDDA",
    "DBCDDA",
    "DABCD",
    "DDABCD",
    "HABIN",
    "DHABIN",
    "RAD",
    "DEG",
    "LEN",
    "RIGHT",
    "LEFT",
    "MIDR",
    "MIDW",
    "INSTR",
    "EMOD",
    "EREXP",
    "STRINS",
    "STRDEL",
    // transfer / logic / rotation
    "CML",
    "DCML",
    "BMOV",
    "FMOV",
    "DFMOV",
    "XCH",
    "DXCH",
    "BXCH",
    "SWAP",
    "$MOV",
    "WAND",
    "DAND",
    "WOR",
    "DOR",
    "WXOR",
    "DXOR",
    "WXNR",
    "DXNR",
    "BKAND",
    "BKOR",
    "BKXOR",
    "BKXNR",
    "BSET",
    "BRST",
    "TEST",
    "DTEST",
    "BKRST",
    "ROR",
    "ROL",
    "RCR",
    "RCL",
    "DROR",
    "DROL",
    "DRCR",
    "DRCL",
    "SFR",
    "SFL",
    "BSFR",
    "BSFL",
    "DSFR",
    "DSFL",
    "ZRST",
    // data processing / tables
    "SER",
    "DSER",
    "SUM",
    "DSUM",
    "DECO",
    "ENCO",
    "SEG",
    "DIS",
    "UNI",
    "NDIS",
    "NUNI",
    "WTOB",
    "BTOW",
    "MAX",
    "MIN",
    "DMAX",
    "DMIN",
    "SORT",
    "DSORT",
    "WSUM",
    "DWSUM",
    "MEAN",
    "DMEAN",
    "FIFW",
    "FIFR",
    "FPOP",
    "FINS",
    "FDEL",
    "LIMIT",
    "DLIMIT",
    "BAND",
    "DBAND",
    "ZONE",
    "DZONE",
    "RND",
    "SRND",
    "BSQR",
    "BDSQR",
    "BSIN",
    "BCOS",
    "BTAN",
    "BASIN",
    "BACOS",
    "BATAN",
    // float functions
    "SIN",
    "COS",
    "TAN",
    "ASIN",
    "ACOS",
    "ATAN",
    "SQR",
    "EXP",
    "LOG",
    "ESQR",
    "POW",
    "LOG10",
    // clock
    "DATERD",
    "DATEWR",
    "DATE+",
    "DATE-",
    "SECOND",
    "DSECOND",
    "HOUR",
    "DHOUR",
    // modules / networks
    "FROM",
    "DFRO",
    "TO",
    "DTO",
    "READ",
    "SREAD",
    "WRITE",
    "SWRITE",
    "SEND",
    "RECV",
    "REQ",
    "ZNFR",
    "ZNTO",
    "RFRP",
    "RTOP",
    "PR",
    "PRC",
    "LED",
    "LEDC",
    "PRN",
    "COMRD",
    "PKEY",
    "MSG",
    "UNIRD",
    "TYPERD",
    "RTWRITE",
    "ZRRDB",
    "ZRWRB",
    "ADRSET",
    "KEY",
    "FWRITE",
    "FREAD",
    "S.TO",
    "S.FROM",
    // PID and process control (their own issues)
    "PIDINIT",
    "PIDCONT",
    "PIDSTOP",
    "PIDRUN",
    "PIDPRMW",
    "S.PIDINIT",
    "S.PIDCONT",
    "S.PIDSTOP",
    "S.PIDRUN",
    "S.PIDPRMW",
    "PID57",
    "S.IN",
    "S.OUT1",
    "S.OUT2",
    "S.PID",
    "S.2PID",
    "S.AT1",
];

/// Instructions that talk to intelligent function modules or networks.
const NEEDS_MODULE: &[&str] = &[
    "FROM", "DFRO", "TO", "DTO", "READ", "SREAD", "WRITE", "SWRITE", "SEND", "RECV", "REQ", "ZNFR",
    "ZNTO", "RFRP", "RTOP", "PR", "PRC", "PRN", "UNIRD", "TYPERD", "RTWRITE", "S.TO", "S.FROM",
    "PID57",
];

/// Why a known instruction is rejected, for the "unsupported instruction" message.
pub fn unsupported_reason(m: &str) -> &'static str {
    let base = m
        .strip_suffix('P')
        .filter(|b| KNOWN.contains(b))
        .unwrap_or(m);
    if NEEDS_MODULE.contains(&base) {
        return "it needs an intelligent function module or network, which softplc does not simulate";
    }
    match base {
        "CMP" | "DCMP" | "ECMP" | "ZCP" | "DZCP" => {
            "not a MELSEC-Q instruction (FX series); use the comparison contacts or BKCMP"
        }
        "MEAN" | "DMEAN" | "DFMOV" | "POW" | "LOG10" | "STRINS" | "STRDEL" | "EMOD" | "EREXP"
        | "ESQR" | "DSECOND" | "DHOUR" => {
            "not in the QnH instruction set (Universal model QnU or later)"
        }
        "FCALL" | "ECALL" | "EFCALL" | "XCALL" => {
            "subroutine calls with arguments or into another file's local pointers are not implemented; use CALL with a common pointer"
        }
        "COM" => "refresh during the scan (COM) is not implemented",
        "QDRSET" => "softplc has a single file-register file; select blocks with RSET",
        "PLOAD" | "PUNLOAD" | "PSWAP" | "FWRITE" | "FREAD" => {
            "program and data files on memory cards are not modelled"
        }
        "SPD" | "PLSY" | "PWM" | "MTR" | "UDCNT1" | "UDCNT2" | "TTMR" => {
            "it needs input/output hardware timing (pulse output, high-speed counting, matrix input)"
        }
        "LED" | "LEDC" | "PKEY" | "KEY" | "MSG" => {
            "it needs the CPU's display or a peripheral keyboard, which softplc does not model"
        }
        "COMRD" => "device comments are not loaded",
        "S.IN" | "S.OUT1" | "S.OUT2" | "S.PID" | "S.2PID" | "S.AT1" => {
            "process-control instructions (QnPH) are not implemented yet"
        }
        _ => "not implemented yet; see COMPATIBILITY.md",
    }
}

/// True when the mnemonic is a MELSEC-Q instruction (implemented or not), with or
/// without its pulse suffix, or a string/float comparison contact.
pub fn is_known(m: &str) -> bool {
    let base = |s: &str| KNOWN.contains(&s) || application(s).is_some();
    base(m)
        || m.strip_suffix('P').is_some_and(base)
        || ["LD$", "AND$", "OR$"].iter().any(|p| m.starts_with(p))
        || m.strip_prefix("SP.")
            .is_some_and(|r| base(&format!("S.{r}")))
}

/// Steps an instruction occupies, as the CPU counts them for error reports.
///
/// Decision: a list file carries no step numbers, so they are counted with the
/// QnH rule of thumb: contacts, coils and stack instructions 1 step, plus 1 for an
/// index-modified, digit-specified or word-bit operand; OUT T/C 4; PLS/PLF/FF, MC,
/// SET/RST of words or timers 2; every other instruction 1 + its operand count.
/// A GX Works2 CSV export gives exact numbers, which are used instead.
pub fn steps(m: &str, operands: &[Token]) -> u32 {
    let extended = |t: &Token| {
        let u = t.text.to_ascii_uppercase();
        u.contains('.') && !u.starts_with('E')
            || u.starts_with('K') && u.len() > 2 && u.as_bytes()[2].is_ascii_alphabetic()
            || u.chars().skip(1).any(|c| c == 'Z') && !u.starts_with("ZR")
    };
    let simple = 1 + operands.iter().filter(|t| extended(t)).count() as u32;
    match m {
        "LD" | "LDI" | "AND" | "ANI" | "OR" | "ORI" | "LDP" | "LDF" | "ANDP" | "ANDF" | "ORP"
        | "ORF" | "ANB" | "ORB" | "MPS" | "MRD" | "MPP" | "INV" | "MEP" | "MEF" | "EGP" | "EGF"
        | "NOP" | "END" | "FEND" | "MCR" | "NEXT" | "RET" | "STOP" => simple,
        "OUT" | "OUTH" if operands.len() == 2 => 4,
        "OUT" | "SET" => simple,
        "RST" => {
            let u = operands
                .first()
                .map(|t| t.text.to_ascii_uppercase())
                .unwrap_or_default();
            if u.starts_with('T')
                || u.starts_with('C')
                || u.starts_with("ST")
                || u.starts_with('D')
                || u.starts_with('W')
                || u.starts_with('R')
            {
                2
            } else {
                simple
            }
        }
        "PLS" | "PLF" | "FF" | "MC" => 2,
        _ => 1 + operands.len() as u32,
    }
}
