//! Every load diagnostic names file:line:column and the token (contract
//! §1.1, §2).

mod common;
use common::errors;

fn one(src: &str, want: &str) {
    let e = errors(src);
    assert!(e.contains(want), "expected `{want}` in:\n{e}");
}

#[test]
fn devices() {
    one("LD X8\nOUT Y0\n", "t.apl:1:4: `X8`: X is numbered in octal");
    one(
        "LD X0\nOUT Y18\n",
        "t.apl:2:5: `Y18`: Y is numbered in octal",
    );
    one(
        "LD X200\nOUT Y0\n",
        "t.apl:1:4: `X200` is out of range (X0-X177)",
    );
    one("LD M0\nOUT D8000\n", "`D8000` is out of range (D0-D7999)");
    // The manual's typo `LD SMO` (L3657) is not a device.
    one(
        "LD SMO\nOUT Y0\n",
        "t.apl:1:4: `SMO` is not a device, constant or variable",
    );
    one(
        "LD M0\nOUT X0\n",
        "t.apl:2:5: `X0` cannot be written by this instruction (X is read-only, APLC programming manual §3.1.3)",
    );
    one(
        "LD M0\nMOV 10 X0\n",
        "t.apl:2:8: `X0` is a bit device; a word operand needs a bit group",
    );
    one("LD M0\nOUT SM0\n", "`SM0` is a read-only special relay");
    one("LD D0Z1\nOUT Y0\n", "`D0Z1` is a word device");
    one(
        "LD M0Z1\nOUT Y0\n",
        "`M0Z1`: this operand cannot be indexed",
    );
    one(
        "LD M0\nMOV K5M0 D0\n",
        "`K5M0`: a 16-bit operand takes K1-K4",
    );
    one(
        "LD M0\nDMOV K4M0 D0\n",
        "`K4M0`: a 32-bit operand takes K5-K8",
    );
    one(
        "LD M0\nMOV C200 D0\n",
        "`C200`: C200-C255 are 32-bit counters",
    );
    one(
        "LD M0\nDMOV D0 D7999\n",
        "`D7999`: a 32-bit operand needs D8000 too",
    );
    one("LD M0\nCTU C200 5\n", "`C200`: CTU counts C0-C199");
    one("LD M0\nMOV K1X0 K1X0\n", "`K1X0` cannot be a destination");
    one("LD M0\nMOV 1 SD20\n", "`SD20` cannot be a destination here");
}

#[test]
fn constants() {
    one(
        "LD M0\nMOV 65536 D0\n",
        "t.apl:2:5: constant `65536` does not fit a 16-bit operand (-32768..65535)",
    );
    one(
        "LD M0\nMOV -32769 D0\n",
        "constant `-32769` does not fit a 16-bit operand",
    );
    one(
        "LD M0\nDMOV 4294967296 D0\n",
        "constant `4294967296` does not fit a 32-bit operand",
    );
    one(
        "LD M0\nMOV 16#10000 D0\n",
        "constant `16#10000` does not fit a 16-bit operand",
    );
    one(
        "LD M0\nMOV 8#78 D0\n",
        "`8#78`: bad digit in a octal constant",
    );
    one(
        "LD M0\nMOV 2#102 D0\n",
        "`2#102`: bad digit in a binary constant",
    );
    one(
        "LD M0\nMOV 1.5 D0\n",
        "REAL constant `1.5` where an integer operand is needed",
    );
    one("LD M0\nRMOV 1E39 D0\n", "REAL constant `1E39` is outside");
    one("LD M0\nMOV 1 2\n", "constant `2` cannot be a destination");
    one(
        "LD 1\nOUT Y0\n",
        "constant `1` where the operand table lists none",
    );
    one("LD M0\nMOV K10 D0\n", "`K10`");
}

