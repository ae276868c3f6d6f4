//! Exceptions 01/02/03/04 and their order, and the Q map's boundaries
//! (contract §3: outside every range → 02, bad quantity → 03).

mod common;

use common::*;
use softplc_core::device::DeviceKind::*;
use softplc_core::engine::Cpu;
use softplc_modbus::{serve, Frame, Map, Proto, Request, Slave};

/// Serves a PDU over TCP (unit 1) and returns the response PDU.
fn pdu(cpu: &mut Cpu, map: &Map, slave: &mut Slave, pdu: &[u8]) -> Vec<u8> {
    let f = Frame::new(Proto::Tcp, 1, 1, pdu.to_vec());
    let r = serve(slave, map, &f, cpu).expect("a TCP request is answered");
    assert_eq!(r[..7], [0, 1, 0, 0, 0, (r.len() - 6) as u8, 1]);
    r[7..].to_vec()
}

fn q(cpu: &mut Cpu, req: Request) -> Vec<u8> {
    pdu(cpu, &Map::q_default(), &mut Slave::new(1), &req.to_pdu())
}

use Request::*;

#[test]
fn q_map_register_boundaries() {
    let mut cpu = cpu();
    let map = Map::q_default();
    set_word(&mut cpu, R, 32767, 0xABCD);
    // 53247 (CF FF) is the last R: R32767.
    assert_eq!(
        rtu(&mut cpu, &map, "01 03 CF FF 00 01 8B 2E").unwrap(),
        "01 03 02 AB CD 06 E1"
    );
    // 53248 (D0 00) is outside every range: 02.
    assert_eq!(
        rtu(&mut cpu, &map, "01 03 D0 00 00 01 BC CA").unwrap(),
        "01 83 02 C0 F1"
    );
    // Two registers from 53247 run past the end: 02.
    assert_eq!(
        q(
            &mut cpu,
            ReadHoldingRegisters {
                address: 53247,
                quantity: 2
            }
        ),
        [0x83, 2]
    );
    // D12287 / W0 / W1FFF / R0 boundaries, read across in one request.
    set_word(&mut cpu, D, 12287, 1);
    set_word(&mut cpu, W, 0, 2);
    set_word(&mut cpu, W, 0x1FFF, 3);
    set_word(&mut cpu, R, 0, 4);
    assert_eq!(
        q(
            &mut cpu,
            ReadHoldingRegisters {
                address: 12287,
                quantity: 2
            }
        ),
        [3, 4, 0, 1, 0, 2]
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadHoldingRegisters {
                address: 20479,
                quantity: 2
            }
        ),
        [3, 4, 0, 3, 0, 4]
    );
    // Input registers: SD0-SD2047; 2048 is 02.
    set_word(&mut cpu, SD, 2047, 9);
    assert_eq!(
        q(
            &mut cpu,
            ReadInputRegisters {
                address: 2047,
                quantity: 1
            }
        ),
        [4, 2, 0, 9]
    );
    assert_eq!(
        rtu(&mut cpu, &map, "01 04 08 00 00 01 33 AA").unwrap(),
        "01 84 02 C2 C1"
    );
}

