//! Mnemonics of seed 002 that softplc does not run: each one a
//! `Def::rejected` with its reason, so that nothing is silently ignored.
//! Those APLC-TCP lacks (spec aplc.md §11 D6-D7) are load errors for good;
//! the others are not implemented yet in softplc.

use softplc_lang::isa::Def;

const INVERTER: &str = "not available in softplc: the manual names the inverter action but not the register or value the inverter receives for it (APLC programming manual §6.12.2-§6.12.10 and Appendix 5 give no register map, and no public Modbus register map of the EV-series drives it names could be found); use `Modbus` or `EVWRT` with the drive's own register map";
const CLOCK: &str = "not available on APLC-TCP: no real-time clock; the clock and date/time-compare instructions are unsupported (APLC programming manual table 1-1, §1.1.1)";
const HSIO: &str =
    "not available on APLC-TCP: no high-speed I/O (APLC programming manual table 1-1, §1.1.1, and chapter 8)";
const VRRD: &str =
    "not available on APLC-TCP: no analog potentiometer (APLC programming manual §1.1.1, §2.1.1)";
const NONE: &str =
    "not available on APLC-TCP: the manual defines no body for it (\"无\", decision D7)";

pub static DEFS: &[Def] = &[
    Def::rejected("EVFWD", INVERTER).no_pulse(),
    Def::rejected("EVREV", INVERTER).no_pulse(),
    Def::rejected("EVDFWD", INVERTER).no_pulse(),
    Def::rejected("EVDREV", INVERTER).no_pulse(),
    Def::rejected("EVSTOP", INVERTER).no_pulse(),
    Def::rejected("EVFRQ", INVERTER).no_pulse(),
    Def::rejected("EVRDST", INVERTER).no_pulse(),
    Def::rejected("EVDRST", INVERTER).no_pulse(),
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
