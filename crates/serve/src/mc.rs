//! The MC protocol (SLMP) server over TCP: 3E/4E frames, binary or ASCII,
//! detected per frame (contract §3). Decoding and the commands are in
//! `softplc-mc`; this adapter cuts frames from the stream and serves them at END.
//! A multi-CPU system has one server: each frame's request destination module
//! I/O number picks the CPU (`softplc_mc::destination`).
//!
//! Remote password guesses are throttled per peer address: after the n-th
//! wrong unlock in a row from an address, unlocks from it are refused
//! (C200, without checking) for 1 s × 2^(n-1), at most 60 s, and every wrong
//! guess is logged. A right guess resets the count.

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use softplc_mc::{
    decode_request, destination, encode_response, handle_station, Command, EndCode, FrameError,
    Response, Session,
};

use crate::engine::ServeState;
use crate::tcp::{FrameLen, Protocol};

/// First delay after a wrong remote password; doubled per further wrong one.
const FIRST_DELAY: Duration = Duration::from_secs(1);
const MAX_DELAY: Duration = Duration::from_secs(60);
/// Peer addresses remembered for throttling.
const MAX_TRACKED: usize = 4096;

/// Wrong guesses in a row from one address.
#[derive(Debug, Clone, Copy)]
struct Guesses {
    wrong: u32,
    /// Unlocks before this are refused without a check.
    until: Instant,
}

/// MC protocol server settings.
pub struct Mc {
    /// Remote password (checked with [`check_password`]); `None`: no password.
    pub password: Option<String>,
    guesses: Mutex<HashMap<IpAddr, Guesses>>,
}

/// A remote password as the QCPU holds it: exactly 4 ASCII characters, letters
/// and digits (qcpu.md §4.14: "a 4-character alphanumeric password").
pub fn check_password(p: &str) -> Result<(), String> {
    if p.is_empty() {
        return Err("the remote password must not be empty".into());
    }
    if p.len() != 4 || !p.bytes().all(|b| b.is_ascii_alphanumeric()) {
        return Err(format!(
            "remote password must be exactly 4 ASCII letters or digits (got {} characters{})",
            p.chars().count(),
            if p.chars().all(|c| c.is_ascii_alphanumeric()) {
                ""
            } else {
                ", not all letters or digits"
            }
        ));
    }
    Ok(())
}

impl Mc {
    pub fn new(password: Option<String>) -> Mc {
        Mc {
            password,
            guesses: Mutex::new(HashMap::new()),
        }
    }

    /// Serves one delimited frame for `peer` (engine thread, at END). Returns
    /// the reply, or `None` to close the connection.
    pub fn serve_frame(
        &self,
        frame: &[u8],
        session: &mut Session,
        peer: Option<SocketAddr>,
        s: &mut ServeState,
    ) -> Option<Vec<u8>> {
        let req = match decode_request(frame) {
            Ok((req, _)) => req,
            Err(FrameError::Rejected(r)) => return Some(r.response()),
            Err(_) => return None,
        };
        let unlock = matches!(req.command, Command::Unlock { .. }) && self.password.is_some();
        let ip = peer.map(|p| p.ip());
        let now = Instant::now();
        if unlock {
            if let Some(g) = ip.and_then(|ip| self.guesses.lock().ok()?.get(&ip).copied()) {
                if now < g.until {
                    let (command, subcommand) = req.command.codes();
                    let resp = Response::Error {
                        end_code: EndCode::PASSWORD_MISMATCH,
                        command,
                        subcommand,
                    };
                    return Some(encode_response(&req.header, &resp));
                }
            }
        }
        if req.command.changes_memory() {
            // An absent CPU changes nothing; a system's RESET may touch all.
            match destination(req.header.io, s.cpu_count()) {
                Ok(i) if !matches!(req.command, Command::RemoteReset) => s.mark_wrote(i),
                Ok(_) => (0..s.cpu_count()).for_each(|i| s.mark_wrote(i)),
                Err(_) => {}
            }
        }
        let resp = handle_station(&req, &mut s.cpus, session, self.password.as_deref());
        if unlock {
            self.count_guess(ip, peer, matches!(resp, Response::Ok(_)), now);
        }
        Some(encode_response(&req.header, &resp))
    }

    fn count_guess(&self, ip: Option<IpAddr>, peer: Option<SocketAddr>, right: bool, now: Instant) {
        let (Some(ip), Ok(mut map)) = (ip, self.guesses.lock()) else {
            return;
        };
        if right {
            map.remove(&ip);
            return;
        }
        if map.len() >= MAX_TRACKED && !map.contains_key(&ip) {
            map.retain(|_, g| g.until > now);
            if map.len() >= MAX_TRACKED {
                return;
            }
        }
        let g = map.entry(ip).or_insert(Guesses {
            wrong: 0,
            until: now,
        });
        g.wrong = g.wrong.saturating_add(1);
        let delay = FIRST_DELAY
            .saturating_mul(1u32 << (g.wrong - 1).min(6))
            .min(MAX_DELAY);
        g.until = now + delay;
        eprintln!(
            "softplc: MC: wrong remote password from {} ({} in a row); unlocks from it refused for {:?}",
            peer.map_or_else(|| ip.to_string(), |p| p.to_string()),
            g.wrong,
            delay
        );
    }
}

impl Protocol for Mc {
    type Session = (Session, Option<SocketAddr>);

    fn session(&self, peer: Option<SocketAddr>) -> Self::Session {
        let session = peer.map_or_else(Session::new, |p| Session::from_peer(p.ip()));
        (session, peer)
    }

    fn frame_len(&self, buf: &[u8]) -> FrameLen {
        match decode_request(buf) {
            Ok((_, used)) => FrameLen::Frame(used),
            Err(FrameError::Incomplete) => FrameLen::More,
            // A delimited but wrong request is answered with its end code at END.
            Err(FrameError::Rejected(r)) => FrameLen::Frame(r.used),
            Err(FrameError::Malformed { .. }) => FrameLen::Garbage(None),
        }
    }

    fn serve(
        &self,
        frame: &[u8],
        session: &mut Self::Session,
        s: &mut ServeState,
    ) -> Option<Vec<u8>> {
        let (session, peer) = session;
        self.serve_frame(frame, session, *peer, s)
    }

    fn busy(&self, _frame: &[u8]) -> Option<Vec<u8>> {
        None
    }

    fn door(&self) -> &'static str {
        "MC protocol"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passwords_are_four_alphanumeric_ascii_characters() {
        assert!(check_password("ab12").is_ok());
        assert!(check_password("").unwrap_err().contains("empty"));
        assert!(check_password("abc").is_err());
        assert!(check_password("abcde").is_err());
        assert!(check_password("ab 1")
            .unwrap_err()
            .contains("letters or digits"));
        assert!(check_password("äb1").is_err());
    }
}
