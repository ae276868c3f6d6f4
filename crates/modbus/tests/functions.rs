//! Every function code over TCP, RTU (CRC) and ASCII (LRC), byte for byte, on the
//! Q map against a real CPU. Expected bytes are written from the protocol:
//! - TCP: transaction 00 01, protocol 00 00, length (unit + PDU), unit 01, PDU.
//! - RTU: station 01, PDU, CRC-16 low byte first.
//! - ASCII: ':' + hex of station, PDU and LRC (two's complement of the byte sum) + CR LF.
//!
//! Several requests are the examples of the Modbus application protocol
//! specification V1.1b3 (FC 15, 16, 22, 23, 08), with their data.

mod common;

use common::*;
use softplc_core::device::DeviceKind::*;
use softplc_core::engine::Cpu;
use softplc_modbus::{Map, Proto, Slave};

/// Sends one request per transport and checks each response exactly.
fn check(cpu: &mut Cpu, cases: &[(Proto, &[u8], &[u8])]) {
    let map = Map::q_default();
    let mut slave = Slave::new(1);
    for (proto, req, resp) in cases {
        let got = exchange(&mut slave, &map, *proto, req, cpu);
        assert_eq!(
            got.as_deref(),
            Some(*resp),
            "{proto}: request {:?}",
            String::from_utf8_lossy(req)
        );
    }
}

fn b(s: &str) -> Vec<u8> {
    hex(s)
}

#[test]
fn canonical_crc_example() {
    // Modbus over serial line V1.02 / application protocol: station 01 reads
    // holding registers 0x006B-0x006D; the CRC of 01 03 00 6B 00 03 is 74 17
    // (low byte 0x74 first).
    assert_eq!(softplc_modbus::crc16(&b("01 03 00 6B 00 03")), 0x1774);
    // Station 0x11 (17), the specification's example slave: CRC 76 87.
    assert_eq!(softplc_modbus::crc16(&b("11 03 00 6B 00 03")), 0x8776);
    // ASCII LRC of the same request: 0x11+0x03+0x6B+0x03 = 0x82 → 0x7E.
    assert_eq!(softplc_modbus::lrc(&b("11 03 00 6B 00 03")), 0x7E);

    let mut cpu = cpu();
    set_word(&mut cpu, D, 107, 0x022B);
    set_word(&mut cpu, D, 108, 0x0000);
    set_word(&mut cpu, D, 109, 0x0064);
    // Response 01 03 06 02 2B 00 00 00 64 + CRC (the specification's data).
    let req = b("01 03 00 6B 00 03 74 17");
    let resp = b("01 03 06 02 2B 00 00 00 64 05 7A");
    assert_eq!(
        softplc_modbus::crc16(&resp[..9]).to_le_bytes(),
        [0x05, 0x7A]
    );
    check(&mut cpu, &[(Proto::Rtu, &req, &resp)]);
}

#[test]
fn fc01_read_coils() {
    let mut cpu = cpu();
    // Y0, Y2 and Y9 ON: first byte 0000 0101 = 05, second byte bit 1 = 02.
    for n in [0, 2, 9] {
        set_bit(&mut cpu, Y, n, true);
    }
    check(
        &mut cpu,
        &[
            (
                Proto::Tcp,
                &b("00 01 00 00 00 06 01 01 00 00 00 0A"),
                &b("00 01 00 00 00 05 01 01 02 05 02"),
            ),
            (
                Proto::Rtu,
                &b("01 01 00 00 00 0A BC 0D"),
                &b("01 01 02 05 02 3B 6D"),
            ),
            (Proto::Ascii, b":01010000000AF4\r\n", b":0101020502F5\r\n"),
        ],
    );
}

#[test]
fn fc02_read_discrete_inputs() {
    let mut cpu = cpu();
    // X0 and X3 ON: 0000 1001 = 09.
    cpu.set_input(0, true);
    cpu.set_input(3, true);
    check(
        &mut cpu,
        &[
            (
                Proto::Tcp,
                &b("00 01 00 00 00 06 01 02 00 00 00 04"),
                &b("00 01 00 00 00 04 01 02 01 09"),
            ),
            (
                Proto::Rtu,
                &b("01 02 00 00 00 04 79 C9"),
                &b("01 02 01 09 61 8E"),
            ),
            (Proto::Ascii, b":010200000004F9\r\n", b":01020109F3\r\n"),
        ],
    );
}

