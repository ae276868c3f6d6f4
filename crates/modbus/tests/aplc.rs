//! The APLC dialect: seed 002's worked frames (spec/aplc.md §6.5, each checked
//! against the standard CRC) and spot checks of its address map (§6.4).

mod common;

use common::*;
use softplc_core::device::DeviceKind::*;
use softplc_core::engine::Cpu;
use softplc_modbus::{serve, Frame, Map, Proto, Request, Slave, Table};

fn aplc(cpu: &mut Cpu, request: &str) -> Option<String> {
    rtu(cpu, &Map::aplc(), request)
}

/// Serves a request PDU on the APLC map over TCP; returns the response PDU.
fn pdu(cpu: &mut Cpu, req: &Request) -> Vec<u8> {
    let f = Frame::new(Proto::Tcp, 1, 8, req.to_pdu());
    let r = serve(&mut Slave::new(8), &Map::aplc(), &f, cpu).unwrap();
    r[7..].to_vec()
}

use Request::*;

#[test]
fn seed_002_worked_examples() {
    let mut cpu = cpu();
    // 1. Y0, 256 bits: a normal reply, 32 data bytes (all OFF).
    let mut expect = String::from("01 01 20");
    for _ in 0..32 {
        expect.push_str(" 00");
    }
    expect.push_str(" 93 E0");
    assert_eq!(aplc(&mut cpu, "01 01 00 00 01 00 3D 9A").unwrap(), expect);
    // 2. 257 bits: more than the 256 Y points → 03.
    assert_eq!(
        aplc(&mut cpu, "01 01 00 00 01 01 FC 5A").unwrap(),
        "01 81 03 00 51"
    );
    // 3. Start 100, 160 bits: only 156 Y remain → 02.
    assert_eq!(
        aplc(&mut cpu, "01 01 00 64 00 A0 7D AD").unwrap(),
        "01 81 02 C1 91"
    );
    // 4. Start 300: no bit device there → 02.
    assert_eq!(
        aplc(&mut cpu, "01 01 01 2C 00 0A 7C 38").unwrap(),
        "01 81 02 C1 91"
    );
    // Appendix 7 §3.10: start 1, 256 bits → 02 (only 255 Y from address 1).
    assert_eq!(
        aplc(&mut cpu, "01 01 00 01 01 00 6C 5A").unwrap(),
        "01 81 02 C1 91"
    );
    // 5. FC 04 is not supported by APLC-TCP → 01.
    assert_eq!(
        aplc(&mut cpu, "01 04 00 02 00 0A D1 CD").unwrap(),
        "01 84 01 82 C0"
    );
    // 6. FC 02, X0-X11 (10 inputs): 2 bytes 00 00.
    assert_eq!(
        aplc(&mut cpu, "01 02 00 00 00 0A F8 0D").unwrap(),
        "01 02 02 00 00 B9 B8"
    );
    // 7. FC 01 at 1200 (04 B0): the same X0-X11 through the coil space.
    assert_eq!(
        aplc(&mut cpu, "01 01 04 B0 00 0A BC DA").unwrap(),
        "01 01 02 00 00 B9 FC"
    );
    // §10.4.9: C200-C255 (9700-9811) from odd 9701 → 02; 5 registers from 9700 → 03.
    assert_eq!(
        aplc(&mut cpu, "01 03 25 E5 00 04 5E F2").unwrap(),
        "01 83 02 C0 F1"
    );
    assert_eq!(
        aplc(&mut cpu, "01 03 25 E4 00 05 CE F2").unwrap(),
        "01 83 03 01 31"
    );
}

#[test]
fn x_reads_both_ways_and_ignores_writes() {
    let mut cpu = cpu();
    // X10 (octal) is device number 8: bit 8 of the request → second byte bit 0.
    cpu.set_input(8, true);
    cpu.set_input(0, true);
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadDiscreteInputs {
                address: 0,
                quantity: 10
            }
        ),
        [2, 2, 1, 1]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 1200,
                quantity: 10
            }
        ),
        [1, 2, 1, 1]
    );
    // FC 05/15 to X: normal reply, no effect (§6.4).
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteSingleCoil {
                address: 1200,
                value: 0
            }
        ),
        [5, 0x04, 0xB0, 0, 0]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteMultipleCoils {
                address: 1201,
                quantity: 8,
                bits: vec![0xFF]
            }
        ),
        [15, 0x04, 0xB1, 0, 8]
    );
    assert!(bit(&cpu, X, 0) && !bit(&cpu, X, 1) && bit(&cpu, X, 8));
    // X is 256 points (X0-X377): 1455 is the last, 1456 is unmapped.
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 1455,
                quantity: 1
            }
        ),
        [1, 1, 0]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 1456,
                quantity: 1
            }
        ),
        [0x81, 2]
    );
}

