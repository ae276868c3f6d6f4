//! What the compiled program tells the tools that show it
//! (`Program::listing`): each definition's ladder role agrees with its
//! mnemonic and class, the compiler records every instruction and label as
//! `compile::listing` does without compiling, and the loop memories the PID
//! and process instructions own are recorded with their blocks.

use softplc_ir::device::DeviceConfig;
use softplc_ir::listing::{CoilRole, Entry, Held, Link, Role, Test};
use softplc_ir::ops::{Join, Num};
use softplc_lang::compile::{compile, listing};
use softplc_lang::il::parse_il;
use softplc_lang::isa::{class_of, Def};
use softplc_melsec::{dialect, isa, process_isa, redundant_dialect};

fn defs() -> impl Iterator<Item = &'static Def> {
    isa().all().chain(process_isa().all())
}

#[test]
fn every_role_is_of_its_class_and_contacts_join_as_they_are_named() {
    for d in defs() {
        assert_eq!(class_of(d.role), d.class, "{}", d.name);
        if let Role::Contact { join, test } = d.role {
            let want = if d.name.starts_with("LD") {
                Join::Load
            } else if d.name.starts_with("AND") || d.name.starts_with("ANI") {
                Join::And
            } else {
                Join::Or
            };
            assert_eq!(join, want, "{}", d.name);
            let rest = d
                .name
                .trim_start_matches("LD")
                .trim_start_matches("AND")
                .trim_start_matches("OR");
            let compare = match rest.chars().next() {
                Some('=' | '<' | '>') => Some(Test::Compare(Num::I16)),
                Some('D') => Some(Test::Compare(Num::I32)),
                Some('E') => Some(Test::Compare(Num::F32)),
                Some('$') => Some(Test::Computed),
                _ => None,
            };
            if let Some(t) = compare {
                assert_eq!(test, t, "{}", d.name);
            }
        }
    }
}

#[test]
fn sequence_instructions_have_the_roles_the_ladder_draws() {
    let role = |m: &str| {
        defs()
            .find(|d| d.name == m)
            .map(|d| d.role)
            .unwrap_or_else(|| panic!("{m} is defined"))
    };
    let contact = |join, test| Role::Contact { join, test };
    assert_eq!(role("LDI"), contact(Join::Load, Test::Closed));
    assert_eq!(role("ANDP"), contact(Join::And, Test::Rising));
    assert_eq!(role("ORF"), contact(Join::Or, Test::Falling));
    assert_eq!(role("ANB"), Role::Link(Link::BlockAnd));
    assert_eq!(role("MRD"), Role::Link(Link::Read));
    assert_eq!(role("MEF"), Role::Link(Link::Falling));
    assert_eq!(role("RST"), Role::Coil(CoilRole::Reset));
    assert_eq!(role("PLF"), Role::Coil(CoilRole::Pulse));
    assert_eq!(role("MOV"), Role::Box);
    assert_eq!(role("PIDCONT"), Role::Box);
    assert_eq!(role("FEND"), Role::Standalone);
    assert_eq!(role("NEXT"), Role::Standalone);
}

