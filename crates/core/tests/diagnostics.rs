//! Load-time diagnostics: every error is reported as `line:col: message` at the
//! offending token, and the message names that token (contract §2). Positions
//! are worked out by hand from the source text (1-based character columns).

mod common;
use common::diagnostics;
use softplc_core::program::compile_il;

/// The single diagnostic of a program that must fail to load.
fn one(src: &str) -> String {
    let d = diagnostics(src);
    assert_eq!(d.len(), 1, "expected exactly one diagnostic, got {d:#?}");
    d.into_iter().next().unwrap()
}

/// Asserts the diagnostic is at `pos` ("line:col") and its message contains
/// every one of `parts`.
fn assert_diag(d: &str, pos: &str, parts: &[&str]) {
    let (at, msg) = d
        .split_once(": ")
        .unwrap_or_else(|| panic!("malformed diagnostic {d:?}"));
    assert_eq!(at, pos, "position of {d:?}");
    for p in parts {
        assert!(msg.contains(p), "{d:?} should mention {p:?}");
    }
}

fn loads(src: &str) {
    if let Err(d) = compile_il(
        "test.il",
        src,
        &softplc_core::profile::default_config().devices,
    ) {
        panic!("should load:\n{src}\n{d}");
    }
}

// ---------------------------------------------------------------- mnemonics

#[test]
fn unknown_instruction() {
    // `FOO` is the first token of line 1.
    let d = one("FOO X0\nEND\n");
    assert_eq!(d, "1:1: unknown instruction `FOO`");
}

#[test]
fn unknown_instruction_is_case_insensitive_and_names_token() {
    // Line 3, indented by two spaces → column 3.
    let d = one("LD X0\nOUT Y0\n  bar D0\nEND\n");
    assert_diag(&d, "3:3", &["unknown instruction", "BAR"]);
}

#[test]
fn unsupported_but_known_instruction() {
    // PLOAD (load a program file from a memory card) is a Q instruction softplc
    // does not implement.
    let d = one("LD X0\nPLOAD \"A.QPG\"\nEND\n");
    assert_diag(&d, "2:1", &["unsupported", "`PLOAD`"]);
    // Its pulse form too.
    let d = one("LD X0\nPLOADP \"A.QPG\"\nEND\n");
    assert_diag(&d, "2:1", &["unsupported", "PLOADP"]);
    // Instructions for intelligent modules softplc does not implement say so
    // (FROM/TO work on the rack's buffer memory: golden_rack.rs).
    let d = one("LD X0\nUNIRD H0 K0 D0 K1\nEND\n");
    assert_diag(
        &d,
        "2:1",
        &["unsupported", "`UNIRD`", "intelligent function module"],
    );
}

// ---------------------------------------------------------------- operand count

#[test]
fn too_few_operands_points_at_mnemonic() {
    // `MOV K1` lacks its destination: reported at the mnemonic, line 2 col 1.
    let d = diagnostics("LD X0\nMOV K1\nEND\n");
    assert_diag(&d[0], "2:1", &["`MOV`", "2 operands", "found 1"]);
}

#[test]
fn too_many_operands_points_at_first_extra() {
    // "MOV K1 D0 D1": M=1, K1=5, D0=8, D1=11 → the extra operand at col 11.
    let d = diagnostics("LD X0\nMOV K1 D0 D1\nEND\n");
    assert_diag(&d[0], "2:11", &["`MOV`", "2 operands", "found 3"]);
    // "LD X0 X1": X1 at col 7.
    let d = diagnostics("LD X0 X1\nOUT Y0\nEND\n");
    assert_diag(&d[0], "1:7", &["`LD`", "1 operand", "found 2"]);
}

#[test]
fn arithmetic_accepts_two_or_three_operands_only() {
    // "+ K1 K2 D0 D1": +=1, K1=3, K2=6, D0=9, D1=12.
    let d = diagnostics("LD X0\n+ K1 K2 D0 D1\nEND\n");
    assert_diag(&d[0], "2:12", &["`+`", "2 or 3", "found 4"]);
}

