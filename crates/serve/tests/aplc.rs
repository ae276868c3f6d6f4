//! Modbus TCP against an APLC-TCP program with the real client `tokio-modbus`
//! (spec/aplc.md §6.3-6.5, contract §3): seed 002's map over the APLC's
//! device memory at unit address 8, C200-C255 as true 32-bit pairs (even
//! address = high word), octal Y, and the map's exceptions.

use std::time::Duration;

use softplc_core::engine::MonotonicClock;
use softplc_modbus::{Map, Slave};
use softplc_serve::{modbus::ModbusTcp, Background, EngineConfig, Listener, ServeState};

/// M0 drives Y10 (octal: output 8, coil 8); C200's 32-bit value is copied
/// to D100 (high word) and D101 each scan.
const PROGRAM: &str = "LD M0\nOUT Y10\nLD SM0\nDMOV C200 D100\n";

fn start() -> Background {
    let prog = softplc_core::aplc::load_bytes("t.apl", PROGRAM.as_bytes()).unwrap();
    let cpu = softplc_core::aplc::single_cpu(
        prog,
        softplc_core::aplc::cpu_config(),
        Box::new(MonotonicClock::default()),
    )
    .unwrap();
    let cfg = EngineConfig {
        period: Duration::from_millis(2),
        end_budget: Duration::from_millis(1),
        queue: 64,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    // Unit address 8 only (tcp_any_unit = false), as `[modbus]` would give.
    let table: toml::Table = toml::from_str("tcp_any_unit = false").unwrap();
    let slave = Slave::from_toml_with(&table, 8).unwrap();
    let any = "127.0.0.1:0".parse().unwrap();
    let l = vec![Listener::tcp(any, ModbusTcp::new(Map::aplc(), slave), 4)];
    Background::start(ServeState::new(cpu), cfg, l, vec![]).unwrap()
}

#[test]
fn tokio_modbus_on_an_aplc_program_at_unit_8() {
    use tokio_modbus::prelude::*;
    let bg = start();
    let mut ctx = tokio_modbus::client::sync::tcp::connect_slave(bg.addrs[0], Slave(8)).unwrap();
    // C200 = 100000 = 16#0001_86A0 by FC 16 at 9700 (high word first).
    ctx.write_multiple_registers(9700, &[0x0001, 0x86A0])
        .unwrap()
        .unwrap();
    assert_eq!(
        ctx.read_holding_registers(9700, 2).unwrap().unwrap(),
        vec![0x0001, 0x86A0]
    );
    // The program saw the true 32-bit value: DMOV C200 D100 gives D100 = 1,
    // D101 = 16#86A0 (34464), read at holding registers 100-101.
    std::thread::sleep(Duration::from_millis(30));
    assert_eq!(
        ctx.read_holding_registers(100, 2).unwrap().unwrap(),
        vec![1, 34464]
    );
    // M0 is coil 2000; Y10 (octal) is coil 8.
    ctx.write_single_coil(2000, true).unwrap().unwrap();
    std::thread::sleep(Duration::from_millis(30));
    assert_eq!(ctx.read_coils(8, 1).unwrap().unwrap(), vec![true]);
    assert_eq!(ctx.read_coils(7, 1).unwrap().unwrap(), vec![false]);
    // FC 06 into the 32-bit counters: 02 (decision D24); odd start: 02; odd
    // count: 03; FC 04 is not an APLC function: 01.
    assert_eq!(
        ctx.write_single_register(9700, 1).unwrap(),
        Err(ExceptionCode::IllegalDataAddress)
    );
    assert_eq!(
        ctx.read_holding_registers(9701, 2).unwrap(),
        Err(ExceptionCode::IllegalDataAddress)
    );
    assert_eq!(
        ctx.read_holding_registers(9700, 3).unwrap(),
        Err(ExceptionCode::IllegalDataValue)
    );
    assert_eq!(
        ctx.read_input_registers(0, 1).unwrap(),
        Err(ExceptionCode::IllegalFunction)
    );
    // SD as the map says (spec/aplc.md §7.2): SD50 is R/W, SD20 (the error
    // code) is read-only: the write is answered and changes nothing.
    ctx.write_single_register(8050, 123).unwrap().unwrap();
    ctx.write_single_register(8020, 5).unwrap().unwrap();
    std::thread::sleep(Duration::from_millis(10));
    assert_eq!(
        ctx.read_holding_registers(8050, 1).unwrap().unwrap(),
        vec![123]
    );
    assert_eq!(
        ctx.read_holding_registers(8020, 1).unwrap().unwrap(),
        vec![0]
    );
    // The refused writes changed nothing.
    assert_eq!(
        ctx.read_holding_registers(9700, 2).unwrap().unwrap(),
        vec![0x0001, 0x86A0]
    );
    bg.stop().unwrap();
}
