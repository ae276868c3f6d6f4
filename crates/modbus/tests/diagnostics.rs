//! FC 08 sub-functions and counters, broadcast rules, listen-only mode and unit
//! id handling (spec/aplc.md §6.5-§6.7).

mod common;

use common::*;
use softplc_core::device::DeviceKind::*;
use softplc_core::engine::Cpu;
use softplc_modbus::{crc16, Counters, Frame, FrameErrorKind, Map, Proto, Slave, Step};

/// An RTU frame: `body` + its CRC (the CRC itself is checked in functions.rs).
fn rtu_frame(body: &str) -> Vec<u8> {
    let mut f = hex(body);
    let crc = crc16(&f);
    f.extend_from_slice(&crc.to_le_bytes());
    f
}

struct Bus {
    cpu: Cpu,
    map: Map,
    slave: Slave,
}

impl Bus {
    fn new(map: Map) -> Bus {
        Bus {
            cpu: cpu(),
            map,
            slave: Slave::new(1),
        }
    }

    fn send(&mut self, frame: &[u8]) -> Option<Vec<u8>> {
        match self
            .slave
            .handle(&self.map, Proto::Rtu, frame, &mut self.cpu)
        {
            Step::Served { used, response } => {
                assert_eq!(used, frame.len());
                response
            }
            other => panic!("{frame:02X?}: {other:?}"),
        }
    }

    fn body(&mut self, body: &str) -> Option<String> {
        self.send(&rtu_frame(body))
            .map(|r| to_hex(&r[..r.len() - 2]))
    }

    /// FC 08 counter `sub` read over RTU.
    fn count(&mut self, sub: u8) -> u16 {
        let r = self
            .send(&rtu_frame(&format!("01 08 00 {sub:02X} 00 00")))
            .unwrap();
        assert_eq!(r[..4], [1, 8, 0, sub]);
        u16::from_be_bytes([r[4], r[5]])
    }
}

#[test]
fn counters_follow_the_traffic() {
    let mut bus = Bus::new(Map::q_default());
    // 1. Addressed read: answered.
    assert_eq!(bus.body("01 03 00 00 00 01").unwrap(), "01 03 02 00 00");
    // 2. Another station: silently ignored (a bus message, not a slave message).
    assert_eq!(bus.body("02 03 00 00 00 01"), None);
    // 3. Bad CRC: no frame, counted as a bus communication error.
    let mut bad = rtu_frame("01 03 00 00 00 01");
    bad[7] ^= 0xFF;
    let e = match bus.slave.handle(&bus.map, Proto::Rtu, &bad, &mut bus.cpu) {
        Step::Error(e) => e,
        other => panic!("{other:?}"),
    };
    assert_eq!((e.kind, e.skip), (FrameErrorKind::BadChecksum, 8));
    // 4. Broadcast write D0 = 7 (00 06 00 00 00 07 C9 D9): executed, not answered.
    assert_eq!(bus.send(&hex("00 06 00 00 00 07 C9 D9")), None);
    assert_eq!(word(&bus.cpu, D, 0), 7);
    // 5. Broadcast read: not processed, not answered.
    assert_eq!(bus.body("00 03 00 00 00 01"), None);
    // 6. Broadcast write to an unmapped register: the exception is counted, not sent.
    assert_eq!(bus.body("00 06 FF FF 00 01"), None);
    // 7. Unsupported function: exception 01.
    assert_eq!(bus.body("01 07").unwrap(), "01 87 01");
    assert_eq!(
        bus.slave.counters,
        Counters {
            bus_messages: 6,
            bus_errors: 1,
            exceptions: 2,
            slave_messages: 5,
            no_responses: 3,
            overruns: 0,
        }
    );
    // 0x0B bus message count: 01 08 00 0B 00 00 91 C9 → 7 (this request included),
    // response 01 08 00 0B 00 07 D0 0B.
    assert_eq!(
        bus.send(&hex("01 08 00 0B 00 00 91 C9")).unwrap(),
        hex("01 08 00 0B 00 07 D0 0B")
    );
    // 0x0C CRC errors: 01 08 00 0C 00 00 20 08 → 01 08 00 0C 00 01 E1 C8.
    assert_eq!(
        bus.send(&hex("01 08 00 0C 00 00 20 08")).unwrap(),
        hex("01 08 00 0C 00 01 E1 C8")
    );
    assert_eq!(bus.count(0x0D), 2);
    assert_eq!(bus.count(0x0E), 9);
    assert_eq!(bus.count(0x0F), 3);
    assert_eq!(bus.count(0x12), 0);
    // An RTU FC 16 with byte count 255 would be 264 bytes: character overrun.
    let mut long = hex("01 10 00 00 00 7F FF");
    long.resize(300, 0);
    match bus.slave.handle(&bus.map, Proto::Rtu, &long, &mut bus.cpu) {
        Step::Error(e) => assert_eq!(e.kind, FrameErrorKind::Overrun),
        other => panic!("{other:?}"),
    }
    assert_eq!(bus.count(0x12), 1);
    // Counter data must be 0000.
    assert_eq!(bus.body("01 08 00 0B 00 01").unwrap(), "01 88 03");
}

