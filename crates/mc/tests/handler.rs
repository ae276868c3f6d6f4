//! The handler against a real CPU: device access, remote operations, password.

mod common;

use common::*;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, CpuState, LatchRange};
use softplc_mc::*;

/// Serves one frame; returns the decoded response.
fn call(cpu: &mut Cpu, s: &mut Session, pw: Option<&str>, bytes: &[u8]) -> ResponseFrame {
    match serve(bytes, cpu, s, pw) {
        Served::Reply { response, used } => {
            assert_eq!(used, bytes.len());
            decode_response(&response).unwrap().0
        }
        other => panic!("{other:?}"),
    }
}

fn ok(cpu: &mut Cpu, bytes: &[u8]) -> ResponseFrame {
    let r = call(cpu, &mut Session::new(), None, bytes);
    assert_eq!(
        r.end_code,
        EndCode::OK,
        "{:?}",
        String::from_utf8_lossy(bytes)
    );
    r
}

fn req(command: Command) -> Request {
    Request {
        header: Header::default(),
        command,
    }
}

fn run(cpu: &mut Cpu, command: Command) -> Response {
    handle(&req(command), cpu, &mut Session::new(), None)
}

fn dev(s: &str) -> DeviceRef {
    DeviceRef::parse(s).unwrap()
}

#[test]
fn batch_write_then_read_words_binary_and_ascii() {
    let mut cpu = cpu();
    // 3E binary: write D100-D102 = 1, FFFF, 1234.
    ok(
        &mut cpu,
        &bin3e(&[
            0x01, 0x14, 0x00, 0x00, 0x64, 0x00, 0x00, 0xA8, 0x03, 0x00, 0x01, 0x00, 0xFF, 0xFF,
            0x34, 0x12,
        ]),
    );
    assert_eq!(cpu.memory().get_word(DeviceKind::D, 101).unwrap(), 0xFFFF);
    // 3E binary read, byte exact.
    let resp = serve(
        &bin3e(&[0x01, 0x04, 0x00, 0x00, 0x64, 0x00, 0x00, 0xA8, 0x03, 0x00]),
        &mut cpu,
        &mut Session::new(),
        None,
    );
    assert_eq!(
        resp,
        Served::Reply {
            response: bin3e_ok(&[0x01, 0x00, 0xFF, 0xFF, 0x34, 0x12]),
            used: 21
        }
    );
    // 3E ASCII read.
    let Served::Reply { response, .. } = serve(
        &ascii3e("04010000D*0001000003"),
        &mut cpu,
        &mut Session::new(),
        None,
    ) else {
        panic!()
    };
    assert_eq!(response, ascii3e_ok("0001FFFF1234"));
    // 4E binary read echoes the serial.
    let Served::Reply { response, .. } = serve(
        &bin4e(&[0x01, 0x04, 0x00, 0x00, 0x65, 0x00, 0x00, 0xA8, 0x01, 0x00]),
        &mut cpu,
        &mut Session::new(),
        None,
    ) else {
        panic!()
    };
    assert_eq!(response, bin4e_ok(&[0xFF, 0xFF]));
}

#[test]
fn bit_devices_in_bit_units_and_word_units() {
    let mut cpu = cpu();
    // Bit units: M0..M4 = 1 0 1 1 0 (ASCII), then read back 5 points in binary.
    ok(&mut cpu, &ascii3e("14010001M*000000000510110"));
    let r = ok(
        &mut cpu,
        &bin3e(&[0x01, 0x04, 0x01, 0x00, 0, 0, 0, 0x90, 5, 0]),
    );
    assert_eq!(r.data, [0x10, 0x11, 0x00]);
    assert_eq!(r.bits(5), Some(vec![true, false, true, true, false]));
    // Word units pack 16 points a word, the lowest number in bit 0.
    cpu.set_bit(DeviceKind::M, 16, true).unwrap();
    cpu.set_bit(DeviceKind::M, 31, true).unwrap();
    let r = ok(&mut cpu, &ascii3e("04010000M*0000000002"));
    assert_eq!(r.words(), Some(vec![0b0_1101, 0x8001]));
    // Writing a word to bit devices sets 16 points; B is numbered in hex.
    ok(&mut cpu, &ascii3e("14010000B*0000100001A5C3"));
    for i in 0..16 {
        let b = cpu.memory().get_bit(DeviceKind::B, 0x10 + i).unwrap();
        assert_eq!(b, 0xA5C3u16 >> i & 1 != 0, "B{:X}", 0x10 + i);
    }
    assert!(!cpu.memory().get_bit(DeviceKind::B, 0x20).unwrap());
}

