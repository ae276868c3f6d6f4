//! The real-time engine and the TCP plumbing with a tiny line protocol:
//! "D0\n" → the device's value at END, "STATS\n" → scans, anything else closes.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::time::Duration;

use softplc_core::access::DeviceSpec;
use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_core::program::compile_il;
use softplc_serve::{Background, EngineConfig, FrameLen, Listener, Protocol, ServeState};

struct Lines;

impl Protocol for Lines {
    type Session = u32;
    fn session(&self, _peer: Option<std::net::SocketAddr>) -> u32 {
        0
    }
    fn frame_len(&self, buf: &[u8]) -> FrameLen {
        match buf.iter().position(|b| *b == b'\n') {
            Some(i)
                if buf[..i]
                    .iter()
                    .all(|b| b.is_ascii_alphanumeric() || *b == b':') =>
            {
                FrameLen::Frame(i + 1)
            }
            Some(_) => FrameLen::Garbage(Some(b"ERR\n".to_vec())),
            None => FrameLen::More,
        }
    }
    fn serve(&self, frame: &[u8], n: &mut u32, s: &mut ServeState) -> Option<Vec<u8>> {
        *n += 1;
        let text = std::str::from_utf8(&frame[..frame.len() - 1]).ok()?;
        let reply = if text == "STATS" {
            format!("{} {}\n", s.stats.scans, n)
        } else {
            let spec = DeviceSpec::parse(text).ok()?;
            format!("{}\n", s.cpu().read_device(&spec).ok()?)
        };
        Some(reply.into_bytes())
    }
    fn busy(&self, _: &[u8]) -> Option<Vec<u8>> {
        Some(b"BUSY\n".to_vec())
    }
}

fn ask(c: &mut BufReader<TcpStream>, q: &str) -> String {
    c.get_mut().write_all(q.as_bytes()).unwrap();
    let mut line = String::new();
    c.read_line(&mut line).unwrap();
    line.trim().to_string()
}

