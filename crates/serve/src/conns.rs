//! The connection table of a TCP door (MC, Modbus TCP, the web monitor): at
//! most `max` connections at once. At the limit a new connection takes the
//! place of one that has never completed a request (the oldest such), else of
//! one idle (no request, nothing in progress) for at least [`IDLE_EVICT`];
//! when every connection is an active client the new one is refused. So churn,
//! half-sent requests and idle sockets cannot push out an HMI that polls, nor
//! use up the process's descriptors.

use std::net::SocketAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use tokio::task::AbortHandle;

/// A connection that completed no request for this long may be evicted for a
/// new one at the connection limit.
pub const IDLE_EVICT: Duration = Duration::from_secs(10);

struct Conn {
    id: u64,
    /// When it connected.
    opened: Instant,
    /// When it last completed a request or got a reply (`None`: never talked).
    served: Option<Instant>,
    /// Requests in progress (an answer being computed or streamed): such a
    /// connection is an active client, never idle.
    busy: usize,
    /// Ends its task; `None` until the task is spawned.
    abort: Option<AbortHandle>,
}

/// The connections of one door.
pub struct Conns {
    /// The door's name in log lines ("MC protocol", "web monitor").
    door: String,
    max: usize,
    table: Mutex<Vec<Conn>>,
    ids: AtomicU64,
    refused: AtomicU64,
}

/// Which connection a new one replaces at the limit: the oldest that never
/// completed a request, else the one idle longest if idle ≥ [`IDLE_EVICT`];
/// `None`: all are active clients, refuse the new one.
fn victim(conns: &[Conn], now: Instant) -> Option<usize> {
    let never = conns
        .iter()
        .enumerate()
        .filter(|(_, c)| c.served.is_none() && c.busy == 0)
        .min_by_key(|(_, c)| c.opened)
        .map(|(i, _)| i);
    never.or_else(|| {
        conns
            .iter()
            .enumerate()
            .filter(|(_, c)| c.busy == 0)
            .filter_map(|(i, c)| c.served.map(|t| (i, t)))
            .filter(|(_, t)| now.saturating_duration_since(*t) >= IDLE_EVICT)
            .min_by_key(|(_, t)| *t)
            .map(|(i, _)| i)
    })
}

impl Conns {
    /// A table of at most `max` (at least 1) connections for `door`.
    pub fn new(door: impl Into<String>, max: usize) -> Arc<Conns> {
        Arc::new(Conns {
            door: door.into(),
            max: max.max(1),
            table: Mutex::new(Vec::new()),
            ids: AtomicU64::new(0),
            refused: AtomicU64::new(0),
        })
    }

    fn table(&self) -> MutexGuard<'_, Vec<Conn>> {
        // The table stays consistent whatever a panicking holder did.
        self.table.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Connections open now.
    pub fn len(&self) -> usize {
        self.table().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Takes a place for a new connection from `peer`, evicting another at
    /// the limit; `None`: refused (every connection is an active client).
    /// Hand the connection's task to [`Slot::started`] once spawned.
    pub fn admit(self: &Arc<Conns>, peer: SocketAddr) -> Option<Slot> {
        let mut t = self.table();
        if t.len() >= self.max {
            match victim(&t, Instant::now()) {
                Some(i) => {
                    if let Some(a) = t.remove(i).abort {
                        a.abort();
                    }
                }
                None => {
                    let refused = self.refused.fetch_add(1, Ordering::Relaxed) + 1;
                    if refused.is_power_of_two() {
                        eprintln!(
                            "softplc: {}: connection limit ({}) reached by active clients; \
                             refused {refused} connections so far (last from {peer})",
                            self.door, self.max
                        );
                    }
                    return None;
                }
            }
        }
        let id = self.ids.fetch_add(1, Ordering::Relaxed);
        t.push(Conn {
            id,
            opened: Instant::now(),
            served: None,
            busy: 0,
            abort: None,
        });
        Some(Slot {
            conns: self.clone(),
            id,
        })
    }

    fn with(&self, id: u64, f: impl FnOnce(&mut Conn)) {
        if let Some(c) = self.table().iter_mut().find(|c| c.id == id) {
            f(c);
        }
    }
}

/// A connection's place in its door's table; dropping it (the connection's
/// task ended or was aborted) frees the place.
pub struct Slot {
    conns: Arc<Conns>,
    id: u64,
}

impl Slot {
    /// The connection's task: aborted when the connection is evicted.
    pub fn started(&self, task: AbortHandle) {
        self.conns.with(self.id, |c| c.abort = Some(task));
    }