#[test]
fn fc03_read_holding_registers() {
    let mut cpu = cpu();
    set_word(&mut cpu, D, 0, 0x1234);
    set_word(&mut cpu, D, 1, 0xABCD);
    check(
        &mut cpu,
        &[
            (
                Proto::Tcp,
                &b("00 01 00 00 00 06 01 03 00 00 00 02"),
                &b("00 01 00 00 00 07 01 03 04 12 34 AB CD"),
            ),
            (
                Proto::Rtu,
                &b("01 03 00 00 00 02 C4 0B"),
                &b("01 03 04 12 34 AB CD 00 20"),
            ),
            (
                Proto::Ascii,
                b":010300000002FA\r\n",
                b":0103041234ABCD3A\r\n",
            ),
        ],
    );
}

#[test]
fn fc04_read_input_registers() {
    let mut cpu = cpu();
    // Input register 100 = SD100.
    set_word(&mut cpu, SD, 100, 100);
    check(
        &mut cpu,
        &[
            (
                Proto::Tcp,
                &b("00 01 00 00 00 06 01 04 00 64 00 01"),
                &b("00 01 00 00 00 05 01 04 02 00 64"),
            ),
            (
                Proto::Rtu,
                &b("01 04 00 64 00 01 70 15"),
                &b("01 04 02 00 64 B8 DB"),
            ),
            (Proto::Ascii, b":01040064000196\r\n", b":010402006495\r\n"),
        ],
    );
}

#[test]
fn fc05_write_single_coil() {
    let mut cpu = cpu();
    // Coil 8193 (0x2001) = M1, FF00 = ON; the response echoes the request.
    for (proto, req) in [
        (Proto::Tcp, b("00 01 00 00 00 06 01 05 20 01 FF 00")),
        (Proto::Rtu, b("01 05 20 01 FF 00 D6 3A")),
        (Proto::Ascii, b":01052001FF00DA\r\n".to_vec()),
    ] {
        set_bit(&mut cpu, M, 1, false);
        check(&mut cpu, &[(proto, &req, &req)]);
        assert!(bit(&cpu, M, 1), "{proto}");
    }
    // 0000 = OFF: 01 05 20 01 00 00 → CRC 97 CA.
    assert_eq!(softplc_modbus::crc16(&b("01 05 20 01 00 00")), 0xCA97);
    let off = b("01 05 20 01 00 00 97 CA");
    check(&mut cpu, &[(Proto::Rtu, &off, &off)]);
    assert!(!bit(&cpu, M, 1));
}

#[test]
fn fc06_write_single_register() {
    let mut cpu = cpu();
    // Register 12288 (0x3000) = W0.
    for (proto, req) in [
        (Proto::Tcp, b("00 01 00 00 00 06 01 06 30 00 01 02")),
        (Proto::Rtu, b("01 06 30 00 01 02 06 9B")),
        (Proto::Ascii, b":010630000102C6\r\n".to_vec()),
    ] {
        set_word(&mut cpu, W, 0, 0);
        check(&mut cpu, &[(proto, &req, &req)]);
        assert_eq!(word(&cpu, W, 0), 0x0102, "{proto}");
    }
}

