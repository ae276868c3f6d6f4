//! Framing: delimiting, incomplete input, garbage, and the transport fields.

mod common;

use common::*;
use softplc_modbus::{decode, decode_exact, Frame, FrameErrorKind, Map, Proto, Slave, Step};

fn ok(proto: Proto, buf: &[u8]) -> (Frame, usize) {
    decode(proto, buf).unwrap().unwrap()
}

fn err(proto: Proto, buf: &[u8]) -> (FrameErrorKind, usize, usize) {
    let e = decode(proto, buf).unwrap_err();
    assert_eq!(e.proto, proto);
    (e.kind, e.offset, e.skip)
}

#[test]
fn tcp_header() {
    let req = hex("12 34 00 00 00 06 07 03 00 0A 00 02");
    let (f, used) = ok(Proto::Tcp, &req);
    assert_eq!(used, 12);
    assert_eq!(f, Frame::new(Proto::Tcp, 0x1234, 7, hex("03 00 0A 00 02")));
    assert_eq!(f.encode(), req);
    // Every proper prefix needs more bytes.
    for n in 0..req.len() {
        assert_eq!(decode(Proto::Tcp, &req[..n]).unwrap(), None, "{n}");
    }
    // Two requests in one read: the first one, then the second.
    let mut two = req.clone();
    two.extend_from_slice(&hex("12 35 00 00 00 06 07 03 00 0B 00 01"));
    assert_eq!(ok(Proto::Tcp, &two).1, 12);
    assert_eq!(ok(Proto::Tcp, &two[12..]).0.transaction, 0x1235);
    // Protocol id 0001; lengths 0, 1 and 255.
    assert_eq!(
        err(Proto::Tcp, &hex("12 34 00 01 00 06 07 03 00 0A 00 02")),
        (FrameErrorKind::BadHeader, 2, 12)
    );
    for len in ["00 00", "00 01", "00 FF", "FF FF"] {
        let buf = hex(&format!("00 01 00 00 {len} 01"));
        assert_eq!(err(Proto::Tcp, &buf).0, FrameErrorKind::BadHeader, "{len}");
    }
    // Length 2: unit and function code only → served as a malformed request (03).
    let (f, _) = ok(Proto::Tcp, &hex("00 01 00 00 00 02 01 03"));
    let mut cpu = cpu();
    let r = softplc_modbus::serve(&mut Slave::new(1), &Map::q_default(), &f, &mut cpu).unwrap();
    assert_eq!(r, hex("00 01 00 00 00 03 01 83 03"));
    // The largest PDU (253 bytes): length 254.
    let mut big = hex("00 01 00 00 00 FE 01 08 00 00");
    big.resize(6 + 254, 0xAA);
    assert_eq!(ok(Proto::Tcp, &big).0.pdu.len(), 253);
}

#[test]
fn rtu_lengths_by_function_code() {
    // 8-byte requests: every prefix is incomplete.
    let req = hex("01 03 00 6B 00 03 74 17");
    for n in 0..8 {
        assert_eq!(decode(Proto::Rtu, &req[..n]).unwrap(), None);
    }
    let mut two = req.clone();
    two.extend_from_slice(&req);
    assert_eq!(
        ok(Proto::Rtu, &two),
        (Frame::new(Proto::Rtu, 0, 1, hex("03 00 6B 00 03")), 8)
    );
    // FC 15/16: 9 + byte count.
    let fc15 = hex("01 0F 00 13 00 0A 02 CD 01 72 CB");
    for n in 0..fc15.len() {
        assert_eq!(decode(Proto::Rtu, &fc15[..n]).unwrap(), None);
    }
    assert_eq!(ok(Proto::Rtu, &fc15).1, 11);
    // FC 22: 10; FC 23: 13 + byte count.
    assert_eq!(ok(Proto::Rtu, &hex("01 16 00 04 00 F2 00 25 67 EE")).1, 10);
    let fc23 = hex("01 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF 46 91");
    assert_eq!(decode(Proto::Rtu, &fc23[..18]).unwrap(), None);
    assert_eq!(ok(Proto::Rtu, &fc23).1, 19);
}

#[test]
fn rtu_unknown_function_codes_end_at_their_crc() {
    // FC 07 (no data) and FC 43/14 (read device identification): delimited by the
    // first valid CRC, then answered with exception 01.
    assert_eq!(
        ok(Proto::Rtu, &hex("01 07 41 E2")),
        (Frame::new(Proto::Rtu, 0, 1, vec![7]), 4)
    );
    let mei = hex("01 2B 0E 01 00 70 77");
    assert_eq!(decode(Proto::Rtu, &mei[..6]).unwrap(), None);
    let (f, used) = ok(Proto::Rtu, &mei);
    assert_eq!((f.pdu, used), (hex("2B 0E 01 00"), 7));
    let mut cpu = cpu();
    assert_eq!(
        rtu(&mut cpu, &Map::q_default(), "01 2B 0E 01 00 70 77").unwrap(),
        "01 AB 01 9E F0"
    );
    // 256 bytes with no CRC anywhere: overrun, all dropped.
    let junk = vec![0x01, 0x64]
        .into_iter()
        .chain(std::iter::repeat_n(0u8, 300))
        .collect::<Vec<_>>();
    assert_eq!(err(Proto::Rtu, &junk), (FrameErrorKind::Overrun, 256, 302));
}

#[test]
fn rtu_bad_crc_drops_the_frame() {
    let mut req = hex("01 03 00 6B 00 03 74 17 01 03");
    req[7] = 0x18;
    assert_eq!(err(Proto::Rtu, &req), (FrameErrorKind::BadChecksum, 6, 8));
    // A byte count that would make the frame longer than 256 bytes: overrun.
    let mut long = hex("01 10 00 00 00 7F FF");
    long.resize(264, 0);
    assert_eq!(err(Proto::Rtu, &long).0, FrameErrorKind::Overrun);
}

