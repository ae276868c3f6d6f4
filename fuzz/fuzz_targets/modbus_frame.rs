//! Modbus frames: decoding arbitrary bytes never panics for TCP, RTU or ASCII,
//! and whatever decodes is served on a small CPU (Q or APLC map) without
//! panicking, answered with a frame that decodes again. The input is consumed
//! frame by frame, as a server does with a stream; the first byte picks the
//! transport, the map and the slave's modes.
#![no_main]
use libfuzzer_sys::fuzz_target;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_modbus::{decode, decode_exact, serve, Map, Proto, Slave};

fuzz_target!(|data: &[u8]| {
    let Some((&flags, mut rest)) = data.split_first() else {
        return;
    };
    let proto = Proto::ALL[(flags & 3) as usize % 3];
    let map = if flags & 4 != 0 {
        Map::aplc()
    } else {
        Map::q_default()
    };
    // Both maps reach at most R32767 (ZR block 0): one file-register block
    // instead of the 1 MB default serves every mapped address and keeps the
    // CPU built per input small.
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(DeviceKind::ZR, 32768);
    let prog = compile_il("fuzz.il", "LD X0\nOUT Y0\nEND\n", &cfg.devices)
        .expect("the fuzz program compiles");
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    let mut slave = Slave::new(1);
    slave.read_only = flags & 8 != 0;
    slave.tcp_any_unit = flags & 16 == 0;

    // Every transport must survive the same bytes.
    for p in Proto::ALL {
        let _ = decode(p, rest);
        let _ = decode_exact(p, rest);
    }
    for _ in 0..32 {
        match decode(proto, rest) {
            Ok(Some((frame, used))) => {
                assert!(used > 0 && used <= rest.len());
                if let Some(resp) = serve(&mut slave, &map, &frame, &mut cpu) {
                    let back = decode_exact(proto, &resp).expect("responses decode");
                    assert_eq!(
                        (back.transaction, back.unit),
                        (frame.transaction, frame.unit)
                    );
                }
                rest = &rest[used..];
            }
            Ok(None) => break,
            Err(e) => {
                assert!(e.skip > 0 && e.skip <= rest.len());
                slave.frame_error(&e);
                rest = &rest[e.skip..];
            }
        }
        clock.advance_us(10_000);
        cpu.scan();
    }
});
