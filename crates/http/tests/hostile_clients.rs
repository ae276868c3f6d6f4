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

/// Whether the server closed `c` (EOF or reset) within `wait`.
async fn closed_within(c: &mut TcpStream, wait: Duration) -> bool {
    use tokio::io::AsyncReadExt;
    let mut buf = [0u8; 1024];
    let t0 = Instant::now();
    while t0.elapsed() < wait {
        match tokio::time::timeout(wait - t0.elapsed(), c.read(&mut buf)).await {
            Err(_) => return false,
            Ok(Ok(0)) | Ok(Err(_)) => return true,
            // An answer (e.g. 408): read on until the close.
            Ok(Ok(_)) => continue,
        }
    }
    false
}

fn limits(max: usize, header: u64, body: u64) -> softplc_http::door::Limits {
    softplc_http::door::Limits {
        max_connections: max,
        header_timeout: Duration::from_millis(header),
        body_timeout: Duration::from_millis(body),
    }
}

/// Issue #31 defect 2: half-sent requests beyond the connection limit do
/// not pile up (each new one takes the place of one that never completed a
/// request), and a new client is still served.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn half_sent_requests_beyond_the_limit_do_not_pile_up() {
    let s = start_limited(PROGRAM, None, limits(8, 30_000, 30_000));
    let mut held = Vec::new();
    for _ in 0..100 {
        let mut c = TcpStream::connect(s.addr).await.unwrap();
        c.write_all(b"GET /api/v1/status HTTP/1.1\r\nHost: x\r\n")
            .await
            .unwrap();
        held.push(c);
    }
    // A new client is served (it evicts one of the half-sent requests).
    let r = get(s.addr, "/api/v1/status").await;
    assert_eq!(r.status, 200, "{}", r.body);
    let mut open = 0;
    for c in &mut held {
        if !closed_within(c, Duration::from_millis(20)).await {
            open += 1;
        }
    }
    assert!(
        open <= 8,
        "{open} half-sent requests still hold a connection"
    );
}

/// An event stream is an active client: at the limit it is not evicted,
/// an idle connection is, and with only active clients a new one is refused.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn event_streams_keep_their_place_at_the_limit() {
    let s = start_limited(PROGRAM, None, limits(2, 30_000, 30_000));
    let mut a = TcpStream::connect(s.addr).await.unwrap();
    a.write_all(b"GET /api/v1/events?names=D100 HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    let mut b = TcpStream::connect(s.addr).await.unwrap();
    b.write_all(b"GET /api/v1/events?names=Y0 HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    // Both streams are active: a third connection is refused (closed).
    let mut c = TcpStream::connect(s.addr).await.unwrap();
    c.write_all(b"GET /api/v1/status HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    assert!(closed_within(&mut c, Duration::from_secs(2)).await);
    assert!(!closed_within(&mut a, Duration::from_millis(300)).await);
    assert!(!closed_within(&mut b, Duration::from_millis(10)).await);
    // One stream ends: there is room again.
    drop(b);
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert_eq!(get(s.addr, "/api/v1/status").await.status, 200);
}

/// Slowloris: a request head dribbled a byte at a time is closed after the
/// header timeout; so is a kept-alive connection that stays silent.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn slow_heads_and_silent_connections_are_closed_after_the_header_timeout() {
    let s = start_limited(PROGRAM, None, limits(64, 500, 30_000));
    let mut slow = TcpStream::connect(s.addr).await.unwrap();
    let t0 = Instant::now();
    let head = b"GET /api/v1/status HTTP/1.1\r\nHost: localhost\r\nX-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa";
    let mut closed = false;
    for byte in head {
        if slow.write_all(&[*byte]).await.is_err() {
            closed = true;
            break;
        }
        if closed_within(&mut slow, Duration::from_millis(100)).await {
            closed = true;
            break;
        }
    }
    let took = t0.elapsed();
    assert!(closed, "a head dribbled over {took:?} was never closed");
    assert!(took < Duration::from_millis(2000), "closed after {took:?}");
    // A connection that never sends anything.
    let mut silent = TcpStream::connect(s.addr).await.unwrap();
    assert!(closed_within(&mut silent, Duration::from_secs(3)).await);
    // Kept alive after an answer, then silent.
    let mut kept = TcpStream::connect(s.addr).await.unwrap();
    kept.write_all(b"GET /api/v1/status HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    assert!(closed_within(&mut kept, Duration::from_secs(3)).await);
}

/// A body that does not arrive within the body timeout is 408 and closes
/// the connection; nothing of it is written.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_slow_body_is_408() {
    let s = start_limited(PROGRAM, Some(TOKEN), limits(64, 30_000, 500));
    let mut c = TcpStream::connect(s.addr).await.unwrap();
    let head = format!(
        "POST /api/v1/devices HTTP/1.1\r\nHost: x\r\n{}\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{{\"D0\": 7",
        bearer(TOKEN)
    );
    c.write_all(head.as_bytes()).await.unwrap();
    let t0 = Instant::now();
    let mut reply = Vec::new();
    use tokio::io::AsyncReadExt;
    tokio::time::timeout(Duration::from_secs(5), c.read_to_end(&mut reply))
        .await
        .expect("answered and closed")
        .unwrap();
    let text = String::from_utf8_lossy(&reply);
    assert!(text.starts_with("HTTP/1.1 408"), "{text}");
    assert!(t0.elapsed() >= Duration::from_millis(400));
    let j = get(s.addr, "/api/v1/devices?names=D0").await.json();
    assert_eq!(j["devices"]["D0"], 0);
}
