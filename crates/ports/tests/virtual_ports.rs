//! The communication phase on virtual lines (spec aplc.md §6.8-§6.9, D26):
//! the manual's examples, several slaves on one port, every master error
//! code from hand-made frames, the free port's completions and events, the
//! slave on a port, and random bytes that never stop the scan.

mod common;

use common::{port, rig, shared};
use proptest::prelude::*;
use softplc_aplc::comm::{Mode, Val};
use softplc_modbus::{crc16, Proto};
use softplc_ports::master::encode;
use softplc_ports::peers::{Bus, Script, SimSlave, Step};

fn rtu(bytes: &[u8]) -> Vec<u8> {
    encode(Mode::Rtu, bytes)
}

fn master() -> softplc_aplc::comm::PortConfig {
    port(1, &[("protocol", Val::Str("modbus-master"))])
}

/// D26's corrected example of L8108-8121: slave 3, FC 01, coils 10-14.
const MANUAL_POLL: &str = "LD SM1\nMOV 3 D0\nMOV 1 D1\nMOV 0 D2\nMOV 10 D3\nMOV 0 D4\nMOV 5 D5\nLD X0\nModbus 1 D0 D100\n";

/// Worked example #77 (L8108-8121, D26).
#[test]
fn manual_modbus_example() {
    let mut slave = SimSlave::new(3, Proto::Rtu, 100, 2000);
    slave.coils[10..15].copy_from_slice(&[true, false, true, true, false]);
    let (slave, peer) = shared(slave);
    let mut r = rig(MANUAL_POLL, vec![(master(), peer)]);
    r.scan().set("X0", "1").scan();
    assert!(!r.bit("SM124"), "busy while the request is on the line");
    r.scans(5);
    // The request went out as 03 01 00 0A 00 05 + CRC.
    assert_eq!(slave.lock().unwrap().log, [rtu(&[3, 1, 0, 10, 0, 5])]);
    // Reply 03 01 01 0D: coils 10-14 = 1 0 1 1 0, LSB first.
    assert_eq!(r.words(100, 4), [3, 1, 1, 0x0D]);
    assert!(r.bit("SM135") && !r.bit("SM136") && r.bit("SM124"));
    assert_eq!(r.int("SD139"), 0);
}

#[test]
fn modbus_ascii_write_and_read_back() {
    let cfg = port(
        1,
        &[
            ("protocol", Val::Str("modbus-master")),
            ("mode", Val::Str("ascii")),
        ],
    );
    let (slave, peer) = shared(SimSlave::new(7, Proto::Ascii, 100, 2000));
    // FC 16: registers 4-5 = 1500, 50 (bytes 05 DC 00 32), then FC 03 reads them.
    let src = "LD SM1\nMOV 7 D0\nMOV 16 D1\nMOV 0 D2\nMOV 4 D3\nMOV 0 D4\nMOV 2 D5\nMOV 4 D6\n\
MOV 5 D7\nMOV 220 D8\nMOV 0 D9\nMOV 50 D10\n\
MOV 7 D20\nMOV 3 D21\nMOV 0 D22\nMOV 4 D23\nMOV 0 D24\nMOV 2 D25\n\
LD X0\nModbus 1 D0 D100\nLD X1\nModbus 1 D20 D200\n";
    let mut r = rig(src, vec![(cfg, peer)]);
    r.scan().set("X0", "1").scans(20);
    assert_eq!(slave.lock().unwrap().holding[4..6], [1500, 50]);
    // The echo: 07 10 00 04 00 02.
    assert_eq!(r.words(100, 6), [7, 16, 0, 4, 0, 2]);
    assert!(r.bit("SM135"));
    r.set("X1", "1").scans(20);
    assert_eq!(r.words(200, 7), [7, 3, 4, 0x05, 0xDC, 0x00, 0x32]);
    // The ASCII frame on the wire: `:` hex LRC CR LF.
    let log = &slave.lock().unwrap().log;
    assert_eq!(log[1], b":070300040002F0\r\n");
}

/// A drive (station 1) and a meter (station 2) on one RS-485 line, polled in
/// turn: each completion (SM135 or SM136) moves to the next.
pub const TWO_SLAVES: &str = "LD SM1\nMOV 1 D0\nMOV 3 D1\nMOV 0 D2\nMOV 0 D3\nMOV 0 D4\nMOV 2 D5\n\
MOV 2 D10\nMOV 3 D11\nMOV 0 D12\nMOV 0 D13\nMOV 0 D14\nMOV 4 D15\n\
LD SM135\nOR SM136\nEU\nINC D50\nLD>= D50 2\nMOV 0 D50\n\
LD SM124\nAND= D50 0\nModbus 1 D0 D100\nLD SM124\nAND= D50 1\nModbus 1 D10 D200\n";

