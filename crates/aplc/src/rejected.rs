//! Mnemonics of seed 002 that softplc does not run: each one a
//! `Def::rejected` with its reason, so that nothing is silently ignored.
//! Those APLC-TCP lacks (spec aplc.md §11 D6-D7) are load errors for good;
//! the others are not implemented yet in softplc.

use softplc_lang::isa::Def;

const NOT_YET: &str = "not implemented yet in softplc (issue #13)";
const CLOCK: &str = "not available on APLC-TCP: no real-time clock; the clock and date/time-compare instructions are unsupported (table 1-1 L682-683, decision D6)";
const HSIO: &str =
    "not available on APLC-TCP: no high-speed I/O (table 1-1 L686, L10062, decision D7)";
const VRRD: &str = "not available on APLC-TCP: no analog potentiometer (L677, L878, decision D7)";
const NONE: &str =
    "not available on APLC-TCP: the manual defines no body for it (\"无\", decision D7)";

pub static DEFS: &[Def] = &[
    Def::rejected("MODBUS", NOT_YET).no_pulse(),
    Def::rejected("EVFWD", NOT_YET).no_pulse(),
    Def::rejected("EVREV", NOT_YET).no_pulse(),
    Def::rejected("EVDFWD", NOT_YET).no_pulse(),
    Def::rejected("EVDREV", NOT_YET).no_pulse(),
    Def::rejected("EVSTOP", NOT_YET).no_pulse(),
    Def::rejected("EVFRQ", NOT_YET).no_pulse(),
    Def::rejected("EVWRT", NOT_YET).no_pulse(),
    Def::rejected("EVRDST", NOT_YET).no_pulse(),
    Def::rejected("EVDRST", NOT_YET).no_pulse(),
    Def::rejected("EVRD", NOT_YET).no_pulse(),
    Def::rejected("XMT", NOT_YET).no_pulse(),
    Def::rejected("RCV", NOT_YET).no_pulse(),
    Def::rejected("TRD", CLOCK).no_pulse(),
    Def::rejected("TWR", CLOCK).no_pulse(),
    Def::rejected("TADD", CLOCK).no_pulse(),
    Def::rejected("TSUB", CLOCK).no_pulse(),
    Def::rejected("HOUR", CLOCK).no_pulse(),
    Def::rejected("HOURL", CLOCK).no_pulse(),
    Def::rejected("DCMP=", CLOCK).no_pulse(),
    Def::rejected("DCMP<>", CLOCK).no_pulse(),
    Def::rejected("DCMP>", CLOCK).no_pulse(),
    Def::rejected("DCMP<", CLOCK).no_pulse(),
    Def::rejected("DCMP>=", CLOCK).no_pulse(),
    Def::rejected("DCMP<=", CLOCK).no_pulse(),
    Def::rejected("TCMP=", CLOCK).no_pulse(),
    Def::rejected("TCMP<>", CLOCK).no_pulse(),
    Def::rejected("TCMP>", CLOCK).no_pulse(),
    Def::rejected("TCMP<", CLOCK).no_pulse(),
    Def::rejected("TCMP>=", CLOCK).no_pulse(),
    Def::rejected("TCMP<=", CLOCK).no_pulse(),
    Def::rejected("HCNT", HSIO).no_pulse(),
    Def::rejected("DHSCS", HSIO).no_pulse(),
    Def::rejected("DHSCI", HSIO).no_pulse(),
    Def::rejected("DHSCR", HSIO).no_pulse(),
    Def::rejected("DHSZ", HSIO).no_pulse(),
    Def::rejected("DHST", HSIO).no_pulse(),
    Def::rejected("DHSP", HSIO).no_pulse(),
    Def::rejected("SPD", HSIO).no_pulse(),
    Def::rejected("PLSY", HSIO).no_pulse(),
    Def::rejected("PLSR", HSIO).no_pulse(),
    Def::rejected("PLS", HSIO).no_pulse(),
    Def::rejected("PLSB", HSIO).no_pulse(),
    Def::rejected("PWM", HSIO).no_pulse(),
    Def::rejected("VRRD", VRRD).no_pulse(),
    Def::rejected("ABSD", NONE).no_pulse(),
    Def::rejected("DABSD", NONE).no_pulse(),
    Def::rejected("ALT", NONE).no_pulse(),
    Def::rejected("MODRW", NONE).no_pulse(),
    Def::rejected("CMP", NONE).no_pulse(),
    Def::rejected("LCMP", NONE).no_pulse(),
    Def::rejected("RCMP", NONE).no_pulse(),
    Def::rejected("PR", NONE).no_pulse(),
];
