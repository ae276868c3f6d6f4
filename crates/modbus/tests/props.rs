//! Property tests: decoding never panics and always makes progress; frames and
//! requests round-trip; serving arbitrary frames never panics and answers with
//! well-formed frames; registers written read back.

mod common;

use common::*;
use proptest::prelude::*;
use softplc_modbus::{decode, decode_exact, serve, Frame, Map, Proto, Request, Slave, Step};

fn proto() -> impl Strategy<Value = Proto> {
    prop_oneof![Just(Proto::Tcp), Just(Proto::Rtu), Just(Proto::Ascii)]
}

/// Requests whose PDU fits a frame; FC 08 with two data bytes (the RTU form).
fn request() -> impl Strategy<Value = Request> {
    use Request::*;
    let aq = (any::<u16>(), any::<u16>());
    prop_oneof![
        aq.prop_map(|(address, quantity)| ReadCoils { address, quantity }),
        aq.prop_map(|(address, quantity)| ReadDiscreteInputs { address, quantity }),
        aq.prop_map(|(address, quantity)| ReadHoldingRegisters { address, quantity }),
        aq.prop_map(|(address, quantity)| ReadInputRegisters { address, quantity }),
        aq.prop_map(|(address, value)| WriteSingleCoil { address, value }),
        aq.prop_map(|(address, value)| WriteSingleRegister { address, value }),
        (any::<u16>(), any::<[u8; 2]>()).prop_map(|(sub, d)| Diagnostics {
            sub,
            data: d.to_vec()
        }),
        (any::<u16>(), 0u16..=1968).prop_flat_map(|(address, quantity)| {
            proptest::collection::vec(any::<u8>(), (quantity as usize).div_ceil(8)).prop_map(
                move |bits| WriteMultipleCoils {
                    address,
                    quantity,
                    bits,
                },
            )
        }),
        (
            any::<u16>(),
            proptest::collection::vec(any::<u16>(), 0..=123)
        )
            .prop_map(|(address, values)| WriteMultipleRegisters { address, values }),
        (any::<u16>(), any::<u16>(), any::<u16>()).prop_map(|(address, and_mask, or_mask)| {
            MaskWriteRegister {
                address,
                and_mask,
                or_mask,
            }
        }),
        (
            any::<u16>(),
            any::<u16>(),
            any::<u16>(),
            proptest::collection::vec(any::<u16>(), 0..=121)
        )
            .prop_map(|(read_address, read_quantity, write_address, values)| {
                ReadWriteMultipleRegisters {
                    read_address,
                    read_quantity,
                    write_address,
                    values,
                }
            }),
    ]
}

/// Addresses near the interesting places of both maps.
fn address() -> impl Strategy<Value = u16> {
    prop_oneof![
        any::<u16>(),
        (0u16..300),
        (1190u16..1470),
        (8180u16..8210),
        (9690u16..9820),
        (53200u16..53300),
    ]
}

/// Small quantities near the limits.
fn quantity() -> impl Strategy<Value = u16> {
    prop_oneof![
        0u16..10,
        118u16..130,
        250u16..260,
        1960u16..2010,
        any::<u16>()
    ]
}

