//! A TCP server for a frame-oriented protocol: frames are cut from the byte
//! stream by the protocol, served at END processing by the engine thread, and
//! the replies written back in order. A malformed frame closes only its own
//! connection.
//!
//! At the connection limit a new connection takes the place of one that has
//! never sent a request (the oldest such), else of one idle (no request) for
//! at least [`IDLE_EVICT`]; when every connection is an active
//! client the new one is refused. So churn and idle sockets cannot push out an
//! HMI that polls. When accepting fails (e.g. EMFILE, out of descriptors) the
//! loop backs off instead of spinning.

use std::net::SocketAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::task::AbortHandle;

use crate::engine::{EngineHandle, ServeState};

/// How much of a buffer forms the next frame.
#[derive(Debug, PartialEq, Eq)]
pub enum FrameLen {
    /// The first `n` bytes are a frame.
    Frame(usize),
    /// Not enough bytes yet.
    More,
    /// Not this protocol: optionally reply, then close the connection.
    Garbage(Option<Vec<u8>>),
}

/// A request/response protocol served at END processing.
pub trait Protocol: Send + Sync + 'static {
    /// Per-connection state (e.g. the MC remote-password unlock).
    type Session: Send + 'static;
    /// A new connection's state; `peer` is its address when known.
    fn session(&self, peer: Option<std::net::SocketAddr>) -> Self::Session;
    fn frame_len(&self, buf: &[u8]) -> FrameLen;
    /// Serves one frame against the CPU (runs on the engine thread at END).
    fn serve(
        &self,
        frame: &[u8],
        session: &mut Self::Session,
        s: &mut ServeState,
    ) -> Option<Vec<u8>>;
    /// The reply when the engine cannot take the request (queue full).
    fn busy(&self, frame: &[u8]) -> Option<Vec<u8>>;
}

/// Largest frame buffered before the connection is dropped.
const MAX_BUFFER: usize = 64 * 1024;

/// A connection that completed no request for this long may be evicted for a
/// new one at the connection limit.
pub const IDLE_EVICT: Duration = Duration::from_secs(10);

struct Conn {
    id: u64,
    /// When it connected.
    opened: Instant,
    /// When it last sent a frame or got a reply (`None`: never talked).
    served: Option<Instant>,
    abort: AbortHandle,
}

/// Which connection a new one replaces at the limit: the oldest that never
/// sent a request, else the one idle longest if idle ≥ [`IDLE_EVICT`];
/// `None`: all are active clients, refuse the new one.
fn victim(conns: &[Conn], now: Instant) -> Option<usize> {
    let never = conns
        .iter()
        .enumerate()
        .filter(|(_, c)| c.served.is_none())
        .min_by_key(|(_, c)| c.opened)
        .map(|(i, _)| i);
    never.or_else(|| {
        conns
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.served.map(|t| (i, t)))
            .filter(|(_, t)| now.saturating_duration_since(*t) >= IDLE_EVICT)
            .min_by_key(|(_, t)| *t)
            .map(|(i, _)| i)
    })
}

/// How long to wait before accepting again after `accept` failed: out of
/// descriptors or memory waits for connections to close; others retry soon.
pub fn accept_backoff(e: &std::io::Error) -> Duration {
    match e.raw_os_error() {
        Some(libc::EMFILE | libc::ENFILE | libc::ENOBUFS | libc::ENOMEM) => {
            Duration::from_millis(100)
        }
        _ => Duration::from_millis(5),
    }
}