#[test]
fn two_slaves_polled_on_one_port() {
    let mut drive = SimSlave::new(1, Proto::Rtu, 16, 2000);
    drive.holding[..2].copy_from_slice(&[1500, 50]);
    let mut meter = SimSlave::new(2, Proto::Rtu, 16, 2000);
    meter.holding[..4].copy_from_slice(&[230, 5, 1200, 0]);
    let bus = Bus(vec![Box::new(drive), Box::new(meter)]);
    let cfg = port(
        1,
        &[
            ("protocol", Val::Str("modbus-master")),
            ("address", Val::Int(9)),
        ],
    );
    let mut r = rig(TWO_SLAVES, vec![(cfg, Box::new(bus))]);
    r.scans(30);
    assert_eq!(r.words(100, 7), [1, 3, 4, 0x05, 0xDC, 0x00, 0x32]);
    assert_eq!(r.words(200, 11), [2, 3, 8, 0, 230, 0, 5, 0x04, 0xB0, 0, 0]);
    assert_eq!(r.int("SD139"), 0);
}

/// The manual's poll answered by a scripted device with `answer`.
fn answered(
    answer: Vec<u8>,
    retries: i64,
) -> (common::Rig, std::sync::Arc<std::sync::Mutex<Script>>) {
    let req = rtu(&[3, 1, 0, 10, 0, 5]);
    let steps = (0..=retries)
        .map(|_| Step::Expect {
            expect: req.clone(),
            answer: answer.clone(),
            delay_us: 2000,
        })
        .collect();
    let (script, peer) = shared(Script::new(steps));
    let cfg = port(1, &[("protocol", Val::Str("modbus-master"))]);
    let mut r = rig(MANUAL_POLL, vec![(cfg, peer)]);
    r.scan()
        .set("SD137", &retries.to_string())
        .set("X0", "1")
        .scans(400);
    (r, script)
}

#[test]
fn master_error_codes_from_hand_made_frames() {
    let good = rtu(&[3, 1, 1, 0x0D]);
    let mut bad_crc = good.clone();
    bad_crc[5] ^= 0xFF;
    let cases: Vec<(&str, Vec<u8>, i64)> = vec![
        ("bad CRC", bad_crc, 0x1A),
        ("another station", rtu(&[4, 1, 1, 0x0D]), 0x16),
        ("another function", rtu(&[3, 2, 1, 0x0D]), 0x17),
        ("exception 02", rtu(&[3, 0x81, 2]), 2),
        ("byte count 2 for 5 coils", rtu(&[3, 1, 2, 0x0D, 0]), 0x19),
        ("cut short", vec![3, 1, 1], 0x11),
        ("silent", Vec::new(), 0x10),
    ];
    for (what, answer, code) in cases {
        let (r, _) = answered(answer, 0);
        assert!(r.bit("SM136") && !r.bit("SM135"), "{what}");
        assert_eq!(r.int("SD139"), code, "{what}");
        assert!(r.bit("SM124"), "{what}: idle again");
        assert!(r.cpu.state() == softplc_core::engine::CpuState::Run);
    }
    // The exception reply is written to S3 as received.
    let (r, _) = answered(rtu(&[3, 0x81, 2]), 0);
    assert_eq!(r.words(100, 3), [3, 0x81, 2]);
}

#[test]
fn retries_resend_a_missing_reply() {
    // Silent: 1 + 2 retries, 1000 ms each (SD136 = 0), then 0x10.
    let (r, script) = answered(Vec::new(), 2);
    assert_eq!(script.lock().unwrap().received.len(), 3 * 8);
    assert_eq!(r.int("SD139"), 0x10);
    // A bad CRC, then a good reply on the retry.
    let req = rtu(&[3, 1, 0, 10, 0, 5]);
    let mut bad = rtu(&[3, 1, 1, 0x0D]);
    bad[4] ^= 1;
    let steps = vec![
        Step::Expect {
            expect: req.clone(),
            answer: bad,
            delay_us: 2000,
        },
        Step::Expect {
            expect: req,
            answer: rtu(&[3, 1, 1, 0x0D]),
            delay_us: 2000,
        },
    ];
    let (_s, peer) = shared(Script::new(steps));
    let mut r = rig(MANUAL_POLL, vec![(master(), peer)]);
    r.scan().set("SD137", "1").set("X0", "1").scans(20);
    assert!(r.bit("SM135"));
    assert_eq!(r.words(100, 4), [3, 1, 1, 0x0D]);
}

