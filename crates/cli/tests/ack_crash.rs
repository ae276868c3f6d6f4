//! An acknowledged write is never lost (issue 11 item 1): a Modbus TCP client
//! writes increasing values to a latched data register (D0) of `softplc serve`, which
//! is killed with SIGKILL at random moments. After each kill the value in the
//! state directory must be at least the last one the server acknowledged (and
//! never more than the last one sent).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

/// xorshift: reproducible random delays without a dependency.
fn next(seed: &mut u64) -> u64 {
    *seed ^= *seed << 13;
    *seed ^= *seed >> 7;
    *seed ^= *seed << 17;
    *seed
}

/// FC 06 write single register: holding register 0 is D0 (default map).
fn write_d0(c: &mut TcpStream, tid: u16, value: u16) -> std::io::Result<bool> {
    let mut req = Vec::with_capacity(12);
    req.extend_from_slice(&tid.to_be_bytes());
    req.extend_from_slice(&[0, 0, 0, 6, 1, 6]);
    req.extend_from_slice(&0u16.to_be_bytes());
    req.extend_from_slice(&value.to_be_bytes());
    c.write_all(&req)?;
    let mut resp = [0u8; 12];
    c.read_exact(&mut resp)?;
    Ok(resp == req[..])
}

#[test]
fn kill_9_never_loses_an_acknowledged_write() {
    let dir = tempfile::tempdir().unwrap();
    // D0-D99 latched; small file registers keep the debug build's commits short.
    std::fs::write(
        dir.path().join("plc.toml"),
        "[[program]]\nfile = \"p.il\"\n[devices]\nfile_register = 1024\n\
         [latch]\nlatch1 = [\"D0-D99\"]\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("p.il"), "LD SM400\nINC D200\nEND\n").unwrap();
    let prog = dir.path().to_path_buf();
    let state = dir.path().join("state");
    let state_s = state.to_str().unwrap();
    let kills: u32 = std::env::var("SOFTPLC_ACK_KILLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(120);
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let started = Instant::now();
    let mut sent_total = 0u64;
    let mut acked_total = 0u64;
    let mut last_saved = 0u64;
    let mut next_value = 1u64;
    for k in 0..kills {
        let mut server = softplc()
            .args(["serve", prog.to_str().unwrap(), "--state", state_s])
            .args(["--scan-time", "2ms", "--modbus", "127.0.0.1:0"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut err = BufReader::new(server.stderr.take().unwrap());
        let mut line = String::new();
        while !line.contains("Modbus TCP on ") {
            line.clear();
            assert!(err.read_line(&mut line).unwrap() > 0, "serve exited early");
        }
        let addr = line
            .split("Modbus TCP on ")
            .nth(1)
            .unwrap()
            .trim()
            .to_string();
        // Keep draining stderr so the server never blocks on it.
        std::thread::spawn(move || std::io::copy(&mut err, &mut std::io::sink()));

        let acked = Arc::new(AtomicU64::new(0));
        let sent = Arc::new(AtomicU64::new(0));
        let (a, s) = (acked.clone(), sent.clone());
        let first = next_value;
        let writer = std::thread::spawn(move || {
            let Ok(mut c) = TcpStream::connect(&addr) else {
                return;
            };
            let _ = c.set_nodelay(true);
            let _ = c.set_read_timeout(Some(Duration::from_secs(5)));
            let mut v = first;
            loop {
                s.store(v, Ordering::SeqCst);
                match write_d0(&mut c, v as u16, v as u16) {
                    Ok(true) => a.store(v, Ordering::SeqCst),
                    _ => return,
                }
                v += 1;
            }
        });
        // Kill at a random moment once writes are flowing.
        let t0 = Instant::now();
        while acked.load(Ordering::SeqCst) == 0 && t0.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_micros(200));
        }
        std::thread::sleep(Duration::from_micros(next(&mut seed) % 40_000));
        server.kill().unwrap();
        server.wait().unwrap();
        writer.join().unwrap();
        let (acked, sent) = (acked.load(Ordering::SeqCst), sent.load(Ordering::SeqCst));

        let out = softplc()
            .args(["run", prog.to_str().unwrap(), "--state", state_s])
            .args(["--scans", "0", "--json", "--show", "D0:u16"])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "restart {k}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let saved = v["devices"]["D0:u16"].as_u64().unwrap();
        if acked > 0 {
            assert!(
                saved >= acked,
                "kill {k}: acknowledged write {acked} lost (state holds {saved})"
            );
            acked_total += acked - first + 1;
        }
        if sent > 0 {
            assert!(
                saved <= sent,
                "kill {k}: {saved} was never sent (last {sent})"
            );
            sent_total += sent - first + 1;
        }
        assert!(saved >= last_saved, "kill {k}: went back");
        last_saved = saved;
        next_value = sent.max(next_value) + 1;
        assert!(next_value < 60_000, "values must fit a register");
    }
    eprintln!(
        "{kills} kills in {:.1} s: {acked_total} writes acknowledged, {sent_total} sent, 0 acknowledged lost",
        started.elapsed().as_secs_f64()
    );
    assert!(
        acked_total > u64::from(kills),
        "the writer must get replies"
    );
}