#[test]
fn instructions() {
    one(
        "LD M0\nTRD D0\n",
        "t.apl:2:1: unsupported instruction `TRD`: not available on APLC-TCP: no real-time clock",
    );
    one(
        "LD M0\nDCMP= D0 D10 M0\n",
        "unsupported instruction `DCMP=`: not available on APLC-TCP",
    );
    one(
        "LD M0\nHCNT C236 100\n",
        "unsupported instruction `HCNT`: not available on APLC-TCP: no high-speed I/O",
    );
    one("LD M0\nVRRD 0 D0\n", "no analog potentiometer");
    one("LD M0\nALT M1\n", "the manual defines no body for it");
    one(
        "LD M0\nEROMWR D5999 16\n",
        "t.apl:2:8: `D5999`: EROMWR writes from D6000-D6999, without index",
    );
    one(
        "LD M0\nModbus 0 D0 D100\n",
        "t.apl:2:8: channel 0 is PORT0, the USB programming port",
    );
    one(
        "LD M0\nEV RD 2 1 1 D0\n",
        "the inverter instructions use channel 1 (PORT1) only",
    );
    one(
        "LD M0\nMOVP 1 D0\n",
        "t.apl:2:1: unknown instruction `MOVP`",
    );
    one("LD M0\nOUT Y0\nEND\n", "the APLC has no END");
    one("LD M0\nMOV 1\n", "`MOV` takes 2 operands, found 1");
}

#[test]
fn ladder_structure() {
    one(
        "LD M0\nLD M1\nANB M2\nOUT Y0\n",
        "t.apl:3:5: `ANB` takes no operand",
    );
    one(
        "LD M0\nMPS\nMPS\nMPS\nMPS\nMPS\nMPS\nMPS\nMPS\nMPS\nOUT Y0\n",
        "t.apl:10:1: more than 8 MPS without MPP",
    );
    one("LD M0\nCJ 5\n", "t.apl:2:4: CJ 5: no LBL 5 in this POU");
    one(
        "LBL 1\nLD M0\nOUT Y0\nLBL 1\n",
        "t.apl:4:5: LBL 1 defined twice",
    );
    one("LD M0\nCJ 128\n", "`128`: a constant 0-127 is needed here");
    one("LD M0\nMC 0\nLD M1\nOUT Y0\n", "MC 0 without MCR 0");
    one("LD M0\nMC 8\n", "`8`: a constant 0-7 is needed here");
    one("LD M0\nMC 1\nLD M1\nMC 1\n", "MC 1 is already open");
    one(
        "LD M0\nAND M1\n",
        "the last contacts of the POU lead to no output",
    );
    one("OUT Y0\n", "`OUT` needs a preceding LD");
    one(
        "LD M0\nFOR 3\nLD M1\nOUT Y0\n",
        "t.apl:2:1: FOR without its NEXT in this POU",
    );
    one("LD M0\nOUT Y0\nNEXT\n", "t.apl:3:1: NEXT without FOR");
}