#[test]
fn the_compiler_records_what_the_source_listing_says() {
    let text = "LD X0\nOR M0\nANI X1\nMPS\nAND X2\nOUT Y0\nMPP\nMOVP K1 D0\nP10\nLDD> D0 K5\nINV\nSET M1\nSP.PIDCONT D800\nFEND\nEND\n";
    let src = parse_il("t.il", text).unwrap();
    let p = compile(&src, &DeviceConfig::default(), dialect(), None).unwrap();
    let l = listing(&src, dialect());
    // The same entries; only the compiler knows where their state is.
    let bare: Vec<Entry> = p
        .listing
        .entries
        .iter()
        .cloned()
        .map(|e| match e {
            Entry::Instr(mut i) => {
                i.held = Held::default();
                Entry::Instr(i)
            }
            label => label,
        })
        .collect();
    assert_eq!(bare, l.entries);
    assert_eq!(p.listing.entries.len(), 15);
    let Entry::Instr(mov) = &p.listing.entries[7] else {
        panic!("MOVP is an instruction")
    };
    assert_eq!(mov.role, Role::Box);
    assert_eq!(mov.mnemonic, "MOVP");
    assert_eq!(mov.operands, ["K1", "D0"]);
    assert_eq!(mov.line, 8);
    // Seven 1-step instructions before it; its pulse gate's edge memory is
    // the program's first; 3 steps.
    assert_eq!(
        mov.held,
        Held {
            edges: 0..1,
            words: 0..0,
            steps: 7..10
        }
    );
    assert_eq!(
        p.listing.entries[8],
        Entry::Label {
            text: "P10".into(),
            line: 9
        }
    );
    let Entry::Instr(cmp) = &p.listing.entries[9] else {
        panic!("LDD> is an instruction")
    };
    assert_eq!(
        cmp.role,
        Role::Contact {
            join: Join::Load,
            test: Test::Compare(Num::I32)
        }
    );
    // The pulse form owns its loop memory like the plain name.
    assert_eq!(p.listing.loops.len(), 1);
    let u = &p.listing.loops[0];
    assert_eq!(
        (u.mnemonic.as_str(), u.block.as_str(), u.line),
        ("SP.PIDCONT", "D800", 13)
    );
    assert!(u.memory.is(&softplc_melsec::pid::S_PID_IO));
    assert!(u
        .memory
        .settings
        .is_some_and(|s| s.is(&softplc_melsec::pid::S_PID_DATA)));
}

#[test]
fn a_source_that_does_not_compile_still_lists_every_instruction() {
    let src = parse_il("t.il", "ANB\nP10\nLD X0\nFOO D0\nOR X1\n").unwrap();
    assert!(compile(&src, &DeviceConfig::default(), dialect(), None).is_err());
    let l = listing(&src, dialect());
    let roles: Vec<Option<Role>> = l
        .entries
        .iter()
        .map(|e| match e {
            Entry::Instr(i) => Some(i.role),
            Entry::Label { .. } => None,
        })
        .collect();
    assert_eq!(
        roles,
        [
            Some(Role::Link(Link::BlockAnd)),
            None,
            Some(Role::Contact {
                join: Join::Load,
                test: Test::Open
            }),
            // An unknown mnemonic is a box.
            Some(Role::Box),
            Some(Role::Contact {
                join: Join::Or,
                test: Test::Open
            }),
        ]
    );
}

#[test]
fn loop_memories_of_pid_and_process_instructions() {
    use softplc_melsec::process::tag::{LoopTag, LOOP_TAG};
    let text = "LD SM400\nPIDINIT D500\nPIDCONT D600\nS.IN R0 R100 R200 R1000\nS.PID R40 R140 R240 R1000 SD1506\nS.BC D0 D10 SD1506 D3000\nS.ADD R0 R2 R4 SD1506\nEND\n";
    let src = parse_il("t.il", text).unwrap();
    let p = compile(
        &src,
        &DeviceConfig::default(),
        &redundant_dialect(Default::default()),
        None,
    )
    .unwrap();
    let loops: Vec<(&str, &str)> = p
        .listing
        .loops
        .iter()
        .map(|u| (u.mnemonic.as_str(), u.block.as_str()))
        .collect();
    assert_eq!(
        loops,
        [
            ("PIDINIT", "D500"),
            ("PIDCONT", "D600"),
            ("S.IN", "R1000"),
            ("S.PID", "R1000"),
            ("S.BC", "D3000"),
        ]
    );
    let [init, cont, s_in, _, bc] = &p.listing.loops[..] else {
        panic!("five loop memories")
    };
    // PIDINIT: n at +0, loop k's 10 words of control data from +2.
    assert_eq!(init.memory.count, Some(0));
    assert_eq!(init.memory.fields.len(), 10);
    let kp = init.memory.field("kp").unwrap();
    assert_eq!(init.memory.offset(1, kp), 2 + 10 + 2);
    // PIDCONT: 10 common words, 18 a loop; its settings are PIDINIT's.
    let mode = cont.memory.field("mode").unwrap();
    assert_eq!(cont.memory.offset(2, mode), 10 + 2 * 18 + 5);
    assert!(cont.memory.settings.is_some_and(|s| s.is(init.memory)));
    // The process loops share the declared loop tag; S.BC has its own.
    assert!(s_in.memory.is(&LOOP_TAG));
    assert_eq!(s_in.memory.fields, LoopTag::FIELDS);
    assert!(!bc.memory.is(&LOOP_TAG));
}
