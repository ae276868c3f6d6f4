//! A TCP server for a frame-oriented protocol: frames are cut from the byte
//! stream by the protocol, served at END processing by the engine thread, and
//! the replies written back in order. A malformed frame closes only its own
//! connection.
//!
//! The connections are limited by the door's [`Conns`] table: at the limit a
//! new connection takes the place of one that has never sent a whole request,
//! else of one idle for at least [`crate::conns::IDLE_EVICT`]; when every
//! connection is an active client the new one is refused. So churn and idle
//! sockets cannot push out an HMI that polls. When accepting fails (e.g.
//! EMFILE, out of descriptors) the loop backs off instead of spinning.

use std::net::SocketAddr;
use std::sync::Arc;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

use crate::conns::Slot;
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
    /// The door's name in log lines and recordings (`serve --record`).
    fn door(&self) -> &'static str {
        "TCP server"
    }
}

/// Largest frame buffered before the connection is dropped.
const MAX_BUFFER: usize = 64 * 1024;

/// Accepts connections until the listener fails; at most `max_conns` at once.
pub async fn serve<P: Protocol>(
    listener: TcpListener,
    proto: Arc<P>,
    engine: EngineHandle,
    max_conns: usize,
) {
    let door = proto.door().to_string();
    crate::conns::serve(listener, &door, max_conns, |stream, peer, slot| {
        tokio::spawn(connection(
            stream,
            proto.clone(),
            engine.clone(),
            slot,
            peer,
        ))
    })
    .await
}

async fn connection<P: Protocol>(
    mut stream: TcpStream,
    proto: Arc<P>,
    engine: EngineHandle,
    slot: Arc<Slot>,
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
                    slot.touch();
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
                        slot.touch();
                    }
                }
            }
        }
    }
    // Dropping `slot` (here, or when the task is aborted) frees the place.
    drop(slot);
}
