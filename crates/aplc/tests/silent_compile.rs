//! No APLC instruction runs as another: every definition compiles, under a
//! name that is not its own, to its own instruction or to a load error that
//! says it is a softplc bug (the MELSEC twin is in `softplc-melsec`).

use softplc_ir::device::DeviceMap;
use softplc_lang::audit::renamed;
use softplc_lang::isa::Def;

/// Operand sets to try: devices of each kind and constants in a few
/// patterns, then the forms some instructions need.
fn candidates(_: &Def) -> Vec<Vec<String>> {
    let mut sets = softplc_lang::audit::operand_sets(
        |k| format!("D{}", 1000 * k),
        |k| format!("M{}", 100 * k),
        |k| format!("{}", k + 1),
    );
    let special: &[&[&str]] = &[
        &["T0", "10"],
        &["C0", "10"],
        &["X0", "Y0"],
        &["0"],
        &["C200", "10"],
        &["M0", "M100", "16", "4"],
        &["D0", "D10", "D20", "10", "M0"],
        &["65", "66", "D0"],
        &["X0", "8"],
        &["D6000", "10"],
    ];
    sets.extend(
        special
            .iter()
            .map(|s| s.iter().map(|t| t.to_string()).collect()),
    );
    sets
}

/// Compiled by the POU driver by their exact names (`compile.rs`): their
/// definitions' own functions only say so (CIRET there outside an interrupt
/// routine), so no operand set compiles through them.
const BY_DRIVER: &[&str] = &["STL", "RET", "CALL", "CSRET", "CIRET"];

#[test]
fn no_definition_compiles_as_another_under_a_foreign_name() {
    let map = DeviceMap::new(&softplc_aplc::device_config());
    let bug = |d: &str| d.contains("a softplc bug");
    let r = renamed(softplc_aplc::dialect(), &map, "ZZ", &candidates, &bug);
    assert!(
        r.differing.is_empty(),
        "{}",
        r.differing
            .iter()
            .map(|(n, a, b)| format!("{n}:\n  own   {a:?}\n  alias {b:?}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
    let mut uncovered = r.uncovered.clone();
    uncovered.sort_unstable();
    let mut by_driver = BY_DRIVER.to_vec();
    by_driver.sort_unstable();
    assert_eq!(uncovered, by_driver, "no operand set compiles");
    assert!(r.checked.len() > 200, "{}", r.checked.len());
}