#[test]
fn rtu_exact_frames() {
    // With silence-delimited frames, FC 08 may carry any data: 0x00 echoes it.
    let req = hex("01 08 00 00 01 02 03 04 A9 08");
    let f = decode_exact(Proto::Rtu, &req).unwrap();
    assert_eq!(f.pdu, hex("08 00 00 01 02 03 04"));
    let mut cpu = cpu();
    let r = softplc_modbus::serve(&mut Slave::new(1), &Map::q_default(), &f, &mut cpu).unwrap();
    assert_eq!(r, req);
    // Short, bad CRC, too long.
    assert_eq!(
        decode_exact(Proto::Rtu, &hex("01 03 00")).unwrap_err().kind,
        FrameErrorKind::BadChecksum
    );
    assert_eq!(
        decode_exact(Proto::Rtu, &hex("01 08 00 00 01 02 03 04 A9 09"))
            .unwrap_err()
            .kind,
        FrameErrorKind::BadChecksum
    );
    assert_eq!(
        decode_exact(Proto::Rtu, &[0; 257]).unwrap_err().kind,
        FrameErrorKind::Overrun
    );
    // TCP and ASCII: exactly one frame.
    assert!(decode_exact(Proto::Ascii, b":010300000001FB\r\n").is_ok());
    let e = decode_exact(Proto::Ascii, b":010300000001FB\r\n:").unwrap_err();
    assert_eq!((e.kind, e.skip), (FrameErrorKind::Junk, 18));
    assert_eq!(
        decode_exact(Proto::Tcp, &hex("00 01 00 00 00 06 01"))
            .unwrap_err()
            .kind,
        FrameErrorKind::BadHeader
    );
}

#[test]
fn ascii_frames() {
    let req = b":010300000001FB\r\n";
    let (f, used) = ok(Proto::Ascii, req);
    assert_eq!(
        (f.clone(), used),
        (Frame::new(Proto::Ascii, 0, 1, hex("03 00 00 00 01")), 17)
    );
    assert_eq!(f.encode(), req);
    for n in 0..req.len() {
        assert_eq!(decode(Proto::Ascii, &req[..n]).unwrap(), None);
    }
    // Lower-case hex is accepted; responses are upper case.
    assert_eq!(ok(Proto::Ascii, b":010300000001fb\r\n").0, f);
    // Junk before ':' is skipped up to the ':'.
    assert_eq!(
        err(Proto::Ascii, b"\r\nxx:0103"),
        (FrameErrorKind::Junk, 0, 4)
    );
    assert_eq!(err(Proto::Ascii, b"garbage"), (FrameErrorKind::Junk, 0, 7));
    // A ':' inside a frame restarts: the cut frame is junk.
    assert_eq!(
        err(Proto::Ascii, b":0103:010300000001FB\r\n"),
        (FrameErrorKind::Junk, 5, 5)
    );
    assert_eq!(ok(Proto::Ascii, &b":0103:010300000001FB\r\n"[5..]).0, f);
    // LF without CR, non-hex characters, odd digit count, too short.
    assert_eq!(
        err(Proto::Ascii, b":010300000001FB\n").0,
        FrameErrorKind::BadAscii
    );
    assert_eq!(
        err(Proto::Ascii, b":0103000G0001FB\r\n"),
        (FrameErrorKind::BadAscii, 8, 17)
    );
    assert_eq!(
        err(Proto::Ascii, b":010300000001F\r\n").0,
        FrameErrorKind::BadAscii
    );
    assert_eq!(err(Proto::Ascii, b":01FE\r\n").0, FrameErrorKind::BadAscii);
    // LRC mismatch.
    assert_eq!(
        err(Proto::Ascii, b":010300000001FC\r\n"),
        (FrameErrorKind::BadChecksum, 13, 17)
    );
    // 513 characters without an LF: overrun.
    let mut long = b":".to_vec();
    long.resize(513, b'0');
    assert_eq!(decode(Proto::Ascii, &long[..512]).unwrap(), None);
    assert_eq!(err(Proto::Ascii, &long).0, FrameErrorKind::Overrun);
}

#[test]
fn ascii_errors_are_counted_and_not_answered() {
    let (mut cpu, map) = (cpu(), Map::q_default());
    let mut slave = Slave::new(1);
    match slave.handle(&map, Proto::Ascii, b":010300000001FC\r\n", &mut cpu) {
        Step::Error(e) => assert_eq!(e.skip, 17),
        other => panic!("{other:?}"),
    }
    assert_eq!(
        slave.handle(&map, Proto::Ascii, b":0103", &mut cpu),
        Step::NeedMore
    );
    assert_eq!(slave.counters.bus_errors, 1);
    assert_eq!(slave.counters.bus_messages, 0);
}

#[test]
fn replies_keep_the_transport() {
    let f = Frame::new(Proto::Tcp, 0xFFFF, 0xFF, vec![3]);
    let r = f.reply(vec![0x83, 2]);
    assert_eq!(r.encode(), hex("FF FF 00 00 00 03 FF 83 02"));
    let f = Frame::new(Proto::Rtu, 0, 0x11, vec![0x83, 2]);
    assert_eq!(
        softplc_modbus::crc16(&f.encode()),
        0,
        "a frame with its CRC checks to 0"
    );
    let f = Frame::new(Proto::Ascii, 0, 0x11, vec![0x83, 2]);
    // 11 + 83 + 02 = 96 → LRC 6A.
    assert_eq!(f.encode(), b":1183026A\r\n");
}