#[test]
fn pous_and_variables() {
    one(
        "LD M0\nPOU MAIN\nOUT Y0\n",
        "t.apl:1:1: `LD` before the first POU header",
    );
    one(
        "POU MAIN\nLD M0\nOUT Y0\nPOU MAIN\n",
        "t.apl:4:5: POU `MAIN` defined twice",
    );
    one("POU SBR_1\nLD M0\nOUT Y0\n", "has no `POU MAIN`");
    one(
        "POU SBR_64\nPOU MAIN\nLD M0\nOUT Y0\n",
        "`SBR_64`: subroutines are SBR_0-SBR_63",
    );
    one(
        "POU MAIN\nLD M0\nOUT Y0\nPOU INT_1 EVENT 8\n",
        "t.apl:4:17: event `8`: events 8 and 9 are reserved",
    );
    one(
        "POU MAIN\nLD M0\nOUT Y0\nPOU INT_1 EVENT 18\n",
        "not on APLC-TCP",
    );
    one("POU MAIN\nLD M0\nOUT Y0\nPOU INT_1\n", "needs `EVENT <e>`");
    one(
        "POU MAIN\nLD M0\nOUT Y0\nPOU INT_1 EVENT 3\nLD M0\nOUT Y1\nPOU INT_2 EVENT 13\n",
        "one edge per input",
    );
    one(
        "POU MAIN\nLD M0\nOUT Y0\nPOU INT_1 EVENT 26\nLD M0\nOUT Y1\nPOU INT_1 EVENT 27\n",
        "POU `INT_1` defined twice",
    );
    one(
        "POU MAIN\nVAR\n  A IN INT\nEND_VAR\nLD M0\nOUT Y0\n",
        "t.apl:3:5: `IN`: MAIN and interrupt routines declare TEMP only",
    );
    one(
        "POU MAIN\nVAR\n  V1 A TEMP INT\nEND_VAR\nLD M0\nOUT Y0\n",
        "`V1`: variables are allocated in table order; this one is V0",
    );
    one(
        "POU MAIN\nVAR\n  A TEMP CHAR\nEND_VAR\n",
        "`CHAR`: the type is BOOL",
    );
    one(
        "POU MAIN\nLD #X\nOUT Y0\n",
        "t.apl:2:4: `#X`: no local variable `X` in this POU",
    );
    one(
        "VAR_GLOBAL\n X8 Y0\nEND_VAR\nLD M0\nOUT Y0\n",
        "t.apl:2:2: variable name `X8`: it looks like a device",
    );
    one(
        "VAR_GLOBAL\n MOV Y0\nEND_VAR\nLD M0\nOUT Y0\n",
        "variable name `MOV`: it is a keyword, type name or mnemonic",
    );
    one(
        "VAR_GLOBAL\n ABCDEFGHI Y0\nEND_VAR\nLD M0\nOUT Y0\n",
        "at most 8 characters",
    );
    one(
        "VAR_GLOBAL\n A LM0\nEND_VAR\nLD M0\nOUT Y0\n",
        "`LM0`: LM and V are local, not global",
    );
    one(
        "VAR_GLOBAL\n A K4M0\nEND_VAR\nLD M0\nOUT Y0\n",
        "one device without K<n> or index",
    );
    one(
        "LD M0\nOUT Y0\nVAR_GLOBAL\nA M1\nEND_VAR\n",
        "VAR_GLOBAL must come before the first POU and instruction",
    );
    one(
        "LD M0 /* never closed\nOUT Y0\n",
        "t.apl:1:7: `/*`: block comment without `*/`",
    );
}

/// Manual listings load (contract §1.1: L2185-2208, L3655-3662 with SM0,
/// L7761-7797, L7862-7882).
#[test]
fn manual_listings_load() {
    let pid = "LD      SM1           //初始化程序只需运行一次\nMOV     1000    D500   //设定目标值\n\
MOV     500     D510   //采样时间 (Ts) 范围为 1~32767 (ms) 但比运算周期\n                        //短的时间数值无法执行\n\
MOV     7       D511   //动作方向\nMOV     70     D512\nMOV     100    D513\nMOV    25      D514\nMOV    0        D515\n\
MOV    63      D516\nFMOV    0        D517      8  //清除 PID 运算中间数据存储区\nMOV    2000     D525\nMOV    2000     D526\n\
MOV    2000     D527\nMOV    2000     D528\n//PID 指令执行运算\nLD      M0\nFROM    0    5    D501      1\n\
PID      D500 D501 D510 D502  //PID 指令: PID S1 S2 S3 D\nTO      0    8    D502      1\n";
    softplc_aplc::load_bytes("pid.apl", pid.as_bytes()).unwrap();
    let ramp = "LD      SM1\nMOV     0 D0\nMOV     2000 D1\nLD      X0\nRAMP D0 D1 D10 1000 M0\nLD X1\nTO 0 6 D10 1\n";
    softplc_aplc::load_bytes("ramp.apl", ramp.as_bytes()).unwrap();
    let cj = "LD M0\nCJ 0\nLD SM0\nMOV 100 D0\nCFEND\nLBL 0\nLD M1\nMOV 200 D0\n";
    softplc_aplc::load_bytes("cj.apl", cj.as_bytes()).unwrap();
}

/// A listing that is not a program: nothing panics on junk.
#[test]
fn junk_does_not_panic() {
    for src in [
        "\u{0}\u{1}",
        "LD",
        "POU",
        "VAR\nVAR\n",
        "END_VAR",
        "LD>= ",
        "LDR < >",
        "#",
        "K9M0",
        "CJ",
        "POU INT_ EVENT x",
        "LD K1X0Z99",
    ] {
        let _ = softplc_aplc::load_bytes("j.apl", src.as_bytes());
    }
    let _ = softplc_aplc::load_bytes("j.apl", &[0xff, 0xfe, 0x00, 0x80]);
}
