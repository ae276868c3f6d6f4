//! Load test of `softplc serve` on loopback (issue 6): N MC-protocol clients
//! hammer a CPU scanning at a 10 ms constant scan for a bounded time; prints
//! requests/s, latency percentiles and the engine's overruns and jitter.
//!
//! Run: `cargo run --release -p softplc-serve --example mc_load -- [clients] [seconds]`

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_core::program::compile_il;
use softplc_serve::{mc::Mc, Background, EngineConfig, Listener, ServeState};

/// 3E binary batch read of D100 × 3 words (what pymcprotocol sends).
const READ_D100: [u8; 21] = [
    0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0C, 0x00, 0x04, 0x00, 0x01, 0x04, 0x00, 0x00, 0x64,
    0x00, 0x00, 0xA8, 0x03, 0x00,
];
/// Its reply: 11-byte header (end code 0) + 6 data bytes.
const REPLY_LEN: usize = 17;

fn main() {
    let mut args = std::env::args().skip(1);
    let clients: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(32);
    let seconds: u64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(5);
    // A small program: 200 rungs of contacts, a timer, arithmetic.
    let mut src = String::new();
    for i in 0..200 {
        src += &format!("LD X{i:X}\nOR M{i}\nANI X{:X}\nOUT M{i}\n", i + 1);
    }
    src += "LD SM400\nINC D0\n+ D0 K1 D100\nOUT T0 K10\nEND\n";
    let prog = compile_il("load.il", &src, &Default::default()).expect("program");
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let cfg = EngineConfig {
        period: Duration::from_millis(10),
        end_budget: Duration::from_micros(2500),
        queue: 1024,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::default(),
        ack_after_commit: true,
    };
    let l = Listener::tcp("127.0.0.1:0".parse().unwrap(), Mc::new(None), clients + 4);
    let bg = Background::start(ServeState::new(cpu), cfg, vec![l], vec![]).expect("serve");
    let addr = bg.addrs[0];
    let deadline = Instant::now() + Duration::from_secs(seconds);
    let workers: Vec<_> = (0..clients)
        .map(|_| {
            std::thread::spawn(move || {
                let mut s = TcpStream::connect(addr).unwrap();
                s.set_nodelay(true).unwrap();
                let mut lat = Vec::new();
                let mut reply = [0u8; REPLY_LEN];
                while Instant::now() < deadline {
                    let t = Instant::now();
                    s.write_all(&READ_D100).unwrap();
                    s.read_exact(&mut reply).unwrap();
                    assert_eq!(&reply[9..11], &[0, 0], "end code");
                    lat.push(t.elapsed());
                }
                lat
            })
        })
        .collect();
    let mut lat: Vec<Duration> = workers
        .into_iter()
        .flat_map(|w| w.join().unwrap())
        .collect();
    let state = bg.stop().expect("serve");
    lat.sort();
    let pct = |p: f64| lat[((lat.len() as f64 * p) as usize).min(lat.len() - 1)];
    let st = &state.stats;
    println!(
        "clients: {clients}, duration: {seconds} s, constant scan 10 ms, real-time priority: {}",
        state.stats.realtime
    );
    println!(
        "requests: {} ({:.0}/s), latency p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
        lat.len(),
        lat.len() as f64 / seconds as f64,
        pct(0.50).as_secs_f64() * 1e3,
        pct(0.99).as_secs_f64() * 1e3,
        lat.last().unwrap().as_secs_f64() * 1e3
    );
    println!(
        "scans: {}, overruns: {}, scan+END max {} us, start jitter max {} us mean {:.0} us",
        st.scans, st.overruns, st.max_us, st.jitter_max_us, st.jitter_mean_us
    );
}
