//! The MC protocol over UDP (contract §3: "TCP; UDP too"): one request frame per
//! datagram, served at END processing, the reply sent back to the sender. Each
//! sender address has its own session (remote-password unlock), as a UDP
//! "connection" of the Ethernet module.
//!
//! Datagrams are handed to the engine as they arrive (not one per END), so
//! every datagram queued by the next END is served within its budget. A sender
//! may have at most [`MAX_IN_FLIGHT`] requests waiting; beyond that its
//! datagrams are dropped (UDP clients retry), so a flood from one address
//! cannot fill the engine queue and starve the others.

use std::collections::{HashMap, VecDeque};
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};

use softplc_mc::Session;
use tokio::net::UdpSocket;

use crate::engine::EngineHandle;
use crate::mc::Mc;

/// Senders remembered for their sessions; the oldest is forgotten beyond this.
const MAX_PEERS: usize = 256;
/// Requests of one sender waiting for END at once.
pub const MAX_IN_FLIGHT: usize = 32;

/// The sessions of UDP senders, kept on the engine thread.
#[derive(Default)]
struct Sessions {
    map: HashMap<SocketAddr, Session>,
    order: VecDeque<SocketAddr>,
}

impl Sessions {
    fn get(&mut self, peer: SocketAddr) -> &mut Session {
        if !self.map.contains_key(&peer) {
            if self.order.len() >= MAX_PEERS {
                if let Some(old) = self.order.pop_front() {
                    self.map.remove(&old);
                }
            }
            self.order.push_back(peer);
        }
        self.map.entry(peer).or_default()
    }
}

pub async fn serve(socket: UdpSocket, mc: Arc<Mc>, engine: EngineHandle) {
    let socket = Arc::new(socket);
    let in_flight: Arc<Mutex<HashMap<SocketAddr, usize>>> = Arc::default();
    let mut buf = vec![0u8; 8192];
    loop {
        let Ok((n, peer)) = socket.recv_from(&mut buf).await else {
            continue;
        };
        {
            let mut f = in_flight.lock().expect("in-flight table");
            let k = f.entry(peer).or_insert(0);
            if *k >= MAX_IN_FLIGHT {
                continue; // this sender is flooding: drop, the others go on
            }
            *k += 1;
        }
        let frame = buf[..n].to_vec();
        let (m, e, sock, f) = (
            mc.clone(),
            engine.clone(),
            socket.clone(),
            in_flight.clone(),
        );
        tokio::spawn(async move {
            let reply = e
                .at_end(move |s| {
                    let mut sessions = std::mem::take(s.ext::<Sessions>());
                    let r = m.serve_frame(&frame, sessions.get(peer), Some(peer), s);
                    *s.ext::<Sessions>() = sessions;
                    r
                })
                .await;
            {
                let mut f = f.lock().expect("in-flight table");
                if let Some(k) = f.get_mut(&peer) {
                    *k -= 1;
                    if *k == 0 {
                        f.remove(&peer);
                    }
                }
            }
            if let Ok(Some(response)) = reply {
                let _ = sock.send_to(&response, peer).await;
            }
        });
    }
}
