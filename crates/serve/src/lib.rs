//! softplc-serve: `softplc serve` — the CPU scans in real time at its constant
//! scan period while protocol servers (MC protocol, Modbus) talk to it. Every
//! request is served by the engine thread at END processing (see [`engine`]),
//! the way the CPU processes communication, so replies are consistent with a
//! completed scan and clients can never stall a scan. With `--time-scale` or
//! `--lockstep` the CPUs run in virtual time instead (see [`sim`]).

// `unsafe` only in the modules marked `#[allow(unsafe_code)]`, each block with its SAFETY reason.
#![deny(unsafe_code)]

pub mod conns;
pub mod engine;
pub mod mc;
pub mod modbus;
pub mod online;
// pthread_setschedparam for the real-time engine thread.
#[allow(unsafe_code)]
pub mod realtime;
pub mod serial;
pub mod sim;
pub mod tcp;
pub mod timing;
pub mod udp;

use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

pub use engine::{Busy, CpuStats, EngineConfig, EngineHandle, Hook, ScanStats, ServeState};
pub use realtime::RealTime;
pub use sim::{Advance, AdvanceRefused, Advanced, TimeScale, VirtualTime};
pub use softplc_core::system::Cpus;
pub use tcp::{FrameLen, Protocol};
pub use timing::{Dist, Timing, TimingReport};

/// A protocol server to start.
pub struct Listener {
    pub addr: SocketAddr,
    udp: bool,
    /// The door its requests come through (a recording names it).
    door: &'static str,
    /// A client of a server elsewhere (MQTT): nothing is bound.
    client: bool,
    start: Box<dyn FnOnce(Bound, EngineHandle) -> tokio::task::JoinHandle<()> + Send>,
}

/// A bound socket handed to a server.
pub enum Bound {
    Tcp(tokio::net::TcpListener),
    Udp(tokio::net::UdpSocket),
    /// Nothing bound: a client's task ([`Listener::client`]).
    None,
}

impl Listener {
    /// Names the door its requests come through (`"MC protocol"`, `"Modbus TCP"`,
    /// `"HTTP"`, `"OPC UA"`): a recording tells them apart by it.
    pub fn door(mut self, door: &'static str) -> Listener {
        self.door = door;
        self
    }

    /// The MC protocol over UDP on `addr`.
    pub fn mc_udp(addr: SocketAddr, mc: mc::Mc) -> Listener {
        let mc = Arc::new(mc);
        Listener {
            addr,
            udp: true,
            door: "MC protocol",
            client: false,
            start: Box::new(move |l, e| match l {
                Bound::Udp(s) => tokio::spawn(udp::serve(s, mc, e)),
                _ => unreachable!("a UDP listener is bound to a UDP socket"),
            }),
        }
    }

    /// A TCP server of its own on `addr` (the web monitor, crates/http): `start`
    /// gets the bound listener and the engine handle and spawns the server.
    pub fn tcp_with(
        addr: SocketAddr,
        start: impl FnOnce(tokio::net::TcpListener, EngineHandle) -> tokio::task::JoinHandle<()>
            + Send
            + 'static,
    ) -> Listener {
        Listener {
            addr,
            udp: false,
            door: "",
            client: false,
            start: Box::new(move |l, e| match l {
                Bound::Tcp(l) => start(l, e),
                _ => unreachable!("a TCP listener is bound to a TCP socket"),
            }),
        }
    }

    /// A client task (the MQTT publisher): started with the engine handle
    /// like a server, but binds nothing and is not among the bound addresses.
    pub fn client(
        start: impl FnOnce(EngineHandle) -> tokio::task::JoinHandle<()> + Send + 'static,
    ) -> Listener {
        Listener {
            addr: SocketAddr::from(([0, 0, 0, 0], 0)),
            udp: false,
            client: true,
            door: "",
            start: Box::new(move |_, e| start(e)),
        }
    }

    /// A TCP server of protocol `P` on `addr` with at most `max_conns` connections.
    pub fn tcp<P: Protocol>(addr: SocketAddr, proto: P, max_conns: usize) -> Listener {
        let proto = Arc::new(proto);
        Listener {
            addr,
            udp: false,
            door: proto.door(),
            client: false,
            start: Box::new(move |l, e| match l {
                Bound::Tcp(l) => tokio::spawn(tcp::serve(l, proto, e, max_conns)),
                _ => unreachable!("a TCP listener is bound to a TCP socket"),
            }),
        }
    }
}

/// A Modbus RTU or ASCII slave on an opened serial line ([`serial::open`]).
pub struct SerialSlave {
    pub line: serial::SerialLine,
    pub proto: softplc_modbus::Proto,
    pub map: softplc_modbus::Map,
    pub slave: softplc_modbus::Slave,
}