#[test]
fn writing_x_survives_the_input_refresh() {
    let (mut cpu, clock) = cpu_with(softplc_core::profile::default_config());
    // Batch write X0 ON in bit units (program: LD X0 OUT Y0).
    ok(
        &mut cpu,
        &bin3e(&[
            0x01, 0x14, 0x01, 0x00, 0x00, 0x00, 0x00, 0x9C, 0x01, 0x00, 0x10,
        ]),
    );
    clock.advance_us(10_000);
    cpu.scan();
    cpu.scan();
    let r = ok(&mut cpu, &ascii3e("04010001X*0000000001"));
    assert_eq!(r.data, b"1", "X0 still ON after the input refresh");
    let r = ok(&mut cpu, &ascii3e("04010001Y*0000000001"));
    assert_eq!(r.data, b"1", "the program saw X0");
    // Word units and random write reach the input image too; DX is X.
    ok(&mut cpu, &ascii3e("14010000X*0000100001FFFF"));
    ok(&mut cpu, &ascii3e("1402000101DX00000000"));
    cpu.scan();
    assert!(!cpu.memory().get_bit(DeviceKind::X, 0).unwrap());
    assert!(cpu.memory().get_bit(DeviceKind::X, 0x1F).unwrap());
    let r = ok(&mut cpu, &ascii3e("04010000X*0000000002"));
    assert_eq!(r.words(), Some(vec![0, 0xFFFF]));
    cpu.scan();
    assert!(!cpu.output(0));
}

#[test]
fn timer_counter_and_special_devices() {
    let mut cpu = cpu();
    // TN0 and CN3 current values, SD100, Z2; TS/CS contacts in bit units.
    ok(&mut cpu, &ascii3e("14010000TN00000000010064"));
    ok(&mut cpu, &ascii3e("14010000CN0000030001000A"));
    ok(&mut cpu, &ascii3e("140200000200SD0001001234Z*0000020005"));
    assert_eq!(cpu.memory().get_word(DeviceKind::TN, 0).unwrap(), 100);
    assert_eq!(cpu.memory().get_word(DeviceKind::CN, 3).unwrap(), 10);
    assert_eq!(cpu.memory().get_word(DeviceKind::SD, 100).unwrap(), 0x1234);
    assert_eq!(cpu.memory().get_word(DeviceKind::Z, 2).unwrap(), 5);
    cpu.set_bit(DeviceKind::TS, 1, true).unwrap();
    cpu.set_bit(DeviceKind::CC, 2, true).unwrap();
    let r = ok(&mut cpu, &ascii3e("04010001TS0000000002"));
    assert_eq!(r.data, b"01");
    let r = ok(&mut cpu, &ascii3e("04010001CC0000020001"));
    assert_eq!(r.data, b"1");
    // SM400 is always ON while running (set by the scan).
    cpu.scan();
    let r = ok(&mut cpu, &ascii3e("04010001SM0004000001"));
    assert_eq!(r.data, b"1");
}

#[test]
fn retentive_timers_when_configured() {
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(DeviceKind::STS, 64);
    let (mut cpu, _) = cpu_with(cfg);
    ok(&mut cpu, &ascii3e("14010000SN0000630001002A"));
    assert_eq!(cpu.memory().get_word(DeviceKind::STN, 63).unwrap(), 42);
    ok(&mut cpu, &ascii3e("1402000102SS00000001SC00000101"));
    assert!(cpu.memory().get_bit(DeviceKind::STS, 0).unwrap());
    assert!(cpu.memory().get_bit(DeviceKind::STC, 1).unwrap());
    let r = call(
        &mut cpu,
        &mut Session::new(),
        None,
        &ascii3e("04010000SN0000640001"),
    );
    assert_eq!(r.end_code, EndCode::ADDRESS_RANGE);
}