// ---------------------------------------------------------------- operand kinds

#[test]
fn constant_as_destination() {
    // "MOV D0 K1": K1 at col 8.
    let d = one("LD X0\nMOV D0 K1\nEND\n");
    assert_diag(&d, "2:8", &["constant", "`K1`", "destination"]);
}

#[test]
fn bit_device_where_a_word_is_needed() {
    // "MOV M0 D0": M0 at col 5.
    let d = one("LD X0\nMOV M0 D0\nEND\n");
    assert_diag(&d, "2:5", &["`M0`", "bit device", "K4M0"]);
}

#[test]
fn word_device_where_a_bit_is_needed() {
    // "LD D0": D0 at col 4.
    let d = one("LD D0\nOUT Y0\nEND\n");
    assert_diag(&d, "1:4", &["`D0`", "word device"]);
    // As a coil: "OUT D5", D5 at col 5.
    let d = one("LD X0\nOUT D5\nEND\n");
    assert_diag(&d, "2:5", &["`D5`", "word device"]);
}

#[test]
fn bit_of_word_where_a_word_is_needed() {
    // "MOV D0.F D1": D0.F at col 5.
    let d = one("LD X0\nMOV D0.F D1\nEND\n");
    assert_diag(&d, "2:5", &["`D0.F`"]);
}

#[test]
fn devices_out_of_range() {
    // M has 8192 points: M0-M8191. "LD M99999": col 4.
    let d = one("LD M99999\nOUT Y0\nEND\n");
    assert_diag(&d, "1:4", &["`M99999`", "out of range", "M8191"]);
    // D has 12288 points: D0-D12287. "MOV K1 D12288": col 8.
    let d = one("LD X0\nMOV K1 D12288\nEND\n");
    assert_diag(&d, "2:8", &["`D12288`", "out of range", "D12287"]);
    let d = one("LD X0\nMOV K1 D99999\nEND\n");
    assert_diag(&d, "2:8", &["`D99999`", "out of range"]);
    // X is hex, X0-X1FFF: X2000 is the first one past the end.
    let d = one("LD X2000\nOUT Y0\nEND\n");
    assert_diag(&d, "1:4", &["`X2000`", "out of range", "X1FFF"]);
    // The last devices themselves are fine.
    loads("LD M8191\nOUT Y1FFF\nLD X0\nMOV K1 D12287\nEND\n");
}

#[test]
fn digit_specification_past_the_last_device() {
    // K4M8189 needs M8189-M8204; M ends at M8191. "MOV K4M8189 D0": col 5.
    let d = one("LD X0\nMOV K4M8189 D0\nEND\n");
    assert_diag(&d, "2:5", &["`K4M8189`"]);
    // K4M8176 = M8176-M8191 is the last full 16 bits.
    loads("LD X0\nMOV K4M8176 D0\nEND\n");
}

#[test]
fn constants_out_of_range() {
    // 16-bit: K-32768…K32767, H0…HFFFF. "MOV K70000 D0": col 5.
    let d = one("LD X0\nMOV K70000 D0\nEND\n");
    assert_diag(&d, "2:5", &["`K70000`", "16-bit"]);
    let d = one("LD X0\nMOV H10000 D0\nEND\n");
    assert_diag(&d, "2:5", &["`H10000`", "16-bit"]);
    let d = one("LD X0\nMOV K-32769 D0\nEND\n");
    assert_diag(&d, "2:5", &["`K-32769`"]);
    // 32-bit: K-2147483648…K2147483647. "DMOV K3000000000 D0": col 6.
    let d = one("LD X0\nDMOV K3000000000 D0\nEND\n");
    assert_diag(&d, "2:6", &["`K3000000000`", "32-bit"]);
    // The limits themselves load.
    loads(
        "LD X0\nMOV K-32768 D0\nMOV K32767 D0\nMOV HFFFF D0\n\
         DMOV K-2147483648 D0\nDMOV K2147483647 D0\nDMOV HFFFFFFFF D0\nEND\n",
    );
}

