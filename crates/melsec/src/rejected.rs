//! MELSEC-Q instructions softplc knows of but rejects at load, each with the
//! reason the "unsupported instruction" diagnostic gives (COMPATIBILITY.md
//! "Rejected at load" is generated from this list). A mnemonic in no list is
//! an "unknown instruction".

use softplc_lang::isa::{Def, Pulse};

const MODULE: &str =
    "it needs an intelligent function module or network, which softplc does not simulate";
const HARDWARE: &str =
    "it needs input/output hardware timing (pulse output, high-speed counting, matrix input)";
const DISPLAY: &str =
    "it needs the CPU's display or a peripheral keyboard, which softplc does not model";
const CARD: &str = "program and data files on memory cards are not modelled";
const XCALL: &str = "XCALL is not an instruction of the High Performance model QCPU: its \
                     manuals define CALL, FCALL, ECALL and EFCALL only";
const PROGRAM_FILES: &str =
    "PLOAD/PUNLOAD/PSWAP load program files from standard ROM or a memory card \
                     into program memory during RUN (and need the program table fixed in STOP); \
                     softplc has no drives, and a CPU's programs are fixed when it is built";
const CHK: &str = "CHKST/CHK/CHKCIR/CHKEND special-format failure checks work on the ladder \
                   pattern programmed around them (program structure)";
const IX: &str = "IX/IXEND index-modification blocks (the devices of the enclosed ladder would \
                  be modified by the offset table) are not implemented";
const IXDEV: &str = "IXDEV/IXSET build the IX/IXEND offset table from the devices of the ladder \
                     between them (program structure); IX/IXEND index-modification blocks are \
                     not supported";
const FX: &str = "not a MELSEC-Q instruction (FX series); use the comparison contacts or BKCMP";
const REFRESH: &str = "a partial refresh of I/O or network link devices during the scan is not \
                       implemented (the input refresh runs at scan start, DX reads a module \
                       at once, and COM refreshes every input)";
const DELTA: &str = "the pulse conversion of a direct output is not implemented; drive DY with \
                     OUT, SET, RST, PLS or PLF";
const MOTION: &str = "it needs a motion CPU, which softplc does not simulate (the motion \
                      instructions, S.DDWR/S.DDRD device access and S.GINT interrupt requests go \
                      from a QCPU to a motion CPU)";
const S_FROM: &str = "not a MELSEC-Q instruction: a QCPU reads another CPU's shared memory with \
                      FROM or U3E0\\G-U3E3\\G operands, and writes its own with S.TO";
const QNU: &str = "a Universal model (QnU) instruction softplc does not implement yet (it is \
                   not in the QnH instruction set)";

/// The rejected instructions.
pub static DEFS: &[Def] = &[
    Def::rejected("RFS", REFRESH),
    Def::rejected("ZCOM", REFRESH),
    Def::rejected("DELTA", DELTA),
    Def::rejected("READ", MODULE),
    Def::rejected("SREAD", MODULE),
    Def::rejected("WRITE", MODULE),
    Def::rejected("SWRITE", MODULE),
    Def::rejected("SEND", MODULE),
    Def::rejected("RECV", MODULE),
    Def::rejected("REQ", MODULE),
    Def::rejected("ZNFR", MODULE),
    Def::rejected("ZNTO", MODULE),
    Def::rejected("RFRP", MODULE),
    Def::rejected("RTOP", MODULE),
    Def::rejected("PR", MODULE),
    Def::rejected("PRC", MODULE),
    Def::rejected("PRN", MODULE),
    Def::rejected("UNIRD", MODULE),
    Def::rejected("TYPERD", MODULE),
    Def::rejected("RTWRITE", MODULE),
    Def::rejected("S.FROM", S_FROM).pulse(Pulse::SPrefix),
    Def::rejected("S.SFCS", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("S.SVST", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("S.CHGV", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("S.CHGT", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("S.CHGA", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("S.DDWR", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("S.DDRD", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("S.GINT", MOTION).pulse(Pulse::SPrefix),
    Def::rejected("SPD", HARDWARE),
    Def::rejected("PLSY", HARDWARE),
    Def::rejected("PWM", HARDWARE),
    Def::rejected("MTR", HARDWARE),
    Def::rejected("UDCNT1", HARDWARE),
    Def::rejected("UDCNT2", HARDWARE),
    Def::rejected("TTMR", HARDWARE),
    Def::rejected("LED", DISPLAY),
    Def::rejected("LEDC", DISPLAY),
    Def::rejected("PKEY", DISPLAY),
    Def::rejected("KEY", DISPLAY),
    Def::rejected("MSG", DISPLAY),
    Def::rejected("COMRD", "device comments are not loaded"),
    Def::rejected("PLOAD", PROGRAM_FILES),
    Def::rejected("PUNLOAD", PROGRAM_FILES),
    Def::rejected("PSWAP", PROGRAM_FILES),
    Def::rejected("FWRITE", CARD),
    Def::rejected("FREAD", CARD),
    Def::rejected(
        "QDRSET",
        "QDRSET selects the file-register file the programs use (QCPU manual §10.7.3 (1) (a)); softplc has one file-register file per project ([devices] file_register, file_register_name): select blocks with RSET",
    ),
    Def::rejected("XCALL", XCALL),
    Def::rejected(
        "ROTC",
        "rotary table shortest-direction control is not implemented: its counting and drive \
         rules are not in the manuals softplc follows, so it could not be reproduced faithfully",
    ),
    Def::rejected("CHKST", CHK),
    Def::rejected("CHK", CHK),
    Def::rejected("CHKCIR", CHK),
    Def::rejected("CHKEND", CHK),
    Def::rejected("IX", IX),
    Def::rejected("IXEND", IX),
    Def::rejected("IXDEV", IXDEV),
    Def::rejected("IXSET", IXDEV),
    Def::rejected(
        "ADRSET",
        "indirect addresses (ADRSET) are not modelled: devices have no memory addresses",
    ),
    Def::rejected("CMP", FX),
    Def::rejected("DCMP", FX),
    Def::rejected("ECMP", FX),
    Def::rejected("ZCP", FX),
    Def::rejected("DZCP", FX),
    Def::rejected(
        "ZRST",
        "`ZRST` is not a MELSEC-Q (QnH) instruction (it is an FX instruction); use BKRST",
    ),
    Def::rejected("MEAN", QNU),
    Def::rejected("DMEAN", QNU),
    Def::rejected("POW", QNU),
    Def::rejected("LOG10", QNU),
    Def::rejected("STRINS", QNU),
    Def::rejected("STRDEL", QNU),
    Def::rejected("EMOD", QNU),
    Def::rejected("EREXP", QNU),
    Def::rejected("ESQR", QNU),
    Def::rejected("DSECOND", QNU),
    Def::rejected("DHOUR", QNU),
];