#[test]
fn file_registers_r_follow_the_block_in_sd648() {
    let mut cpu = cpu();
    ok(&mut cpu, &ascii3e("14010000R*0000050001AAAA"));
    assert_eq!(cpu.memory().get_word(DeviceKind::ZR, 5).unwrap(), 0xAAAA);
    cpu.set_word(DeviceKind::SD, 648, 1).unwrap();
    ok(&mut cpu, &ascii3e("14010000R*0000050001BBBB"));
    assert_eq!(
        cpu.memory().get_word(DeviceKind::ZR, 32768 + 5).unwrap(),
        0xBBBB
    );
    // ZR is numbered in hex in ASCII: ZR8005 = 32773.
    let r = ok(&mut cpu, &ascii3e("04010000ZR0080050001"));
    assert_eq!(r.words(), Some(vec![0xBBBB]));
    // R stops at R32767 whatever the block; the last block ends with ZR.
    let r = call(
        &mut cpu,
        &mut Session::new(),
        None,
        &ascii3e("04010000R*0327670002"),
    );
    assert_eq!(r.end_code, EndCode::ADDRESS_RANGE);
    cpu.set_word(DeviceKind::SD, 648, 15).unwrap(); // ZR 491520..524287 > 517119
    let r = call(
        &mut cpu,
        &mut Session::new(),
        None,
        &ascii3e("04010000R*0300000001"),
    );
    assert_eq!(r.end_code, EndCode::ADDRESS_RANGE);
}

#[test]
fn random_read_and_write_with_double_words() {
    let mut cpu = cpu();
    let resp = run(
        &mut cpu,
        Command::RandomWriteWords {
            words: vec![(dev("D5"), 7), (dev("W1F"), 0xBEEF)],
            dwords: vec![(dev("D10"), 0x1234_5678), (dev("M32"), 0x8000_0001)],
        },
    );
    assert_eq!(resp, Response::Ok(ResponseData::None));
    assert_eq!(cpu.memory().get_word(DeviceKind::D, 10).unwrap(), 0x5678);
    assert_eq!(cpu.memory().get_word(DeviceKind::D, 11).unwrap(), 0x1234);
    assert!(cpu.memory().get_bit(DeviceKind::M, 32).unwrap());
    assert!(cpu.memory().get_bit(DeviceKind::M, 63).unwrap());
    assert!(!cpu.memory().get_bit(DeviceKind::M, 33).unwrap());
    let resp = run(
        &mut cpu,
        Command::RandomRead {
            words: vec![dev("W1F"), dev("D5"), dev("M32")],
            dwords: vec![dev("D10"), dev("M32")],
        },
    );
    assert_eq!(
        resp,
        Response::Ok(ResponseData::Random {
            words: vec![0xBEEF, 7, 1],
            dwords: vec![0x1234_5678, 0x8000_0001],
        })
    );
    // The same read as a 3E binary frame, byte exact: 2 words, 1 dword.
    let bytes = bin3e(&[
        0x03, 0x04, 0x00, 0x00, 0x02, 0x01, // counts
        0x05, 0x00, 0x00, 0xA8, // D5
        0x1F, 0x00, 0x00, 0xB4, // W1F
        0x0A, 0x00, 0x00, 0xA8, // D10 (dword)
    ]);
    let Served::Reply { response, .. } = serve(&bytes, &mut cpu, &mut Session::new(), None) else {
        panic!()
    };
    assert_eq!(
        response,
        bin3e_ok(&[0x07, 0x00, 0xEF, 0xBE, 0x78, 0x56, 0x34, 0x12])
    );
    // Random write in bit units.
    run(
        &mut cpu,
        Command::RandomWriteBits {
            points: vec![(dev("L7"), true), (dev("M32"), false), (dev("Y1F"), true)],
        },
    );
    assert!(cpu.memory().get_bit(DeviceKind::L, 7).unwrap());
    assert!(!cpu.memory().get_bit(DeviceKind::M, 32).unwrap());
    assert!(cpu.memory().get_bit(DeviceKind::Y, 0x1F).unwrap());
}

