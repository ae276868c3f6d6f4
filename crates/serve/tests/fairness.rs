//! No client can silence or starve the others (issue 11 item 5): Modbus FC 08
//! sub-function 04 (listen-only) affects only its TCP connection and is
//! refused by a read-only slave; connection churn at the connection limit does
//! not cost a polling client its polls; MC over UDP serves every queued
//! datagram at one END and a flooding sender does not starve another.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_core::program::compile_il;
use softplc_modbus::{Map, Slave};
use softplc_serve::mc::Mc;
use softplc_serve::modbus::ModbusTcp;
use softplc_serve::{Background, EngineConfig, Listener, ServeState};

/// The tests of this file load the machine (floods, churn): one at a time.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

fn start(listener: Listener, period_ms: u64) -> Background {
    let prog = compile_il("t.il", "LD SM400\nINC D0\nEND\n", &Default::default()).unwrap();
    let cpu = Cpu::new(
        prog,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let period = Duration::from_millis(period_ms);
    let cfg = EngineConfig {
        period,
        end_budget: period / 2,
        queue: 1024,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    Background::start(ServeState::new(cpu), cfg, vec![listener], vec![]).unwrap()
}

fn modbus(read_only: bool, max_conns: usize) -> Background {
    let slave = Slave {
        read_only,
        ..Slave::default()
    };
    let l = Listener::tcp(
        "127.0.0.1:0".parse().unwrap(),
        ModbusTcp::new(Map::default(), slave),
        max_conns,
    );
    start(l, 2)
}

fn connect(addr: SocketAddr) -> TcpStream {
    let c = TcpStream::connect(addr).unwrap();
    c.set_nodelay(true).unwrap();
    c.set_read_timeout(Some(Duration::from_millis(400)))
        .unwrap();
    c
}

/// Sends a Modbus TCP request (unit 1) and reads a reply of `len` bytes.
fn ask(c: &mut TcpStream, pdu: &[u8], len: usize) -> std::io::Result<Vec<u8>> {
    let mut req = vec![0, 7, 0, 0, 0, (pdu.len() + 1) as u8, 1];
    req.extend_from_slice(pdu);
    c.write_all(&req)?;
    let mut r = vec![0; len];
    c.read_exact(&mut r)?;
    Ok(r[7..].to_vec())
}

const READ_D0: [u8; 5] = [3, 0, 0, 0, 1];

#[test]
fn listen_only_silences_only_its_own_connection() {
    let _serial = one_at_a_time();
    let bg = modbus(false, 8);
    let mut a = connect(bg.addrs[0]);
    let mut b = connect(bg.addrs[0]);
    // A: 08/0004 force listen-only (no reply is due).
    a.write_all(&[0, 1, 0, 0, 0, 6, 1, 8, 0, 4, 0, 0]).unwrap();
    std::thread::sleep(Duration::from_millis(50));
    // B is still answered.
    assert_eq!(ask(&mut b, &READ_D0, 11).unwrap()[0], 3);
    // A is silent until its 08/0001 restart.
    assert!(ask(&mut a, &READ_D0, 11).is_err(), "A is listen-only");
    let mut a = connect(bg.addrs[0]); // a new connection starts normal
    assert_eq!(ask(&mut a, &READ_D0, 11).unwrap()[0], 3);
    assert_eq!(ask(&mut b, &READ_D0, 11).unwrap()[0], 3);
    bg.stop().unwrap();

    // A read-only slave refuses it with exception 01.
    let bg = modbus(true, 8);
    let mut a = connect(bg.addrs[0]);
    assert_eq!(ask(&mut a, &[8, 0, 4, 0, 0], 9).unwrap(), [0x88, 0x01]);
    assert_eq!(ask(&mut a, &READ_D0, 11).unwrap()[0], 3);
    bg.stop().unwrap();
}

#[test]
fn connection_churn_does_not_cost_a_polling_client_its_polls() {
    let _serial = one_at_a_time();
    let bg = modbus(false, 4);
    let addr = bg.addrs[0];
    let stop = Arc::new(AtomicBool::new(false));
    let opened = Arc::new(AtomicU64::new(0));
    // Churners: connect, stay a few ms without a word, close; as fast as possible.
    let churners: Vec<_> = (0..3)
        .map(|k| {
            let (stop, opened) = (stop.clone(), opened.clone());
            std::thread::spawn(move || {
                let mut n = 0u64;
                while !stop.load(Ordering::Relaxed) {
                    if let Ok(c) = TcpStream::connect(addr) {
                        opened.fetch_add(1, Ordering::Relaxed);
                        std::thread::sleep(Duration::from_millis(1 + (n + k) % 4));
                        drop(c);
                    }
                    n += 1;
                }
            })
        })
        .collect();
    // The HMI: 200 polls at 20 ms (reconnecting when dropped).
    let polls = 200;
    let mut lost = 0;
    let mut c = connect(addr);
    let started = Instant::now();
    for _ in 0..polls {
        let t = Instant::now();
        if ask(&mut c, &READ_D0, 11).is_err() {
            lost += 1;
            c = connect(addr);
        }
        std::thread::sleep(Duration::from_millis(20).saturating_sub(t.elapsed()));
    }
    let secs = started.elapsed().as_secs_f64();
    stop.store(true, Ordering::Relaxed);
    churners.into_iter().for_each(|t| t.join().unwrap());
    let rate = opened.load(Ordering::Relaxed) as f64 / secs;
    eprintln!(
        "churn {rate:.0} connections/s for {secs:.1} s: {lost} of {polls} polls lost ({:.1} %)",
        100.0 * lost as f64 / polls as f64
    );
    assert!(rate > 100.0, "the churn must be real ({rate:.0}/s)");
    assert!(lost * 100 <= polls, "{lost} of {polls} polls lost");
    bg.stop().unwrap();
}

/// 3E binary batch read of D0 × 1 word.
const MC_READ_D0: [u8; 21] = [
    0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0C, 0x00, 0x04, 0x00, 0x01, 0x04, 0x00, 0x00, 0x00,
    0x00, 0x00, 0xA8, 0x01, 0x00,
];

fn mc_udp() -> Background {
    start(
        Listener::mc_udp("127.0.0.1:0".parse().unwrap(), Mc::new(None)),
        10,
    )
}

#[test]
fn udp_serves_every_queued_datagram_at_one_end() {
    let _serial = one_at_a_time();
    let bg = mc_udp();
    let s = UdpSocket::bind("127.0.0.1:0").unwrap();
    s.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
    for _ in 0..24 {
        s.send_to(&MC_READ_D0, bg.addrs[0]).unwrap();
    }
    let mut scans = std::collections::BTreeSet::new();
    let mut buf = [0u8; 64];
    for _ in 0..24 {
        let (n, _) = s.recv_from(&mut buf).expect("every datagram answered");
        assert_eq!(n, 13);
        scans.insert(u16::from_le_bytes([buf[11], buf[12]]));
    }
    // D0 counts scans: 24 requests served at no more than 3 ENDs (10 ms apart).
    assert!(
        scans.len() <= 3,
        "served over {} ENDs: {scans:?}",
        scans.len()
    );
    bg.stop().unwrap();
}

#[test]
fn a_udp_flood_does_not_starve_another_sender() {
    let _serial = one_at_a_time();
    let bg = mc_udp();
    let addr = bg.addrs[0];
    let stop = Arc::new(AtomicBool::new(false));
    let st = stop.clone();
    let flood = std::thread::spawn(move || {
        let s = UdpSocket::bind("127.0.0.1:0").unwrap();
        let mut sent = 0u64;
        // ~20,000 datagrams/s: 200 times what one reply per END could serve,
        // yet leaving the machine (2 cores) able to drain its socket.
        while !st.load(Ordering::Relaxed) {
            for _ in 0..20 {
                let _ = s.send_to(&MC_READ_D0, addr);
                sent += 1;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        sent
    });
    let s = UdpSocket::bind("127.0.0.1:0").unwrap();
    s.set_read_timeout(Some(Duration::from_millis(500)))
        .unwrap();
    let mut buf = [0u8; 64];
    let mut answered = 0;
    for _ in 0..50 {
        s.send_to(&MC_READ_D0, addr).unwrap();
        if s.recv_from(&mut buf).is_ok() {
            answered += 1;
        }
    }
    stop.store(true, Ordering::Relaxed);
    let sent = flood.join().unwrap();
    eprintln!("flood of {sent} datagrams: the other sender got {answered} of 50 replies");
    assert!(answered >= 48, "starved: {answered} of 50");
    bg.stop().unwrap();
}
