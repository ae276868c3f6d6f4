//! A real server on 127.0.0.1:0 and a small HTTP/1.1 client for the tests.

#![allow(dead_code)]

use std::net::SocketAddr;
use std::time::Duration;

use serde_json::Value;
use softplc_core::device::DeviceConfig;
use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_http::HttpConfig;
use softplc_serve::{Background, EngineConfig, ServeState};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

pub const TOKEN: &str = "s3cret-token";

/// X0 → Y0, M0 → Y1, D100 counts executed scans.
pub const PROGRAM: &str = "LD X0\nOUT Y0\nLD M0\nOUT Y1\nLD SM400\nINC D100\nEND\n";

pub struct Server {
    pub addr: SocketAddr,
    bg: Option<Background>,
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Some(bg) = self.bg.take() {
            let _ = bg.stop();
        }
    }
}

pub fn start(token: Option<&str>) -> Server {
    start_program(PROGRAM, token)
}

pub fn start_program(src: &str, token: Option<&str>) -> Server {
    start_limited(src, token, Default::default())
}

/// A server of `src` whose door has `limits`.
pub fn start_limited(src: &str, token: Option<&str>, limits: softplc_http::door::Limits) -> Server {
    start_configured(src, token, limits, softplc_core::profile::default_config())
}

/// [`start`] on a CPU whose parameters allow remote RESET (`[ras]
/// remote_reset = true`).
pub fn start_remote_reset(token: Option<&str>) -> Server {
    let mut cfg = softplc_core::profile::default_config();
    cfg.remote_reset = true;
    start_configured(PROGRAM, token, Default::default(), cfg)
}

/// A server of `src` on a CPU of `cfg` whose door has `limits`.
pub fn start_configured(
    src: &str,
    token: Option<&str>,
    limits: softplc_http::door::Limits,
    cfg: softplc_core::engine::CpuConfig,
) -> Server {
    let p = softplc_core::program::compile_il("main.il", src, &DeviceConfig::default()).unwrap();
    let source = softplc_core::program::il::parse_il("main.il", src).unwrap();
    let cpu = Cpu::new(p, cfg, Box::new(MonotonicClock::default()));
    let cfg = HttpConfig {
        token: token.map(str::to_string),
        model: "Q06HCPU".into(),
        ladder: vec![softplc_http::ladder::LadderProgram::from_source(&source)],
        limits,
        online: None,
    };
    start_cpu(cpu, cfg)
}

/// A server of the project in `dir` (plc.toml and its programs) with the
/// token and its programs' ladders.
pub fn start_project(dir: &std::path::Path) -> Server {
    let cpu = softplc_core::project::load_project(dir)
        .and_then(|p| p.build_cpu(Box::new(MonotonicClock::default())))
        .unwrap_or_else(|d| panic!("{:?}", d.0));
    let cfg = HttpConfig {
        token: Some(TOKEN.into()),
        model: "Q06HCPU".into(),
        ladder: softplc_http::ladder::load_programs(&cpu),
        limits: Default::default(),
        online: None,
    };
    start_cpu(cpu, cfg)
}

/// A server of `cpu` at a 5 ms constant scan with the web monitor of `http`.
pub fn start_cpu(cpu: Cpu, http: HttpConfig) -> Server {
    start_state(ServeState::new(cpu), http)
}

/// A server of `state` (one CPU or a multi-CPU system) at a 5 ms period.
pub fn start_state(state: ServeState, http: HttpConfig) -> Server {
    start_state_at(state, http, Duration::from_millis(5))
}

/// A server of `src` with the token on the virtual clock at `scale`, held
/// in lockstep when `lockstep`, at a 10 ms scan.
pub fn start_virtual(src: &str, scale: softplc_serve::TimeScale, lockstep: bool) -> Server {
    let p = softplc_core::program::compile_il("main.il", src, &DeviceConfig::default()).unwrap();
    let clock = softplc_core::engine::VirtualClock::new();
    let cpu = Cpu::new(
        p,
        softplc_core::profile::default_config(),
        Box::new(clock.clone()),
    );
    let mut state = ServeState::new(cpu);
    state.set_virtual_time(softplc_serve::VirtualTime {
        clock,
        scale,
        lockstep,
    });
    let http = HttpConfig {
        token: Some(TOKEN.into()),
        model: "Q06HCPU".into(),
        ladder: Vec::new(),
        limits: Default::default(),
        online: None,
    };
    start_state_at(state, http, Duration::from_millis(10))
}

