//! `GET`/`PUT /api/v1/snapshot` (contract §7): the state file taken at an
//! END, restored at the next one with the scan count and the time; a bad
//! file is 400 with `{"error"}` and changes nothing; writes need the token.

mod common;

use std::net::SocketAddr;
use std::time::Duration;

use common::{bearer, get, start, TOKEN};
use softplc_core::engine::{Cpu, VirtualClock};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

/// One request with a binary body; the status and the body's bytes.
async fn raw(addr: SocketAddr, method: &str, token: Option<&str>, body: &[u8]) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(addr).await.unwrap();
    let mut req = format!(
        "{method} /api/v1/snapshot HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\
         Content-Type: application/octet-stream\r\nContent-Length: {}\r\n",
        body.len()
    );
    if let Some(t) = token {
        req += &format!("Authorization: Bearer {t}\r\n");
    }
    req += "\r\n";
    s.write_all(req.as_bytes()).await.unwrap();
    s.write_all(body).await.unwrap();
    let mut buf = Vec::new();
    tokio::time::timeout(Duration::from_secs(30), s.read_to_end(&mut buf))
        .await
        .expect("reply in time")
        .unwrap();
    let at = buf.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8_lossy(&buf[..at]);
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, buf[at + 4..].to_vec())
}

fn json(body: &[u8]) -> serde_json::Value {
    serde_json::from_slice(body)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(body)))
}

/// D100 counts executed scans: in every END it equals the scan count.
async fn scan_and_d100(addr: SocketAddr) -> (i64, i64) {
    let v = get(addr, "/api/v1/devices?names=D100").await.json();
    (
        v["scan"].as_i64().unwrap(),
        v["devices"]["D100"].as_i64().unwrap(),
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_snapshot_comes_back_with_its_scan_count() {
    let srv = start(Some(TOKEN));
    tokio::time::sleep(Duration::from_millis(50)).await;
    let (status, file) = raw(srv.addr, "GET", None, &[]).await;
    assert_eq!(status, 200);
    assert!(file.starts_with(b"SPLCSTAT"));
    // Time passes: 300 ms of 5 ms scans.
    tokio::time::sleep(Duration::from_millis(300)).await;
    let (before, d) = scan_and_d100(srv.addr).await;
    assert_eq!(before, d);
    let (status, body) = raw(srv.addr, "PUT", Some(TOKEN), &file).await;
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    let v = json(&body);
    let restored = v["scan"].as_i64().unwrap();
    assert!(
        restored + 20 < before,
        "restored scan {restored}, before {before}"
    );
    assert!(v["time_ms"].as_f64().unwrap() < 300.0);
    // The scan count and D100 came back together and go on from there.
    let (scan, d) = scan_and_d100(srv.addr).await;
    assert_eq!(scan, d);
    assert!(
        scan >= restored && scan < before,
        "{restored} ≤ {scan} < {before}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_bad_file_is_400_and_changes_nothing() {
    let srv = start(Some(TOKEN));
    let (_, file) = raw(srv.addr, "GET", None, &[]).await;
    tokio::time::sleep(Duration::from_millis(100)).await;
    let (before, _) = scan_and_d100(srv.addr).await;
    let mut damaged = file.clone();
    let last = damaged.len() - 1;
    damaged[last] ^= 0xFF;
    let (status, body) = raw(srv.addr, "PUT", Some(TOKEN), &damaged).await;
    assert_eq!(status, 400);
    let e = json(&body)["error"].as_str().unwrap().to_string();
    assert!(e.contains("damaged"), "{e}");
    // Another program's file.
    let cfg = softplc_core::profile::default_config();
    let p =
        softplc_core::program::compile_il("main.il", "LD X0\nOUT Y5\nEND\n", &cfg.devices).unwrap();
    let mut other = Cpu::new(p, cfg, Box::new(VirtualClock::new()));
    let (status, body) = raw(
        srv.addr,
        "PUT",
        Some(TOKEN),
        &softplc_core::snapshot::save(&mut other),
    )
    .await;
    assert_eq!(status, 400);
    assert!(json(&body)["error"]
        .as_str()
        .unwrap()
        .contains("other programs"));
    // Nothing went back: the count goes on.
    let (scan, d) = scan_and_d100(srv.addr).await;
    assert_eq!(scan, d);
    assert!(scan >= before);
    // Writes need the token.
    assert_eq!(raw(srv.addr, "PUT", None, &file).await.0, 401);
    assert_eq!(raw(srv.addr, "PUT", Some("wrong"), &file).await.0, 401);
    let ro = start(None);
    assert_eq!(raw(ro.addr, "PUT", Some(TOKEN), &file).await.0, 403);
    let _ = bearer(TOKEN);
}
