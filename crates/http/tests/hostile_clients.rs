//! The web monitor under clients that misbehave: event streams opened and
//! dropped at once, more connections than the limit, slow headers and
//! bodies (issue #31).

mod common;

use std::time::{Duration, Instant};

use common::*;
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;

/// `watched` in status.
async fn watched(addr: std::net::SocketAddr) -> u64 {
    get(addr, "/api/v1/status").await.json()["watched"]
        .as_u64()
        .expect("status has watched")
}

/// Polls `watched` until it is `want` (at most `limit`); returns the last value.
async fn watched_becomes(addr: std::net::SocketAddr, want: u64, limit: Duration) -> u64 {
    let t0 = Instant::now();
    loop {
        let w = watched(addr).await;
        if w == want || t0.elapsed() > limit {
            return w;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// Issue #31 defect 1: an event stream whose client goes away at once,
/// before or after its answer started, gives its subscription back.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn event_streams_dropped_at_once_unsubscribe() {
    let s = start(None);
    let base = watched(s.addr).await;
    for i in 0..400u32 {
        let mut c = TcpStream::connect(s.addr).await.unwrap();
        let req = format!(
            "GET /api/v1/events?names=D{},M{} HTTP/1.1\r\nHost: localhost\r\nAccept: text/event-stream\r\n\r\n",
            1000 + i,
            i
        );
        c.write_all(req.as_bytes()).await.unwrap();
        if i % 2 == 1 {
            // Some wait for their subscription to be made first.
            tokio::time::sleep(Duration::from_millis(2)).await;
        }
        drop(c);
    }
    let w = watched_becomes(s.addr, base, Duration::from_secs(5)).await;
    assert_eq!(w, base, "the dropped streams' devices are still watched");
    // Dropped streams of 1,000 names each, 12,000 names in all: more than
    // the monitor watches at once (4,096), had they stayed.
    for k in 0..12u32 {
        let names: Vec<String> = (0..1000)
            .map(|i| format!("D{}", 2000 + k * 1000 + i))
            .collect();
        let mut c = TcpStream::connect(s.addr).await.unwrap();
        let req = format!(
            "GET /api/v1/events?names={} HTTP/1.1\r\nHost: localhost\r\n\r\n",
            names.join(",")
        );
        c.write_all(req.as_bytes()).await.unwrap();
        tokio::time::sleep(Duration::from_millis(20)).await;
        drop(c);
    }
    // New streams are still accepted and served.
    let (_, ev) = sse(s.addr, "/api/v1/events?names=D100", 2).await;
    assert!(ev[1].1["devices"]["D100"].is_u64());
    let w = watched_becomes(s.addr, base, Duration::from_secs(5)).await;
    assert_eq!(w, base);
}
