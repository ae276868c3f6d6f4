//! The APLC driver records what the tools that show a program need
//! (`Program::listing`): every instruction with its definition's ladder role,
//! SFC steps and the end of the SFC section included, operands as devices.

use softplc_ir::listing::{CoilRole, Entry, Link, Role, Test};
use softplc_ir::ops::{Join, Num};
use softplc_lang::isa::class_of;

#[test]
fn every_role_is_of_its_class() {
    for d in softplc_aplc::isa().all() {
        assert_eq!(class_of(d.role), d.class, "{}", d.name);
    }
}

#[test]
fn the_driver_lists_every_instruction_with_its_role() {
    let src = "VAR_GLOBAL\n  RUN M5\nEND_VAR\nLD SM1\nSET S0\nSTL S0\nLD RUN\nBANI D0 3\nEU\nSET S20\nSTL S20\nLDD> D0 100\nOUT Y0\nRET\nLD X0\nMPS\nTON T1 10\nMPP\nMOV 1 D2\n";
    let p = softplc_aplc::load_bytes("t.apl", src.as_bytes()).unwrap();
    let listed: Vec<(Role, &str, Vec<&str>)> = p
        .listing
        .entries
        .iter()
        .map(|e| match e {
            Entry::Instr(l) => (
                l.role,
                l.mnemonic.as_str(),
                l.operands.iter().map(String::as_str).collect(),
            ),
            Entry::Label { .. } => panic!("no labels in APLC programs"),
        })
        .collect();
    let contact = |join, test| Role::Contact { join, test };
    assert_eq!(
        listed,
        [
            (contact(Join::Load, Test::Open), "LD", vec!["SM1"]),
            (Role::Coil(CoilRole::Set), "SET", vec!["S0"]),
            (Role::Step, "STL", vec!["S0"]),
            // The global is listed as its device.
            (contact(Join::Load, Test::Open), "LD", vec!["M5"]),
            (
                contact(Join::And, Test::WordBit { closed: true }),
                "BANI",
                vec!["D0", "3"]
            ),
            (Role::Link(Link::Rising), "EU", vec![]),
            (Role::Coil(CoilRole::Set), "SET", vec!["S20"]),
            (Role::Step, "STL", vec!["S20"]),
            (
                contact(Join::Load, Test::Compare(Num::I32)),
                "LDD>",
                vec!["D0", "100"]
            ),
            (Role::Coil(CoilRole::Out), "OUT", vec!["Y0"]),
            (Role::StepsEnd, "RET", vec![]),
            (contact(Join::Load, Test::Open), "LD", vec!["X0"]),
            (Role::Link(Link::Push), "MPS", vec![]),
            (Role::Box, "TON", vec!["T1", "10"]),
            (Role::Link(Link::Pop), "MPP", vec![]),
            (Role::Box, "MOV", vec!["1", "D2"]),
        ]
    );
    assert!(p.listing.loops.is_empty());
}

#[test]
fn pid_owns_its_parameter_block() {
    let p = softplc_aplc::load_bytes("t.apl", b"LD SM0\nPID D500 D501 D510 D502\n").unwrap();
    let [u] = &p.listing.loops[..] else {
        panic!("one loop memory")
    };
    assert_eq!((u.mnemonic.as_str(), u.block.as_str()), ("PID", "D510"));
    assert!(u.memory.is(&softplc_aplc::pid::PID_BLOCK));
    assert_eq!(u.memory.field("alarms").map(|f| f.offset), Some(19));
}
