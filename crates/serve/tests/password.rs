//! Remote password guesses are throttled per peer (issue 11 item 8): after a
//! wrong unlock, unlocks from that address are refused without a check for a
//! growing delay (1 s, 2 s, 4 s … 60 s), so guessing runs at about one try a
//! second instead of ~1,600/s; the right password still works afterwards.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_core::program::compile_il;
use softplc_serve::mc::Mc;
use softplc_serve::{Background, EngineConfig, Listener, ServeState};

fn unlock(pw: &[u8; 4]) -> Vec<u8> {
    let mut f = vec![
        0x50, 0, 0, 0xFF, 0xFF, 0x03, 0, 12, 0, 0x10, 0, 0x30, 0x16, 0, 0, 4, 0,
    ];
    f.extend_from_slice(pw);
    f
}

/// 3E binary batch read of D0 × 1 word.
const READ_D0: [u8; 21] = [
    0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0C, 0x00, 0x04, 0x00, 0x01, 0x04, 0x00, 0x00, 0x00,
    0x00, 0x00, 0xA8, 0x01, 0x00,
];

/// Sends a frame and returns the reply's end code.
fn end_code(c: &mut TcpStream, frame: &[u8]) -> u16 {
    c.write_all(frame).unwrap();
    let mut head = [0u8; 9];
    c.read_exact(&mut head).unwrap();
    let mut rest = vec![0; u16::from_le_bytes([head[7], head[8]]) as usize];
    c.read_exact(&mut rest).unwrap();
    u16::from_le_bytes([rest[0], rest[1]])
}

#[test]
fn wrong_guesses_are_throttled_per_peer() {
    let prog = compile_il("t.il", "LD SM400\nINC D0\nEND\n", &Default::default()).unwrap();
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
    let l = Listener::tcp(
        "127.0.0.1:0".parse().unwrap(),
        Mc::new(Some("ab12".into())),
        8,
    );
    let bg = Background::start(ServeState::new(cpu), cfg, vec![l], vec![]).unwrap();
    let mut c = TcpStream::connect(bg.addrs[0]).unwrap();
    assert_eq!(end_code(&mut c, &READ_D0), 0xC201, "locked");
    assert_eq!(end_code(&mut c, &unlock(b"zzzz")), 0xC200, "wrong");
    // Right away, even the right password is refused: the address is throttled.
    assert_eq!(end_code(&mut c, &unlock(b"ab12")), 0xC200, "throttled");
    assert_eq!(end_code(&mut c, &READ_D0), 0xC201, "still locked");
    // Per address, not per connection: a new connection does not reset it.
    let mut d = TcpStream::connect(bg.addrs[0]).unwrap();
    assert_eq!(end_code(&mut d, &unlock(b"ab12")), 0xC200, "throttled");
    // After the delay the right password unlocks.
    std::thread::sleep(Duration::from_millis(1100));
    assert_eq!(end_code(&mut c, &unlock(b"ab12")), 0);
    assert_eq!(end_code(&mut c, &READ_D0), 0);
    bg.stop().unwrap();
}
