//! `[port1]`/`[port2]` of an APLC-TCP project (contract §3.3): the
//! settings, each error at its value (`line:col`, worked out by hand), and
//! the SD registers they show once the CPU is on.

mod common;
use common::project::{error, ok, with_main};
use softplc_core::engine::VirtualClock;

const APLC: &str = "[cpu]\nmodel = \"APLC-TCP\"\n";

#[test]
fn port_settings_reach_the_sd_registers() {
    let p = ok(&with_main(&format!(
        "{APLC}[port1]\nprotocol = \"modbus-master\"\nbaud = 9600\naddress = 3\ntimeout_ms = 250\nretries = 2\n\
         [port2]\nprotocol = \"free\"\nend_char = 13\n"
    )));
    assert_eq!(p.ports.len(), 2);
    assert_eq!(
        (p.ports[0].port, p.ports[0].baud, p.ports[0].address),
        (1, 9600, 3)
    );
    // The APLC project compiles its program files as .apl: give it one.
    let dir = std::env::temp_dir().join(format!("softplc-ports-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("main.apl"), "LD SM0\nOUT M0\n").unwrap();
    std::fs::write(
        dir.join("plc.toml"),
        format!("{APLC}[[program]]\nfile = \"main.apl\"\n[port1]\nprotocol = \"modbus-master\"\nbaud = 9600\naddress = 3\ntimeout_ms = 250\nretries = 2\n[port2]\nprotocol = \"free\"\nend_char = 13\n"),
    )
    .unwrap();
    let proj = softplc_core::project::load_project(&dir).unwrap();
    let cpu = proj.build_cpu(Box::new(VirtualClock::new())).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let sd = |n: i64| {
        cpu.memory()
            .get_word(softplc_core::device::DeviceKind::SD, n)
            .unwrap()
    };
    // SD120: 9600 (code 010), parity even enabled (bit 5): 16#22.
    assert_eq!((sd(120), sd(135), sd(136), sd(137)), (0x22, 3, 250, 2));
    // SD150: 9600 8N1 (010) with the end-character mode (bit 8); SD152 = 13.
    assert_eq!((sd(150), sd(152)), (0x102, 13));
}

#[test]
fn port_errors_point_at_the_value() {
    assert_eq!(
        error(&with_main(&format!("{APLC}[port1]\nprotocol = \"modbus-master\"\nbaud = 300\n"))),
        "5:8: [port1] baud: baud 300: expected 1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200 (APLC programming manual §10.3.2, SD120)"
    );
    assert_eq!(
        error(&with_main(&format!(
            "{APLC}[port2]\nprotocol = \"free\"\nretries = 1\n"
        ))),
        "5:11: [port2] retries: a Modbus setting, but the protocol is free"
    );
    assert_eq!(
        error(&with_main("[port1]\nprotocol = \"free\"\n")),
        "1:2: [port1] is an APLC-TCP setting (set [cpu] model = \"APLC-TCP\")"
    );
}