/// Requests aimed at the maps (addresses and quantities near the edges).
fn aimed_request() -> impl Strategy<Value = Request> {
    use Request::*;
    prop_oneof![
        (address(), quantity()).prop_map(|(address, quantity)| ReadCoils { address, quantity }),
        (address(), quantity())
            .prop_map(|(address, quantity)| ReadDiscreteInputs { address, quantity }),
        (address(), quantity())
            .prop_map(|(address, quantity)| ReadHoldingRegisters { address, quantity }),
        (address(), quantity())
            .prop_map(|(address, quantity)| ReadInputRegisters { address, quantity }),
        (
            address(),
            prop_oneof![Just(0u16), Just(0xFF00), any::<u16>()]
        )
            .prop_map(|(address, value)| WriteSingleCoil { address, value }),
        (address(), any::<u16>())
            .prop_map(|(address, value)| WriteSingleRegister { address, value }),
        (0u16..0x14, any::<[u8; 2]>(), any::<bool>()).prop_map(|(sub, d, zero)| Diagnostics {
            sub,
            data: if zero { vec![0, 0] } else { d.to_vec() }
        }),
        request(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn decode_never_panics_and_progresses(p in proto(), bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        match decode(p, &bytes) {
            Ok(Some((f, used))) => {
                prop_assert!(used >= 1 && used <= bytes.len());
                prop_assert!(!f.pdu.is_empty());
                prop_assert_eq!(f.proto, p);
            }
            Ok(None) => {}
            Err(e) => prop_assert!(e.skip >= 1 && e.skip <= bytes.len().max(1)),
        }
        let _ = decode_exact(p, &bytes);
    }

    #[test]
    fn ascii_like_input_never_panics(body in "[:0-9A-Fa-fG\r\n]{0,80}") {
        let bytes = body.as_bytes();
        if let Err(e) = decode(Proto::Ascii, bytes) {
            prop_assert!(e.skip >= 1 && e.skip <= bytes.len());
        }
    }

    #[test]
    fn frames_round_trip(p in proto(), tid in any::<u16>(), unit in any::<u8>(), req in request()) {
        let pdu = req.to_pdu();
        let tid = if p == Proto::Tcp { tid } else { 0 };
        let f = Frame::new(p, tid, unit, pdu);
        let bytes = f.encode();
        prop_assert_eq!(decode(p, &bytes).unwrap(), Some((f.clone(), bytes.len())));
        prop_assert_eq!(decode_exact(p, &bytes).unwrap(), f);
    }

    #[test]
    fn any_pdu_round_trips_exactly(p in proto(), tid in any::<u16>(), unit in any::<u8>(),
                                   pdu in proptest::collection::vec(any::<u8>(), 1..=253)) {
        let tid = if p == Proto::Tcp { tid } else { 0 };
        let f = Frame::new(p, tid, unit, pdu);
        prop_assert_eq!(decode_exact(p, &f.encode()).unwrap(), f);
    }

    #[test]
    fn requests_round_trip(req in request()) {
        prop_assert_eq!(Request::parse(&req.to_pdu()), Ok(req));
    }

    #[test]
    fn serving_never_panics(
        aplc in any::<bool>(),
        p in proto(),
        unit in prop_oneof![Just(0u8), Just(1u8), any::<u8>()],
        read_only in any::<bool>(),
        listen_only in any::<bool>(),
        reqs in proptest::collection::vec(
            prop_oneof![
                aimed_request().prop_map(|r| r.to_pdu()),
                proptest::collection::vec(any::<u8>(), 1..20),
            ],
            1..8,
        ),
    ) {
        let map = if aplc { Map::aplc() } else { Map::q_default() };
        let mut cpu = cpu();
        let mut slave = Slave::new(1);
        slave.read_only = read_only;
        slave.listen_only = listen_only;
        for pdu in reqs {
            let f = Frame::new(p, if p == Proto::Tcp { 7 } else { 0 }, unit, pdu.clone());
            let Some(resp) = serve(&mut slave, &map, &f, &mut cpu) else { continue };
            let r = decode_exact(p, &resp).unwrap();
            prop_assert_eq!((r.proto, r.transaction, r.unit), (p, f.transaction, unit));
            prop_assert!(r.pdu.len() <= 253);
            if r.pdu[0] & 0x80 != 0 {
                prop_assert_eq!(r.pdu.len(), 2);
                prop_assert_eq!(r.pdu[0], pdu[0] | 0x80);
                prop_assert!((1..=4).contains(&r.pdu[1]));
            } else {
                prop_assert_eq!(r.pdu[0], pdu[0]);
                prop_assert!(map.supports(pdu[0]));
            }
        }
    }

    #[test]
    fn byte_streams_are_consumed(p in proto(), chunks in proptest::collection::vec(
        prop_oneof![
            request().prop_map(|r| r.to_pdu()),
            proptest::collection::vec(any::<u8>(), 1..12),
        ], 0..6)) {
        // Valid frames mixed with junk: the handle loop always terminates.
        let mut buf = Vec::new();
        for (i, pdu) in chunks.iter().enumerate() {
            if i % 2 == 0 {
                buf.extend(Frame::new(p, i as u16, 1, pdu.clone()).encode());
            } else {
                buf.extend_from_slice(pdu);
            }
        }
        let map = Map::q_default();
        let mut cpu = cpu();
        let mut slave = Slave::new(1);
        let mut rest = &buf[..];
        for _ in 0..=buf.len() {
            match slave.handle(&map, p, rest, &mut cpu) {
                Step::NeedMore => break,
                Step::Served { used, .. } => rest = &rest[used..],
                Step::Error(e) => rest = &rest[e.skip..],
            }
            if rest.is_empty() {
                break;
            }
        }
    }

    #[test]
    fn written_registers_read_back(
        address in 0u16..53248,
        values in proptest::collection::vec(any::<u16>(), 1..=123),
    ) {
        let map = Map::q_default();
        let mut cpu = cpu();
        let mut slave = Slave::new(1);
        let n = values.len() as u16;
        let send = |req: Request, slave: &mut Slave, cpu: &mut softplc_core::engine::Cpu| {
            let f = Frame::new(Proto::Tcp, 1, 1, req.to_pdu());
            serve(slave, &map, &f, cpu).unwrap()[7..].to_vec()
        };
        let w = send(Request::WriteMultipleRegisters { address, values: values.clone() }, &mut slave, &mut cpu);
        if address as u32 + n as u32 > 53248 {
            prop_assert_eq!(w, vec![0x90, 2]);
        } else {
            prop_assert_eq!(w[0], 16);
            let r = send(Request::ReadHoldingRegisters { address, quantity: n }, &mut slave, &mut cpu);
            let got: Vec<u16> = r[2..].chunks(2).map(|c| u16::from_be_bytes([c[0], c[1]])).collect();
            prop_assert_eq!(got, values);
        }
    }
}
