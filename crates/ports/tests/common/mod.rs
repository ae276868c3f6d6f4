//! An APLC-TCP CPU with ports on virtual lines, scanned in virtual time
//! with the communication phase after each END.
#![allow(dead_code)]

use std::time::Duration;

use softplc_aplc::comm::{PortConfig, Val};
use softplc_core::access::Value;
use softplc_core::aplc;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_ports::{Peer, Ports};

pub struct Rig {
    pub cpu: Cpu,
    pub clock: VirtualClock,
    pub ports: Ports,
    pub scan_us: u64,
}

pub fn port(n: u8, items: &[(&str, Val<'_>)]) -> PortConfig {
    PortConfig::build(n, items).unwrap()
}

pub use softplc_ports::peers::shared;

pub fn rig(src: &str, ports: Vec<(PortConfig, Box<dyn Peer>)>) -> Rig {
    let program = aplc::load_bytes("t.apl", src.as_bytes()).unwrap_or_else(|d| panic!("{d}"));
    let cfgs = ports.iter().map(|(c, _)| c.clone()).collect();
    let cfg = aplc::cpu_config_with_ports(Duration::from_millis(200), None, cfgs);
    let clock = VirtualClock::new();
    let cpu = aplc::single_cpu(program, cfg, Box::new(clock.clone())).unwrap();
    let mut p = Ports::new();
    for (c, peer) in ports {
        p.add_virtual(c, peer);
    }
    Rig {
        cpu,
        clock,
        ports: p,
        scan_us: 10_000,
    }
}

impl Rig {
    pub fn scan(&mut self) -> &mut Self {
        self.clock.advance_us(self.scan_us);
        self.cpu.scan();
        self.ports.after_end(&mut self.cpu);
        self
    }

    pub fn scans(&mut self, n: u32) -> &mut Self {
        for _ in 0..n {
            self.scan();
        }
        self
    }

    pub fn set(&mut self, name: &str, v: &str) -> &mut Self {
        let n = aplc::Name::parse(name).unwrap();
        let v = n.value(v).unwrap();
        self.cpu.write_value(&n.spec, &v).unwrap();
        self
    }

    pub fn int(&self, name: &str) -> i64 {
        let n = aplc::Name::parse(name).unwrap();
        match n.present(self.cpu.read_device(&n.spec).unwrap()) {
            Value::Int(i) => i,
            Value::Bool(b) => b as i64,
            v => panic!("{name} = {v:?}"),
        }
    }

    pub fn bit(&self, name: &str) -> bool {
        self.int(name) != 0
    }

    pub fn words(&self, first: u32, n: u32) -> Vec<i64> {
        (first..first + n)
            .map(|k| self.int(&format!("D{k}")))
            .collect()
    }
}