#[test]
fn y_octal_addresses() {
    let mut cpu = cpu();
    // Y10 (octal) = address 8 = device number 8. 01 05 00 08 FF 00 + CRC 0D F8.
    assert_eq!(
        aplc(&mut cpu, "01 05 00 08 FF 00 0D F8").unwrap(),
        "01 05 00 08 FF 00 0D F8"
    );
    assert!(bit(&cpu, Y, 8));
    // Y377 = address 255 is the last Y address; the APLC has Y0-Y177, so the
    // write is answered and ignored (decision D2).
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteSingleCoil {
                address: 255,
                value: 0xFF00
            }
        )[0],
        5
    );
    assert!(!bit(&cpu, Y, 255));
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteSingleCoil {
                address: 256,
                value: 0xFF00
            }
        ),
        [0x85, 2]
    );
}

#[test]
fn bit_map_spot_checks() {
    let map = Map::aplc();
    let at = |a| map.device_at(Table::Coils, a);
    assert_eq!(at(2000), Some((M, 0)));
    assert_eq!(at(3999), Some((M, 1999)));
    assert_eq!(at(4000), None);
    assert_eq!(at(4400), Some((SM, 0)));
    assert_eq!(at(4655), Some((SM, 255)));
    assert_eq!(at(6000), Some((S, 0)));
    assert_eq!(at(6991), Some((S, 991)));
    assert_eq!(at(6992), None);
    assert_eq!(at(8000), Some((TS, 0)));
    assert_eq!(at(9200), Some((CS, 0)));
    assert_eq!(at(9455), Some((CS, 255)));
    assert_eq!(map.device_at(Table::DiscreteInputs, 255), Some((X, 255)));
    assert_eq!(map.device_at(Table::DiscreteInputs, 256), None);

    let mut cpu = cpu();
    // M0 = protocol address 2000 (Modicon 0:2001).
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteSingleCoil {
                address: 2000,
                value: 0xFF00
            }
        )[0],
        5
    );
    assert!(bit(&cpu, M, 0));
    // T5 contact, C7 contact, S3.
    set_bit(&mut cpu, TS, 5, true);
    set_bit(&mut cpu, CS, 7, true);
    set_bit(&mut cpu, S, 3, true);
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 8000,
                quantity: 8
            }
        ),
        [1, 1, 0x20]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 9200,
                quantity: 8
            }
        ),
        [1, 1, 0x80]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 6000,
                quantity: 4
            }
        ),
        [1, 1, 0x08]
    );
    // One device type per request: M1999 + the gap after it → 02; 2000 M from 2000 is fine.
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 3999,
                quantity: 2
            }
        ),
        [0x81, 2]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 2000,
                quantity: 2000
            }
        )[..2],
        [1, 250]
    );
    // More than the 992 S points → 03; past the end of S → 02.
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 6000,
                quantity: 993
            }
        ),
        [0x81, 3]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 6001,
                quantity: 992
            }
        ),
        [0x81, 2]
    );
}

#[test]
fn read_only_sm_and_sd_accept_writes_without_effect() {
    let mut cpu = cpu();
    // SM0 (read-only) and SM40 (R/W): 15 coils... write SM0-SM47 all ON.
    let r = pdu(
        &mut cpu,
        &WriteMultipleCoils {
            address: 4400,
            quantity: 48,
            bits: vec![0xFF; 6],
        },
    );
    assert_eq!(r, [15, 0x11, 0x30, 0, 48]);
    assert!(!bit(&cpu, SM, 0) && !bit(&cpu, SM, 39));
    assert!(bit(&cpu, SM, 40) && bit(&cpu, SM, 47));
    // SD0 (PLC type, read-only) and SD50 (pulse total, R/W): addresses 8000, 8050.
    let sd0 = word(&cpu, SD, 0);
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteSingleRegister {
                address: 8000,
                value: 77
            }
        )[0],
        6
    );
    assert_eq!(word(&cpu, SD, 0), sd0);
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteSingleRegister {
                address: 8050,
                value: 77
            }
        )[0],
        6
    );
    assert_eq!(word(&cpu, SD, 50), 77);
    // SD135 station number is R/W, SD139 (master error code) is not.
    pdu(
        &mut cpu,
        &WriteMultipleRegisters {
            address: 8135,
            values: vec![1; 5],
        },
    );
    assert_eq!(
        [135, 136, 137, 138, 139].map(|n| word(&cpu, SD, n)),
        [1, 1, 1, 1, 0]
    );
}

