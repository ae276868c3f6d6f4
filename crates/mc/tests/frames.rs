//! Byte-exact request and response frames for every command in 3E binary, 4E
//! binary, 3E ASCII and 4E ASCII, built by hand from the protocol layout.

mod common;

use common::*;
use softplc_mc::*;

fn d(device: Device, number: u32) -> DeviceRef {
    DeviceRef::new(device, number)
}

struct Case {
    command: Command,
    /// Command, subcommand and request data in binary.
    bin: Vec<u8>,
    /// The same in ASCII.
    ascii: &'static str,
}

fn cases() -> Vec<Case> {
    use Device::*;
    vec![
        // 0401/0000 batch read D100, 3 words:
        // command 01 04, subcommand 00 00, device number 64 00 00, code A8, points 03 00.
        Case {
            command: Command::BatchRead {
                unit: Unit::Word,
                head: d(D, 100),
                points: 3,
            },
            bin: vec![0x01, 0x04, 0x00, 0x00, 0x64, 0x00, 0x00, 0xA8, 0x03, 0x00],
            ascii: "04010000D*0001000003",
        },
        // 0401/0001 batch read M100, 5 points (bit units).
        Case {
            command: Command::BatchRead {
                unit: Unit::Bit,
                head: d(M, 100),
                points: 5,
            },
            bin: vec![0x01, 0x04, 0x01, 0x00, 0x64, 0x00, 0x00, 0x90, 0x05, 0x00],
            ascii: "04010001M*0001000005",
        },
        // 0401/0000 batch read X20-X3F as 2 words: X numbers are hexadecimal in
        // ASCII ("000020"), binary 0x20.
        Case {
            command: Command::BatchRead {
                unit: Unit::Word,
                head: d(X, 0x20),
                points: 2,
            },
            bin: vec![0x01, 0x04, 0x00, 0x00, 0x20, 0x00, 0x00, 0x9C, 0x02, 0x00],
            ascii: "04010000X*0000200002",
        },
        // 1401/0000 batch write D0, 2 words 1234H ABCDH (little-endian words).
        Case {
            command: Command::BatchWriteWords {
                head: d(D, 0),
                values: vec![0x1234, 0xABCD],
            },
            bin: vec![
                0x01, 0x14, 0x00, 0x00, 0x00, 0x00, 0x00, 0xA8, 0x02, 0x00, 0x34, 0x12, 0xCD, 0xAB,
            ],
            ascii: "14010000D*00000000021234ABCD",
        },
        // 1401/0001 batch write Y20, 3 points ON OFF ON: binary two points a
        // byte, first in the high nibble (10 10); ASCII one character a point.
        Case {
            command: Command::BatchWriteBits {
                head: d(Y, 0x20),
                values: vec![true, false, true],
            },
            bin: vec![
                0x01, 0x14, 0x01, 0x00, 0x20, 0x00, 0x00, 0x9D, 0x03, 0x00, 0x10, 0x10,
            ],
            ascii: "14010001Y*0000200003101",
        },
        // 0403/0000 random read: 2 word points (D0, TN5), 1 dword point (W1A).
        Case {
            command: Command::RandomRead {
                words: vec![d(D, 0), d(TN, 5)],
                dwords: vec![d(W, 0x1A)],
            },
            bin: vec![
                0x03, 0x04, 0x00, 0x00, 0x02, 0x01, // counts
                0x00, 0x00, 0x00, 0xA8, // D0
                0x05, 0x00, 0x00, 0xC2, // TN5
                0x1A, 0x00, 0x00, 0xB4, // W1A
            ],
            ascii: "040300000201D*000000TN000005W*00001A",
        },
        // 1402/0000 random write: D10 = 0102H, dword ZR1F = 12345678H.
        Case {
            command: Command::RandomWriteWords {
                words: vec![(d(D, 10), 0x0102)],
                dwords: vec![(d(ZR, 0x1F), 0x1234_5678)],
            },
            bin: vec![
                0x02, 0x14, 0x00, 0x00, 0x01, 0x01, // counts
                0x0A, 0x00, 0x00, 0xA8, 0x02, 0x01, // D10 = 0102
                0x1F, 0x00, 0x00, 0xB0, 0x78, 0x56, 0x34, 0x12, // ZR1F
            ],
            ascii: "140200000101D*0000100102ZR00001F12345678",
        },
        // 1402/0001 random write bits: M5 ON, SB1A OFF (1 byte / 2 chars each).
        Case {
            command: Command::RandomWriteBits {
                points: vec![(d(M, 5), true), (d(SB, 0x1A), false)],
            },
            bin: vec![
                0x02, 0x14, 0x01, 0x00, 0x02, // count
                0x05, 0x00, 0x00, 0x90, 0x01, // M5 ON
                0x1A, 0x00, 0x00, 0xA1, 0x00, // SB1A OFF
            ],
            ascii: "1402000102M*00000501SB00001A00",
        },
        // 1001 remote RUN: mode 0001, clear mode 00, fixed 00.
        Case {
            command: Command::RemoteRun {
                force: false,
                clear: ClearMode::None,
            },
            bin: vec![0x01, 0x10, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00],
            ascii: "1001000000010000",
        },
        // 1001 remote RUN forced (0003), clear outside latch (01).
        Case {
            command: Command::RemoteRun {
                force: true,
                clear: ClearMode::OutsideLatch,
            },
            bin: vec![0x01, 0x10, 0x00, 0x00, 0x03, 0x00, 0x01, 0x00],
            ascii: "1001000000030100",
        },
        // 1002 remote STOP: fixed 0001.
        Case {
            command: Command::RemoteStop,
            bin: vec![0x02, 0x10, 0x00, 0x00, 0x01, 0x00],
            ascii: "100200000001",
        },
        // 1003 remote PAUSE, forced (0003).
        Case {
            command: Command::RemotePause { force: true },
            bin: vec![0x03, 0x10, 0x00, 0x00, 0x03, 0x00],
            ascii: "100300000003",
        },
        // 1005 remote latch clear: fixed 0001.
        Case {
            command: Command::RemoteLatchClear,
            bin: vec![0x05, 0x10, 0x00, 0x00, 0x01, 0x00],
            ascii: "100500000001",
        },
        // 1006 remote RESET: fixed 0001.
        Case {
            command: Command::RemoteReset,
            bin: vec![0x06, 0x10, 0x00, 0x00, 0x01, 0x00],
            ascii: "100600000001",
        },
        // 0101 read CPU model: no request data.
        Case {
            command: Command::ReadCpuModel,
            bin: vec![0x01, 0x01, 0x00, 0x00],
            ascii: "01010000",
        },
        // 1630 unlock, SLMP layout: length 0004, then the characters as they are
        // (also in ASCII).
        Case {
            command: Command::Unlock {
                password: b"ab12".to_vec(),
            },
            bin: vec![0x30, 0x16, 0x00, 0x00, 0x04, 0x00, b'a', b'b', b'1', b'2'],
            ascii: "163000000004ab12",
        },
        // 1631 lock.
        Case {
            command: Command::Lock {
                password: b"ab12".to_vec(),
            },
            bin: vec![0x31, 0x16, 0x00, 0x00, 0x04, 0x00, b'a', b'b', b'1', b'2'],
            ascii: "163100000004ab12",
        },
        // 0619 loopback: length 0005, "ABCDE".
        Case {
            command: Command::Loopback {
                data: b"ABCDE".to_vec(),
            },
            bin: vec![
                0x19, 0x06, 0x00, 0x00, 0x05, 0x00, b'A', b'B', b'C', b'D', b'E',
            ],
            ascii: "061900000005ABCDE",
        },
    ]
}