#[test]
fn clear_counters_and_broadcast_diagnostics() {
    let mut bus = Bus::new(Map::q_default());
    bus.body("01 03 00 00 00 01");
    bus.body("01 07");
    // 0x0A answered with an echo; everything is zero afterwards.
    assert_eq!(bus.body("01 08 00 0A 00 00").unwrap(), "01 08 00 0A 00 00");
    assert_eq!(bus.slave.counters, Counters::default());
    bus.body("01 03 00 00 00 01");
    // 0x0A by broadcast: executed, no reply.
    assert_eq!(bus.body("00 08 00 0A 00 00"), None);
    assert_eq!(bus.slave.counters, Counters::default());
    // Other sub-functions by broadcast are not executed (0x00 would echo).
    assert_eq!(bus.body("00 08 00 00 12 34"), None);
    assert_eq!(bus.body("00 08 00 0B 00 00"), None);
    assert_eq!(bus.slave.counters.exceptions, 0);
    assert_eq!(bus.count(0x0F), 2);
}

#[test]
fn listen_only_mode() {
    let mut bus = Bus::new(Map::q_default());
    // 0x04: 01 08 00 04 00 00 A1 CA, no response.
    assert_eq!(bus.send(&hex("01 08 00 04 00 00 A1 CA")), None);
    assert!(bus.slave.listen_only);
    // Nothing is executed or answered...
    assert_eq!(bus.body("01 06 00 00 00 05"), None);
    assert_eq!(word(&bus.cpu, D, 0), 0);
    assert_eq!(bus.body("01 08 00 0B 00 00"), None);
    assert_eq!(bus.body("01 08 00 00 00 00"), None);
    assert_eq!(bus.body("00 06 00 00 00 05"), None);
    assert_eq!(word(&bus.cpu, D, 0), 0);
    // A restart with bad data is ignored too (no 03 from a listen-only slave).
    assert_eq!(bus.body("01 08 00 01 12 34"), None);
    assert!(bus.slave.listen_only);
    // ...but the messages are counted.
    assert_eq!(bus.slave.counters.no_responses, 6);
    // 0x01 with FF00 (01 08 00 01 FF 00 F0 3B): leaves listen-only, echoes, clears
    // the counters.
    assert_eq!(
        bus.send(&hex("01 08 00 01 FF 00 F0 3B")).unwrap(),
        hex("01 08 00 01 FF 00 F0 3B")
    );
    assert!(!bus.slave.listen_only);
    assert_eq!(bus.count(0x0B), 1);
    assert_eq!(bus.body("01 06 00 00 00 05").unwrap(), "01 06 00 00 00 05");
    // 0x01 data other than 0000/FF00 → 03; 0x04 data other than 0000 → 03.
    assert_eq!(bus.body("01 08 00 01 00 01").unwrap(), "01 88 03");
    assert_eq!(bus.body("01 08 00 04 FF 00").unwrap(), "01 88 03");
    assert!(!bus.slave.listen_only);
    // Listen-only by broadcast, left by broadcast.
    assert_eq!(bus.body("00 08 00 04 00 00"), None);
    assert!(bus.slave.listen_only);
    assert_eq!(bus.body("00 08 00 01 00 00"), None);
    assert!(!bus.slave.listen_only);
}