#[test]
fn requests_are_served_at_end_while_scanning() {
    let prog = compile_il(
        "t.il",
        "LD SM400\nINC D0\nMOV D0 D1\nEND\n",
        &Default::default(),
    )
    .unwrap();
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let cfg = EngineConfig {
        period: Duration::from_millis(2),
        end_budget: Duration::from_millis(1),
        queue: 64,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    let l = Listener::tcp("127.0.0.1:0".parse().unwrap(), Lines, 2);
    let bg = Background::start(ServeState::new(cpu), cfg, vec![l], vec![]).unwrap();
    let addr = bg.addrs[0];
    let mut c = BufReader::new(TcpStream::connect(addr).unwrap());
    // D0 and D1 are equal at every END: a reply never shows half a scan.
    for _ in 0..20 {
        let d0: i64 = ask(&mut c, "D0\n").parse().unwrap();
        let d1: i64 = ask(&mut c, "D1\n").parse().unwrap();
        assert!(d1 >= d0, "D1 {d1} read after D0 {d0}");
    }
    let first: i64 = ask(&mut c, "D0\n").parse().unwrap();
    std::thread::sleep(Duration::from_millis(50));
    let later: i64 = ask(&mut c, "D0\n").parse().unwrap();
    assert!(
        later > first + 5,
        "the engine scans on its own: {first} → {later}"
    );
    // A malformed frame closes only its connection.
    let mut bad = BufReader::new(TcpStream::connect(addr).unwrap());
    assert_eq!(ask(&mut bad, "D0 ?\n"), "ERR");
    assert!(
        ask(&mut c, "STATS\n")
            .split(' ')
            .next()
            .unwrap()
            .parse::<u64>()
            .unwrap()
            > 10
    );
    // The connection limit (2) evicts a connection that never completed a
    // request, not the active client.
    let mut d = BufReader::new(TcpStream::connect(addr).unwrap());
    let mut e = BufReader::new(TcpStream::connect(addr).unwrap());
    assert!(!ask(&mut e, "D0\n").is_empty());
    assert!(!ask(&mut c, "D0\n").is_empty());
    let _ = d.get_mut().write_all(b"D0\n");
    let mut line = String::new();
    assert!(
        matches!(d.read_line(&mut line), Ok(0) | Err(_)),
        "the silent connection was evicted: {line:?}"
    );
    let state = bg.stop().unwrap();
    assert!(state.stats.scans > 20);
    assert!(state.stats.requests >= 40);
}

#[test]
fn mc_protocol_over_tcp_and_udp() {
    use softplc_serve::mc::Mc;
    use std::io::Read;
    use std::net::UdpSocket;
    // 3E binary batch read of D100 × 3 words (pymcprotocol's bytes).
    const READ_D100: [u8; 21] = [
        0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0C, 0x00, 0x04, 0x00, 0x01, 0x04, 0x00, 0x00,
        0x64, 0x00, 0x00, 0xA8, 0x03, 0x00,
    ];
    let prog = compile_il("t.il", "LD SM400\nMOV K7 D101\nEND\n", &Default::default()).unwrap();
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let cfg = EngineConfig {
        period: Duration::from_millis(2),
        end_budget: Duration::from_millis(1),
        queue: 64,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    let any = "127.0.0.1:0".parse().unwrap();
    let l = vec![
        Listener::tcp(any, Mc::new(None), 4),
        Listener::mc_udp(any, Mc::new(None)),
    ];
    let bg = Background::start(ServeState::new(cpu), cfg, l, vec![]).unwrap();
    let addrs = bg.addrs.clone();
    // Reply: D0 00 00 FF FF 03 00, length 8, end code 0, then D100-D102 = 0, 7, 0.
    let want = [
        0xD0, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x08, 0x00, 0x00, 0x00, 0, 0, 7, 0, 0, 0,
    ];
    std::thread::sleep(Duration::from_millis(20));
    let mut t = TcpStream::connect(addrs[0]).unwrap();
    t.write_all(&READ_D100).unwrap();
    let mut reply = [0u8; 17];
    t.read_exact(&mut reply).unwrap();
    assert_eq!(reply, want);
    let u = UdpSocket::bind("127.0.0.1:0").unwrap();
    u.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
    u.send_to(&READ_D100, addrs[1]).unwrap();
    let mut buf = [0u8; 64];
    let (n, _) = u.recv_from(&mut buf).unwrap();
    assert_eq!(&buf[..n], &want);
    bg.stop().unwrap();
}

#[test]
#[cfg(target_os = "linux")]
fn the_engine_thread_asks_for_sched_fifo_and_says_what_it_got() {
    let prog = compile_il("t.il", "LD X0\nOUT Y0\nEND\n", &Default::default()).unwrap();
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let cfg = EngineConfig {
        period: Duration::from_millis(2),
        end_budget: Duration::from_millis(1),
        queue: 8,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::default(),
        ack_after_commit: true,
    };
    let l = Listener::tcp("127.0.0.1:0".parse().unwrap(), Lines, 2);
    let bg = Background::start(ServeState::new(cpu), cfg, vec![l], vec![]).unwrap();
    let mut c = BufReader::new(TcpStream::connect(bg.addrs[0]).unwrap());
    assert!(!ask(&mut c, "STATS\n").is_empty());
    let state = bg.stop().unwrap();
    let st = &state.stats;
    if st.realtime {
        assert!(
            st.realtime_note.starts_with("SCHED_FIFO priority"),
            "{}",
            st.realtime_note
        );
    } else {
        // Without the privilege: the normal policy, and the reason.
        assert!(
            st.realtime_note.starts_with("not granted"),
            "{}",
            st.realtime_note
        );
    }
    // As root (CI, this machine) it is granted for real: the policy of the
    // thread that served the request is SCHED_FIFO.
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } == 0 {
        assert!(st.realtime, "{}", st.realtime_note);
    }
}

#[test]
#[cfg(target_os = "linux")]
fn requests_run_on_the_sched_fifo_thread() {
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        return; // needs the privilege
    }
    let prog = compile_il("t.il", "LD X0\nOUT Y0\nEND\n", &Default::default()).unwrap();
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let cfg = EngineConfig {
        period: Duration::from_millis(2),
        end_budget: Duration::from_millis(1),
        queue: 8,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::default(),
        ack_after_commit: true,
    };
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let (handle, join) = softplc_serve::engine::spawn(ServeState::new(cpu), cfg, stop.clone());
    // SAFETY: sched_getscheduler(0) queries the calling thread (the engine's).
    let policy = handle
        .call(|_| unsafe { libc::sched_getscheduler(0) })
        .unwrap();
    assert_eq!(policy, libc::SCHED_FIFO);
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    assert!(join.join().unwrap().stats.realtime);
}