fn header(frame: Frame, code: DataCode) -> Header {
    Header {
        frame,
        code,
        timer: 0x10,
        ..Header::default()
    }
}

#[test]
fn every_command_in_every_frame_decodes_and_encodes_byte_exact() {
    let e4 = Frame::E4 { serial: 0x1234 };
    for case in cases() {
        let forms = [
            (bin3e(&case.bin), header(Frame::E3, DataCode::Binary)),
            (bin4e(&case.bin), header(e4, DataCode::Binary)),
            (ascii3e(case.ascii), header(Frame::E3, DataCode::Ascii)),
            (ascii4e(case.ascii), header(e4, DataCode::Ascii)),
        ];
        for (bytes, header) in forms {
            let want = Request {
                header,
                command: case.command.clone(),
            };
            let (got, used) = decode_request(&bytes)
                .unwrap_or_else(|e| panic!("{:?}: {e}", String::from_utf8_lossy(&bytes)));
            assert_eq!(got, want, "{:?}", String::from_utf8_lossy(&bytes));
            assert_eq!(used, bytes.len());
            assert_eq!(encode_request(&want), bytes, "{:?}", case.command);
        }
    }
}

#[test]
fn pymcprotocol_batch_read_d100_x3() {
    // pymcprotocol 0.3 `Type3E().batchread_wordunits("D100", 3)` with the default
    // access options (binary, network 0, PC FF, I/O 03FF, station 0, timer 4 =
    // 1 s) sends exactly these 21 bytes:
    let sent = [
        0x50, 0x00, // subheader
        0x00, // network No.
        0xFF, // PC No.
        0xFF, 0x03, // request destination module I/O No. 03FF
        0x00, // station No.
        0x0C, 0x00, // request data length 12
        0x04, 0x00, // monitoring timer 4 (x 250 ms)
        0x01, 0x04, // command 0401
        0x00, 0x00, // subcommand 0000 (word units)
        0x64, 0x00, 0x00, // device number 100
        0xA8, // device code D
        0x03, 0x00, // 3 points
    ];
    let (req, used) = decode_request(&sent).unwrap();
    assert_eq!(used, 21);
    assert_eq!(req.header.timer, 4);
    assert_eq!(
        req.command,
        Command::BatchRead {
            unit: Unit::Word,
            head: DeviceRef::new(Device::D, 100),
            points: 3
        }
    );
    // pymcprotocol reads the end code at offset 9 and the words from offset 11.
    let mut cpu = cpu();
    let mem = &mut cpu;
    for (i, v) in [1u16, 0xFFFF, 0x1234].iter().enumerate() {
        mem.set_word(softplc_core::device::DeviceKind::D, 100 + i as i64, *v)
            .unwrap();
    }
    let Served::Reply { response, .. } = serve(&sent, &mut cpu, &mut Session::new(), None) else {
        panic!()
    };
    assert_eq!(
        response,
        [
            0xD0, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, // subheader, echoed route
            0x08, 0x00, // response data length 8
            0x00, 0x00, // end code
            0x01, 0x00, 0xFF, 0xFF, 0x34, 0x12, // D100-D102
        ]
    );
}

