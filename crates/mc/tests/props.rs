//! Properties: decoding never panics, valid requests round-trip, serving never
//! panics and always answers a delimited frame.

mod common;

use proptest::collection::vec;
use proptest::prelude::*;
use softplc_mc::*;

fn any_header() -> impl Strategy<Value = Header> {
    (
        prop_oneof![
            Just(Frame::E3),
            any::<u16>().prop_map(|serial| Frame::E4 { serial })
        ],
        prop_oneof![Just(DataCode::Binary), Just(DataCode::Ascii)],
        any::<u8>(),
        any::<u8>(),
        any::<u16>(),
        any::<u8>(),
        any::<u16>(),
    )
        .prop_map(|(frame, code, network, pc, io, station, timer)| Header {
            frame,
            code,
            network,
            pc,
            io,
            station,
            timer,
        })
}

/// Device numbers an ASCII frame can carry too (decimal: 6 digits).
fn any_device() -> impl Strategy<Value = DeviceRef> {
    (0..Device::ALL.len(), 0u32..=999_999).prop_map(|(i, n)| DeviceRef::new(Device::ALL[i], n))
}

fn bit_device() -> impl Strategy<Value = DeviceRef> {
    any_device().prop_filter("bit device", |d| d.device.is_bit())
}

fn any_command() -> impl Strategy<Value = Command> {
    prop_oneof![
        (any_device(), 1u16..=960).prop_map(|(head, points)| Command::BatchRead {
            unit: Unit::Word,
            head,
            points
        }),
        (bit_device(), 1u16..=7168).prop_map(|(head, points)| Command::BatchRead {
            unit: Unit::Bit,
            head,
            points
        }),
        (any_device(), vec(any::<u16>(), 1..=960))
            .prop_map(|(head, values)| Command::BatchWriteWords { head, values }),
        (bit_device(), vec(any::<bool>(), 1..=7168))
            .prop_map(|(head, values)| Command::BatchWriteBits { head, values }),
        (vec(any_device(), 0..=96), vec(any_device(), 0..=96))
            .prop_filter("1 point or more", |(w, d)| !w.is_empty() || !d.is_empty())
            .prop_map(|(words, dwords)| Command::RandomRead { words, dwords }),
        (
            vec((any_device(), any::<u16>()), 0..=80),
            vec((any_device(), any::<u32>()), 0..=68)
        )
            .prop_filter("1 point or more", |(w, d)| !w.is_empty() || !d.is_empty())
            .prop_map(|(words, dwords)| Command::RandomWriteWords { words, dwords }),
        vec((bit_device(), any::<bool>()), 1..=188)
            .prop_map(|points| Command::RandomWriteBits { points }),
        (
            any::<bool>(),
            prop_oneof![
                Just(ClearMode::None),
                Just(ClearMode::OutsideLatch),
                Just(ClearMode::All)
            ]
        )
            .prop_map(|(force, clear)| Command::RemoteRun { force, clear }),
        Just(Command::RemoteStop),
        any::<bool>().prop_map(|force| Command::RemotePause { force }),
        Just(Command::RemoteLatchClear),
        Just(Command::RemoteReset),
        Just(Command::ReadCpuModel),
        vec(any::<u8>(), 1..=32).prop_map(|password| Command::Unlock { password }),
        vec(any::<u8>(), 1..=32).prop_map(|password| Command::Lock { password }),
        vec(any::<u8>(), 1..=960).prop_map(|data| Command::Loopback { data }),
        (any::<u32>(), 1u16..=960, any::<u16>()).prop_map(|(start, words, module)| {
            Command::BufferRead {
                start: start & !1,
                bytes: words * 2,
                module,
            }
        }),
        (any::<u32>(), any::<u16>(), vec(any::<u16>(), 1..=960)).prop_map(
            |(start, module, values)| Command::BufferWrite {
                start: start & !1,
                module,
                values,
            }
        ),
        extended_command(),
    ]
}

/// Buffer memory `U<n>\G<addr>` (units an ASCII frame carries: 3 hex
/// digits) and plain devices in the device extension specification.
fn extended_device() -> impl Strategy<Value = DeviceRef> {
    prop_oneof![
        (0u16..=0xFFF, 0u32..=999_999).prop_map(|(u, n)| DeviceRef::module(u, n)),
        any_device(),
    ]
}

fn extended_command() -> impl Strategy<Value = Command> {
    prop_oneof![
        (extended_device(), 1u16..=960).prop_map(|(head, points)| Command::BatchRead {
            unit: Unit::Word,
            head,
            points
        }),
        (extended_device(), vec(any::<u16>(), 1..=960))
            .prop_map(|(head, values)| Command::BatchWriteWords { head, values }),
        (
            vec(extended_device(), 1..=96),
            vec(extended_device(), 0..=96)
        )
            .prop_map(|(words, dwords)| Command::RandomRead { words, dwords }),
        vec((extended_device(), any::<u16>()), 1..=80).prop_map(|words| {
            Command::RandomWriteWords {
                words,
                dwords: vec![],
            }
        }),
    ]
    .prop_map(|c| Command::Extended(Box::new(c)))
}

