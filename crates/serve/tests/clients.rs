//! Real client libraries against the in-process server: the Rust SLMP client
//! `plc-comm-slmp` (MC protocol) and `tokio-modbus` (Modbus TCP).

use std::time::Duration;

use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_core::program::compile_il;
use softplc_modbus::{Map, Slave};
use softplc_serve::{mc::Mc, modbus::ModbusTcp, Background, EngineConfig, Listener, ServeState};

/// Starts a server with MC and Modbus TCP; returns their addresses and a stopper.
fn start() -> Background {
    let src = "LD X0\nOUT Y0\nLD SM400\nINC D0\nMOV D100 D101\nEND\n";
    let prog = compile_il("t.il", src, &Default::default()).unwrap();
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let cfg = EngineConfig {
        period: Duration::from_millis(2),
        end_budget: Duration::from_millis(1),
        queue: 64,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    let any = "127.0.0.1:0".parse().unwrap();
    let l = vec![
        Listener::tcp(any, Mc::new(None), 4),
        Listener::tcp(any, ModbusTcp::new(Map::q_default(), Slave::new(1)), 4),
    ];
    Background::start(ServeState::new(cpu), cfg, l, vec![]).unwrap()
}

#[test]
fn plc_comm_slmp_reads_and_writes() {
    use plc_comm_slmp::{
        SlmpAddress, SlmpClient, SlmpConnectionOptions, SlmpPlcProfile, SlmpTargetAddress,
        SlmpTransportMode,
    };
    let bg = start();
    let addrs = bg.addrs.clone();
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        // A Q CPU reached through its Ethernet module (QJ71E71-100), as the
        // client requires for Q-series connections.
        let p = SlmpPlcProfile::QCpuQj71E71100;
        let opts = SlmpConnectionOptions::new(
            "127.0.0.1",
            addrs[0].port(),
            SlmpTransportMode::Tcp,
            SlmpTargetAddress::default(),
            p,
        )
        .unwrap();
        let c = SlmpClient::connect(opts).await.unwrap();
        let at = |d: &str| SlmpAddress::parse(d, p).unwrap();
        assert_eq!(c.read_type_name().await.unwrap().model.trim(), "Q06HCPU");
        c.write_words(at("D100"), &[4242]).await.unwrap();
        tokio::time::sleep(Duration::from_millis(20)).await;
        assert_eq!(c.read_words(at("D101"), 1).await.unwrap(), vec![4242]);
        c.write_bits(at("X0"), &[true]).await.unwrap();
        tokio::time::sleep(Duration::from_millis(20)).await;
        assert_eq!(c.read_bits(at("Y0"), 1).await.unwrap(), vec![true]);
        let a = c.read_words(at("D0"), 1).await.unwrap()[0];
        tokio::time::sleep(Duration::from_millis(30)).await;
        assert!(c.read_words(at("D0"), 1).await.unwrap()[0] > a);
        c.close().await.unwrap();
    });
    bg.stop().unwrap();
}

#[test]
fn tokio_modbus_reads_and_writes() {
    use tokio_modbus::prelude::*;
    let bg = start();
    let addrs = bg.addrs.clone();
    let mut ctx = tokio_modbus::client::sync::tcp::connect_slave(addrs[1], Slave(1)).unwrap();
    ctx.write_single_register(100, 777).unwrap().unwrap();
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(
        ctx.read_holding_registers(101, 1).unwrap().unwrap(),
        vec![777]
    );
    // Coil 8192 = M0 (contract §3 map).
    ctx.write_single_coil(8192, true).unwrap().unwrap();
    assert_eq!(ctx.read_coils(8192, 1).unwrap().unwrap(), vec![true]);
    // Past the last mapped holding register (R32767 = 53247): exception 02.
    let e = ctx.read_holding_registers(53248, 1).unwrap();
    assert_eq!(e, Err(ExceptionCode::IllegalDataAddress));
    // FC 23: write D200-D201, read D200-D202 in one request.
    let r = ctx
        .read_write_multiple_registers(200, 3, 200, &[5, 6])
        .unwrap()
        .unwrap();
    assert_eq!(r, vec![5, 6, 0]);
    bg.stop().unwrap();
}