#[test]
fn q_style_bare_password_is_accepted() {
    // The QnA/Q MC protocol manuals put the 4 password characters without a
    // length in front.
    let (req, _) =
        decode_request(&bin3e(&[0x30, 0x16, 0x00, 0x00, b'p', b'a', b's', b's'])).unwrap();
    assert_eq!(
        req.command,
        Command::Unlock {
            password: b"pass".to_vec()
        }
    );
    let (req, _) = decode_request(&ascii3e("16310000pass")).unwrap();
    assert_eq!(
        req.command,
        Command::Lock {
            password: b"pass".to_vec()
        }
    );
    // "0000" as a bare password, not an empty length-prefixed one.
    let (req, _) = decode_request(&ascii3e("163000000000")).unwrap();
    assert_eq!(
        req.command,
        Command::Unlock {
            password: b"0000".to_vec()
        }
    );
}

#[test]
fn ascii_device_code_may_be_padded_with_a_space_and_hex_may_be_lower_case() {
    let (req, _) = decode_request(&ascii3e("04010000D 0001000003")).unwrap();
    assert_eq!(
        req.command,
        Command::BatchRead {
            unit: Unit::Word,
            head: DeviceRef::new(Device::D, 100),
            points: 3
        }
    );
    let (req, _) = decode_request(&ascii3e("04010000W*00ff1a000a")).unwrap();
    assert_eq!(
        req.command,
        Command::BatchRead {
            unit: Unit::Word,
            head: DeviceRef::new(Device::W, 0xFF1A),
            points: 10
        }
    );
}