/// A server of `state` at a `period` scan.
pub fn start_state_at(state: ServeState, http: HttpConfig, period: Duration) -> Server {
    let engine = EngineConfig {
        period,
        end_budget: Duration::from_millis(2),
        queue: 256,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    let l = softplc_http::listener("127.0.0.1:0".parse().unwrap(), http);
    let bg = Background::start(state, engine, vec![l], vec![]).unwrap();
    Server {
        addr: bg.addrs[0],
        bg: Some(bg),
    }
}

pub struct Reply {
    pub status: u16,
    pub headers: String,
    pub body: String,
}

impl Reply {
    pub fn json(&self) -> Value {
        serde_json::from_str(&self.body).unwrap_or_else(|e| panic!("not JSON ({e}): {}", self.body))
    }
}

/// One request with `Connection: close`; `extra` are header lines.
pub async fn request(
    addr: SocketAddr,
    method: &str,
    path: &str,
    extra: &[&str],
    body: Option<&str>,
) -> Reply {
    let mut s = TcpStream::connect(addr).await.unwrap();
    let mut req = format!("{method} {path} HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n");
    for h in extra {
        req.push_str(h);
        req.push_str("\r\n");
    }
    let body = body.unwrap_or("");
    if !body.is_empty() || method != "GET" {
        req.push_str(&format!(
            "Content-Type: application/json\r\nContent-Length: {}\r\n",
            body.len()
        ));
    }
    req.push_str("\r\n");
    req.push_str(body);
    s.write_all(req.as_bytes()).await.unwrap();
    let mut buf = Vec::new();
    tokio::time::timeout(Duration::from_secs(30), s.read_to_end(&mut buf))
        .await
        .expect("reply in time")
        .unwrap();
    let text = String::from_utf8_lossy(&buf).to_string();
    let (head, body) = text.split_once("\r\n\r\n").unwrap_or((&text, ""));
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    let body = if head
        .to_ascii_lowercase()
        .contains("transfer-encoding: chunked")
    {
        dechunk(body)
    } else {
        body.to_string()
    };
    Reply {
        status,
        headers: head.to_string(),
        body,
    }
}

fn dechunk(mut s: &str) -> String {
    let mut out = String::new();
    while let Some((len, rest)) = s.split_once("\r\n") {
        let n = usize::from_str_radix(len.trim(), 16).unwrap_or(0);
        if n == 0 || rest.len() < n {
            break;
        }
        out.push_str(&rest[..n]);
        s = rest[n..].trim_start_matches("\r\n");
    }
    out
}

pub async fn get(addr: SocketAddr, path: &str) -> Reply {
    request(addr, "GET", path, &[], None).await
}

pub fn bearer(t: &str) -> String {
    format!("Authorization: Bearer {t}")
}

/// An authorised request.
pub async fn send(addr: SocketAddr, method: &str, path: &str, body: Option<&str>) -> Reply {
    let auth = bearer(TOKEN);
    request(addr, method, path, &[&auth], body).await
}

/// Reads `n` SSE events' data from `path`, with the time they arrived.
pub async fn sse(addr: SocketAddr, path: &str, n: usize) -> (String, Vec<(Duration, Value)>) {
    let mut s = TcpStream::connect(addr).await.unwrap();
    let req =
        format!("GET {path} HTTP/1.1\r\nHost: localhost\r\nAccept: text/event-stream\r\n\r\n");
    s.write_all(req.as_bytes()).await.unwrap();
    let t0 = std::time::Instant::now();
    let mut text = String::new();
    let mut events = Vec::new();
    let mut buf = [0u8; 4096];
    let mut head = None;
    while events.len() < n {
        let k = tokio::time::timeout(Duration::from_secs(10), s.read(&mut buf))
            .await
            .expect("events in time")
            .unwrap();
        assert!(k > 0, "stream closed: {text}");
        text.push_str(&String::from_utf8_lossy(&buf[..k]));
        if head.is_none() {
            if let Some((h, rest)) = text.clone().split_once("\r\n\r\n") {
                head = Some(h.to_string());
                text = rest.to_string();
            }
        }
        if head.is_some() {
            // Every line starting with `data:` is one event (single-line data).
            while let Some(i) = text.find("data:") {
                let rest = &text[i + 5..];
                let Some(end) = rest.find('\n') else { break };
                let data = rest[..end].trim().to_string();
                events.push((t0.elapsed(), serde_json::from_str(&data).unwrap()));
                text = rest[end..].to_string();
            }
        }
    }
    (head.unwrap_or_default(), events)
}