#[test]
fn q_map_coil_boundaries() {
    let mut cpu = cpu();
    let map = Map::q_default();
    // Coil 8191 is Y1FFF, 8192 is M0: one request reads across (1, 1 → 03).
    set_bit(&mut cpu, Y, 0x1FFF, true);
    set_bit(&mut cpu, M, 0, true);
    assert_eq!(
        rtu(&mut cpu, &map, "01 01 1F FF 00 02 8A 2F").unwrap(),
        "01 01 01 03 11 89"
    );
    // 16383/16384: M8191 → L0; 24575/24576: L8191 → B0; 32767 is B1FFF.
    set_bit(&mut cpu, L, 0, true);
    set_bit(&mut cpu, B, 0, true);
    set_bit(&mut cpu, B, 0x1FFF, true);
    assert_eq!(
        q(
            &mut cpu,
            ReadCoils {
                address: 16383,
                quantity: 2
            }
        ),
        [1, 1, 2]
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadCoils {
                address: 24575,
                quantity: 2
            }
        ),
        [1, 1, 2]
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadCoils {
                address: 32767,
                quantity: 1
            }
        ),
        [1, 1, 1]
    );
    // 32768 (80 00) is outside: 02.
    assert_eq!(
        rtu(&mut cpu, &map, "01 01 80 00 00 01 D4 0A").unwrap(),
        "01 81 02 C1 91"
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadCoils {
                address: 32767,
                quantity: 2
            }
        ),
        [0x81, 2]
    );
    // Writes across Y1FFF/M0.
    assert_eq!(
        q(
            &mut cpu,
            WriteMultipleCoils {
                address: 8191,
                quantity: 2,
                bits: vec![0]
            }
        ),
        [15, 0x1F, 0xFF, 0, 2]
    );
    assert!(!bit(&cpu, Y, 0x1FFF) && !bit(&cpu, M, 0));
    assert_eq!(
        q(
            &mut cpu,
            WriteSingleCoil {
                address: 32767,
                value: 0xFF00
            }
        )[0],
        5
    );
    assert_eq!(
        q(
            &mut cpu,
            WriteSingleCoil {
                address: 32768,
                value: 0xFF00
            }
        ),
        [0x85, 2]
    );
    // Discrete inputs: X0-X1FFF; 8192 is 02.
    cpu.set_input(0x1FFF, true);
    assert_eq!(
        q(
            &mut cpu,
            ReadDiscreteInputs {
                address: 8191,
                quantity: 1
            }
        ),
        [2, 1, 1]
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadDiscreteInputs {
                address: 8191,
                quantity: 2
            }
        ),
        [0x82, 2]
    );
}

#[test]
fn quantity_limits_are_03() {
    let mut cpu = cpu();
    let map = Map::q_default();
    // FC 01 quantity 0 and 2001 (07 D1).
    assert_eq!(
        rtu(&mut cpu, &map, "01 01 00 00 00 00 3C 0A").unwrap(),
        "01 81 03 00 51"
    );
    assert_eq!(
        rtu(&mut cpu, &map, "01 01 00 00 07 D1 FE 66").unwrap(),
        "01 81 03 00 51"
    );
    // The quantity is checked before the address: 2001 at unmapped 40000 is 03.
    assert_eq!(
        rtu(&mut cpu, &map, "01 01 9C 40 07 D1 D1 E2").unwrap(),
        "01 81 03 00 51"
    );
    for (req, fc) in [
        (
            ReadDiscreteInputs {
                address: 0,
                quantity: 2001,
            },
            2,
        ),
        (
            ReadHoldingRegisters {
                address: 0,
                quantity: 126,
            },
            3,
        ),
        (
            ReadHoldingRegisters {
                address: 0,
                quantity: 0,
            },
            3,
        ),
        (
            ReadInputRegisters {
                address: 0,
                quantity: 126,
            },
            4,
        ),
        (
            WriteMultipleRegisters {
                address: 0,
                values: vec![0; 124],
            },
            16,
        ),
        (
            WriteMultipleRegisters {
                address: 60000,
                values: vec![],
            },
            16,
        ),
        (
            WriteMultipleCoils {
                address: 0,
                quantity: 1969,
                bits: vec![0; 247],
            },
            15,
        ),
        (
            WriteMultipleCoils {
                address: 0,
                quantity: 0,
                bits: vec![],
            },
            15,
        ),
        (
            ReadWriteMultipleRegisters {
                read_address: 0,
                read_quantity: 126,
                write_address: 0,
                values: vec![1],
            },
            23,
        ),
        (
            ReadWriteMultipleRegisters {
                read_address: 0,
                read_quantity: 1,
                write_address: 0,
                values: vec![1; 122],
            },
            23,
        ),
    ] {
        assert_eq!(q(&mut cpu, req.clone()), [0x80 | fc, 3], "{req:?}");
    }
    // At the limits: served.
    assert_eq!(
        q(
            &mut cpu,
            ReadInputRegisters {
                address: 0,
                quantity: 125
            }
        )[..2],
        [4, 250]
    );
    let r = q(
        &mut cpu,
        ReadWriteMultipleRegisters {
            read_address: 0,
            read_quantity: 125,
            write_address: 0,
            values: vec![1; 121],
        },
    );
    assert_eq!(r[..2], [23, 250]);
}

