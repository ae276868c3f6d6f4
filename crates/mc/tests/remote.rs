//! Remote operations over the wire (004 §7.6): one client per host, another
//! client's hold refused with `C05F` unless forced (mode 0003), remote
//! RESET refused with `C05F` unless the parameter allows it (`4010` outside
//! STOP), remote PAUSE one END after SM204.

mod common;

use std::net::{IpAddr, Ipv4Addr};

use common::*;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, CpuState};
use softplc_mc::*;

const STOP: &str = "100200000001";
const RUN: &str = "1001000000010000";
const FORCED_RUN: &str = "1001000000030000";
const PAUSE: &str = "100300000001";

fn end(cpu: &mut Cpu, s: &mut Session, frame: &str) -> EndCode {
    let bytes = ascii3e(frame);
    match serve(&bytes, cpu, s, None) {
        Served::Reply { response, .. } => decode_response(&response).unwrap().0.end_code,
        other => panic!("{other:?}"),
    }
}

fn host(last: u8) -> Session {
    Session::from_peer(IpAddr::V4(Ipv4Addr::new(192, 168, 0, last)))
}

fn sm(cpu: &Cpu, n: i64) -> bool {
    cpu.memory().get_bit(DeviceKind::SM, n).unwrap()
}

#[test]
fn a_pause_held_by_one_host_blocks_another_until_forced() {
    let (mut cpu, _) = cpu_with(softplc_core::profile::default_config());
    let (mut a, mut b) = (host(1), host(2));
    assert_eq!(end(&mut cpu, &mut a, PAUSE), EndCode::OK);
    cpu.scan();
    assert!(sm(&cpu, 204), "SM204 at the END after the request");
    assert_eq!(cpu.state(), CpuState::Run);
    cpu.scan();
    assert_eq!(cpu.state(), CpuState::Pause);
    // Host B can neither stop nor run the CPU while A holds its PAUSE.
    assert_eq!(end(&mut cpu, &mut b, STOP), EndCode::NOT_EXECUTABLE);
    assert_eq!(end(&mut cpu, &mut b, RUN), EndCode::NOT_EXECUTABLE);
    assert_eq!(cpu.state(), CpuState::Pause);
    // A reconnection from host A is the same client.
    let mut a2 = host(1);
    assert_eq!(end(&mut cpu, &mut a2, STOP), EndCode::OK);
    assert_eq!(cpu.state(), CpuState::Stop);
    // Forced RUN (mode 0003) from B overrides A's STOP.
    assert_eq!(end(&mut cpu, &mut b, FORCED_RUN), EndCode::OK);
    assert_eq!(cpu.state(), CpuState::Run);
}

#[test]
fn remote_run_does_not_cancel_the_key_switch() {
    let (mut cpu, _) = cpu_with(softplc_core::profile::default_config());
    let mut a = host(1);
    cpu.set_stop();
    assert_eq!(end(&mut cpu, &mut a, RUN), EndCode::NOT_EXECUTABLE);
    assert_eq!(cpu.state(), CpuState::Stop);
}

#[test]
fn remote_reset_needs_the_parameter() {
    let reset = bin3e(&[0x06, 0x10, 0x00, 0x00, 0x01, 0x00]);
    let code = |cpu: &mut Cpu| match serve(&reset, cpu, &mut Session::new(), None) {
        Served::Reply { response, .. } => decode_response(&response).unwrap().0.end_code,
        other => panic!("{other:?}"),
    };
    let (mut cpu, _) = cpu_with(softplc_core::profile::default_config());
    assert_eq!(code(&mut cpu), EndCode::CPU_RUNNING);
    assert_eq!(end(&mut cpu, &mut Session::new(), STOP), EndCode::OK);
    assert_eq!(code(&mut cpu), EndCode::NOT_EXECUTABLE);
    assert_eq!(cpu.state(), CpuState::Stop);
    let mut cfg = softplc_core::profile::default_config();
    cfg.remote_reset = true;
    let (mut cpu, _) = cpu_with(cfg);
    assert_eq!(end(&mut cpu, &mut Session::new(), STOP), EndCode::OK);
    assert_eq!(code(&mut cpu), EndCode::OK);
    assert_eq!(cpu.state(), CpuState::Run);
}
