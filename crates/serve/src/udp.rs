//! The MC protocol over UDP (contract §3: "TCP; UDP too"): one request frame per
//! datagram, served at END processing, the reply sent back to the sender. Each
//! sender address has its own session (remote-password unlock), as a UDP
//! "connection" of the Ethernet module.

use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::Arc;

use softplc_mc::{Served, Session};
use tokio::net::UdpSocket;

use crate::engine::EngineHandle;
use crate::mc::Mc;

/// Senders remembered for their sessions; the oldest is forgotten beyond this.
const MAX_PEERS: usize = 256;

pub async fn serve(socket: UdpSocket, mc: Arc<Mc>, engine: EngineHandle) {
    let mut sessions: HashMap<SocketAddr, Session> = HashMap::new();
    let mut order: Vec<SocketAddr> = Vec::new();
    let mut buf = vec![0u8; 8192];
    loop {
        let Ok((n, peer)) = socket.recv_from(&mut buf).await else {
            continue;
        };
        let frame = buf[..n].to_vec();
        let session = sessions.remove(&peer).unwrap_or_default();
        let m = mc.clone();
        let Ok((served, session)) = engine
            .at_end(move |s| {
                let mut session = session;
                let r = softplc_mc::serve(&frame, &mut s.cpu, &mut session, m.password.as_deref());
                (r, session)
            })
            .await
        else {
            continue;
        };
        if !order.contains(&peer) {
            order.push(peer);
            if order.len() > MAX_PEERS {
                let old = order.remove(0);
                sessions.remove(&old);
            }
        }
        sessions.insert(peer, session);
        if let Served::Reply { response, .. } = served {
            let _ = socket.send_to(&response, peer).await;
        }
    }
}