#[test]
fn evrd_reads_and_evwrt_writes_an_inverter_register() {
    let (slave, peer) = shared(SimSlave::new(4, Proto::Rtu, 16, 2000));
    slave.lock().unwrap().holding[3] = 4321;
    let src = "LD X0\nEVRD 1 4 3 D500\nLD X1\nEVWRT 1 4 5 D10\nLD X2\nEVRD 1 4 40 D501\n";
    let mut r = rig(src, vec![(master(), peer)]);
    r.set("X0", "1").scans(5);
    assert_eq!(r.int("D500"), 4321);
    // The reply in the inverter RX buffer D7970.. (Appendix 3).
    assert_eq!(r.words(7970, 5), [4, 3, 2, 0x10, 0xE1]);
    assert!(r.bit("SM135"));
    r.set("D10", "1500").set("X1", "1").scans(5);
    assert_eq!(slave.lock().unwrap().holding[5], 1500);
    // Register 40 is past the inverter's 16: its error 0x2 (Appendix 5).
    r.set("X2", "1").scans(5);
    assert!(r.bit("SM136"));
    assert_eq!(r.int("SD139"), 2);
    assert_eq!(r.int("D501"), 0);
}

/// The free-port example of L10403-10422.
const MANUAL_FREE: &str = "LD SM1\nMOV 16#01 D0\nMOV 16#FF D1\nMOV 0 D2\nMOV 1 D3\nMOV 2 D4\n\
LD X0\nEU\nRST SM122\nXMT 1 D0 5\n\
LD SM122\nEU\nRST SM123\nRCV 1 D10 6\n\
BLD SD125 2\nAND SM123\nEU\nINC D100\n";

/// Worked example #76 (L10403-10422).
#[test]
fn manual_free_port_example() {
    let steps = vec![Step::Expect {
        expect: vec![0x01, 0xFF, 0x00, 0x01, 0x02],
        answer: vec![0x01, 0xFF, 0x02, 0x03, 0x05, 0xFE],
        delay_us: 30_000,
    }];
    let (script, peer) = shared(Script::new(steps));
    let cfg = port(1, &[("protocol", Val::Str("free"))]);
    let mut r = rig(MANUAL_FREE, vec![(cfg, peer)]);
    r.scan().set("X0", "1").scans(20);
    assert_eq!(script.lock().unwrap().received, [1, 0xFF, 0, 1, 2]);
    assert_eq!(r.words(10, 6), [0x01, 0xFF, 0x02, 0x03, 0x05, 0xFE]);
    // SD125 bit 2: the maximum count; SD126 the last character, SD127 the count.
    assert_eq!(r.int("SD125"), 4);
    assert_eq!(
        (r.int("SD126"), r.int("SD127"), r.int("SD128")),
        (0xFE, 6, 2)
    );
    assert_eq!(r.int("D100"), 1);
    assert!(r.bit("SM122") && r.bit("SM123") && r.bit("SM124"));
}

#[test]
fn rcv_ends_on_end_character_start_character_and_timeouts() {
    // A reader sends junk, then STX "A1" CR at 50 ms; start 2, end 13.
    let steps = vec![Step::Send {
        at_us: 50_000,
        bytes: b"xx\x02A1\r".to_vec(),
    }];
    let (_s, peer) = shared(Script::new(steps));
    let cfg = port(
        1,
        &[
            ("protocol", Val::Str("free")),
            ("start_char", Val::Int(2)),
            ("end_char", Val::Int(13)),
        ],
    );
    let mut r = rig("LD SM1\nRCV 1 D10 20\n", vec![(cfg, peer)]);
    r.scans(10);
    assert_eq!(r.words(10, 5), [2, b'A' as i64, b'1' as i64, 13, 0]);
    assert_eq!(r.int("SD125"), 2);
    assert_eq!(r.int("SD127"), 4);
    // Frame timeout 100 ms with nothing on the line: bit 4.
    let (_s, peer) = shared(Script::new(Vec::new()));
    let cfg = port(
        1,
        &[
            ("protocol", Val::Str("free")),
            ("frame_timeout_ms", Val::Int(100)),
        ],
    );
    let mut r = rig("LD SM1\nRCV 1 D10 20\n", vec![(cfg, peer)]);
    r.scans(9);
    assert!(!r.bit("SM123"));
    r.scans(2);
    assert!(r.bit("SM123"));
    assert_eq!(r.int("SD125"), 16);
    // Inter-character timeout 20 ms: "AB" then a pause: bit 3, two bytes.
    let steps = vec![
        Step::Send {
            at_us: 15_000,
            bytes: b"AB".to_vec(),
        },
        Step::Send {
            at_us: 80_000,
            bytes: b"C".to_vec(),
        },
    ];
    let (_s, peer) = shared(Script::new(steps));
    let cfg = port(
        1,
        &[
            ("protocol", Val::Str("free")),
            ("char_timeout_ms", Val::Int(20)),
        ],
    );
    let mut r = rig("LD SM1\nRCV 1 D10 20\n", vec![(cfg, peer)]);
    r.scans(12);
    assert_eq!(r.int("SD125"), 8);
    assert_eq!(r.words(10, 3), [b'A' as i64, b'B' as i64, 0]);
}