#[test]
fn every_device_code_binary_and_ascii() {
    // (device, binary code, ASCII code, number as the ASCII frame writes 26 decimal)
    use Device::*;
    let table: [(Device, u8, &str, &str); 28] = [
        (X, 0x9C, "X*", "00001A"),
        (Y, 0x9D, "Y*", "00001A"),
        (M, 0x90, "M*", "000026"),
        (L, 0x92, "L*", "000026"),
        (F, 0x93, "F*", "000026"),
        (V, 0x94, "V*", "000026"),
        (B, 0xA0, "B*", "00001A"),
        (SB, 0xA1, "SB", "00001A"),
        (S, 0x98, "S*", "000026"),
        (SM, 0x91, "SM", "000026"),
        (TS, 0xC1, "TS", "000026"),
        (TC, 0xC0, "TC", "000026"),
        (TN, 0xC2, "TN", "000026"),
        (SS, 0xC7, "SS", "000026"),
        (SC, 0xC6, "SC", "000026"),
        (SN, 0xC8, "SN", "000026"),
        (CS, 0xC4, "CS", "000026"),
        (CC, 0xC3, "CC", "000026"),
        (CN, 0xC5, "CN", "000026"),
        (D, 0xA8, "D*", "000026"),
        (W, 0xB4, "W*", "00001A"),
        (SW, 0xB5, "SW", "00001A"),
        (SD, 0xA9, "SD", "000026"),
        (Z, 0xCC, "Z*", "000026"),
        (R, 0xAF, "R*", "000026"),
        (ZR, 0xB0, "ZR", "00001A"),
        (DX, 0xA2, "DX", "00001A"),
        (DY, 0xA3, "DY", "00001A"),
    ];
    for (dev, bin, ascii, num) in table {
        assert_eq!(dev.binary_code(), bin);
        assert_eq!(&dev.ascii_code(), ascii.as_bytes());
        let want = Command::BatchRead {
            unit: Unit::Word,
            head: DeviceRef::new(dev, 26),
            points: 1,
        };
        let (req, _) =
            decode_request(&bin3e(&[0x01, 0x04, 0x00, 0x00, 26, 0, 0, bin, 1, 0])).unwrap();
        assert_eq!(req.command, want, "{dev}");
        let (req, _) = decode_request(&ascii3e(&format!("04010000{ascii}{num}0001"))).unwrap();
        assert_eq!(req.command, want, "{dev}");
    }
}

#[test]
fn device_names_parse_in_their_numbering() {
    let p = |s| DeviceRef::parse(s).map(|d| d.to_string());
    assert_eq!(p("D100").as_deref(), Some("D100"));
    assert_eq!(p("XFF").as_deref(), Some("XFF"));
    assert_eq!(p("x1f").as_deref(), Some("X1F"));
    assert_eq!(p("SB1F").as_deref(), Some("SB1F"));
    assert_eq!(p("SM400").as_deref(), Some("SM400"));
    assert_eq!(p("SN3").as_deref(), Some("SN3"));
    assert_eq!(p("ZR1F").as_deref(), Some("ZR1F"));
    assert_eq!(DeviceRef::parse("ZR10").unwrap().number, 16);
    assert_eq!(p("DX10").as_deref(), Some("DX10"));
    assert_eq!(p("D1F"), None);
    assert_eq!(p("Q1"), None);
    assert_eq!(p("M"), None);
}