#[test]
fn bad_values_and_lengths_are_03() {
    let mut cpu = cpu();
    let map = Map::q_default();
    let mut slave = Slave::new(1);
    // FC 05 value 1234 is neither FF00 nor 0000.
    assert_eq!(
        rtu(&mut cpu, &map, "01 05 00 00 12 34 C0 BD").unwrap(),
        "01 85 03 02 91"
    );
    assert!(!bit(&cpu, Y, 0));
    // ... checked before the address (65535 is unmapped).
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("05 FF FF 12 34")),
        [0x85, 3]
    );
    // FC 15 byte count 1 for 10 coils; FC 16 byte count 3 for 2 registers.
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("0F 00 00 00 0A 01 FF")),
        [0x8F, 3]
    );
    assert_eq!(
        pdu(
            &mut cpu,
            &map,
            &mut slave,
            &hex("10 00 00 00 02 03 00 01 00")
        ),
        [0x90, 3]
    );
    // Byte count not matching the data that follows.
    assert_eq!(
        pdu(
            &mut cpu,
            &map,
            &mut slave,
            &hex("10 00 00 00 02 04 00 01 00")
        ),
        [0x90, 3]
    );
    // PDU too short or too long for the function.
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("03 00 00 00")),
        [0x83, 3]
    );
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("03 00 00 00 01 00")),
        [0x83, 3]
    );
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("16 00 00 FF FF")),
        [0x96, 3]
    );
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("17 00 00 00 01 00 00")),
        [0x97, 3]
    );
    assert_eq!(pdu(&mut cpu, &map, &mut slave, &hex("08 00")), [0x88, 3]);
    assert_eq!(slave.counters.exceptions, 9);
}

#[test]
fn unsupported_functions_are_01() {
    let mut cpu = cpu();
    let map = Map::q_default();
    // FC 07 (read exception status) is not supported; the frame is 01 07 + CRC.
    assert_eq!(
        rtu(&mut cpu, &map, "01 07 41 E2").unwrap(),
        "01 87 01 82 30"
    );
    let mut slave = Slave::new(1);
    for fc in [0u8, 7, 11, 12, 17, 20, 21, 24, 43, 0x41, 0x7F] {
        assert_eq!(
            pdu(&mut cpu, &map, &mut slave, &[fc, 0, 0, 0, 1]),
            [fc | 0x80, 1]
        );
    }
    // Unknown FC 08 sub-functions (0x02 diagnostic register, 0x10 NAK count).
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("08 00 02 00 00")),
        [0x88, 1]
    );
    assert_eq!(
        pdu(&mut cpu, &map, &mut slave, &hex("08 00 10 00 00")),
        [0x88, 1]
    );
    // The function is checked before anything else: a malformed FC 07 is still 01.
    assert_eq!(pdu(&mut cpu, &map, &mut slave, &[7]), [0x87, 1]);
}