#[test]
fn operand_spanning_past_the_last_device() {
    // A 32-bit operand at D12287 would also use D12288. "DMOV K1 D12287": col 9.
    let d = one("LD X0\nDMOV K1 D12287\nEND\n");
    assert_diag(&d, "2:9", &["`D12287`", "D12288"]);
    // 16-bit `*` writes D, D+1. "* K1 K2 D12287": *=1, K1=3, K2=6, D12287=9.
    let d = one("LD X0\n* K1 K2 D12287\nEND\n");
    assert_diag(&d, "2:9", &["`D12287`"]);
    // 32-bit `D*` writes four words: D12285-D12288. "D* K1 K2 D12285": col 10.
    let d = one("LD X0\nD* K1 K2 D12285\nEND\n");
    assert_diag(&d, "2:10", &["`D12285`", "D12288"]);
    loads("LD X0\nDMOV K1 D12286\nD* K1 K2 D12284\nEND\n");
}

#[test]
fn real_constant_for_bin_operand_and_k_for_real_operand() {
    // "MOV E1.5 D0": E1.5 at col 5.
    let d = one("LD X0\nMOV E1.5 D0\nEND\n");
    assert_diag(&d, "2:5", &["`E1.5`", "BIN"]);
    // "EMOV K1 D0": K1 at col 6.
    let d = one("LD X0\nEMOV K1 D0\nEND\n");
    assert_diag(&d, "2:6", &["`K1`", "real"]);
    // "E+ E1.0 K2 D0": E+=1, E1.0=4, K2=9.
    let d = one("LD X0\nE+ E1.0 K2 D0\nEND\n");
    assert_diag(&d, "2:9", &["`K2`", "real"]);
}

#[test]
fn real_constant_outside_single_precision() {
    // 1·10³⁹ > 3.40282·10³⁸. "EMOV E1.0+39 D0": col 6.
    let d = one("LD X0\nEMOV E1.0+39 D0\nEND\n");
    assert_diag(&d, "2:6", &["`E1.0+39`"]);
}

// ---------------------------------------------------------------- structure

#[test]
fn mc_without_mcr() {
    // Reported at the nesting number of the MC: "MC N0 M0", N0 at col 4.
    let d = one("LD X0\nMC N0 M0\nLD X1\nOUT Y0\nEND\n");
    assert_diag(&d, "2:4", &["MC N0", "MCR"]);
}

#[test]
fn mcr_without_mc() {
    // "MCR N0": N0 at col 5.
    let d = one("MCR N0\nEND\n");
    assert_diag(&d, "1:5", &["MCR N0", "MC"]);
}

#[test]
fn mc_mcr_pair_loads() {
    loads("LD X0\nMC N0 M0\nLD X1\nOUT Y0\nMCR N0\nEND\n");
}

#[test]
fn for_without_next() {
    let d = one("FOR K3\nEND\n");
    assert_diag(&d, "1:1", &["FOR", "NEXT"]);
}

#[test]
fn next_without_for() {
    let d = one("LD X0\nOUT Y0\nNEXT\nEND\n");
    assert_diag(&d, "3:1", &["NEXT", "FOR"]);
}

#[test]
fn missing_end_is_reported() {
    // Reported at the last item of the file: `OUT` on line 2.
    let d = one("LD X0\nOUT Y0\n");
    assert_diag(&d, "2:1", &["END"]);
    // An empty file has no END either.
    let d = one("");
    assert_diag(&d, "1:1", &["END"]);
}

#[test]
fn duplicate_pointer_names_first_line() {
    let d = one("P10\nLD X0\nOUT Y0\nP10\nLD X1\nOUT Y1\nEND\n");
    assert_diag(&d, "4:1", &["P10", "line 1"]);
}