// --- responses ---

fn h(frame: Frame, code: DataCode) -> Header {
    Header {
        frame,
        code,
        ..Header::default()
    }
}

#[test]
fn normal_responses_byte_exact() {
    let b3 = h(Frame::E3, DataCode::Binary);
    let b4 = h(Frame::E4 { serial: 0x1234 }, DataCode::Binary);
    let a3 = h(Frame::E3, DataCode::Ascii);
    let ok = |d| Response::Ok(d);
    // Writes and remote operations: no data.
    assert_eq!(encode_response(&b3, &ok(ResponseData::None)), bin3e_ok(&[]));
    assert_eq!(encode_response(&b4, &ok(ResponseData::None)), bin4e_ok(&[]));
    assert_eq!(
        encode_response(&a3, &ok(ResponseData::None)),
        ascii3e_ok("")
    );
    // Words.
    let words = ok(ResponseData::Words(vec![0x1234, 0x00FF]));
    assert_eq!(
        encode_response(&b3, &words),
        bin3e_ok(&[0x34, 0x12, 0xFF, 0x00])
    );
    assert_eq!(
        encode_response(&b4, &words),
        bin4e_ok(&[0x34, 0x12, 0xFF, 0x00])
    );
    assert_eq!(encode_response(&a3, &words), ascii3e_ok("123400FF"));
    // Bits: 5 points 1 0 1 1 1 -> 10 11 10 (odd point padded with a 0 nibble).
    let bits = ok(ResponseData::Bits(vec![true, false, true, true, true]));
    assert_eq!(encode_response(&b3, &bits), bin3e_ok(&[0x10, 0x11, 0x10]));
    assert_eq!(encode_response(&a3, &bits), ascii3e_ok("10111"));
    // Random read: words then dwords.
    let random = ok(ResponseData::Random {
        words: vec![0x0102],
        dwords: vec![0x1234_5678],
    });
    assert_eq!(
        encode_response(&b3, &random),
        bin3e_ok(&[0x02, 0x01, 0x78, 0x56, 0x34, 0x12])
    );
    assert_eq!(encode_response(&a3, &random), ascii3e_ok("010212345678"));
    // CPU model: 16 characters, then the model code (binary 42 00, ASCII "0042").
    let model = ok(ResponseData::CpuModel {
        name: *b"Q06HCPU         ",
        code: 0x42,
    });
    let mut want = b"Q06HCPU         ".to_vec();
    want.extend_from_slice(&[0x42, 0x00]);
    assert_eq!(encode_response(&b3, &model), bin3e_ok(&want));
    assert_eq!(
        encode_response(&a3, &model),
        ascii3e_ok("Q06HCPU         0042")
    );
    // Loopback: length then the data.
    let lb = ok(ResponseData::Loopback(b"ABCDE".to_vec()));
    assert_eq!(
        encode_response(&b3, &lb),
        bin3e_ok(&[0x05, 0x00, b'A', b'B', b'C', b'D', b'E'])
    );
    assert_eq!(encode_response(&a3, &lb), ascii3e_ok("0005ABCDE"));
}