#[test]
fn read_only_slave_refuses_writes_with_01() {
    let mut cpu = cpu();
    let map = Map::q_default();
    let mut slave = Slave::new(1);
    slave.read_only = true;
    // 01 06 00 00 00 01 → 01 86 01, D0 unchanged; reads still work.
    let r = exchange(
        &mut slave,
        &map,
        Proto::Rtu,
        &hex("01 06 00 00 00 01 48 0A"),
        &mut cpu,
    );
    assert_eq!(to_hex(&r.unwrap()), "01 86 01 83 A0");
    assert_eq!(word(&cpu, D, 0), 0);
    for req in [
        WriteSingleCoil {
            address: 0,
            value: 0xFF00,
        },
        WriteMultipleCoils {
            address: 0,
            quantity: 1,
            bits: vec![1],
        },
        WriteMultipleRegisters {
            address: 0,
            values: vec![1],
        },
        MaskWriteRegister {
            address: 0,
            and_mask: 0,
            or_mask: 1,
        },
        ReadWriteMultipleRegisters {
            read_address: 0,
            read_quantity: 1,
            write_address: 0,
            values: vec![1],
        },
    ] {
        let fc = req.function();
        assert_eq!(
            pdu(&mut cpu, &map, &mut slave, &req.to_pdu()),
            [0x80 | fc, 1]
        );
    }
    assert!(!bit(&cpu, Y, 0) && word(&cpu, D, 0) == 0);
    assert_eq!(
        pdu(
            &mut cpu,
            &map,
            &mut slave,
            &ReadHoldingRegisters {
                address: 0,
                quantity: 1
            }
            .to_pdu()
        ),
        [3, 2, 0, 0]
    );
}

#[test]
fn devices_missing_in_the_cpu_are_04_and_nothing_is_written() {
    // A CPU with 1024 D points under the Q map (D0-D12287 mapped).
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(D, 1024);
    let mut cpu = cpu_with(cfg.clone());
    let map = Map::q_default();
    assert_eq!(
        map.check_devices(&cfg.devices),
        ["holding_registers 0-12287 → D0-D12287: the CPU has 1024 D points"]
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadHoldingRegisters {
                address: 1023,
                quantity: 1
            }
        ),
        [3, 2, 0, 0]
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadHoldingRegisters {
                address: 1024,
                quantity: 1
            }
        ),
        [0x83, 4]
    );
    assert_eq!(
        q(
            &mut cpu,
            WriteMultipleRegisters {
                address: 1023,
                values: vec![7, 7]
            }
        ),
        [0x90, 4]
    );
    assert_eq!(word(&cpu, D, 1023), 0);
    // 03 and 02 still come first.
    assert_eq!(
        q(
            &mut cpu,
            ReadHoldingRegisters {
                address: 2000,
                quantity: 0
            }
        ),
        [0x83, 3]
    );
    assert_eq!(
        q(
            &mut cpu,
            ReadHoldingRegisters {
                address: 60000,
                quantity: 1
            }
        ),
        [0x83, 2]
    );
    // FC 23: a bad write part leaves the devices unchanged.
    assert_eq!(
        q(
            &mut cpu,
            ReadWriteMultipleRegisters {
                read_address: 0,
                read_quantity: 1,
                write_address: 1023,
                values: vec![5, 5],
            }
        ),
        [0x97, 4]
    );
    assert_eq!(word(&cpu, D, 1023), 0);
}

#[test]
fn failed_writes_change_nothing() {
    let mut cpu = cpu();
    // 10 registers from 53240: the last 2 are past R32767 → 02, R untouched.
    assert_eq!(
        q(
            &mut cpu,
            WriteMultipleRegisters {
                address: 53240,
                values: vec![1; 10]
            }
        ),
        [0x90, 2]
    );
    assert_eq!(word(&cpu, R, 32760), 0);
    // FC 23 with a good write and a bad read: 02, nothing written.
    assert_eq!(
        q(
            &mut cpu,
            ReadWriteMultipleRegisters {
                read_address: 60000,
                read_quantity: 1,
                write_address: 0,
                values: vec![5],
            }
        ),
        [0x97, 2]
    );
    assert_eq!(word(&cpu, D, 0), 0);
}