fn any_request() -> impl Strategy<Value = Request> {
    (any_header(), any_command()).prop_map(|(header, command)| Request { header, command })
}

/// A well-delimited frame with an arbitrary body, so that the body decoder is
/// exercised rather than the subheader check.
fn framed_garbage() -> impl Strategy<Value = Vec<u8>> {
    (
        any_header(),
        any::<u16>(),
        any::<u16>(),
        vec(any::<u8>(), 0..64),
    )
        .prop_map(|(header, command, sub, tail)| {
            let mut bytes = encode_request(&Request {
                header,
                command: Command::ReadCpuModel,
            });
            // Replace command and subcommand, append the tail, fix the length.
            let (len_at, w) = match (header.frame, header.code) {
                (Frame::E3, DataCode::Binary) => (7, 2),
                (Frame::E4 { .. }, DataCode::Binary) => (11, 2),
                (Frame::E3, DataCode::Ascii) => (14, 4),
                (Frame::E4 { .. }, DataCode::Ascii) => (22, 4),
            };
            let body_at = len_at + w + w; // after the timer
            bytes.truncate(body_at);
            match header.code {
                DataCode::Binary => {
                    bytes.extend_from_slice(&command.to_le_bytes());
                    bytes.extend_from_slice(&sub.to_le_bytes());
                    bytes.extend_from_slice(&tail);
                    let len = (bytes.len() - len_at - 2) as u16;
                    bytes[len_at..len_at + 2].copy_from_slice(&len.to_le_bytes());
                }
                DataCode::Ascii => {
                    bytes.extend_from_slice(format!("{command:04X}{sub:04X}").as_bytes());
                    // Mostly hex digits and device-code letters.
                    bytes.extend(
                        tail.iter()
                            .map(|b| b"0123456789ABCDEF*DMXYZRSWT "[*b as usize % 27]),
                    );
                    let len = format!("{:04X}", bytes.len() - len_at - 4);
                    bytes[len_at..len_at + 4].copy_from_slice(len.as_bytes());
                }
            }
            bytes
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn decode_never_panics(bytes in vec(any::<u8>(), 0..256)) {
        let _ = decode_request(&bytes);
        let _ = decode_response(&bytes);
    }

    #[test]
    fn decode_never_panics_on_ascii_text(bytes in vec(prop_oneof![Just(b'5'), Just(b'0'), Just(b'4'), Just(b'F'), any::<u8>()], 0..128)) {
        let _ = decode_request(&bytes);
    }

    #[test]
    fn valid_requests_round_trip(req in any_request()) {
        let bytes = encode_request(&req);
        let (got, used) = decode_request(&bytes).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert_eq!(used, bytes.len());
        prop_assert_eq!(got, req);
        // Every proper prefix asks for more (checked on a few cut points).
        for cut in [0, 1, bytes.len() / 2, bytes.len() - 1] {
            prop_assert_eq!(decode_request(&bytes[..cut]), Err(FrameError::Incomplete));
        }
    }

    #[test]
    fn delimited_frames_are_decoded_or_answered(bytes in framed_garbage()) {
        match decode_request(&bytes) {
            Ok((_, used)) => prop_assert_eq!(used, bytes.len()),
            Err(FrameError::Rejected(r)) => {
                prop_assert_eq!(r.used, bytes.len());
                prop_assert!(!r.end_code.is_ok());
                let (resp, _) = decode_response(&r.response()).unwrap();
                prop_assert_eq!(resp.end_code, r.end_code);
            }
            Err(e) => prop_assert!(false, "{e}"),
        }
    }

    #[test]
    fn responses_round_trip_their_header_and_end_code(header in any_header(), code in any::<u16>(), cmd in any::<u16>(), sub in any::<u16>()) {
        let header = Header { timer: 0, ..header };
        let resp = if code == 0 {
            Response::Ok(ResponseData::Words(vec![cmd, sub]))
        } else {
            Response::Error { end_code: EndCode(code), command: cmd, subcommand: sub }
        };
        let out = encode_response(&header, &resp);
        let (r, used) = decode_response(&out).unwrap();
        prop_assert_eq!(used, out.len());
        prop_assert_eq!(r.header, header);
        prop_assert_eq!(r.end_code, EndCode(code));
        if code == 0 {
            prop_assert_eq!(r.words(), Some(vec![cmd, sub]));
        } else {
            let e = r.error.unwrap();
            prop_assert_eq!((e.command, e.subcommand), (cmd, sub));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Any valid request or delimited garbage, served on a CPU, gets an answer
    /// that decodes, whatever state the CPU is in.
    #[test]
    fn serving_always_answers(reqs in vec(prop_oneof![any_request().prop_map(|r| encode_request(&r)), framed_garbage()], 1..8), locked in any::<bool>()) {
        let mut cpu = common::cpu();
        let mut session = Session::new();
        let pw = locked.then_some("ab12");
        for bytes in reqs {
            match serve(&bytes, &mut cpu, &mut session, pw) {
                Served::Reply { response, used } => {
                    prop_assert_eq!(used, bytes.len());
                    decode_response(&response).unwrap();
                }
                other => prop_assert!(false, "{other:?}"),
            }
            cpu.scan();
        }
    }
}
