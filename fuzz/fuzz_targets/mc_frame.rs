//! MC protocol frames: decoding arbitrary bytes never panics, and whatever
//! decodes (or is refused with an end code) is executed on a small CPU and
//! answered without panicking. The input is consumed frame by frame, as the
//! server does with a TCP stream; the first byte picks whether the connection
//! has a remote password.
#![no_main]
use libfuzzer_sys::fuzz_target;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_mc::{decode_request, encode_response, handle, FrameError, Session};

fuzz_target!(|data: &[u8]| {
    let Some((&flags, mut rest)) = data.split_first() else {
        return;
    };
    // Two file-register blocks instead of the 1 MB default keep runs fast.
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(DeviceKind::ZR, 65536);
    let prog = compile_il(
        "fuzz.il",
        "LD X0\nOUT Y0\nLD X1\n/ D0 K0 D1\nEND\n",
        &cfg.devices,
    )
    .expect("the fuzz program compiles");
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    let mut session = Session::new();
    let password = (flags & 1 != 0).then_some("ab12");
    for _ in 0..16 {
        match decode_request(rest) {
            Ok((req, used)) => {
                assert!(used > 0 && used <= rest.len());
                let resp = handle(&req, &mut cpu, &mut session, password);
                let _ = encode_response(&req.header, &resp);
                rest = &rest[used..];
            }
            Err(FrameError::Rejected(r)) => {
                assert!(r.used > 0 && r.used <= rest.len());
                let _ = r.response();
                rest = &rest[r.used..];
            }
            Err(FrameError::Incomplete) | Err(FrameError::Malformed { .. }) => break,
        }
        clock.advance_us(10_000);
        cpu.scan();
    }
});
