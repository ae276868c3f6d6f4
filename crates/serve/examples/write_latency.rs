//! What acknowledged writes cost (issue 11 item 1): Modbus TCP writes (FC 06 to
//! latched D0) against a CPU with the default 1 MiB of file registers in a
//! state directory, with the reply sent after the END's commit (the default)
//! and, for comparison, before it. Prints round-trip p50/p99 per mode and the
//! time of one `Battery::commit` with one changed word (the added work).
//!
//! Run: `cargo run --release -p softplc-serve --example write_latency -- [writes] [period_ms]`

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, LatchRange, MonotonicClock};
use softplc_core::persist::Battery;
use softplc_core::program::compile_il;
use softplc_modbus::{Map, Slave};
use softplc_serve::{modbus::ModbusTcp, Background, EngineConfig, Listener, ServeState};

fn cpu() -> Cpu {
    let prog = compile_il("w.il", "LD SM400\nINC D200\nEND\n", &Default::default()).unwrap();
    let mut cfg = softplc_core::profile::default_config();
    cfg.latch.push(LatchRange {
        kind: DeviceKind::D,
        start: 0,
        end: 99,
        clearable: true,
    });
    Cpu::new(prog, cfg, Box::new(MonotonicClock::default()))
}

fn pct(v: &[Duration], p: f64) -> Duration {
    v[((v.len() as f64 * p) as usize).min(v.len() - 1)]
}

fn run(writes: usize, period: Duration, ack_after_commit: bool) -> Vec<Duration> {
    let dir = std::env::temp_dir().join(format!(
        "softplc-write-latency-{}-{ack_after_commit}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    let mut cpu = cpu();
    let battery = Battery::attach(&dir, &mut cpu, false).expect("state directory");
    let cfg = EngineConfig {
        period,
        end_budget: period / 4,
        queue: 1024,
        battery: Some(battery),
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit,
    };
    let l = Listener::tcp(
        "127.0.0.1:0".parse().unwrap(),
        ModbusTcp::new(Map::default(), Slave::default()),
        4,
    );
    let bg = Background::start(ServeState::new(cpu), cfg, vec![l], vec![]).expect("serve");
    let mut s = TcpStream::connect(bg.addrs[0]).unwrap();
    s.set_nodelay(true).unwrap();
    let mut lat = Vec::with_capacity(writes);
    let mut resp = [0u8; 12];
    for i in 0..writes {
        let v = (i as u16).wrapping_add(1);
        let mut req = vec![0, 1, 0, 0, 0, 6, 1, 6, 0, 0];
        req.extend_from_slice(&v.to_be_bytes());
        let t = Instant::now();
        s.write_all(&req).unwrap();
        s.read_exact(&mut resp).unwrap();
        lat.push(t.elapsed());
        assert_eq!(resp[..], req[..], "echo");
    }
    bg.stop().expect("stop");
    let _ = std::fs::remove_dir_all(&dir);
    lat.sort();
    lat
}

fn main() {
    let mut args = std::env::args().skip(1);
    let writes: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(500);
    let period = Duration::from_millis(args.next().and_then(|a| a.parse().ok()).unwrap_or(10));
    let before = run(writes, period, false);
    let after = run(writes, period, true);
    for (name, l) in [
        ("reply before commit", &before),
        ("reply after commit ", &after),
    ] {
        println!(
            "{name}: {writes} writes, p50 {:>7.0} us, p99 {:>7.0} us",
            pct(l, 0.5).as_secs_f64() * 1e6,
            pct(l, 0.99).as_secs_f64() * 1e6
        );
    }
    println!(
        "added: p50 {:+.0} us, p99 {:+.0} us",
        (pct(&after, 0.5).as_secs_f64() - pct(&before, 0.5).as_secs_f64()) * 1e6,
        (pct(&after, 0.99).as_secs_f64() - pct(&before, 0.99).as_secs_f64()) * 1e6
    );
    // The commit itself: one changed word in 1 MiB of file registers + D0-D99.
    let dir = std::env::temp_dir().join(format!("softplc-commit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut cpu = cpu();
    let mut b = Battery::attach(&dir, &mut cpu, false).expect("state directory");
    let mut t = Vec::new();
    for i in 0..writes {
        cpu.set_word(DeviceKind::D, 0, i as u16).expect("D0");
        let s = Instant::now();
        b.commit(&cpu).expect("commit");
        t.push(s.elapsed());
    }
    t.sort();
    println!(
        "Battery::commit, one changed word: p50 {:.0} us, p99 {:.0} us",
        pct(&t, 0.5).as_secs_f64() * 1e6,
        pct(&t, 0.99).as_secs_f64() * 1e6
    );
    drop(b);
    let _ = std::fs::remove_dir_all(&dir);
}