#[test]
fn register_map_spot_checks() {
    let map = Map::aplc();
    let at = |a| map.device_at(Table::HoldingRegisters, a);
    assert_eq!(at(7999), Some((D, 7999)));
    assert_eq!(at(8000), Some((SD, 0)));
    assert_eq!(at(8255), Some((SD, 255)));
    assert_eq!(at(8256), None);
    assert_eq!(at(8500), Some((Z, 0)));
    assert_eq!(at(8515), Some((Z, 15)));
    assert_eq!(at(9000), Some((TN, 0)));
    assert_eq!(at(9500), Some((CN, 0)));
    assert_eq!(at(9699), Some((CN, 199)));
    assert_eq!(at(9700), Some((CN, 200)));
    // C200+k is CN(200+2k) (high) and CN(201+2k) (low) on an APLC CPU.
    assert_eq!(at(9701), Some((CN, 201)));
    assert_eq!(at(9811), Some((CN, 311)));
    assert_eq!(at(9812), None);

    let mut cpu = cpu();
    set_word(&mut cpu, Z, 15, 0x0F0F);
    set_word(&mut cpu, TN, 3, 33);
    set_word(&mut cpu, CN, 199, 199);
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadHoldingRegisters {
                address: 8515,
                quantity: 1
            }
        ),
        [3, 2, 0x0F, 0x0F]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadHoldingRegisters {
                address: 9003,
                quantity: 1
            }
        ),
        [3, 2, 0, 33]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadHoldingRegisters {
                address: 9699,
                quantity: 1
            }
        ),
        [3, 2, 0, 199]
    );
    // Z has 16 points: 17 registers → 03, 16 from 8501 → 02.
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadHoldingRegisters {
                address: 8500,
                quantity: 17
            }
        ),
        [0x83, 3]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadHoldingRegisters {
                address: 8501,
                quantity: 16
            }
        ),
        [0x83, 2]
    );
    // D7999 + the gap → 02.
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteMultipleRegisters {
                address: 7999,
                values: vec![1, 2]
            }
        ),
        [0x90, 2]
    );
    assert_eq!(word(&cpu, D, 7999), 0);
}

#[test]
fn c200_to_c255_are_register_pairs() {
    let mut cpu = aplc_cpu();
    // C200 = 5: high word CN200 = 0, low word CN201 = 5.
    set_word(&mut cpu, CN, 201, 5);
    // C200 at 9700 (high word, 0) and 9701 (low word): 01 03 25 E4 00 02 + CRC 8F 30.
    assert_eq!(
        aplc(&mut cpu, "01 03 25 E4 00 02 8F 30").unwrap(),
        "01 03 04 00 00 00 05 3A 30"
    );
    // FC 16 writes true 32-bit pairs: C201 = 0001 0007 (65543), C202 =
    // FFFF FFF7 (-9): C201 in CN202/CN203, C202 in CN204/CN205.
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteMultipleRegisters {
                address: 9702,
                values: vec![1, 7, 0xFFFF, 0xFFF7]
            }
        ),
        [16, 0x25, 0xE6, 0, 4]
    );
    assert_eq!(
        [202, 203, 204, 205].map(|n| word(&cpu, CN, n)),
        [1, 7, 0xFFFF, 0xFFF7]
    );
    let c = |cpu: &Cpu, s: &str| {
        softplc_core::names::DevName::parse(s, softplc_core::profile::aplc())
            .unwrap()
            .read(cpu)
            .unwrap()
    };
    assert_eq!(c(&cpu, "CN201"), softplc_core::access::Value::Int(65543));
    assert_eq!(c(&cpu, "CN202"), softplc_core::access::Value::Int(-9));
    // C255 is the last pair (9810-9811).
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadHoldingRegisters {
                address: 9810,
                quantity: 2
            }
        )[..2],
        [3, 4]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadHoldingRegisters {
                address: 9810,
                quantity: 4
            }
        ),
        [0x83, 2]
    );
    // Odd start / odd count, and FC 06 (not allowed on the 32-bit counters → 02).
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteMultipleRegisters {
                address: 9701,
                values: vec![0, 1]
            }
        ),
        [0x90, 2]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteMultipleRegisters {
                address: 9700,
                values: vec![0, 1, 2]
            }
        ),
        [0x90, 3]
    );
    // 01 06 25 E4 00 01 + CRC 03 31 → 01 86 02 C3 A1.
    assert_eq!(
        aplc(&mut cpu, "01 06 25 E4 00 01 03 31").unwrap(),
        "01 86 02 C3 A1"
    );
    assert_eq!(word(&cpu, CN, 200), 0);
}

