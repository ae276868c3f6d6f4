//! The input refresh at the start of a scan (004 §4.3): the input image into
//! X. It is skipped when X already holds the image — no program may write X
//! and nothing changed X or the image since the last refresh — and every
//! case below would show a stale X if that rule were wrong.

mod common;

use common::Plc;
use softplc_core::device::DeviceKind;
use softplc_core::program::compile_il;

fn may_write_x(src: &str) -> bool {
    let devices = softplc_core::profile::default_config().devices;
    compile_il("t.il", src, &devices)
        .unwrap_or_else(|d| panic!("load failed:\n{d}"))
        .may_write_x
}

#[test]
fn contacts_alone_do_not_write_x() {
    let src = "LD X0\nAND X1\nORI X2\nLDP X3\nANB\nLD= K4X0 K5\nORB\nOUT Y0\nLD DX4\nOUT Y1\nEND\n";
    assert!(!may_write_x(src));
}

#[test]
fn every_other_use_of_x_counts_as_a_writer() {
    for src in [
        "LD SM400\nOUT X0\nEND\n",
        "LD SM400\nSET X10\nEND\n",
        "LD SM400\nRST X10\nEND\n",
        "LD SM400\nMOV H5 K4X0\nEND\n",
        "LD SM400\nSET X0Z1\nEND\n",
        "LD SM400\nBMOV K4M0 K4X0 K2\nEND\n",
        // A source only, yet named outside a contact: counted (conservative).
        "LD SM400\nMOV K4X0 D0\nEND\n",
        "LD SM400\nCALL P0 X0\nFEND\nP0\nRET\nEND\n",
    ] {
        assert!(may_write_x(src), "{src}");
    }
}

/// Y0 shows X0 as the scan read it; the program then writes X0 ON.
fn writer_reads_the_image_again(writer: &str) {
    let src = format!("LD X0\nOUT Y0\nLD SM400\n{writer}\nEND\n");
    let mut p = Plc::new(&src);
    assert!(p.cpu.program().may_write_x, "{writer}");
    p.scan();
    assert!(!p.bit("Y0"));
    assert!(p.bit("X0"), "{writer}: the program wrote X0 ON");
    p.scan();
    assert!(!p.bit("Y0"), "{writer}: X0 refreshed from the image (OFF)");
}

#[test]
fn x_written_by_out_is_refreshed_from_the_image() {
    writer_reads_the_image_again("OUT X0");
}

#[test]
fn x_written_by_mov_to_k4x_is_refreshed_from_the_image() {
    writer_reads_the_image_again("MOV H1 K4X0");
}

#[test]
fn x_written_through_an_index_register_is_refreshed_from_the_image() {
    // Z1 = 0 (cleared at power-on): X0Z1 is X0.
    writer_reads_the_image_again("SET X0Z1");
}

/// A program that only reads X: Y0 = X0, Y1 = X1.
const READER: &str = "LD X0\nOUT Y0\nLD X1\nOUT Y1\nEND\n";

#[test]
fn a_reader_sees_every_change_of_the_image() {
    let mut p = Plc::new(READER);
    assert!(!p.cpu.program().may_write_x);
    p.scans(2);
    assert!(!p.bit("Y0"));
    p.cpu.set_input(0, true);
    p.scan();
    assert!(p.bit("Y0"), "set_input between scans");
    p.set("X1", "1").scan();
    assert!(p.bit("Y1"), "a door write to X by name");
    p.set("K4X0", "0").scan();
    assert!(!p.bit("Y0") && !p.bit("Y1"), "a digit-specified door write");
    assert!(
        !p.cpu.input(0) && !p.cpu.input(1),
        "mirrored into the image"
    );
}

#[test]
fn an_index_modified_door_write_to_x_lasts_until_the_next_refresh() {
    // The door does not mirror X0Z0 into the input image: the next input
    // refresh gives X0 the image's OFF again, as before any skip.
    let mut p = Plc::new(READER);
    p.scans(2);
    p.set("X0Z0", "1");
    assert!(p.bit("X0"));
    p.scan();
    assert!(!p.bit("X0"), "X0 refreshed from the image");
    assert!(!p.bit("Y0"));
}

#[test]
fn forced_inputs_win_and_their_release_gives_the_image_back() {
    let mut p = Plc::new(READER);
    p.scans(2);
    p.cpu.force(DeviceKind::X, 0, true).unwrap();
    p.scan();
    assert!(p.bit("Y0"), "forced ON");
    p.cpu.set_input(0, false);
    p.scan();
    assert!(p.bit("Y0"), "still forced ON over the image's OFF");
    p.cpu.release(DeviceKind::X, 0);
    p.scan();
    assert!(!p.bit("Y0"), "released: the image's OFF");
    p.cpu.set_input(1, true);
    p.scan();
    assert!(p.bit("Y1"));
}

#[test]
fn stop_and_run_refresh_the_inputs_again() {
    let mut p = Plc::new(READER);
    p.cpu.set_input(0, true);
    p.scans(2);
    assert!(p.bit("Y0"));
    p.cpu.set_stop();
    p.scan();
    p.cpu.set_input(0, false);
    p.cpu.set_run().unwrap();
    p.scan();
    assert!(!p.bit("Y0"));
}

#[test]
fn an_online_change_to_a_writer_refreshes_every_scan() {
    let mut p = Plc::new(READER);
    p.scans(2);
    let devices = softplc_core::profile::default_config().devices;
    let writer = compile_il(
        "test.il",
        "LD X0\nOUT Y0\nLD SM400\nOUT X0\nEND\n",
        &devices,
    )
    .unwrap();
    p.cpu.replace_program(0, writer).unwrap();
    p.scan();
    assert!(p.bit("X0"), "the new program wrote X0");
    p.scan();
    assert!(!p.bit("Y0"), "X0 refreshed from the image (OFF)");
}
