//! Every end code softplc produces, and the malformed frames that close the
//! connection instead.

mod common;

use common::*;
use softplc_core::device::DeviceKind;
use softplc_core::engine::CpuState;
use softplc_mc::*;

/// Decodes a frame that must be refused; returns the end code and checks that the
/// error response is well formed and names the command.
fn rejected(bytes: &[u8]) -> EndCode {
    match decode_request(bytes) {
        Err(FrameError::Rejected(r)) => {
            assert_eq!(r.used, bytes.len());
            let (resp, used) = decode_response(&r.response()).unwrap();
            assert_eq!(used, r.response().len());
            assert_eq!(resp.end_code, r.end_code);
            let info = resp.error.unwrap();
            assert_eq!((info.command, info.subcommand), (r.command, r.subcommand));
            r.end_code
        }
        other => panic!("{:?}: {other:?}", String::from_utf8_lossy(bytes)),
    }
}

/// Serves a frame on `cpu`; returns the end code of the answer.
fn served(
    cpu: &mut softplc_core::engine::Cpu,
    s: &mut Session,
    pw: Option<&str>,
    bytes: &[u8],
) -> EndCode {
    match serve(bytes, cpu, s, pw) {
        Served::Reply { response, used } => {
            assert_eq!(used, bytes.len());
            decode_response(&response).unwrap().0.end_code
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn c050_ascii_not_hexadecimal() {
    // A decimal device number with a hex digit, a hex number with a G, a points
    // field with a space, a non-hex monitoring timer.
    assert_eq!(
        rejected(&ascii3e("04010000D*00010A0003")),
        EndCode::ASCII_DATA
    );
    assert_eq!(
        rejected(&ascii3e("04010000X*00001G0003")),
        EndCode::ASCII_DATA
    );
    assert_eq!(
        rejected(&ascii3e("04010000D*000100 003")),
        EndCode::ASCII_DATA
    );
    assert_eq!(
        rejected(b"500000FF03FF000018001Z04010000D*0001000003"),
        EndCode::ASCII_DATA
    );
    // Bit data that is not even hexadecimal.
    assert_eq!(
        rejected(&ascii3e("14010001M*00000000021x")),
        EndCode::ASCII_DATA
    );
}

#[test]
fn c051_batch_bit_points() {
    // 7168 points is the limit in bit units (7169 = 1C01H); 0 is refused too.
    let read = |n: u16| {
        let [lo, hi] = n.to_le_bytes();
        bin3e(&[0x01, 0x04, 0x01, 0x00, 0, 0, 0, 0x90, lo, hi])
    };
    assert!(decode_request(&read(7168)).is_ok());
    assert_eq!(rejected(&read(7169)), EndCode::BIT_POINTS);
    assert_eq!(rejected(&read(0)), EndCode::BIT_POINTS);
    assert_eq!(
        rejected(&ascii3e("14010001M*0000001C01")),
        EndCode::BIT_POINTS
    );
}

#[test]
fn c052_batch_word_points() {
    // 960 = 03C0H words is the limit; 961 = 03C1H is refused.
    assert!(decode_request(&bin3e(&[0x01, 0x04, 0x00, 0x00, 0, 0, 0, 0xA8, 0xC0, 0x03])).is_ok());
    assert_eq!(
        rejected(&bin3e(&[0x01, 0x04, 0x00, 0x00, 0, 0, 0, 0xA8, 0xC1, 0x03])),
        EndCode::WORD_POINTS
    );
    assert_eq!(
        rejected(&ascii3e("04010000D*0000000000")),
        EndCode::WORD_POINTS
    );
    // Batch write: checked before the data is read.
    assert_eq!(
        rejected(&ascii3e("14010000D*00000003C1")),
        EndCode::WORD_POINTS
    );
}

#[test]
fn c053_random_bit_points() {
    let frame = |n: u8| {
        let mut body = vec![0x02, 0x14, 0x01, 0x00, n];
        for i in 0..n {
            body.extend_from_slice(&[i, 0, 0, 0x90, 1]);
        }
        bin3e(&body)
    };
    assert!(decode_request(&frame(188)).is_ok());
    assert_eq!(rejected(&frame(189)), EndCode::RANDOM_BIT_POINTS);
    assert_eq!(rejected(&frame(0)), EndCode::RANDOM_BIT_POINTS);
}

#[test]
fn c054_random_word_points() {
    let read = |nw: u8, nd: u8| {
        let mut body = vec![0x03, 0x04, 0x00, 0x00, nw, nd];
        for i in 0..nw as u16 + nd as u16 {
            body.extend_from_slice(&[i as u8, (i >> 8) as u8, 0, 0xA8]);
        }
        bin3e(&body)
    };
    assert!(decode_request(&read(192, 0)).is_ok());
    assert!(decode_request(&read(100, 92)).is_ok());
    assert_eq!(rejected(&read(100, 93)), EndCode::RANDOM_WORD_POINTS);
    assert_eq!(rejected(&read(0, 0)), EndCode::RANDOM_WORD_POINTS);
    // Random write: words x 12 + dwords x 14 <= 1920 (160 words, or 137 dwords).
    let write = |nw: u8, nd: u8| {
        let mut body = vec![0x02, 0x14, 0x00, 0x00, nw, nd];
        for i in 0..nw {
            body.extend_from_slice(&[i, 0, 0, 0xA8, 1, 0]);
        }
        for i in 0..nd {
            body.extend_from_slice(&[i, 1, 0, 0xA8, 1, 0, 0, 0]);
        }
        bin3e(&body)
    };
    assert!(decode_request(&write(160, 0)).is_ok());
    assert_eq!(rejected(&write(161, 0)), EndCode::RANDOM_WORD_POINTS);
    assert!(decode_request(&write(0, 137)).is_ok());
    assert_eq!(rejected(&write(0, 138)), EndCode::RANDOM_WORD_POINTS);
    assert_eq!(rejected(&write(0, 0)), EndCode::RANDOM_WORD_POINTS);
}

#[test]
fn c056_device_range() {
    let mut cpu = cpu();
    let mut s = Session::new();
    // D has 12288 points: D12287 x 1 is fine, x 2 runs past the end.
    assert_eq!(
        served(&mut cpu, &mut s, None, &ascii3e("04010000D*0122870001")),
        EndCode::OK
    );
    assert_eq!(
        served(&mut cpu, &mut s, None, &ascii3e("04010000D*0122870002")),
        EndCode::ADDRESS_RANGE
    );
    // M8191 + 16 points (one word) runs past M's 8192 points.
    assert_eq!(
        served(&mut cpu, &mut s, None, &ascii3e("04010000M*0081910001")),
        EndCode::ADDRESS_RANGE
    );
    // Retentive timers have 0 points by default.
    assert_eq!(
        served(&mut cpu, &mut s, None, &ascii3e("04010000SN0000000001")),
        EndCode::ADDRESS_RANGE
    );
    // The largest 3-byte number.
    assert_eq!(
        served(
            &mut cpu,
            &mut s,
            None,
            &bin3e(&[0x01, 0x04, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xB0, 1, 0])
        ),
        EndCode::ADDRESS_RANGE
    );
    // Writes are checked the same way and write nothing.
    assert_eq!(
        served(
            &mut cpu,
            &mut s,
            None,
            &ascii3e("14010000D*01228700020001FFFF")
        ),
        EndCode::ADDRESS_RANGE
    );
    assert_eq!(cpu.memory().get_word(DeviceKind::D, 12287).unwrap(), 0);
}

#[test]
fn c058_ascii_length_mismatch() {
    // One character too many and one too few for a batch read.
    assert_eq!(
        rejected(&ascii3e("04010000D*00010000031")),
        EndCode::ASCII_LENGTH
    );
    assert_eq!(
        rejected(&ascii3e("04010000D*000100000")),
        EndCode::ASCII_LENGTH
    );
    // The data length covers not even the monitoring timer and command.
    assert_eq!(rejected(b"500000FF03FF00000200"), EndCode::ASCII_LENGTH);
}

#[test]
fn c059_unknown_command_or_subcommand() {
    // 0402 does not exist; 0401 has no subcommand 0002 for a Q CPU (iQ-R format).
    assert_eq!(
        rejected(&bin3e(&[0x02, 0x04, 0x00, 0x00])),
        EndCode::COMMAND
    );
    assert_eq!(
        rejected(&bin3e(&[
            0x01, 0x04, 0x02, 0x00, 0x64, 0, 0, 0, 0xA8, 0, 3, 0
        ])),
        EndCode::COMMAND
    );
    assert_eq!(rejected(&ascii3e("100200010001")), EndCode::COMMAND);
    assert_eq!(rejected(&ascii3e("04030001")), EndCode::COMMAND);
    // The error information names the command as received.
    let Err(FrameError::Rejected(r)) = decode_request(&bin3e(&[0x34, 0x12, 0x78, 0x56])) else {
        panic!()
    };
    assert_eq!((r.command, r.subcommand), (0x1234, 0x5678));
    assert_eq!(r.response(), bin3e_err(0xC059, 0x1234, 0x5678));
}

#[test]
fn c05b_unknown_device() {
    // Binary code 00 and 9F; ASCII "QQ", and iQ-R's "LTN" style is not a Q code.
    assert_eq!(
        rejected(&bin3e(&[0x01, 0x04, 0x00, 0x00, 0, 0, 0, 0x00, 1, 0])),
        EndCode::DEVICE
    );
    assert_eq!(
        rejected(&bin3e(&[0x01, 0x04, 0x00, 0x00, 0, 0, 0, 0x9F, 1, 0])),
        EndCode::DEVICE
    );
    assert_eq!(rejected(&ascii3e("04010000QQ0000000001")), EndCode::DEVICE);
    assert_eq!(rejected(&ascii3e("04010000d*0000000001")), EndCode::DEVICE);
}

#[test]
fn c05c_request_contents() {
    // Bit units on a word device (batch read, batch write, random write).
    assert_eq!(
        rejected(&ascii3e("04010001D*0000000001")),
        EndCode::REQUEST_CONTENTS
    );
    assert_eq!(
        rejected(&ascii3e("14010001TN00000000011")),
        EndCode::REQUEST_CONTENTS
    );
    assert_eq!(
        rejected(&ascii3e("1402000101D*00000001")),
        EndCode::REQUEST_CONTENTS
    );
    // RUN mode 0002, clear mode 03; PAUSE mode 0000.
    assert_eq!(
        rejected(&ascii3e("1001000000020000")),
        EndCode::REQUEST_CONTENTS
    );
    assert_eq!(
        rejected(&ascii3e("1001000000010300")),
        EndCode::REQUEST_CONTENTS
    );
    assert_eq!(
        rejected(&ascii3e("100300000000")),
        EndCode::REQUEST_CONTENTS
    );
    // Loopback of 0 or 961 bytes; a 33-character password.
    assert_eq!(
        rejected(&ascii3e("061900000000")),
        EndCode::REQUEST_CONTENTS
    );
    let mut big = "061900000".to_string() + "3C1";
    big.push_str(&"A".repeat(961));
    assert_eq!(rejected(&ascii3e(&big)), EndCode::REQUEST_CONTENTS);
    let pw = format!("163000000021{}", "x".repeat(33));
    assert_eq!(rejected(&ascii3e(&pw)), EndCode::REQUEST_CONTENTS);
}

#[test]
fn c05f_not_executable_in_this_state() {
    let mut cpu = cpu();
    let mut s = Session::new();
    let stop = bin3e(&[0x02, 0x10, 0x00, 0x00, 0x01, 0x00]);
    let pause = bin3e(&[0x03, 0x10, 0x00, 0x00, 0x01, 0x00]);
    let run = bin3e(&[0x01, 0x10, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00]);
    assert_eq!(served(&mut cpu, &mut s, None, &stop), EndCode::OK);
    // PAUSE only from RUN.
    assert_eq!(
        served(&mut cpu, &mut s, None, &pause),
        EndCode::NOT_EXECUTABLE
    );
    assert_eq!(cpu.state(), CpuState::Stop);
    // A stop error (X1: division by zero) holds the CPU in STOP until RESET.
    assert_eq!(served(&mut cpu, &mut s, None, &run), EndCode::OK);
    cpu.set_input(1, true);
    cpu.scan();
    assert_eq!(cpu.state(), CpuState::Stop);
    assert_eq!(
        served(&mut cpu, &mut s, None, &run),
        EndCode::NOT_EXECUTABLE
    );
    assert_eq!(cpu.state(), CpuState::Stop);
}

#[test]
fn c060_bit_data() {
    // Binary nibble 2, ASCII character '2', random-write value 02.
    assert_eq!(
        rejected(&bin3e(&[0x01, 0x14, 0x01, 0x00, 0, 0, 0, 0x90, 2, 0, 0x12])),
        EndCode::BIT_DATA
    );
    assert_eq!(
        rejected(&ascii3e("14010001M*000000000212")),
        EndCode::BIT_DATA
    );
    assert_eq!(
        rejected(&ascii3e("1402000101M*00000002")),
        EndCode::BIT_DATA
    );
}

#[test]
fn c061_binary_length_mismatch() {
    // Batch read with a byte missing and with a byte extra.
    assert_eq!(
        rejected(&bin3e(&[0x01, 0x04, 0x00, 0x00, 0x64, 0, 0, 0xA8, 3])),
        EndCode::DATA_LENGTH
    );
    assert_eq!(
        rejected(&bin3e(&[0x01, 0x04, 0x00, 0x00, 0x64, 0, 0, 0xA8, 3, 0, 0])),
        EndCode::DATA_LENGTH
    );
    // Batch write of 3 words carrying 2.
    assert_eq!(
        rejected(&bin3e(&[
            0x01, 0x14, 0x00, 0x00, 0, 0, 0, 0xA8, 3, 0, 1, 0, 2, 0
        ])),
        EndCode::DATA_LENGTH
    );
    // STOP without its fixed value; no command at all; a 1-byte body.
    assert_eq!(
        rejected(&bin3e(&[0x02, 0x10, 0x00, 0x00])),
        EndCode::DATA_LENGTH
    );
    assert_eq!(rejected(&bin3e(&[])), EndCode::DATA_LENGTH);
    assert_eq!(
        rejected(&[0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x01, 0x00, 0x10]),
        EndCode::DATA_LENGTH
    );
    // Loopback announcing 5 bytes, carrying 4.
    assert_eq!(
        rejected(&bin3e(&[
            0x19, 0x06, 0x00, 0x00, 5, 0, b'A', b'B', b'C', b'D'
        ])),
        EndCode::DATA_LENGTH
    );
}

#[test]
fn c200_c201_remote_password() {
    let mut cpu = cpu();
    let mut s = Session::new();
    let pw = Some("ab12");
    let read = ascii3e("04010000D*0000000001");
    assert_eq!(
        served(&mut cpu, &mut s, pw, &read),
        EndCode::PASSWORD_LOCKED
    );
    assert_eq!(
        served(&mut cpu, &mut s, pw, &ascii3e("163000000004ab13")),
        EndCode::PASSWORD_MISMATCH
    );
    assert_eq!(
        served(&mut cpu, &mut s, pw, &read),
        EndCode::PASSWORD_LOCKED
    );
    // Locking while locked is refused like everything else.
    assert_eq!(
        served(&mut cpu, &mut s, pw, &ascii3e("163100000004ab12")),
        EndCode::PASSWORD_LOCKED
    );
}

#[test]
fn x4010_latch_clear_and_reset_only_in_stop() {
    let mut cpu = cpu();
    let mut s = Session::new();
    let latch_clear = bin3e(&[0x05, 0x10, 0x00, 0x00, 0x01, 0x00]);
    let reset = bin3e(&[0x06, 0x10, 0x00, 0x00, 0x01, 0x00]);
    assert_eq!(
        served(&mut cpu, &mut s, None, &latch_clear),
        EndCode::CPU_RUNNING
    );
    assert_eq!(served(&mut cpu, &mut s, None, &reset), EndCode::CPU_RUNNING);
    cpu.set_pause().unwrap();
    assert_eq!(served(&mut cpu, &mut s, None, &reset), EndCode::CPU_RUNNING);
}

#[test]
fn every_end_code_is_covered_and_described() {
    // The table the tests above walk through.
    for code in EndCode::ALL {
        assert_ne!(code.description(), "error", "{code:?}");
        assert!(format!("{code}").starts_with(&format!("{:04X}H", code.0)));
    }
}

#[test]
fn error_response_in_4e_ascii_echoes_the_serial() {
    let bytes = ascii4e("04020000");
    let Err(FrameError::Rejected(r)) = decode_request(&bytes) else {
        panic!()
    };
    assert_eq!(
        r.response(),
        b"D4001234000000FF03FF000016C05900FF03FF0004020000".to_vec()
    );
}

// --- frames that cannot be answered ---

fn malformed(bytes: &[u8]) -> usize {
    match decode_request(bytes) {
        Err(FrameError::Malformed { offset, .. }) => offset,
        other => panic!("{:?}: {other:?}", String::from_utf8_lossy(bytes)),
    }
}

#[test]
fn malformed_frames_close_the_connection() {
    assert_eq!(malformed(&[0x00]), 0);
    assert_eq!(malformed(&[0xD0, 0x00]), 0, "a response is not a request");
    assert_eq!(malformed(&[0x50, 0x01]), 1);
    assert_eq!(malformed(b"5001"), 3);
    assert_eq!(malformed(b"5X"), 1);
    assert_eq!(malformed(b"D000"), 0);
    // Header fields that are not hexadecimal.
    assert_eq!(malformed(b"50000GFF03FF000018"), 4);
    assert_eq!(malformed(b"5400XXXX0000"), 4);
    // A length the server will not buffer: 2001H bytes.
    assert_eq!(
        malformed(&[0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x01, 0x20]),
        7
    );
    assert_eq!(malformed(b"500000FF03FF002001"), 14);
    let mut cpu = cpu();
    assert_eq!(
        serve(&[0x00, 0x01], &mut cpu, &mut Session::new(), None),
        Served::Close {
            offset: 0,
            what: "unknown subheader"
        }
    );
    assert_eq!(
        serve(&[0x50], &mut cpu, &mut Session::new(), None),
        Served::Incomplete
    );
}

#[test]
fn refused_requests_leave_the_cpu_alone() {
    let (mut cpu, _) = cpu_with(softplc_core::profile::default_config());
    let mut s = Session::new();
    // Random write: D0 in range, D99999 not: nothing is written.
    let frame = ascii3e("140200000200D*0000000001D*0999990002");
    assert_eq!(
        served(&mut cpu, &mut s, None, &frame),
        EndCode::ADDRESS_RANGE
    );
    assert_eq!(cpu.memory().get_word(DeviceKind::D, 0).unwrap(), 0);
}