/// Accepts connections until the listener fails; at most `max_conns` at once.
pub async fn serve<P: Protocol>(
    listener: TcpListener,
    proto: Arc<P>,
    engine: EngineHandle,
    max_conns: usize,
) {
    let conns: Arc<Mutex<Vec<Conn>>> = Arc::default();
    let ids = AtomicU64::new(0);
    let mut refused = 0u64;
    loop {
        let (stream, peer) = match listener.accept().await {
            Ok(x) => x,
            Err(e) => {
                let wait = accept_backoff(&e);
                if wait >= Duration::from_millis(100) {
                    eprintln!("softplc: accept: {e}; retrying in {wait:?}");
                }
                tokio::time::sleep(wait).await;
                continue;
            }
        };
        let _ = stream.set_nodelay(true);
        let id = ids.fetch_add(1, Ordering::Relaxed);
        {
            let mut c = conns.lock().expect("connection table");
            if c.len() >= max_conns.max(1) {
                match victim(&c, Instant::now()) {
                    Some(i) => c.remove(i).abort.abort(),
                    None => {
                        // Every connection is an active client: refuse.
                        refused += 1;
                        if refused.is_power_of_two() {
                            eprintln!(
                                "softplc: connection limit ({max_conns}) reached by active \
                                 clients; refused {refused} connections so far (last from {peer})"
                            );
                        }
                        drop(stream);
                        continue;
                    }
                }
            }
        }
        let task = tokio::spawn(connection(
            stream,
            proto.clone(),
            engine.clone(),
            conns.clone(),
            id,
            peer,
        ));
        conns.lock().expect("connection table").push(Conn {
            id,
            opened: Instant::now(),
            served: None,
            abort: task.abort_handle(),
        });
    }
}

/// Records that connection `id` talked (sent a frame, got its reply) now.
fn touch(conns: &Mutex<Vec<Conn>>, id: u64) {
    if let Some(c) = conns
        .lock()
        .expect("connection table")
        .iter_mut()
        .find(|c| c.id == id)
    {
        c.served = Some(Instant::now());
    }
}

async fn connection<P: Protocol>(
    mut stream: TcpStream,
    proto: Arc<P>,
    engine: EngineHandle,
    conns: Arc<Mutex<Vec<Conn>>>,
    id: u64,
    peer: SocketAddr,
) {
    let mut buf: Vec<u8> = Vec::with_capacity(4096);
    let mut chunk = [0u8; 4096];
    let mut session = Some(proto.session(Some(peer)));
    'read: loop {
        let n = match stream.read(&mut chunk).await {
            Ok(0) | Err(_) => break,
            Ok(n) => n,
        };
        buf.extend_from_slice(&chunk[..n]);
        loop {
            match proto.frame_len(&buf) {
                FrameLen::More if buf.len() > MAX_BUFFER => break 'read,
                FrameLen::More => break,
                FrameLen::Garbage(reply) => {
                    if let Some(r) = reply {
                        let _ = stream.write_all(&r).await;
                    }
                    break 'read;
                }
                FrameLen::Frame(len) => {
                    // A connection that sent a whole frame is talking: not a
                    // never-talker the limit may evict while its reply waits.
                    touch(&conns, id);
                    let frame: Vec<u8> = buf.drain(..len.min(buf.len())).collect();
                    let p = proto.clone();
                    let mut sess = session.take().expect("session present");
                    let f = frame.clone();
                    let (reply, back) = match engine
                        .at_end(move |s| {
                            let r = p.serve(&f, &mut sess, s);
                            (r, sess)
                        })
                        .await
                    {
                        Ok((r, sess)) => (r, Some(sess)),
                        Err(_) => (proto.busy(&frame), None),
                    };
                    let served = back.is_some();
                    session = back.or_else(|| Some(proto.session(Some(peer))));
                    if let Some(r) = reply {
                        if stream.write_all(&r).await.is_err() {
                            break 'read;
                        }
                    }
                    if served {
                        touch(&conns, id);
                    }
                }
            }
        }
    }
    conns
        .lock()
        .expect("connection table")
        .retain(|c| c.id != id);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accept_backs_off_when_out_of_descriptors() {
        let emfile = std::io::Error::from_raw_os_error(libc::EMFILE);
        assert_eq!(accept_backoff(&emfile), Duration::from_millis(100));
        let other = std::io::Error::from_raw_os_error(libc::ECONNABORTED);
        assert_eq!(accept_backoff(&other), Duration::from_millis(5));
    }
}