#[test]
fn remote_stop_run_pause_over_the_wire() {
    let (mut cpu, clock) = cpu_with(softplc_core::profile::default_config());
    let stop = ascii3e("100200000001");
    let run = ascii3e("1001000000010000");
    let pause = ascii3e("100300000001");
    ok(&mut cpu, &stop);
    assert_eq!(cpu.state(), CpuState::Stop);
    // SM/SD status: the program does not run in STOP.
    cpu.set_input(0, true);
    clock.advance_us(1000);
    cpu.scan();
    assert!(!cpu.output(0));
    ok(&mut cpu, &run);
    assert_eq!(cpu.state(), CpuState::Run);
    cpu.scan();
    assert!(cpu.output(0));
    ok(&mut cpu, &pause);
    // A remote PAUSE shows at the next END and takes hold at the END after.
    cpu.scan();
    cpu.scan();
    assert_eq!(cpu.state(), CpuState::Pause);
    ok(&mut cpu, &run);
    assert_eq!(cpu.state(), CpuState::Run);
    // RUN while running is accepted and changes nothing.
    ok(&mut cpu, &run);
    assert_eq!(cpu.state(), CpuState::Run);
}

#[test]
fn remote_reset_clears_a_stop_error_and_latch_clear_works_in_stop() {
    let mut cfg = softplc_core::profile::default_config();
    cfg.remote_reset = true;
    let (mut cpu, _) = cpu_with(cfg);
    let reset = bin3e(&[0x06, 0x10, 0x00, 0x00, 0x01, 0x00]);
    let latch_clear = bin3e(&[0x05, 0x10, 0x00, 0x00, 0x01, 0x00]);
    cpu.set_bit(DeviceKind::L, 5, true).unwrap();
    cpu.set_word(DeviceKind::D, 5, 9).unwrap();
    // Stop error: X1 divides by zero.
    cpu.set_input(1, true);
    cpu.scan();
    assert_eq!(cpu.state(), CpuState::Stop);
    assert!(cpu.error().is_some());
    cpu.set_input(1, false);
    ok(&mut cpu, &reset);
    assert_eq!(cpu.state(), CpuState::Run);
    assert!(cpu.error().is_none());
    assert_eq!(cpu.memory().get_word(DeviceKind::D, 5).unwrap(), 0);
    assert!(cpu.memory().get_bit(DeviceKind::L, 5).unwrap(), "latched");
    // Remote latch clear, in STOP, clears the latch ranges too.
    cpu.set_stop();
    ok(&mut cpu, &latch_clear);
    assert!(!cpu.memory().get_bit(DeviceKind::L, 5).unwrap());
}

#[test]
fn remote_run_clear_modes() {
    let mut cfg = softplc_core::profile::default_config();
    cfg.latch.push(LatchRange {
        kind: DeviceKind::D,
        start: 100,
        end: 199,
        clearable: true,
    });
    let (mut cpu, _) = cpu_with(cfg);
    let set = |cpu: &mut Cpu| {
        let m = &mut *cpu;
        m.set_bit(DeviceKind::M, 1, true).unwrap();
        m.set_bit(DeviceKind::L, 1, true).unwrap();
        m.set_word(DeviceKind::D, 1, 1).unwrap();
        m.set_word(DeviceKind::D, 150, 1).unwrap();
        m.set_word(DeviceKind::ZR, 1, 1).unwrap();
        m.set_word(DeviceKind::SD, 100, 1).unwrap();
    };
    let get = |cpu: &Cpu| {
        let m = cpu.memory();
        (
            m.get_bit(DeviceKind::M, 1).unwrap(),
            m.get_bit(DeviceKind::L, 1).unwrap(),
            m.get_word(DeviceKind::D, 1).unwrap(),
            m.get_word(DeviceKind::D, 150).unwrap(),
            m.get_word(DeviceKind::ZR, 1).unwrap(),
            m.get_word(DeviceKind::SD, 100).unwrap(),
        )
    };
    // Clear mode 01 from STOP: outside the latch ranges only; ZR and SD kept.
    ok(&mut cpu, &ascii3e("100200000001"));
    set(&mut cpu);
    ok(&mut cpu, &ascii3e("1001000000010100"));
    assert_eq!(get(&cpu), (false, true, 0, 1, 1, 1));
    // Clear mode 02: the latch ranges too.
    ok(&mut cpu, &ascii3e("100200000001"));
    set(&mut cpu);
    ok(&mut cpu, &ascii3e("1001000000030200"));
    assert_eq!(cpu.state(), CpuState::Run);
    assert_eq!(get(&cpu), (false, false, 0, 0, 1, 1));
    // While already running, the clear mode does nothing.
    set(&mut cpu);
    ok(&mut cpu, &ascii3e("1001000000010200"));
    assert_eq!(get(&cpu), (true, true, 1, 1, 1, 1));
}

