//! A TCP server for a frame-oriented protocol: frames are cut from the byte
//! stream by the protocol, served at END processing by the engine thread, and
//! the replies written back in order. A malformed frame closes only its own
//! connection; the connection limit evicts the connection idle the longest.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

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
    fn session(&self) -> Self::Session;
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

struct Conn {
    id: u64,
    last: Instant,
    abort: AbortHandle,
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
    loop {
        let Ok((stream, _)) = listener.accept().await else {
            continue;
        };
        let _ = stream.set_nodelay(true);
        let id = ids.fetch_add(1, Ordering::Relaxed);
        {
            let mut c = conns.lock().expect("connection table");
            if c.len() >= max_conns.max(1) {
                // Evict the connection idle the longest.
                if let Some(i) = c
                    .iter()
                    .enumerate()
                    .min_by_key(|(_, c)| c.last)
                    .map(|(i, _)| i)
                {
                    c.remove(i).abort.abort();
                }
            }
        }
        let task = tokio::spawn(connection(
            stream,
            proto.clone(),
            engine.clone(),
            conns.clone(),
            id,
        ));
        conns.lock().expect("connection table").push(Conn {
            id,
            last: Instant::now(),
            abort: task.abort_handle(),
        });
    }
}

async fn connection<P: Protocol>(
    mut stream: TcpStream,
    proto: Arc<P>,
    engine: EngineHandle,
    conns: Arc<Mutex<Vec<Conn>>>,
    id: u64,
) {
    let mut buf: Vec<u8> = Vec::with_capacity(4096);
    let mut chunk = [0u8; 4096];
    let mut session = Some(proto.session());
    'read: loop {
        let n = match stream.read(&mut chunk).await {
            Ok(0) | Err(_) => break,
            Ok(n) => n,
        };
        if let Some(c) = conns
            .lock()
            .expect("connection table")
            .iter_mut()
            .find(|c| c.id == id)
        {
            c.last = Instant::now();
        }
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
                    session = back.or_else(|| Some(proto.session()));
                    if let Some(r) = reply {
                        if stream.write_all(&r).await.is_err() {
                            break 'read;
                        }
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
