//! The communication instructions' own part (002 §6.10 L8063-8542, spec
//! aplc.md §6.8-§6.9, D26): parameter checks, flags and the request left for
//! the communication phase. Sending and answering are tested with the
//! phase itself in crates/ports/tests.

mod common;

use common::{config, plc_with, Plc};
use softplc_aplc::comm::{mailbox, PortConfig, Val};
use softplc_ir::device::DeviceKind;

fn port(n: u8, protocol: &str) -> PortConfig {
    PortConfig::build(
        n,
        &[("protocol", Val::Str(protocol)), ("address", Val::Int(1))],
    )
    .unwrap()
}

fn with_ports(src: &str, ports: Vec<PortConfig>) -> Plc {
    let mut cfg = config();
    cfg.system = softplc_aplc::system_with_ports(200, 0, ports);
    plc_with(src, cfg)
}

fn sw(p: &Plc, port: u8, off: u32) -> u16 {
    p.cpu
        .memory()
        .get_word(DeviceKind::SW, (mailbox::base(port) + off) as i64)
        .unwrap()
}

const POLL: &str = "LD X0\nModbus 1 D0 D100\n";

fn request(p: &mut Plc, words: &[u16]) {
    for (k, w) in words.iter().enumerate() {
        p.set(&format!("D{k}"), &w.to_string());
    }
    p.set("X0", "1").scan();
}

#[test]
fn modbus_leaves_the_request_for_the_communication_phase() {
    let mut p = with_ports(POLL, vec![port(1, "modbus-master")]);
    p.scan();
    // The settings show in SD135 (station) and SM124 (idle) at power-on.
    assert_eq!(p.int("SD135"), 1);
    assert!(p.bit("SM124"));
    // D26: slave 3, FC 01, start 10, 5 coils.
    request(&mut p, &[3, 1, 0, 10, 0, 5]);
    assert!(!p.bit("SM124") && !p.bit("SM135") && !p.bit("SM136"));
    assert_eq!(sw(&p, 1, mailbox::MB_REQ), 1);
    assert_eq!(sw(&p, 1, mailbox::MB_LEN), 6);
    assert_eq!(sw(&p, 1, mailbox::MB_DEST), 100);
    let bytes: Vec<u16> = (0..6).map(|k| sw(&p, 1, mailbox::MB_BYTES + k)).collect();
    assert_eq!(bytes, [3, 1, 0, 10, 0, 5]);
    // Still busy: a new rising edge is run error 64 and sends nothing new.
    p.set("X0", "0").scan();
    p.set("D0", "4").set("X0", "1").scan();
    assert_eq!(p.int("SD20"), 64);
    assert_eq!(sw(&p, 1, mailbox::MB_BYTES), 3);
}

#[test]
fn modbus_parameter_errors_land_in_sd139() {
    let cases: [(&[u16], u16); 5] = [
        // FC 07 is not one the master sends.
        (&[3, 7, 0, 0, 0, 1], 0x1C),
        // The target is the port's own station (SD135 = 1).
        (&[1, 3, 0, 0, 0, 1], 0x13),
        // 126 registers: more than FC 03 reads.
        (&[3, 3, 0, 0, 0, 126], 0x1E),
        // A broadcast read.
        (&[0, 3, 0, 0, 0, 1], 0x12),
        // FC 16 of 2 registers with byte count 3.
        (&[3, 16, 0, 0, 0, 2, 3, 0, 1, 0, 2], 0x1E),
    ];
    for (words, code) in cases {
        let mut p = with_ports(POLL, vec![port(1, "modbus-master")]);
        request(&mut p, words);
        assert!(p.bit("SM136"), "{words:?}");
        assert_eq!(p.int("SD139"), code as i64, "{words:?}");
        assert!(p.bit("SM124"), "idle after a parameter error");
        assert_eq!(sw(&p, 1, mailbox::MB_REQ), 0);
    }
    // 125 registers into D7900: the reply (3 + 250 words) runs past D7999.
    let mut p = with_ports("LD X0\nModbus 1 D0 D7900\n", vec![port(1, "modbus-master")]);
    request(&mut p, &[3, 3, 0, 0, 0, 125]);
    assert_eq!(p.int("SD139"), 0x14);
    // PORT2 is free port here: 0x12 in SD144, SM138.
    let mut p = with_ports("LD X0\nModbus 2 D0 D100\n", vec![port(2, "free")]);
    request(&mut p, &[3, 3, 0, 0, 0, 1]);
    assert!(p.bit("SM138"));
    assert_eq!(p.int("SD144"), 0x12);
}