#[test]
fn read_cpu_model_answers_as_the_configured_cpu() {
    let mut cpu = cpu();
    // 3E binary: 16 characters "Q06HCPU" padded with spaces, then code 0042.
    let Served::Reply { response, .. } = serve(
        &bin3e(&[0x01, 0x01, 0x00, 0x00]),
        &mut cpu,
        &mut Session::new(),
        None,
    ) else {
        panic!()
    };
    let mut want = b"Q06HCPU         ".to_vec();
    want.extend_from_slice(&[0x42, 0x00]);
    assert_eq!(response, bin3e_ok(&want));
    // ASCII.
    let Served::Reply { response, .. } =
        serve(&ascii3e("01010000"), &mut cpu, &mut Session::new(), None)
    else {
        panic!()
    };
    assert_eq!(response, ascii3e_ok("Q06HCPU         0042"));
    // Another model.
    let q06 = softplc_core::profile::default_profile();
    let q03ude: &'static softplc_core::profile::Profile =
        Box::leak(Box::new(softplc_core::profile::Profile {
            model: "Q03UDECPU",
            doors: softplc_core::profile::Doors {
                mc: Some(0x0268),
                ..q06.doors
            },
            ..*q06
        }));
    let (mut cpu, _) = cpu_with(softplc_core::profile::config(q03ude));
    assert_eq!(
        run(&mut cpu, Command::ReadCpuModel),
        Response::Ok(ResponseData::CpuModel {
            name: *b"Q03UDECPU       ",
            code: 0x0268
        })
    );
    let find = softplc_core::profile::find;
    assert_eq!(find("q06hcpu").unwrap().doors.mc, Some(0x42));
    assert!(find("Q99CPU").is_err());
}

/// Model codes of "read CPU model" (0101), from the MC protocol / SLMP
/// reference tables. Models with built-in Ethernet (`...E...CPU`) answer the
/// code of the same model without it; models without a published code (the
/// process CPUs) answer 0000.
const SLMP_MODEL_CODES: &[(&str, u16)] = &[
    ("Q00JCPU", 0x0250),
    ("Q00CPU", 0x0251),
    ("Q01CPU", 0x0252),
    ("Q02CPU", 0x0041),
    ("Q02HCPU", 0x0041),
    ("Q06HCPU", 0x0042),
    ("Q12HCPU", 0x0043),
    ("Q25HCPU", 0x0044),
    ("Q12PRHCPU", 0x004B),
    ("Q25PRHCPU", 0x004C),
    ("Q00UJCPU", 0x0260),
    ("Q00UCPU", 0x0261),
    ("Q01UCPU", 0x0262),
    ("Q02UCPU", 0x0263),
    ("Q03UDCPU", 0x0268),
    ("Q03UDECPU", 0x0268),
    ("Q04UDHCPU", 0x0269),
    ("Q04UDEHCPU", 0x0269),
    ("Q06UDHCPU", 0x026A),
    ("Q06UDEHCPU", 0x026A),
    ("Q10UDHCPU", 0x0266),
    ("Q10UDEHCPU", 0x0266),
    ("Q13UDHCPU", 0x026B),
    ("Q13UDEHCPU", 0x026B),
    ("Q20UDHCPU", 0x0267),
    ("Q20UDEHCPU", 0x0267),
    ("Q26UDHCPU", 0x026C),
    ("Q26UDEHCPU", 0x026C),
    ("Q50UDEHCPU", 0x026D),
    ("Q100UDEHCPU", 0x026E),
    ("Q03UDVCPU", 0x0366),
    ("Q04UDVCPU", 0x0367),
    ("Q06UDVCPU", 0x0368),
    ("Q13UDVCPU", 0x036A),
    ("Q26UDVCPU", 0x036C),
    ("L02SCPU", 0x0543),
    ("L02CPU", 0x0541),
    ("L06CPU", 0x0544),
    ("L26CPU", 0x0545),
    ("L26CPU-BT", 0x0542),
];