#[test]
fn fc15_write_multiple_coils() {
    // The specification's example: 10 coils from address 19 (0x13), data CD 01:
    // coils 19..26 = 1,0,1,1,0,0,1,1 and 27, 28 = 1, 0. Addresses 19-28 are
    // Y13-Y1C (hex device numbers).
    let expect = [1, 0, 1, 1, 0, 0, 1, 1, 1, 0];
    for (proto, req, resp) in [
        (
            Proto::Tcp,
            b("00 01 00 00 00 09 01 0F 00 13 00 0A 02 CD 01"),
            b("00 01 00 00 00 06 01 0F 00 13 00 0A"),
        ),
        (
            Proto::Rtu,
            b("01 0F 00 13 00 0A 02 CD 01 72 CB"),
            b("01 0F 00 13 00 0A 24 09"),
        ),
        (
            Proto::Ascii,
            b":010F0013000A02CD0103\r\n".to_vec(),
            b":010F0013000AD3\r\n".to_vec(),
        ),
    ] {
        let mut cpu = cpu();
        set_bit(&mut cpu, Y, 20, true); // turned OFF by the request
        check(&mut cpu, &[(proto, &req, &resp)]);
        for (i, e) in expect.iter().enumerate() {
            assert_eq!(
                bit(&cpu, Y, 19 + i as i64),
                *e == 1,
                "{proto} Y{:X}",
                19 + i
            );
        }
        assert!(!bit(&cpu, Y, 18) && !bit(&cpu, Y, 29));
    }
}

#[test]
fn fc16_write_multiple_registers() {
    // The specification's example: registers 1-2 = 000A, 0102 (D1, D2).
    for (proto, req, resp) in [
        (
            Proto::Tcp,
            b("00 01 00 00 00 0B 01 10 00 01 00 02 04 00 0A 01 02"),
            b("00 01 00 00 00 06 01 10 00 01 00 02"),
        ),
        (
            Proto::Rtu,
            b("01 10 00 01 00 02 04 00 0A 01 02 92 30"),
            b("01 10 00 01 00 02 10 08"),
        ),
        (
            Proto::Ascii,
            b":01100001000204000A0102DB\r\n".to_vec(),
            b":011000010002EC\r\n".to_vec(),
        ),
    ] {
        let mut cpu = cpu();
        check(&mut cpu, &[(proto, &req, &resp)]);
        assert_eq!(
            [
                word(&cpu, D, 0),
                word(&cpu, D, 1),
                word(&cpu, D, 2),
                word(&cpu, D, 3)
            ],
            [0, 0x000A, 0x0102, 0]
        );
    }
}

#[test]
fn fc22_mask_write_register() {
    // The specification's example: register 4 holds 0012; AND 00F2, OR 0025
    // → (0012 & 00F2) | (0025 & ~00F2) = 0012 | 0005 = 0017. Echo response.
    for (proto, req) in [
        (Proto::Tcp, b("00 01 00 00 00 08 01 16 00 04 00 F2 00 25")),
        (Proto::Rtu, b("01 16 00 04 00 F2 00 25 67 EE")),
        (Proto::Ascii, b":0116000400F20025CE\r\n".to_vec()),
    ] {
        let mut cpu = cpu();
        set_word(&mut cpu, D, 4, 0x0012);
        check(&mut cpu, &[(proto, &req, &req)]);
        assert_eq!(word(&cpu, D, 4), 0x0017, "{proto}");
    }
}

#[test]
fn fc23_read_write_multiple_registers() {
    // The specification's example: read 6 registers from 3, write 3 registers
    // (00FF each) from 14 (0x0E). D3-D8 hold 00FE 0ACD 0001 0003 000D 00FF.
    for (proto, req, resp) in [
        (
            Proto::Tcp,
            b("00 01 00 00 00 11 01 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF"),
            b("00 01 00 00 00 0F 01 17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF"),
        ),
        (
            Proto::Rtu,
            b("01 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF 46 91"),
            b("01 17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF 1D 79"),
        ),
        (
            Proto::Ascii,
            b":011700030006000E00030600FF00FF00FFCB\r\n".to_vec(),
            b":01170C00FE0ACD00010003000D00FFF7\r\n".to_vec(),
        ),
    ] {
        let mut cpu = cpu();
        for (i, v) in [0x00FE, 0x0ACD, 0x0001, 0x0003, 0x000D, 0x00FF]
            .iter()
            .enumerate()
        {
            set_word(&mut cpu, D, 3 + i as i64, *v);
        }
        check(&mut cpu, &[(proto, &req, &resp)]);
        assert_eq!(
            [word(&cpu, D, 14), word(&cpu, D, 15), word(&cpu, D, 16)],
            [0xFF; 3]
        );
    }
}