#[test]
fn xmt_and_rcv_start_once_and_set_their_flags() {
    let src = "LD X0\nXMT 1 D0 3\nLD X1\nRCV 1 D10 6\n";
    let mut p = with_ports(src, vec![port(1, "free")]);
    p.set("D0", "16#101").set("D1", "16#FF").set("D2", "7");
    p.set("X0", "1").set("X1", "1").scan();
    assert!(p.bit("SM120") && !p.bit("SM122") && p.bit("SM121") && !p.bit("SM123"));
    assert!(!p.bit("SM124"));
    assert_eq!(sw(&p, 1, mailbox::TX_REQ), 1);
    assert_eq!(sw(&p, 1, mailbox::TX_LEN), 3);
    // One byte per word: the low byte.
    let tx: Vec<u16> = (0..3).map(|k| sw(&p, 1, mailbox::TX_BYTES + k)).collect();
    assert_eq!(tx, [1, 0xFF, 7]);
    assert_eq!(sw(&p, 1, mailbox::RX_ARM), 1);
    assert_eq!(sw(&p, 1, mailbox::RX_DEST), 10);
    assert_eq!(sw(&p, 1, mailbox::RX_MAX), 6);
    // Not a free port: run error 64.
    let mut p = with_ports(src, vec![port(1, "modbus-slave")]);
    p.set("X0", "1").scan();
    assert_eq!(p.int("SD20"), 64);
    assert!(!p.bit("SM120"));
}

#[test]
fn xmt_packs_two_bytes_per_word_with_sd120_bit_12() {
    let cfg = PortConfig::build(
        1,
        &[("protocol", Val::Str("free")), ("packed", Val::Bool(true))],
    )
    .unwrap();
    let mut p = with_ports("LD X0\nXMT 1 D0 3\n", vec![cfg]);
    p.set("D0", "16#4241")
        .set("D1", "16#43")
        .set("X0", "1")
        .scan();
    assert_eq!(p.int("SD120") & 1 << 12, 1 << 12);
    let tx: Vec<u16> = (0..3).map(|k| sw(&p, 1, mailbox::TX_BYTES + k)).collect();
    assert_eq!(tx, [0x41, 0x42, 0x43]);
}

#[test]
fn load_errors_name_the_operand() {
    let e = common::errors("LD X0\nModbus 0 D0 D100\n");
    assert!(e.contains("PORT0, the USB programming port"), "{e}");
    let e = common::errors("LD X0\nModbus 1 D0 V0\n");
    assert!(e.contains("V frame is gone"), "{e}");
    let e = common::errors("LD X0\nRCV 1 M0 5\n");
    assert!(e.contains("a D register without index"), "{e}");
    let e = common::errors("LD X0\nXMT 3 D0 5\n");
    assert!(
        e.contains("the channel is the constant 1 (PORT1) or 2 (PORT2)"),
        "{e}"
    );
    let e = common::errors("LD X0\nEVFWD 1 1\n");
    assert!(e.contains("no register map"), "{e}");
}

#[test]
fn evwrt_and_evrd_are_fc_06_and_fc_03_through_the_master() {
    let src = "LD X0\nEVWRT 1 4 16#2000 50\nLD X1\nEVRD 1 4 16#3001 D500\n";
    let mut p = with_ports(src, vec![port(1, "modbus-master")]);
    p.set("X0", "1").scan();
    // FC 06: station 4, register 16#2000, value 50; also in D7940.. (Appendix 3).
    let bytes: Vec<u16> = (0..6).map(|k| sw(&p, 1, mailbox::MB_BYTES + k)).collect();
    assert_eq!(bytes, [4, 6, 0x20, 0x00, 0, 50]);
    assert_eq!(p.int("D7941"), 6);
    assert_eq!(sw(&p, 1, mailbox::MB_DEST), 7970);
    assert_eq!(sw(&p, 1, mailbox::MB_VALUE), 0);
    let mut p = with_ports(src, vec![port(1, "modbus-master")]);
    p.set("X1", "1").scan();
    let bytes: Vec<u16> = (0..6).map(|k| sw(&p, 1, mailbox::MB_BYTES + k)).collect();
    assert_eq!(bytes, [4, 3, 0x30, 0x01, 0, 1]);
    // The register read goes to D500 (1 + its number in the mailbox).
    assert_eq!(sw(&p, 1, mailbox::MB_VALUE), 501);
    // EVRD cannot broadcast: station 0 is 0x12.
    let mut p = with_ports("LD X1\nEVRD 1 0 1 D500\n", vec![port(1, "modbus-master")]);
    p.set("X1", "1").scan();
    assert_eq!(p.int("SD139"), 0x12);
}