#[test]
fn aplc_limits_and_functions() {
    let mut cpu = cpu();
    // At most 120 registers per FC 16 (0x78).
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteMultipleRegisters {
                address: 0,
                values: vec![1; 120]
            }
        ),
        [16, 0, 0, 0, 120]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteMultipleRegisters {
                address: 0,
                values: vec![1; 121]
            }
        ),
        [0x90, 3]
    );
    // FC 22 and 23 are not APLC functions.
    assert_eq!(
        pdu(
            &mut cpu,
            &MaskWriteRegister {
                address: 0,
                and_mask: 0,
                or_mask: 0
            }
        ),
        [0x96, 1]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadWriteMultipleRegisters {
                read_address: 0,
                read_quantity: 1,
                write_address: 0,
                values: vec![1],
            }
        ),
        [0x97, 1]
    );
    // FC 08 is.
    assert_eq!(
        pdu(
            &mut cpu,
            &Diagnostics {
                sub: 0,
                data: vec![1, 2]
            }
        ),
        [8, 0, 0, 1, 2]
    );
}

#[test]
fn io_addresses_past_177_read_off_and_ignore_writes_on_an_aplc_cpu() {
    // Decision D2: 256 addresses, X0-X177/Y0-Y177 exist (128 points).
    let mut cpu = aplc_cpu();
    set_bit(&mut cpu, Y, 127, true);
    // Y170-Y207 (addresses 120-135): only Y177 (bit 7 of the first byte) is ON.
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 120,
                quantity: 16
            }
        ),
        [1, 2, 0x80, 0]
    );
    // A write to Y200 (address 128) is answered and changes nothing.
    assert_eq!(
        pdu(
            &mut cpu,
            &WriteSingleCoil {
                address: 128,
                value: 0xFF00
            }
        ),
        [5, 0, 128, 0xFF, 0]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadCoils {
                address: 128,
                quantity: 128
            }
        )[2..],
        [0; 16]
    );
    // X0-X377 by FC 02: all 256 readable.
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadDiscreteInputs {
                address: 0,
                quantity: 256
            }
        )[..2],
        [2, 32]
    );
}

/// Every range of the APLC map reaches the storage its APLC device lives in
/// on an APLC CPU (crates/aplc/src/devices.rs: T on TS/TN, C on CS/CN,
/// C200+k on the pair CN(200+2k), CN(201+2k)): a value written by APLC name
/// through the door is read back over Modbus at the map's address.
#[test]
fn map_ranges_land_on_the_aplc_storage() {
    use softplc_core::names::DevName;
    let mut cpu = aplc_cpu();
    let set = |cpu: &mut Cpu, name: &str, v: &str| {
        DevName::parse(name, softplc_core::profile::aplc())
            .unwrap()
            .write(cpu, v)
            .unwrap()
    };
    let coil = |cpu: &mut Cpu, a: u16| {
        pdu(
            cpu,
            &ReadCoils {
                address: a,
                quantity: 1,
            },
        )[2] & 1
            == 1
    };
    for (name, address) in [
        ("Y0", 0),
        ("Y177", 127),
        ("X0", 1200),
        ("X177", 1327),
        ("M0", 2000),
        ("M1999", 3999),
        ("SM200", 4600),
        ("S0", 6000),
        ("S991", 6991),
        ("T0", 8000),
        ("T255", 8255),
        ("C0", 9200),
        ("C255", 9455),
    ] {
        assert!(!coil(&mut cpu, address), "{name} before");
        set(&mut cpu, name, "1");
        assert!(coil(&mut cpu, address), "{name} at coil {address}");
    }
    assert_eq!(
        pdu(
            &mut cpu,
            &ReadDiscreteInputs {
                address: 127,
                quantity: 1
            }
        ),
        [2, 1, 1]
    );
    let reg = |cpu: &mut Cpu, a: u16, n: u16| {
        let r = pdu(
            cpu,
            &ReadHoldingRegisters {
                address: a,
                quantity: n,
            },
        );
        r[2..]
            .chunks(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect::<Vec<_>>()
    };
    for (k, (name, address)) in [
        ("D0", 0u16),
        ("D7999", 7999),
        ("SD255", 8255),
        ("Z0", 8500),
        ("Z15", 8515),
        ("TN0", 9000),
        ("TN255", 9255),
        ("CN0", 9500),
        ("CN199", 9699),
    ]
    .into_iter()
    .enumerate()
    {
        let v = 1000 + k as u16;
        set(&mut cpu, name, &v.to_string());
        assert_eq!(reg(&mut cpu, address, 1), [v], "{name} at {address}");
    }
    // 32-bit counters: C200 = 16#0001_0002 at 9700-9701, C255 = -3 at 9810-9811.
    set(&mut cpu, "CN200", "16#00010002");
    set(&mut cpu, "CN255", "-3");
    assert_eq!(reg(&mut cpu, 9700, 2), [1, 2]);
    assert_eq!(reg(&mut cpu, 9810, 2), [0xFFFF, 0xFFFD]);
}
