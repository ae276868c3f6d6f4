//! One MC server for a multi-CPU system (contract §6): the request
//! destination module I/O number of a 3E/4E frame picks the CPU — `03E0`-
//! `03E3` CPU 1-4, `03FF` CPU 1 — and a CPU the system does not have answers
//! `4B00`. Byte-exact frames.

mod common;

use std::time::Duration;

use common::*;
use softplc_core::engine::{CpuState, VirtualClock};
use softplc_core::system::System;
use softplc_mc::{decode_request, encode_response, handle_station, EndCode, Session, Station};

/// CPU 1 (Q06HCPU) puts 11 in D0, CPU 2 (Q12HCPU) 22; one scan each.
fn system() -> (tempfile::TempDir, System) {
    let dir = tempfile::tempdir().unwrap();
    for (i, (model, value)) in [("Q06HCPU", 11), ("Q12HCPU", 22)].iter().enumerate() {
        let d = dir.path().join(format!("cpu{}", i + 1));
        std::fs::create_dir(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!("[cpu]\nmodel = \"{model}\"\n[[program]]\nfile = \"main.il\"\n[multi_cpu]\ncpus = 2\n[ras]\nremote_reset = true\n"),
        )
        .unwrap();
        std::fs::write(
            d.join("main.il"),
            format!("LD SM400\nMOV K{value} D0\nEND\n"),
        )
        .unwrap();
    }
    std::fs::write(
        dir.path().join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    let clock = VirtualClock::new();
    let c = clock.clone();
    let mut sys = System::load(dir.path(), &mut || Box::new(c.clone())).unwrap();
    sys.schedule(Duration::from_millis(10), 0);
    sys.run_until(10_000, &clock);
    (dir, sys)
}

/// `frame` with its request destination module I/O number set to `io`
/// (3E/4E binary and ASCII).
fn to(io: u16, frame: &[u8]) -> Vec<u8> {
    let mut f = frame.to_vec();
    match &f[..2] {
        [0x50, 0x00] => f[4..6].copy_from_slice(&io.to_le_bytes()),
        [0x54, 0x00] => f[8..10].copy_from_slice(&io.to_le_bytes()),
        b"50" => f[8..12].copy_from_slice(format!("{io:04X}").as_bytes()),
        _ => f[16..20].copy_from_slice(format!("{io:04X}").as_bytes()),
    }
    f
}

fn serve(station: &mut dyn Station, frame: &[u8]) -> Vec<u8> {
    let (req, used) = decode_request(frame).unwrap();
    assert_eq!(used, frame.len());
    let resp = handle_station(&req, station, &mut Session::new(), None);
    encode_response(&req.header, &resp)
}

/// Batch read D0, 1 word.
const READ_D0: [u8; 10] = [0x01, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0xA8, 0x01, 0x00];

#[test]
fn the_destination_io_number_picks_the_cpu() {
    let (_dir, mut sys) = system();
    let read = bin3e(&READ_D0);
    // 03FF (own station) and 03E0 are CPU 1; the reply echoes the number.
    assert_eq!(serve(&mut sys, &read), bin3e_ok(&[11, 0]));
    let mut want = bin3e_ok(&[11, 0]);
    want[4..6].copy_from_slice(&[0xE0, 0x03]);
    assert_eq!(serve(&mut sys, &to(0x03E0, &read)), want);
    let mut want = bin3e_ok(&[22, 0]);
    want[4..6].copy_from_slice(&[0xE1, 0x03]);
    assert_eq!(serve(&mut sys, &to(0x03E1, &read)), want);
    // ASCII 4E to CPU 2: "D400" serial, fixed, 00 FF 03E1 00, length 0008,
    // end code 0000, D0 = 0016.
    let req = to(0x03E1, &ascii4e("04010000D*0000000001"));
    assert_eq!(
        serve(&mut sys, &req),
        b"D4001234000000FF03E100000800000016".to_vec()
    );
}

#[test]
fn an_absent_cpu_answers_4b00() {
    let (_dir, mut sys) = system();
    // 3E binary: D0 00, 00 FF E2 03 00, length 11, end code 4B00, then the
    // error information: 00 FF E2 03 00 and the command 0401 0000.
    let got = serve(&mut sys, &to(0x03E2, &bin3e(&READ_D0)));
    assert_eq!(
        got,
        [
            0xD0, 0x00, 0x00, 0xFF, 0xE2, 0x03, 0x00, 0x0B, 0x00, 0x00, 0x4B, 0x00, 0xFF, 0xE2,
            0x03, 0x00, 0x01, 0x04, 0x00, 0x00
        ]
    );
    let got = serve(&mut sys, &to(0x03E3, &ascii3e("04010000D*0000000001")));
    assert_eq!(got, b"D00000FF03E30000164B0000FF03E30004010000".to_vec());
    assert_eq!(EndCode(0x4B00), EndCode::NO_DESTINATION);
    // Nothing was written anywhere: a write to CPU 3 changes no CPU.
    let write = to(
        0x03E2,
        &bin3e(&[
            0x01, 0x14, 0x00, 0x00, 0x00, 0x00, 0x00, 0xA8, 0x01, 0x00, 0x63, 0x00,
        ]),
    );
    assert_eq!(serve(&mut sys, &write)[9..11], [0x00, 0x4B]);
    assert_eq!(serve(&mut sys, &bin3e(&READ_D0)), bin3e_ok(&[11, 0]));
}

#[test]
fn a_single_cpu_answers_every_io_number() {
    let mut cpu = cpu();
    let mut want = bin3e_ok(&[0, 0]);
    want[4..6].copy_from_slice(&[0xE2, 0x03]);
    assert_eq!(serve(&mut cpu, &to(0x03E2, &bin3e(&READ_D0))), want);
}

#[test]
fn writes_and_remote_operations_reach_their_cpu_only() {
    let (_dir, mut sys) = system();
    // Batch write D1 = 0x0063 to CPU 2.
    let write = bin3e(&[
        0x01, 0x14, 0x00, 0x00, 0x01, 0x00, 0x00, 0xA8, 0x01, 0x00, 0x63, 0x00,
    ]);
    let got = serve(&mut sys, &to(0x03E1, &write));
    assert_eq!(got[9..11], [0x00, 0x00]);
    let d1 = |sys: &System, i| {
        sys.cpu(i)
            .memory()
            .get_word(softplc_core::device::DeviceKind::D, 1)
            .unwrap()
    };
    assert_eq!((d1(&sys, 0), d1(&sys, 1)), (0, 0x63));
    // Remote STOP of CPU 2 stops it alone.
    let stop = bin3e(&[0x02, 0x10, 0x00, 0x00, 0x01, 0x00]);
    assert_eq!(serve(&mut sys, &to(0x03E1, &stop))[9..11], [0x00, 0x00]);
    assert_eq!(sys.cpu(0).state(), CpuState::Run);
    assert_eq!(sys.cpu(1).state(), CpuState::Stop);
    // Remote RESET of CPU 2 follows the system's rule: CPU 1 (still in
    // RUN) shows MULTI CPU DOWN 7000.
    let reset = bin3e(&[0x06, 0x10, 0x00, 0x00, 0x01, 0x00]);
    assert_eq!(serve(&mut sys, &to(0x03E1, &reset))[9..11], [0x00, 0x00]);
    assert_eq!(sys.cpu(0).error().map(|e| e.code.0), Some(7000));
    // RESET of a CPU in RUN is refused (4010), as for a single CPU.
    let (_dir2, mut sys) = system();
    assert_eq!(serve(&mut sys, &reset)[9..11], [0x10, 0x40]);
}

#[test]
fn read_cpu_model_answers_per_cpu() {
    let (_dir, mut sys) = system();
    let model = bin3e(&[0x01, 0x01, 0x00, 0x00]);
    let mut want = b"Q06HCPU         ".to_vec();
    want.extend_from_slice(&[0x42, 0x00]);
    assert_eq!(serve(&mut sys, &model), bin3e_ok(&want));
    let mut want = b"Q12HCPU         ".to_vec();
    want.extend_from_slice(&[0x43, 0x00]);
    let mut want = bin3e_ok(&want);
    want[4..6].copy_from_slice(&[0xE1, 0x03]);
    assert_eq!(serve(&mut sys, &to(0x03E1, &model)), want);
}

#[test]
fn a_locked_connection_is_refused_before_the_destination_is_checked() {
    let (_dir, mut sys) = system();
    let (req, _) = decode_request(&to(0x03E3, &bin3e(&READ_D0))).unwrap();
    let resp = handle_station(&req, &mut sys, &mut Session::new(), Some("ab12"));
    let got = encode_response(&req.header, &resp);
    assert_eq!(got[9..11], [0x01, 0xC2]);
}
