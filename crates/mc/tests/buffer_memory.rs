//! Buffer memory of the rack's intelligent function modules through the MC
//! protocol: 0601/1601 (SLMP Reference Manual SH-080956ENG §10.2) and
//! `U<n>\G<addr>` in the device extension specification (subcommands
//! 0080/0081, Appendix 1), byte exact in 3E/4E binary and ASCII.

mod common;

use common::*;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_mc::*;

/// A rack: 16 inputs (X0-XF), a generic module of 100 words at X/Y10
/// (unit 1), an empty slot (20-2F), a generic module of 4096 words at X/Y30
/// (unit 3). The program copies U1\G5 to D0.
fn rack() -> Cpu {
    let dir = std::env::temp_dir().join(format!(
        "softplc-mc-rack-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("plc.toml"),
        "[[program]]\nfile = \"main.il\"\n\
         [[slot]]\ntype = \"input\"\npoints = 16\n\
         [[slot]]\ntype = \"intelligent\"\npoints = 16\nbuffer_words = 100\n\
         [[slot]]\ntype = \"empty\"\n\
         [[slot]]\ntype = \"intelligent\"\npoints = 16\n",
    )
    .unwrap();
    std::fs::write(dir.join("main.il"), "LD SM400\nMOV U1\\G5 D0\nEND\n").unwrap();
    let cpu = softplc_core::project::load_project(&dir)
        .and_then(|p| p.build_cpu(Box::new(VirtualClock::new())))
        .unwrap_or_else(|d| panic!("{:?}", d.0));
    let _ = std::fs::remove_dir_all(&dir);
    cpu
}

fn reply(cpu: &mut Cpu, bytes: &[u8]) -> Vec<u8> {
    match serve(bytes, cpu, &mut Session::new(), None) {
        Served::Reply { response, used } => {
            assert_eq!(used, bytes.len());
            response
        }
        other => panic!("{other:?}"),
    }
}

fn word(cpu: &Cpu, name: &str) -> i64 {
    match softplc_core::names::DevName::parse_for(name, cpu)
        .unwrap()
        .read(cpu)
        .unwrap()
    {
        softplc_core::access::Value::Int(v) => v,
        v => panic!("{v:?}"),
    }
}

/// 1601 then 0601 in 3E binary: start address 14H (word 10 × 2), 4 bytes,
/// module 0001 (the module at X/Y10): U1\G10-U1\G11.
#[test]
fn write_then_read_binary() {
    let mut cpu = rack();
    // 01 16 | 00 00 | start 14 00 00 00 | bytes 04 00 | module 01 00 | 1234H ABCDH.
    let write = bin3e(&[
        0x01, 0x16, 0x00, 0x00, 0x14, 0x00, 0x00, 0x00, 0x04, 0x00, 0x01, 0x00, 0x34, 0x12, 0xCD,
        0xAB,
    ]);
    assert_eq!(reply(&mut cpu, &write), bin3e_ok(&[]));
    assert_eq!(word(&cpu, "U1\\G10:u16"), 0x1234);
    assert_eq!(word(&cpu, "U1\\G11:u16"), 0xABCD);
    let read = bin3e(&[
        0x01, 0x06, 0x00, 0x00, 0x14, 0x00, 0x00, 0x00, 0x04, 0x00, 0x01, 0x00,
    ]);
    assert_eq!(reply(&mut cpu, &read), bin3e_ok(&[0x34, 0x12, 0xCD, 0xAB]));
    // 4E binary echoes the serial.
    let mut read4 = bin4e(&[
        0x01, 0x06, 0x00, 0x00, 0x14, 0x00, 0x00, 0x00, 0x02, 0x00, 0x01, 0x00,
    ]);
    assert_eq!(reply(&mut cpu, &read4), bin4e_ok(&[0x34, 0x12]));
    read4[2] = 0x35;
    assert_eq!(
        decode_response(&reply(&mut cpu, &read4))
            .unwrap()
            .0
            .header
            .frame,
        Frame::E4 { serial: 0x1235 }
    );
}

/// The same in ASCII: start "00000014", bytes "0004", module "0001", one
/// word a buffer-memory address in 4 hexadecimal digits.
#[test]
fn write_then_read_ascii() {
    let mut cpu = rack();
    let write = ascii3e("160100000000001400040001123400FF");
    assert_eq!(reply(&mut cpu, &write), ascii3e_ok(""));
    assert_eq!(word(&cpu, "U1\\G10"), 0x1234);
    assert_eq!(word(&cpu, "U1\\G11"), 0xFF);
    let read = ascii3e("060100000000001400040001");
    assert_eq!(reply(&mut cpu, &read), ascii3e_ok("123400FF"));
    let read4 = ascii4e("060100000000001400020001");
    let r = decode_response(&reply(&mut cpu, &read4)).unwrap().0;
    assert_eq!(r.header.frame, Frame::E4 { serial: 0x1234 });
    assert_eq!(r.words(), Some(vec![0x1234]));
}

/// The program sees what the MC protocol wrote, and the MC protocol what the
/// program and the names layer wrote: one memory.
#[test]
fn one_memory_with_the_program() {
    let mut cpu = rack();
    // U1\G5 = 77 by 1601 (start 0AH).
    reply(
        &mut cpu,
        &bin3e(&[
            0x01, 0x16, 0x00, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x02, 0x00, 0x01, 0x00, 77, 0,
        ]),
    );
    cpu.scan();
    assert_eq!(word(&cpu, "D0"), 77);
    // The last word of the 4096-word module at X/Y30: start 2 × 4095 = 1FFEH.
    softplc_core::names::DevName::parse_for("U3\\G4095", &cpu)
        .unwrap()
        .write(&mut cpu, "-2")
        .unwrap();
    let read = bin3e(&[
        0x01, 0x06, 0x00, 0x00, 0xFE, 0x1F, 0x00, 0x00, 0x02, 0x00, 0x03, 0x00,
    ]);
    assert_eq!(reply(&mut cpu, &read), bin3e_ok(&[0xFE, 0xFF]));
}

/// A module that is not there answers 4043; a range past the buffer memory
/// 4041; nothing is written. Byte counts outside 2-1920 are C052, odd
/// addresses and counts C05C.
#[test]
fn errors() {
    let mut cpu = rack();
    // Module 0002: the empty slot. Module 0000: the input module.
    for module in [0x00, 0x02, 0x3E] {
        let read = bin3e(&[
            0x01, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, module, 0x00,
        ]);
        assert_eq!(
            reply(&mut cpu, &read),
            bin3e_err(0x4043, 0x0601, 0),
            "module {module:02X}"
        );
    }
    // Words 99-100 of the 100-word module: 100 is past it.
    let write = bin3e(&[
        0x01, 0x16, 0x00, 0x00, 0xC6, 0x00, 0x00, 0x00, 0x04, 0x00, 0x01, 0x00, 1, 0, 2, 0,
    ]);
    assert_eq!(reply(&mut cpu, &write), bin3e_err(0x4041, 0x1601, 0));
    assert_eq!(word(&cpu, "U1\\G99"), 0, "nothing written");
    // The last word alone is fine.
    let write = bin3e(&[
        0x01, 0x16, 0x00, 0x00, 0xC6, 0x00, 0x00, 0x00, 0x02, 0x00, 0x01, 0x00, 1, 0,
    ]);
    assert_eq!(reply(&mut cpu, &write), bin3e_ok(&[]));
    // A start address far past any buffer memory.
    let read = ascii3e("0601000012345678000200010");
    let r = decode_response(&reply(&mut cpu, &read)).unwrap().0;
    assert_eq!(r.end_code, EndCode::ASCII_LENGTH, "one character too many");
    let read = ascii3e("060100001234567800020001");
    assert_eq!(reply(&mut cpu, &read), ascii3e_err(0x4041, 0x0601, 0));
    // 0 and 1922 bytes: C052; 3 bytes and an odd address: C05C.
    for (start, bytes, code) in [
        (0u32, 0u16, 0xC052),
        (0, 1922, 0xC052),
        (0, 3, 0xC05C),
        (1, 2, 0xC05C),
    ] {
        let mut body = vec![0x01, 0x06, 0x00, 0x00];
        body.extend_from_slice(&start.to_le_bytes());
        body.extend_from_slice(&bytes.to_le_bytes());
        body.extend_from_slice(&[0x01, 0x00]);
        assert_eq!(
            reply(&mut cpu, &bin3e(&body)),
            bin3e_err(code, 0x0601, 0),
            "start {start} bytes {bytes}"
        );
    }
    // 1601 with fewer data bytes than it says: C061.
    let write = bin3e(&[
        0x01, 0x16, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x01, 0x00, 1, 0,
    ]);
    assert_eq!(reply(&mut cpu, &write), bin3e_err(0xC061, 0x1601, 0));
    // 0601 has no subcommand 0001.
    let read = bin3e(&[
        0x01, 0x06, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x01, 0x00,
    ]);
    assert_eq!(reply(&mut cpu, &read), bin3e_err(0xC059, 0x0601, 1));
}

/// The manual's example (Appendix 1): buffer memory address 1 of the module
/// at start I/O number 0030H, subcommand 0080. Binary: device modification
/// 00 00, number 01 00 00, code AB, extension modification 00 00, extension
/// 03 00, direct memory F8.
#[test]
fn extension_batch_read_and_write_binary() {
    let mut cpu = rack();
    let g1 = [
        0x00, 0x00, 0x01, 0x00, 0x00, 0xAB, 0x00, 0x00, 0x03, 0x00, 0xF8,
    ];
    // 1401/0080: U3\G1-U3\G2 = 5, 6.
    let mut write = vec![0x01, 0x14, 0x80, 0x00];
    write.extend_from_slice(&g1);
    write.extend_from_slice(&[0x02, 0x00, 0x05, 0x00, 0x06, 0x00]);
    assert_eq!(reply(&mut cpu, &bin3e(&write)), bin3e_ok(&[]));
    assert_eq!((word(&cpu, "U3\\G1"), word(&cpu, "U3\\G2")), (5, 6));
    let mut read = vec![0x01, 0x04, 0x80, 0x00];
    read.extend_from_slice(&g1);
    read.extend_from_slice(&[0x02, 0x00]);
    assert_eq!(
        reply(&mut cpu, &bin3e(&read)),
        bin3e_ok(&[0x05, 0x00, 0x06, 0x00])
    );
    // The codec decodes it as the extended command and encodes it back.
    let (req, _) = decode_request(&bin3e(&read)).unwrap();
    assert_eq!(
        req.command,
        Command::Extended(Box::new(Command::BatchRead {
            unit: Unit::Word,
            head: DeviceRef::module(3, 1),
            points: 2,
        }))
    );
    assert_eq!(req.command.codes(), (0x0401, 0x0080));
    assert_eq!(encode_request(&req), bin3e(&read));
}

/// The same example in ASCII: "00", "U003", "000", "G*", "000001", "000".
#[test]
fn extension_batch_read_and_write_ascii() {
    let mut cpu = rack();
    let g1 = "00U003000G*000001000";
    assert_eq!(
        reply(&mut cpu, &ascii3e(&format!("14010080{g1}000200070008"))),
        ascii3e_ok("")
    );
    assert_eq!((word(&cpu, "U3\\G1"), word(&cpu, "U3\\G2")), (7, 8));
    assert_eq!(
        reply(&mut cpu, &ascii3e(&format!("04010080{g1}0002"))),
        ascii3e_ok("00070008")
    );
    let (req, _) = decode_request(&ascii4e(&format!("04010080{g1}0002"))).unwrap();
    assert_eq!(encode_request(&req), ascii4e(&format!("04010080{g1}0002")));
    // A plain device in the extension format: extension "0000".
    let d12 = "000000000D*000012000";
    assert_eq!(
        reply(&mut cpu, &ascii3e(&format!("14010080{d12}0001002A"))),
        ascii3e_ok("")
    );
    assert_eq!(word(&cpu, "D12"), 0x2A);
    assert_eq!(
        reply(&mut cpu, &ascii3e(&format!("04010080{d12}0001"))),
        ascii3e_ok("002A")
    );
    // "U" with another device than G: C05C.
    assert_eq!(
        reply(&mut cpu, &ascii3e("0401008000U001000D*0000120000001")),
        ascii3e_err(0xC05C, 0x0401, 0x0080)
    );
}

/// Random read and write (0403/1402 with 0080) mix U\G and plain devices;
/// units in the extension and their errors.
#[test]
fn extension_random_and_errors() {
    let mut cpu = rack();
    let g = |unit: u16, n: u8| {
        let u = unit.to_le_bytes();
        vec![
            0x00, 0x00, n, 0x00, 0x00, 0xAB, 0x00, 0x00, u[0], u[1], 0xF8,
        ]
    };
    let d = |n: u8| {
        vec![
            0x00, 0x00, n, 0x00, 0x00, 0xA8, 0x00, 0x00, 0x00, 0x00, 0x00,
        ]
    };
    // 1402/0080: 2 word points, 1 dword point: U1\G0 = 11, D3 = 22, U3\G8-9 = 12345678H.
    let mut write = vec![0x02, 0x14, 0x80, 0x00, 0x02, 0x01];
    write.extend(g(1, 0));
    write.extend_from_slice(&[11, 0]);
    write.extend(d(3));
    write.extend_from_slice(&[22, 0]);
    write.extend(g(3, 8));
    write.extend_from_slice(&[0x78, 0x56, 0x34, 0x12]);
    assert_eq!(reply(&mut cpu, &bin3e(&write)), bin3e_ok(&[]));
    assert_eq!(word(&cpu, "U1\\G0"), 11);
    assert_eq!(word(&cpu, "D3"), 22);
    assert_eq!(word(&cpu, "U3\\G8:u32"), 0x1234_5678);
    // 0403/0080 reads them back.
    let mut read = vec![0x03, 0x04, 0x80, 0x00, 0x02, 0x01];
    read.extend(g(1, 0));
    read.extend(d(3));
    read.extend(g(3, 8));
    assert_eq!(
        reply(&mut cpu, &bin3e(&read)),
        bin3e_ok(&[11, 0, 22, 0, 0x78, 0x56, 0x34, 0x12])
    );
    // No module at unit 2 (the empty slot): 4043; U1\G100 is past the
    // module: 4041. A random write with one bad point writes nothing.
    let mut bad = vec![0x01, 0x04, 0x80, 0x00];
    bad.extend(g(2, 0));
    bad.extend_from_slice(&[0x01, 0x00]);
    assert_eq!(
        reply(&mut cpu, &bin3e(&bad)),
        bin3e_err(0x4043, 0x0401, 0x0080)
    );
    let mut write = vec![0x02, 0x14, 0x80, 0x00, 0x02, 0x00];
    write.extend(g(1, 0));
    write.extend_from_slice(&[99, 0]);
    write.extend(g(1, 100));
    write.extend_from_slice(&[99, 0]);
    assert_eq!(
        reply(&mut cpu, &bin3e(&write)),
        bin3e_err(0x4041, 0x1402, 0x0080)
    );
    assert_eq!(word(&cpu, "U1\\G0"), 11, "nothing written");
    // Bit units on buffer memory (a word device): C05C.
    let mut bits = vec![0x01, 0x04, 0x81, 0x00];
    bits.extend(g(1, 0));
    bits.extend_from_slice(&[0x01, 0x00]);
    assert_eq!(
        reply(&mut cpu, &bin3e(&bits)),
        bin3e_err(0xC05C, 0x0401, 0x0081)
    );
    // G without the extension: C05B; in the extension without F8: C05C;
    // index modification (Z4, flags 40): C05C; link direct (F9): C05B.
    let plain_g = bin3e(&[0x01, 0x04, 0x00, 0x00, 0x01, 0x00, 0x00, 0xAB, 0x01, 0x00]);
    assert_eq!(reply(&mut cpu, &plain_g), bin3e_err(0xC05B, 0x0401, 0));
    for (patch, code) in [
        ((10, 0x00), 0xC05C),
        ((1, 0x40), 0xC05C),
        ((10, 0xF9), 0xC05B),
    ] {
        let mut spec = g(1, 0);
        spec[patch.0] = patch.1;
        if patch.0 == 1 {
            spec[0] = 4;
        }
        let mut req = vec![0x01, 0x04, 0x80, 0x00];
        req.extend(spec);
        req.extend_from_slice(&[0x01, 0x00]);
        assert_eq!(
            reply(&mut cpu, &bin3e(&req)),
            bin3e_err(code, 0x0401, 0x0080),
            "{patch:?}"
        );
    }
    // The iQ-R format 0082 is not a Q CPU's: C059.
    let mut iqr = vec![0x01, 0x04, 0x82, 0x00];
    iqr.extend(g(1, 0));
    iqr.extend_from_slice(&[0x01, 0x00]);
    assert_eq!(
        reply(&mut cpu, &bin3e(&iqr)),
        bin3e_err(0xC059, 0x0401, 0x0082)
    );
}

/// Names of buffer memory as a client writes them.
#[test]
fn device_ref_names() {
    let g = DeviceRef::parse("u3\\g1").unwrap();
    assert_eq!(g, DeviceRef::module(3, 1));
    assert_eq!(g.to_string(), "U3\\G1");
    assert_eq!(DeviceRef::parse("U3E\\G65535").unwrap().unit, Some(0x3E));
    assert_eq!(DeviceRef::parse("U3\\D1"), None);
    assert_eq!(DeviceRef::parse("U1234\\G0"), None);
    assert_eq!(DeviceRef::parse("D1").unwrap().unit, None);
}