#[test]
fn error_responses_byte_exact() {
    let err = Response::Error {
        end_code: EndCode::COMMAND,
        command: 0x0401,
        subcommand: 0x0002,
    };
    assert_eq!(
        encode_response(&h(Frame::E3, DataCode::Binary), &err),
        bin3e_err(0xC059, 0x0401, 0x0002)
    );
    assert_eq!(
        encode_response(&h(Frame::E3, DataCode::Ascii), &err),
        ascii3e_err(0xC059, 0x0401, 0x0002)
    );
    // 4E binary: D4 00, serial, 00 00, route, length 11, end code, error info.
    assert_eq!(
        encode_response(&h(Frame::E4 { serial: 0xBEEF }, DataCode::Binary), &err),
        [
            0xD4, 0x00, 0xEF, 0xBE, 0x00, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0B, 0x00, 0x59,
            0xC0, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x01, 0x04, 0x02, 0x00
        ]
    );
    // 4E ASCII.
    assert_eq!(
        encode_response(&h(Frame::E4 { serial: 0xBEEF }, DataCode::Ascii), &err),
        b"D400BEEF000000FF03FF000016C05900FF03FF0004010002".to_vec()
    );
}

#[test]
fn responses_echo_the_route_of_the_request() {
    let hdr = Header {
        network: 0x12,
        pc: 0x34,
        io: 0x03E1,
        station: 0x05,
        ..Header::default()
    };
    let out = encode_response(&hdr, &Response::Ok(ResponseData::None));
    assert_eq!(
        out,
        [0xD0, 0x00, 0x12, 0x34, 0xE1, 0x03, 0x05, 0x02, 0x00, 0x00, 0x00]
    );
}

#[test]
fn responses_decode_for_clients() {
    for code in [DataCode::Binary, DataCode::Ascii] {
        for frame in [Frame::E3, Frame::E4 { serial: 7 }] {
            let hdr = h(frame, code);
            let out = encode_response(&hdr, &Response::Ok(ResponseData::Words(vec![1, 0xFFFF])));
            let (r, used) = decode_response(&out).unwrap();
            assert_eq!(used, out.len());
            assert_eq!(r.header, hdr);
            assert_eq!(r.end_code, EndCode::OK);
            assert_eq!(r.words(), Some(vec![1, 0xFFFF]));
            let out = encode_response(
                &hdr,
                &Response::Ok(ResponseData::Bits(vec![true, false, true])),
            );
            assert_eq!(
                decode_response(&out).unwrap().0.bits(3),
                Some(vec![true, false, true])
            );
            let out = encode_response(
                &hdr,
                &Response::Error {
                    end_code: EndCode::PASSWORD_LOCKED,
                    command: 0x0401,
                    subcommand: 1,
                },
            );
            let (r, _) = decode_response(&out).unwrap();
            assert_eq!(r.end_code, EndCode::PASSWORD_LOCKED);
            let e = r.error.unwrap();
            assert_eq!((e.network, e.pc, e.io, e.station), (0, 0xFF, 0x03FF, 0));
            assert_eq!((e.command, e.subcommand), (0x0401, 1));
            // Every proper prefix is incomplete.
            for n in 0..out.len() {
                assert_eq!(decode_response(&out[..n]), Err(FrameError::Incomplete));
            }
        }
    }
}

#[test]
fn back_to_back_frames_are_delimited_by_their_length() {
    let mut buf = bin3e(&[0x02, 0x10, 0x00, 0x00, 0x01, 0x00]);
    let first = buf.len();
    buf.extend_from_slice(&ascii3e("01010000"));
    let (a, used) = decode_request(&buf).unwrap();
    assert_eq!(a.command, Command::RemoteStop);
    assert_eq!(used, first);
    let (b, used2) = decode_request(&buf[used..]).unwrap();
    assert_eq!(b.command, Command::ReadCpuModel);
    assert_eq!(used + used2, buf.len());
}

#[test]
fn every_proper_prefix_of_a_request_is_incomplete() {
    for case in cases() {
        for bytes in [
            bin3e(&case.bin),
            bin4e(&case.bin),
            ascii3e(case.ascii),
            ascii4e(case.ascii),
        ] {
            for n in 0..bytes.len() {
                assert_eq!(
                    decode_request(&bytes[..n]),
                    Err(FrameError::Incomplete),
                    "{:?}",
                    String::from_utf8_lossy(&bytes[..n])
                );
            }
        }
    }
}