    /// The connection talked (sent a whole request, got its reply) now.
    pub fn touch(&self) {
        self.conns
            .with(self.id, |c| c.served = Some(Instant::now()));
    }

    /// A request in progress until the guard is dropped: the connection is
    /// not evicted meanwhile, and counts as talked from now.
    pub fn busy(self: &Arc<Slot>) -> Busy {
        self.conns.with(self.id, |c| {
            c.busy += 1;
            c.served = Some(Instant::now());
        });
        Busy(self.clone())
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.conns.table().retain(|c| c.id != self.id);
    }
}

/// A request in progress on a connection ([`Slot::busy`]).
pub struct Busy(Arc<Slot>);

impl Drop for Busy {
    fn drop(&mut self) {
        self.0.conns.with(self.0.id, |c| {
            c.busy = c.busy.saturating_sub(1);
            c.served = Some(Instant::now());
        });
    }
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

/// Accepts the next connection on `listener`, backing off (and saying so
/// when out of descriptors) while `accept` fails.
pub async fn accept(listener: &tokio::net::TcpListener) -> (tokio::net::TcpStream, SocketAddr) {
    loop {
        match listener.accept().await {
            Ok(x) => return x,
            Err(e) => {
                let wait = accept_backoff(&e);
                if wait >= Duration::from_millis(100) {
                    eprintln!("softplc: accept: {e}; retrying in {wait:?}");
                }
                tokio::time::sleep(wait).await;
            }
        }
    }
}

/// Accepts connections on `listener` for ever, at most `max` at once
/// ([`Conns::admit`]); `spawn` starts the task that serves each admitted
/// one (every TCP door: MC, Modbus, the web monitor).
pub async fn serve(
    listener: tokio::net::TcpListener,
    door: &str,
    max: usize,
    mut spawn: impl FnMut(tokio::net::TcpStream, SocketAddr, Arc<Slot>) -> tokio::task::JoinHandle<()>,
) {
    let conns = Conns::new(door, max);
    loop {
        let (stream, peer) = accept(&listener).await;
        let _ = stream.set_nodelay(true);
        let Some(slot) = conns.admit(peer) else {
            drop(stream);
            continue;
        };
        let slot = Arc::new(slot);
        let task = spawn(stream, peer, slot.clone());
        slot.started(task.abort_handle());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peer() -> SocketAddr {
        "127.0.0.1:1".parse().unwrap()
    }

    #[test]
    fn accept_backs_off_when_out_of_descriptors() {
        let emfile = std::io::Error::from_raw_os_error(libc::EMFILE);
        assert_eq!(accept_backoff(&emfile), Duration::from_millis(100));
        let other = std::io::Error::from_raw_os_error(libc::ECONNABORTED);
        assert_eq!(accept_backoff(&other), Duration::from_millis(5));
    }

    #[test]
    fn at_the_limit_a_never_talker_makes_room_an_active_client_does_not() {
        let conns = Conns::new("test", 2);
        let a = Arc::new(conns.admit(peer()).unwrap());
        let b = conns.admit(peer()).unwrap();
        b.touch();
        // a never talked: the third takes its place.
        let c = Arc::new(conns.admit(peer()).unwrap());
        assert_eq!(conns.len(), 2);
        drop(a);
        assert_eq!(conns.len(), 2, "the evicted place is gone already");
        // b talked just now, c has a request in progress: refused.
        let busy = c.busy();
        assert!(conns.admit(peer()).is_none());
        drop(busy);
        drop(b);
        assert_eq!(conns.len(), 1);
        assert!(conns.admit(peer()).is_some());
    }
}
