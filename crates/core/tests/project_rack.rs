//! The rack in plc.toml (`[io]`, `[[slot]]`): I/O numbers assigned as the
//! manual's chapter on I/O numbering says (004 §5, L2531-2595), and one
//! failing file per SP.UNIT LAY ERR. rule (L2408, L2707, L2721-2727), with
//! the exact `line:col: message`.

mod common;
use common::project::{errors, ok};
use softplc_core::rack::SlotType;

const MAIN: &str = "[[program]]\nfile = \"main.il\"\n";

fn with(slots: &str) -> String {
    format!("{MAIN}{slots}")
}

/// Left to right from 0, each slot its points, an empty slot 16 by default
/// or `[io] empty_points`; a `start` moves a slot and the next follow it.
#[test]
fn io_numbers_are_assigned_left_to_right() {
    let p = ok(&with(
        "[io]\nempty_points = 32\n\
         [[slot]]\ntype = \"input\"\npoints = 64\n\
         [[slot]]\ntype = \"empty\"\n\
         [[slot]]\ntype = \"output\"\npoints = 16\nstart = \"200\"\n\
         [[slot]]\ntype = \"intelligent\"\nmodule = \"generic\"\nbuffer_words = 10\n\
         [[slot]]\ntype = \"interrupt\"\n",
    ));
    let got: Vec<(SlotType, u32, u32, Option<&str>)> = p
        .config
        .rack
        .slots
        .iter()
        .map(|s| (s.kind, s.start, s.points, s.module.map(|m| m.name)))
        .collect();
    assert_eq!(
        got,
        vec![
            (SlotType::Input, 0x0, 64, None),
            (SlotType::Empty, 0x40, 32, None),
            (SlotType::Output, 0x200, 16, None),
            (SlotType::Intelligent, 0x210, 16, Some("generic")),
            (SlotType::Interrupt, 0x220, 16, Some("QI60")),
        ]
    );
    // The generic module's buffer memory is U21\G0-G9.
    let unit = p.config.devices.units();
    assert_eq!((unit[0].unit, unit[0].words), (0x21, 10));
}

/// The manual's example (L2729-2778): slot 3 starting at 200H, slot 4 at
/// 70H — numbers need not increase, only not overlap.
#[test]
fn start_numbers_may_go_back() {
    let p = ok(&with(
        "[[slot]]\ntype = \"input\"\npoints = 16\n\
         [[slot]]\ntype = \"input\"\npoints = 16\n\
         [[slot]]\ntype = \"input\"\npoints = 32\n\
         [[slot]]\ntype = \"output\"\npoints = 16\nstart = \"200\"\n\
         [[slot]]\ntype = \"output\"\npoints = 16\nstart = \"70\"\n",
    ));
    let starts: Vec<u32> = p.config.rack.slots.iter().map(|s| s.start).collect();
    assert_eq!(starts, vec![0x0, 0x10, 0x20, 0x200, 0x70]);
}

#[test]
fn overlapping_numbers_are_a_layout_error() {
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"input\"\npoints = 32\n\
             [[slot]]\ntype = \"output\"\npoints = 16\nstart = \"10\"\n"
        )),
        vec![
            "6:1: slot 1 (output): SP.UNIT LAY ERR. its I/O numbers 10-1F overlap slot 0's (0-1F)"
        ]
    );
}

#[test]
fn numbers_beyond_fff_are_a_layout_error() {
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"input\"\npoints = 64\nstart = \"FE0\"\n"
        )),
        vec!["3:1: slot 0 (input): SP.UNIT LAY ERR. its I/O numbers FE0-101F go beyond FFF"]
    );
}

#[test]
fn a_start_not_a_multiple_of_16_is_a_layout_error() {
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"input\"\npoints = 16\nstart = \"18\"\n"
        )),
        vec![
            "3:1: slot 0 (input): SP.UNIT LAY ERR. the start I/O number 18 is not a multiple of 16"
        ]
    );
}

/// 64 slots in all: a module in the 65th is an error, an empty slot is not.
#[test]
fn a_module_in_slot_65_is_a_layout_error() {
    let empty = "[[slot]]\ntype = \"empty\"\npoints = 0\n".repeat(64);
    ok(&with(&format!("{empty}[[slot]]\ntype = \"empty\"\n")));
    let e = errors(&with(&format!(
        "{empty}[[slot]]\ntype = \"input\"\npoints = 16\n"
    )));
    assert_eq!(
        e,
        vec!["195:1: slot 64 (input): SP.UNIT LAY ERR. a module in slot 64 (the bases have 64 slots, 0-63)"]
    );
}