/// Every model with the MC protocol answers its name, padded to 16
/// characters, and the code of the reference table (0000 where it has none).
#[test]
fn read_cpu_model_answers_the_reference_code_of_every_model() {
    for p in softplc_core::profile::all() {
        let Some(code) = p.doors.mc else {
            continue;
        };
        let want = SLMP_MODEL_CODES
            .iter()
            .find(|(m, _)| *m == p.model)
            .map_or(0, |(_, c)| *c);
        assert_eq!(code, want, "{}", p.model);
        let (mut cpu, _) = cpu_with(softplc_core::profile::config(p));
        let mut name = [b' '; 16];
        name[..p.model.len()].copy_from_slice(p.model.as_bytes());
        assert_eq!(
            run(&mut cpu, Command::ReadCpuModel),
            Response::Ok(ResponseData::CpuModel { name, code: want }),
            "{}",
            p.model
        );
    }
}

#[test]
fn loopback_echoes() {
    let mut cpu = cpu();
    let Served::Reply { response, .. } = serve(
        &ascii4e("061900000005ABCDE"),
        &mut cpu,
        &mut Session::new(),
        None,
    ) else {
        panic!()
    };
    assert_eq!(
        response,
        b"D4001234000000FF03FF00000D00000005ABCDE".to_vec()
    );
}

#[test]
fn remote_password_lock_and_unlock_per_connection() {
    let mut cpu = cpu();
    let pw = Some("ab12");
    let mut a = Session::new();
    let mut b = Session::new();
    let read = bin3e(&[0x01, 0x04, 0x00, 0x00, 0, 0, 0, 0xA8, 1, 0]);
    let write = ascii3e("14010000D*0000000001ABCD");
    let stop = ascii3e("100200000001");
    let loopback = ascii3e("0619000000011");
    // Locked: everything but unlock and loopback is refused with C201.
    for f in [&read, &write, &stop] {
        assert_eq!(
            call(&mut cpu, &mut a, pw, f).end_code,
            EndCode::PASSWORD_LOCKED
        );
    }
    assert_eq!(cpu.state(), CpuState::Run);
    assert_eq!(call(&mut cpu, &mut a, pw, &loopback).end_code, EndCode::OK);
    // Unlock with the wrong password, then the right one (pymcprotocol layout:
    // length 0004 then the characters).
    let bad = bin3e(&[0x30, 0x16, 0x00, 0x00, 0x04, 0x00, b'a', b'b', b'1', b'3']);
    assert_eq!(
        call(&mut cpu, &mut a, pw, &bad).end_code,
        EndCode::PASSWORD_MISMATCH
    );
    assert!(!a.is_unlocked());
    let good = bin3e(&[0x30, 0x16, 0x00, 0x00, 0x04, 0x00, b'a', b'b', b'1', b'2']);
    assert_eq!(call(&mut cpu, &mut a, pw, &good).end_code, EndCode::OK);
    assert!(a.is_unlocked());
    assert_eq!(call(&mut cpu, &mut a, pw, &write).end_code, EndCode::OK);
    assert_eq!(cpu.memory().get_word(DeviceKind::D, 0).unwrap(), 0xABCD);
    // Another connection is still locked.
    assert_eq!(
        call(&mut cpu, &mut b, pw, &read).end_code,
        EndCode::PASSWORD_LOCKED
    );
    // Lock needs the password too; then the connection is locked again.
    assert_eq!(
        call(&mut cpu, &mut a, pw, &ascii3e("16310000XXXX")).end_code,
        EndCode::PASSWORD_MISMATCH
    );
    assert!(a.is_unlocked());
    assert_eq!(
        call(&mut cpu, &mut a, pw, &ascii3e("16310000ab12")).end_code,
        EndCode::OK
    );
    assert_eq!(
        call(&mut cpu, &mut a, pw, &read).end_code,
        EndCode::PASSWORD_LOCKED
    );
    // Without a configured password, unlock/lock complete and nothing is locked.
    let mut c = Session::new();
    assert_eq!(
        call(&mut cpu, &mut c, None, &ascii3e("16300000zzzz")).end_code,
        EndCode::OK
    );
    assert_eq!(
        call(&mut cpu, &mut c, None, &ascii3e("16310000zzzz")).end_code,
        EndCode::OK
    );
    assert_eq!(call(&mut cpu, &mut c, None, &read).end_code, EndCode::OK);
}