/// Parses a server address: `HOST:PORT`, or a bare port on loopback (servers bind
/// loopback unless an address says otherwise, contract §3).
pub fn parse_addr(s: &str) -> Result<SocketAddr, String> {
    if let Ok(port) = s.parse::<u16>() {
        return Ok(SocketAddr::from(([127, 0, 0, 1], port)));
    }
    s.parse()
        .map_err(|_| format!("`{s}`: expected HOST:PORT (e.g. 127.0.0.1:5020) or a port"))
}

/// Runs the engine and the servers until Ctrl-C/SIGTERM or `stop` is set; then
/// stops the servers, lets the engine commit latched data, and returns the
/// final state. `ready` is called with the bound addresses once serving.
pub fn run(
    state: ServeState,
    cfg: EngineConfig,
    listeners: Vec<Listener>,
    serial: Vec<SerialSlave>,
    stop: Arc<AtomicBool>,
    ready: impl FnOnce(&[SocketAddr]),
) -> std::io::Result<ServeState> {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()?;
    // Stops the CPUs even inside a scan that never ends.
    let aborts = state.cpus.abort_handles();
    let abort = move || {
        for a in &aborts {
            a.store(true, Ordering::Relaxed);
        }
    };
    let (handle, join) = engine::spawn(state, cfg, stop.clone());
    let lines: Vec<_> = serial
        .into_iter()
        .map(|s| {
            serial::spawn(
                s.line,
                s.proto,
                s.map,
                s.slave,
                handle.for_door("serial"),
                stop.clone(),
            )
        })
        .collect();
    let bound = rt.block_on(async {
        let mut bound = Vec::new();
        for l in listeners {
            let socket = if l.client {
                Bound::None
            } else if l.udp {
                let s = tokio::net::UdpSocket::bind(l.addr).await?;
                bound.push(s.local_addr()?);
                Bound::Udp(s)
            } else {
                let s = tokio::net::TcpListener::bind(l.addr).await?;
                bound.push(s.local_addr()?);
                Bound::Tcp(s)
            };
            (l.start)(socket, handle.for_door(l.door));
        }
        Ok::<_, std::io::Error>(bound)
    });
    let bound = match bound {
        Ok(b) => b,
        Err(e) => {
            stop.store(true, Ordering::Relaxed);
            abort();
            let _ = join.join();
            return Err(e);
        }
    };
    ready(&bound);
    rt.block_on(async {
        let term = async {
            #[cfg(unix)]
            {
                use tokio::signal::unix::{signal, SignalKind};
                match signal(SignalKind::terminate()) {
                    Ok(mut s) => {
                        s.recv().await;
                    }
                    Err(_) => std::future::pending::<()>().await,
                }
            }
            #[cfg(not(unix))]
            std::future::pending::<()>().await
        };
        let flag = async {
            while !stop.load(Ordering::Relaxed) {
                tokio::time::sleep(std::time::Duration::from_millis(20)).await;
            }
        };
        tokio::select! {
            _ = tokio::signal::ctrl_c() => {}
            _ = term => {}
            _ = flag => {}
        }
    });
    stop.store(true, Ordering::Relaxed);
    abort();
    rt.shutdown_background();
    for l in lines {
        let _ = l.join();
    }
    join.join()
        .map_err(|_| std::io::Error::other("the engine thread panicked"))
}

/// A server running on its own thread (tests, benchmarks, embedding).
pub struct Background {
    /// The bound addresses, in the order of the listeners.
    pub addrs: Vec<SocketAddr>,
    stop: Arc<AtomicBool>,
    join: std::thread::JoinHandle<std::io::Result<ServeState>>,
}

impl Background {
    /// Starts [`run`] on a thread and waits until the servers are bound.
    pub fn start(
        state: ServeState,
        cfg: EngineConfig,
        listeners: Vec<Listener>,
        serial: Vec<SerialSlave>,
    ) -> std::io::Result<Background> {
        let stop = Arc::new(AtomicBool::new(false));
        let (tx, rx) = std::sync::mpsc::channel();
        let stop2 = stop.clone();
        let join = std::thread::spawn(move || {
            run(state, cfg, listeners, serial, stop2, |a| {
                let _ = tx.send(a.to_vec());
            })
        });
        match rx.recv() {
            Ok(addrs) => Ok(Background { addrs, stop, join }),
            // `run` failed before binding: report its error.
            Err(_) => Err(join
                .join()
                .map_err(|_| std::io::Error::other("the server thread panicked"))?
                .err()
                .unwrap_or_else(|| std::io::Error::other("the server stopped"))),
        }
    }

    /// Stops the servers and the engine; returns the final state.
    pub fn stop(self) -> std::io::Result<ServeState> {
        self.stop.store(true, Ordering::Relaxed);
        self.join
            .join()
            .map_err(|_| std::io::Error::other("the server thread panicked"))?
    }
}