#[test]
fn undefined_pointer() {
    // "CJ P5": P5 at col 4.
    let d = one("LD X0\nCJ P5\nEND\n");
    assert_diag(&d, "2:4", &["P5", "undefined"]);
}

#[test]
fn anb_orb_without_block() {
    let d = one("LD X0\nANB\nOUT Y0\nEND\n");
    assert_diag(&d, "2:1", &["ANB"]);
    let d = one("LD X0\nORB\nOUT Y0\nEND\n");
    assert_diag(&d, "2:1", &["ORB"]);
}

#[test]
fn block_not_closed_before_output() {
    // LD X1 opens a block that no ANB/ORB closes before OUT Y0 (line 3).
    let d = one("LD X0\nLD X1\nOUT Y0\nEND\n");
    assert_diag(&d, "3:1", &["OUT", "ANB"]);
}

#[test]
fn mps_without_mpp() {
    // MPS on line 2 is never popped; the error is found when the rung is closed.
    let d = one("LD X0\nMPS\nOUT Y0\nLD X1\nOUT Y1\nEND\n");
    assert!(d.contains("MPS") && d.contains("MPP"), "{d}");
}

#[test]
fn and_without_ld() {
    let d = diagnostics("AND X0\nOUT Y0\nEND\n");
    assert_diag(&d[0], "1:1", &["`AND`", "LD"]);
}

#[test]
fn jmp_after_contacts() {
    let d = diagnostics("LD X0\nJMP P0\nP0\nEND\n");
    assert_diag(&d[0], "2:1", &["JMP", "CJ"]);
}

#[test]
fn instruction_after_end() {
    // Both instructions after END are never executed; the first is at line 4.
    let d = diagnostics("LD X0\nOUT Y0\nEND\nLD X1\nOUT Y1\n");
    assert_diag(&d[0], "4:1", &["`LD`", "after END"]);
    assert!(d.iter().all(|s| s.contains("after END")), "{d:#?}");
}

#[test]
fn retentive_timer_with_no_points() {
    // ST has 0 points by default (004 Table 10.1). "OUT ST0 K10": ST0 at col 5.
    let d = one("LD X0\nOUT ST0 K10\nEND\n");
    assert_diag(&d, "2:5", &["ST0", "0 points"]);
    // With points assigned it loads.
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices
        .set_points(softplc_core::device::DeviceKind::STS, 16);
    compile_il("test.il", "LD X0\nOUT ST0 K10\nEND\n", &cfg.devices).unwrap();
}

#[test]
fn interrupt_label_rules() {
    // An interrupt program must follow FEND.
    let d = one("I28\nLD X0\nOUT Y0\nEND\n");
    assert_diag(&d, "1:1", &["I28", "must follow FEND"]);
    // I33, I37 and I40-I49 have no interrupt cause (004 App. 3); I32-I39
    // are error interrupts (golden_rack_interrupts.rs).
    let d = one("FEND\nI33\nIRET\nEND\n");
    assert_diag(&d, "2:1", &["not used", "I33"]);
    let d = one("FEND\nI32\nIRET\nI45\nIRET\nEND\n");
    assert_diag(&d, "4:1", &["not used", "I45"]);
    // Each interrupt pointer once.
    let d = one("FEND\nI29\nIRET\nI29\nIRET\nEND\n");
    assert_diag(&d, "4:1", &["duplicate interrupt pointer `I29`", "line 2"]);
}

#[test]
fn bad_operand_syntax_points_into_the_token() {
    // "LD X1G": X1G starts at col 4; the bad `G` is at col 6.
    let d = one("LD X1G\nOUT Y0\nEND\n");
    assert_diag(&d, "1:6", &["X1G"]);
    // "MOV K4D0 D0": K4D0 starts at col 5; digit specification on a word device,
    // the device part `D0` starts at col 7.
    let d = one("LD X0\nMOV K4D0 D0\nEND\n");
    assert_diag(&d, "2:7", &["K4D0"]);
}