/// An intelligent module on a slot typed input, output, io or empty is
/// SP.UNIT LAY ERR. (L2724), as is an interrupt module typed intelligent.
#[test]
fn a_module_of_another_type_is_a_layout_error() {
    for ty in ["input", "output", "io", "empty"] {
        assert_eq!(
            errors(&with(&format!(
                "[[slot]]\ntype = \"{ty}\"\npoints = 16\nmodule = \"generic\"\n"
            ))),
            vec![format!("3:1: slot 0: SP.UNIT LAY ERR. the intelligent module generic is in a slot typed {ty} (write type = \"intelligent\")")]
        );
    }
    assert_eq!(
        errors(&with("[[slot]]\ntype = \"intelligent\"\nmodule = \"QI60\"\n")),
        vec!["3:1: slot 0: SP.UNIT LAY ERR. the interrupt module QI60 is in a slot typed intelligent (write type = \"interrupt\")"]
    );
}

#[test]
fn slot_settings_are_checked() {
    assert_eq!(
        errors(&with("[[slot]]\ntype = \"input\"\npoints = 20\n")),
        vec!["5:10: slot 0: points must be one of 0, 16, 32, 48, 64, 128, 256, 512, 1024"]
    );
    assert_eq!(
        errors(&with("[[slot]]\ntype = \"output\"\n")),
        vec!["3:1: slot 0: an output slot needs points (16, 32, 64 …)"]
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"intelligent\"\nmodule = \"Q99XX\"\n"
        )),
        vec!["5:10: slot 0: no module profile \"Q99XX\" (there are: generic, QI60)"]
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"intelligent\"\nbuffer_words = 0\n"
        )),
        vec!["5:16: slot 0: buffer_words must be 1-65536 words"]
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"interrupt\"\n[[slot]]\ntype = \"interrupt\"\n"
        )),
        vec!["5:1: slot 1 (interrupt QI60): one interrupt module per CPU (slot 0 has one)"]
    );
    assert_eq!(
        errors(&with("[io]\nempty_points = 8\n")),
        vec!["4:16: empty_points must be 16-1024 points in multiples of 16"]
    );
}

/// `interrupts = { cause = "I50" }`: I50-I255, each pointer once.
#[test]
fn interrupt_pointer_settings() {
    let p = ok(&with(
        "[[slot]]\ntype = \"intelligent\"\ninterrupts = { 0 = \"I50\", 3 = \"I255\" }\n",
    ));
    assert_eq!(p.config.rack.slots[0].interrupts, vec![(0, 50), (3, 255)]);
    assert!(p.config.rack.raises(50) && p.config.rack.raises(255));
    assert!(!p.config.rack.raises(51));
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"intelligent\"\ninterrupts = { 0 = \"I49\" }\n"
        )),
        vec!["5:20: slot 0: \"I49\" is not an intelligent module's interrupt pointer (I50-I255)"]
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"intelligent\"\ninterrupts = { 0 = \"I50\" }\n\
             [[slot]]\ntype = \"intelligent\"\ninterrupts = { 1 = \"I50\" }\n"
        )),
        vec![
            "6:1: slot 1 (intelligent generic): interrupt pointer I50 is already raised by slot 0"
        ]
    );
}

#[test]
fn auto_refresh_settings() {
    let p = ok(&with(
        "[[slot]]\ntype = \"intelligent\"\nbuffer_words = 8\n\
         refresh = [{ buffer = 0, to = \"D10\", words = 8 }, { buffer = 4, from = \"R5\", words = 2 }]\n",
    ));
    let r = &p.config.rack.slots[0].refresh;
    assert_eq!(
        (r[0].buffer, r[0].number, r[0].words, r[0].to_cpu),
        (0, 10, 8, true)
    );
    assert_eq!(
        (r[1].device, r[1].number, r[1].to_cpu),
        (softplc_core::device::DeviceKind::ZR, 5, false)
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"intelligent\"\nbuffer_words = 8\nrefresh = [{ buffer = 6, to = \"D10\", words = 4 }]\n"
        )),
        vec!["6:12: slot 0: refresh of 4 words from G6 is outside the module's buffer memory (G0-G7)"]
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"intelligent\"\nrefresh = [{ buffer = 0, to = \"M0\", words = 1 }]\n"
        )),
        vec!["5:31: slot 0: \"M0\" is not a D, W, R or ZR device"]
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"intelligent\"\nrefresh = [{ buffer = 0, to = \"D0\", from = \"D1\", words = 1 }]\n"
        )),
        vec!["5:12: slot 0: a refresh has either to (module → CPU) or from (CPU → module)"]
    );
    assert_eq!(
        errors(&with(
            "[[slot]]\ntype = \"input\"\npoints = 16\nrefresh = [{ buffer = 0, to = \"D0\", words = 1 }]\n"
        )),
        vec!["6:11: slot 0: refresh is an array of { buffer = 11, to = \"D100\", words = 4 } tables on an intelligent module"]
    );
}