#[test]
fn receive_complete_is_interrupt_event_37() {
    let src = "POU MAIN\nLD SM1\nSET SM55\nEI\nRCV 1 D10 2\nPOU INT_3 EVENT 37\nLD SM0\nINC D300\n";
    let steps = vec![Step::Send {
        at_us: 15_000,
        bytes: vec![7, 8],
    }];
    let (_s, peer) = shared(Script::new(steps));
    let cfg = port(1, &[("protocol", Val::Str("free"))]);
    let mut r = rig(src, vec![(cfg, peer)]);
    r.scans(6);
    assert_eq!(r.words(10, 2), [7, 8]);
    assert_eq!(r.int("D300"), 1);
}

#[test]
fn slave_on_a_port_answers_with_the_aplc_map() {
    // A master reads D0-D1 (holding 0-1) of station 5, then writes M0 (coil 2000).
    let read = rtu(&[5, 3, 0, 0, 0, 2]);
    let write = rtu(&[5, 5, 0x07, 0xD0, 0xFF, 0x00]);
    let steps = vec![
        Step::Send {
            at_us: 15_000,
            bytes: read,
        },
        Step::Send {
            at_us: 45_000,
            bytes: write.clone(),
        },
    ];
    let (script, peer) = shared(Script::new(steps));
    let cfg = port(
        1,
        &[
            ("protocol", Val::Str("modbus-slave")),
            ("address", Val::Int(5)),
        ],
    );
    let mut r = rig("LD SM1\nMOV 1234 D0\nMOV 5678 D1\n", vec![(cfg, peer)]);
    r.scans(8);
    let mut reply = vec![5, 3, 4, 0x04, 0xD2, 0x16, 0x2E];
    reply.extend(crc16(&reply).to_le_bytes());
    let mut expect = reply;
    expect.extend(write); // FC 05 echoes the request
    assert_eq!(script.lock().unwrap().received, expect);
    assert!(r.bit("M0"));
}

#[test]
fn an_rtu_frame_waits_for_three_and_a_half_characters_of_silence() {
    // 19200 8E1: 573 µs a character, silence ceil(3.5 × 573) = 2006 µs. The
    // request (8 bytes from 0.5 ms) ends at 5084 µs; with 1 ms scans the
    // reply could start at the END of 6 ms, but waits for 5084 + 2006.
    let read = rtu(&[5, 3, 0, 0, 0, 1]);
    let (script, peer) = shared(Script::new(vec![Step::Send {
        at_us: 500,
        bytes: read,
    }]));
    let cfg = port(
        1,
        &[
            ("protocol", Val::Str("modbus-slave")),
            ("address", Val::Int(5)),
        ],
    );
    let mut r = rig("LD SM0\nMOV 7 D0\n", vec![(cfg, peer)]);
    r.scan_us = 1000;
    r.scans(20);
    let s = script.lock().unwrap();
    assert_eq!(s.received.len(), 7); // 05 03 02 00 07 + CRC
    assert_eq!(s.frames_at, [5084 + 2006 + 7 * 573]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]
    /// Whatever arrives, in chunks at any times, on a master (RTU or ASCII),
    /// slave or free port, the scan goes on and a master always finishes.
    #[test]
    fn random_bytes_never_stop_the_scan(
        chunks in proptest::collection::vec(
            (0u64..400_000, proptest::collection::vec(any::<u8>(), 0..120)), 0..6),
        which in 0..4usize,
    ) {
        let (protocol, mode) = [("modbus-master", "rtu"), ("modbus-master", "ascii"),
            ("modbus-slave", "rtu"), ("free", "rtu")][which];
        let steps = chunks.into_iter().map(|(at_us, bytes)| Step::Send { at_us, bytes }).collect();
        let (_s, peer) = shared(Script::new(steps));
        let cfg = if protocol == "free" {
            port(1, &[("protocol", Val::Str(protocol)), ("char_timeout_ms", Val::Int(5))])
        } else {
            port(1, &[("protocol", Val::Str(protocol)), ("mode", Val::Str(mode)),
                ("timeout_ms", Val::Int(100))])
        };
        let src = if which == 3 { "LD SM0\nRCV 1 D10 100\n" } else { MANUAL_POLL };
        let mut r = rig(src, vec![(cfg, peer)]);
        r.scan().set("X0", "1").scans(60);
        prop_assert!(r.cpu.state() == softplc_core::engine::CpuState::Run);
        if which < 2 {
            prop_assert!(r.bit("SM124"));
            prop_assert!(r.bit("SM135") != r.bit("SM136"));
        }
    }
}