#[test]
fn timer_without_set_value() {
    // "OUT T0": T0 at col 5.
    let d = one("LD X0\nOUT T0\nEND\n");
    assert_diag(&d, "2:5", &["T0", "set value"]);
}

#[test]
fn digit_spec_k8_in_16_bit_instruction() {
    // "MOV K8M0 D0": K8M0 at col 5; a 16-bit operand takes K1-K4.
    let d = one("LD X0\nMOV K8M0 D0\nEND\n");
    assert_diag(&d, "2:5", &["K8M0"]);
}

#[test]
fn three_independent_errors_all_reported_sorted() {
    // Line 2: undefined pointer P9 (found only at the end of the file), col 4.
    // Line 3: M99999 out of range, col 4.
    // Line 6: constant destination K1, col 8.
    let d = diagnostics(
        "LD X0\n\
         CJ P9\n\
         LD M99999\n\
         OUT Y1\n\
         LD X1\n\
         MOV D0 K1\n\
         END\n",
    );
    assert_eq!(d.len(), 3, "{d:#?}");
    assert_diag(&d[0], "2:4", &["P9"]);
    assert_diag(&d[1], "3:4", &["M99999"]);
    assert_diag(&d[2], "6:8", &["K1"]);
}

#[test]
fn errors_on_many_lines_sorted_by_line_and_column() {
    // Line 1: FOR without NEXT (found at the end), line 3: unknown instruction,
    // line 4: two bad operands in one instruction, K70000 (col 5) before D99999
    // (col 12).
    let d = diagnostics(
        "FOR K2\n\
         LD X0\n\
         OUT Y0\n\
         FOO\n\
         MOV K70000 D99999\n\
         END\n",
    );
    let pos: Vec<&str> = d.iter().map(|s| s.split(": ").next().unwrap()).collect();
    assert!(pos.starts_with(&["1:1", "4:1"]), "{d:#?}");
    assert!(d.iter().any(|s| s.starts_with("5:5: ")), "{d:#?}");
    assert!(d.iter().any(|s| s.starts_with("5:12: ")), "{d:#?}");
    let mut sorted = d.clone();
    sorted.sort_by_key(|s| {
        let (l, c) = s.split(": ").next().unwrap().split_once(':').unwrap();
        (l.parse::<u32>().unwrap(), c.parse::<u32>().unwrap())
    });
    assert_eq!(d, sorted);
}

#[test]
fn one_mistake_gives_one_diagnostic() {
    // The rung state recovers after a faulty instruction, so the correct lines
    // after it are not blamed.
    for (src, want) in [
        (
            "LD X0\nMOV K1\nEND\n",
            "2:1: `MOV` takes 2 operands, found 1",
        ),
        ("LD X0\nFOO Y0\nEND\n", "2:1: unknown instruction `FOO`"),
        (
            "LD X0 X1\nOUT Y0\nEND\n",
            "1:7: `LD` takes 1 operand, found 2",
        ),
        ("AND X0\nOUT Y0\nEND\n", "1:1: `AND` needs a preceding LD"),
        (
            "LD X0\nJMP P0\nP0\nEND\n",
            "2:1: JMP is unconditional; use CJ for a conditional jump",
        ),
    ] {
        assert_eq!(diagnostics(src), vec![want.to_string()], "{src}");
    }
}

#[test]
fn mps_without_mpp_is_reported_at_the_mps() {
    assert_eq!(
        diagnostics("LD X0\nMPS\nOUT Y0\nEND\n"),
        vec!["2:1: MPS without MPP".to_string()]
    );
}

#[test]
fn code_after_end_is_reported_once() {
    assert_eq!(
        diagnostics("LD X0\nOUT Y0\nEND\nLD X1\nOUT Y1\n"),
        vec!["4:1: `LD` after END is never executed".to_string()]
    );
}