#[test]
fn fc23_writes_before_reading() {
    let mut cpu = cpu();
    let map = Map::q_default();
    // Read D0-D1 and write D1 = 1234 in one request: the read sees the new value.
    let req = softplc_modbus::Request::ReadWriteMultipleRegisters {
        read_address: 0,
        read_quantity: 2,
        write_address: 1,
        values: vec![0x1234],
    };
    let frame = softplc_modbus::Frame::new(Proto::Tcp, 9, 1, req.to_pdu());
    let mut slave = Slave::new(1);
    let resp = softplc_modbus::serve(&mut slave, &map, &frame, &mut cpu).unwrap();
    assert_eq!(resp, b("00 09 00 00 00 07 01 17 04 00 00 12 34"));
}

#[test]
fn fc08_return_query_data() {
    let mut cpu = cpu();
    // The specification's example: sub-function 0000, data A537, echoed.
    for (proto, req) in [
        (Proto::Tcp, b("00 01 00 00 00 06 01 08 00 00 A5 37")),
        (Proto::Rtu, b("01 08 00 00 A5 37 DA 8D")),
        (Proto::Ascii, b":01080000A5371B\r\n".to_vec()),
    ] {
        check(&mut cpu, &[(proto, &req, &req)]);
    }
}

#[test]
fn tcp_echoes_transaction_and_unit() {
    let mut cpu = cpu();
    set_word(&mut cpu, D, 0, 7);
    // Transaction 0xBEEF, unit 0xFF (the recommended TCP unit id).
    check(
        &mut cpu,
        &[(
            Proto::Tcp,
            &b("BE EF 00 00 00 06 FF 03 00 00 00 01"),
            &b("BE EF 00 00 00 05 FF 03 02 00 07"),
        )],
    );
}

#[test]
fn read_coils_pads_the_last_byte_with_zeros() {
    let mut cpu = cpu();
    for n in 0..16 {
        set_bit(&mut cpu, Y, n, true);
    }
    // 3 coils: one byte 0000 0111; 9 coils: FF 01.
    let map = Map::q_default();
    assert_eq!(
        rtu(&mut cpu, &map, "01 01 00 00 00 03 7C 0B").unwrap(),
        "01 01 01 07 10 4A"
    );
    assert_eq!(
        rtu(&mut cpu, &map, "01 01 00 00 00 09 FC 0C").unwrap(),
        "01 01 02 FF 01 39 CC"
    );
}

#[test]
fn maximum_quantities_are_served() {
    let mut cpu = cpu();
    let map = Map::q_default();
    let mut slave = Slave::new(1);
    let serve = |req: softplc_modbus::Request, slave: &mut Slave, cpu: &mut Cpu| {
        let f = softplc_modbus::Frame::new(Proto::Tcp, 1, 1, req.to_pdu());
        softplc_modbus::serve(slave, &map, &f, cpu).unwrap()
    };
    use softplc_modbus::Request::*;
    // 2000 coils: 250 data bytes.
    let r = serve(
        ReadCoils {
            address: 0,
            quantity: 2000,
        },
        &mut slave,
        &mut cpu,
    );
    assert_eq!((r[7], r[8], r.len()), (1, 250, 9 + 250));
    // 125 registers: 250 data bytes.
    let r = serve(
        ReadHoldingRegisters {
            address: 0,
            quantity: 125,
        },
        &mut slave,
        &mut cpu,
    );
    assert_eq!((r[7], r[8], r.len()), (3, 250, 9 + 250));
    // 1968 coils written.
    let r = serve(
        WriteMultipleCoils {
            address: 0,
            quantity: 1968,
            bits: vec![0xFF; 246],
        },
        &mut slave,
        &mut cpu,
    );
    assert_eq!(r[7..], [15, 0, 0, 0x07, 0xB0]);
    assert!(bit(&cpu, Y, 1967) && !bit(&cpu, Y, 1968));
    // 123 registers written.
    let r = serve(
        WriteMultipleRegisters {
            address: 0,
            values: vec![5; 123],
        },
        &mut slave,
        &mut cpu,
    );
    assert_eq!(r[7..], [16, 0, 0, 0, 123]);
    assert_eq!((word(&cpu, D, 122), word(&cpu, D, 123)), (5, 0));
}
