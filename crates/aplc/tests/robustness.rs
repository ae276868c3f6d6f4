//! No input panics: random programs over the APLC vocabulary load or give
//! diagnostics, and those that load run (property test, the stable-Rust
//! companion of `fuzz/fuzz_targets/run_apl.rs`).

mod common;
use proptest::prelude::*;

const MNEMONICS: &[&str] = &[
    "LD", "LDI", "AND", "ANI", "OR", "ORI", "OUT", "SET", "RST", "ANB", "ORB", "MPS", "MRD", "MPP",
    "EU", "ED", "INV", "MC", "MCR", "TON", "TONR", "TOF", "TMON", "CTU", "CTR", "DCNT", "CJ",
    "LBL", "CFEND", "FOR", "NEXT", "MOV", "DMOV", "RMOV", "BMOV", "FMOV", "ADD", "DIV", "DDIV",
    "INC", "LD>=", "ANDD<", "ORR<>", "ZRST", "SFTR", "WSFL", "PUSH", "FIFO", "RAMP", "TRIANGLE",
    "ROR", "RCL", "INT", "BCD", "SEG", "ITA", "ATI", "CRC16", "BLD", "BOUT", "DECO", "SUM", "STL",
    "RET", "CALL", "CSRET", "SBR_0", "POU", "VAR", "END_VAR",
];
const OPERANDS: &[&str] = &[
    "X0",
    "X17",
    "Y0",
    "M0",
    "M2047",
    "S20",
    "T0",
    "T252",
    "C0",
    "C200",
    "D0",
    "D7999",
    "D10Z1",
    "K4M0",
    "K8M0",
    "K1X0Z2",
    "Z1",
    "V0",
    "LM0",
    "SM0",
    "SD20",
    "0",
    "1",
    "-1",
    "32767",
    "65535",
    "16#FFFF",
    "2147483647",
    "1.5",
    "-3.4E38",
    "200",
    "7",
    "MAIN",
    "SBR_0",
    "#A",
    "EVENT",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]
    #[test]
    fn random_programs_never_panic(lines in proptest::collection::vec(
        (0..MNEMONICS.len(), proptest::collection::vec(0..OPERANDS.len(), 0..5)), 1..30)) {
        let mut src = String::new();
        for (m, ops) in lines {
            src += MNEMONICS[m];
            for o in ops {
                src.push(' ');
                src += OPERANDS[o];
            }
            src.push('\n');
        }
        if softplc_aplc::load_bytes("p.apl", src.as_bytes()).is_ok() {
            let mut p = common::plc(&src);
            p.set("Z1", "30000");
            p.scans(3);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]
    /// Rungs `LD <bit>` + one instruction with random operands: most load,
    /// and run with index registers and values pushed to extremes.
    #[test]
    fn random_rungs_run(rungs in proptest::collection::vec(
        (0..6usize, 0..MNEMONICS.len(), proptest::collection::vec(0..OPERANDS.len(), 0..5)), 1..20),
        z in -40000i32..40000) {
        // Keep the rungs that load on their own, so the program runs.
        let mut src = String::new();
        let mut kept = 0;
        for (b, m, ops) in rungs {
            let mut rung = format!("LD {}\n{}", ["SM0", "X0", "M0", "T0", "C0", "SM1"][b], MNEMONICS[m]);
            for o in ops {
                rung.push(' ');
                rung += OPERANDS[o];
            }
            rung.push('\n');
            if softplc_aplc::load_bytes("r.apl", rung.as_bytes()).is_ok() {
                src += &rung;
                kept += 1;
            }
        }
        if kept > 0 && softplc_aplc::load_bytes("p.apl", src.as_bytes()).is_ok() {
            let mut p = common::plc(&src);
            p.set("Z1", &(z as i16).to_string()).set("D0", &(z as i16).to_string()).set("X0", "1");
            p.scans(3);
        }
    }
}