#[test]
fn broadcast_writes_by_function() {
    let mut bus = Bus::new(Map::q_default());
    // FC 05, 15, 16, 22 by broadcast: executed silently.
    assert_eq!(bus.body("00 05 00 03 FF 00"), None);
    assert_eq!(bus.body("00 0F 00 10 00 03 01 05"), None);
    assert_eq!(bus.body("00 10 00 0A 00 02 04 00 01 00 02"), None);
    set_word(&mut bus.cpu, D, 20, 0x00F0);
    assert_eq!(bus.body("00 16 00 14 00 F0 00 0F"), None);
    assert!(bit(&bus.cpu, Y, 3));
    assert_eq!(
        [
            bit(&bus.cpu, Y, 16),
            bit(&bus.cpu, Y, 17),
            bit(&bus.cpu, Y, 18)
        ],
        [true, false, true]
    );
    assert_eq!([word(&bus.cpu, D, 10), word(&bus.cpu, D, 11)], [1, 2]);
    assert_eq!(word(&bus.cpu, D, 20), 0x00FF);
    // FC 23 and the reads are not processed by broadcast.
    assert_eq!(bus.body("00 17 00 00 00 01 00 1E 00 01 02 00 09"), None);
    assert_eq!(word(&bus.cpu, D, 30), 0);
    assert_eq!(bus.slave.counters.exceptions, 0);
    // A read-only slave counts refused broadcast writes as exceptions.
    bus.slave.read_only = true;
    assert_eq!(bus.body("00 06 00 28 00 01"), None);
    assert_eq!(word(&bus.cpu, D, 40), 0);
    assert_eq!(bus.slave.counters.exceptions, 1);
}

#[test]
fn ascii_station_addressing() {
    let (mut cpu, map) = (cpu(), Map::q_default());
    let mut slave = Slave::new(17);
    // Station 0x11 (17), the specification's example: LRC 7E.
    let r = exchange(
        &mut slave,
        &map,
        Proto::Ascii,
        b":1103006B00037E\r\n",
        &mut cpu,
    )
    .unwrap();
    assert_eq!(r, b":110306000000000000E6\r\n");
    // Station 1 is someone else.
    assert_eq!(
        exchange(
            &mut slave,
            &map,
            Proto::Ascii,
            b":010300000001FB\r\n",
            &mut cpu
        ),
        None
    );
}

#[test]
fn tcp_unit_ids() {
    let (mut cpu, map) = (cpu(), Map::q_default());
    let req = |unit| Frame::new(Proto::Tcp, 5, unit, hex("03 00 00 00 01"));
    // By default every unit id is answered and echoed; 0 is not a broadcast on TCP.
    let mut slave = Slave::new(8);
    for unit in [0u8, 1, 8, 200, 255] {
        let r = softplc_modbus::serve(&mut slave, &map, &req(unit), &mut cpu).unwrap();
        assert_eq!(r, [0, 5, 0, 0, 0, 5, unit, 3, 2, 0, 0]);
    }
    // tcp_any_unit off: only the own unit id (8, APLC's default), 0 and 255.
    slave.tcp_any_unit = false;
    for (unit, answered) in [(0u8, true), (1, false), (8, true), (9, false), (255, true)] {
        let r = softplc_modbus::serve(&mut slave, &map, &req(unit), &mut cpu);
        assert_eq!(r.is_some(), answered, "unit {unit}");
    }
    // Counters work over TCP too.
    assert_eq!(slave.counters.bus_messages, 10);
    assert_eq!(slave.counters.slave_messages, 8);
}
