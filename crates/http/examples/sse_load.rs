//! The web monitor's cost on the scan (issue #15): a 10 ms constant scan of
//! examples/conveyor.il (repeated to ~`--rungs` rungs) for `--secs` seconds
//! without clients, then again with `--clients` SSE clients each watching 40
//! devices (browser equivalents: one event stream and a status poll every
//! 500 ms). Prints overruns, scan-time and period jitter for both runs.
//!
//! `cargo run --release -p softplc-http --example sse_load -- --clients 50 --secs 10`

use std::time::{Duration, Instant};

use softplc_core::device::DeviceConfig;
use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_serve::{Background, EngineConfig, ScanStats, ServeState};
use tokio::io::{AsyncReadExt, AsyncWriteExt};

fn arg(name: &str, default: u64) -> u64 {
    let a: Vec<String> = std::env::args().collect();
    a.iter()
        .position(|x| x == name)
        .and_then(|i| a.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn program(copies: usize) -> String {
    let mut s = String::new();
    for k in 0..copies {
        let (x, y, m, d) = (k * 4, k * 2, k * 2, k * 2);
        s.push_str(&format!(
            "LD X{x:X}\nOR Y{y:X}\nAND X{:X}\nOUT Y{y:X}\nLD Y{y:X}\nAND SM412\nPLS M{m}\nLD M{m}\nINC D{d}\nLD SM400\nMOV D{d} D{}\n",
            x + 1,
            d + 1
        ));
    }
    s.push_str("END\n");
    s
}

fn run(clients: usize, secs: u64, copies: usize) -> ScanStats {
    let src = program(copies);
    let p = softplc_core::program::compile_il("load.il", &src, &DeviceConfig::default()).unwrap();
    let ladder = softplc_http::ladder::LadderProgram::from_source(
        &softplc_core::program::il::parse_il("load.il", &src).unwrap(),
    );
    let names: Vec<String> = ladder.devices().into_iter().take(40).collect();
    let cpu = Cpu::new(
        p,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let cfg = softplc_http::HttpConfig {
        token: None,
        model: "Q06HCPU".into(),
        ladder: vec![ladder],
        limits: Default::default(),
        online: None,
    };
    let engine = EngineConfig {
        period: Duration::from_millis(10),
        end_budget: Duration::from_micros(2500),
        queue: 1024,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::default(),
        ack_after_commit: true,
    };
    let l = softplc_http::listener("127.0.0.1:0".parse().unwrap(), cfg);
    let bg = Background::start(ServeState::new(cpu), engine, vec![l], vec![]).unwrap();
    let addr = bg.addrs[0];
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let events = rt.block_on(async move {
        let path = format!("/api/v1/events?names={}", names.join(","));
        let mut tasks = Vec::new();
        for _ in 0..clients {
            let path = path.clone();
            tasks.push(tokio::spawn(async move {
                let mut s = tokio::net::TcpStream::connect(addr).await.unwrap();
                let req = format!("GET {path} HTTP/1.1\r\nHost: x\r\n\r\n");
                s.write_all(req.as_bytes()).await.unwrap();
                let end = Instant::now() + Duration::from_secs(secs);
                let mut buf = vec![0u8; 16384];
                let mut n = 0usize;
                let mut poll = Instant::now();
                while Instant::now() < end {
                    if let Ok(Ok(k)) = tokio::time::timeout(Duration::from_millis(100), s.read(&mut buf)).await {
                        n += buf[..k].windows(5).filter(|w| w == b"data:").count();
                    }
                    if poll.elapsed() >= Duration::from_millis(500) {
                        poll = Instant::now();
                        // The page's status poll.
                        if let Ok(mut c) = tokio::net::TcpStream::connect(addr).await {
                            let _ = c
                                .write_all(b"GET /api/v1/status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")
                                .await;
                            let mut v = Vec::new();
                            let _ = c.read_to_end(&mut v).await;
                        }
                    }
                }
                n
            }));
        }
        if clients == 0 {
            tokio::time::sleep(Duration::from_secs(secs)).await;
        }
        let mut total = 0;
        for t in tasks {
            total += t.await.unwrap_or(0);
        }
        total
    });
    let st = bg.stop().unwrap().stats;
    println!(
        "{clients:3} clients: {} scans, {} overruns, exec us last/min/max {}/{}/{}, busy max {} us, jitter max {} us mean {:.1} us, {} requests, {} events ({:.1}/s per client), real-time: {}",
        st.scans, st.overruns, st.exec_us, st.exec_min_us, st.exec_max_us, st.max_us, st.jitter_max_us, st.jitter_mean_us, st.requests,
        events, if clients > 0 { events as f64 / clients as f64 / secs as f64 } else { 0.0 }, st.realtime_note
    );
    st
}

fn main() {
    let clients = arg("--clients", 50) as usize;
    let secs = arg("--secs", 10);
    let copies = arg("--rungs", 100) as usize / 5;
    run(0, secs, copies.max(1));
    run(clients, secs, copies.max(1));
}
