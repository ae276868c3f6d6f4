//! softplc-http: `softplc serve --http ADDR`, the web monitor and its JSON API
//! (contract §3.1).
//!
//! Every request is served by the engine thread at END processing through the
//! request queue of `softplc-serve` ([`softplc_serve::EngineHandle::at_end`]),
//! so each answer comes from one END and a write is applied between two
//! scans. Live values (SSE) come from snapshots the engine thread publishes
//! at END, at most 10 a second and only of the names clients subscribed to
//! ([`monitor`]). Step, breakpoints and snapshots run in one END hook.

#![forbid(unsafe_code)]

pub mod api;
pub mod door;
pub mod ladder;
pub mod loops;
pub mod monitor;
pub mod pages;
pub mod process_loops;
pub mod rack;
pub mod values;

use std::net::SocketAddr;
use std::sync::Arc;

use softplc_serve::{EngineHandle, Listener};

/// Largest request body accepted (JSON writes, forces), bytes.
pub const BODY_LIMIT: usize = 64 * 1024;

/// How the HTTP server is set up.
#[derive(Clone, Debug, Default)]
pub struct HttpConfig {
    /// The bearer token that allows writes, forcing and `cpu/*`; `None` makes
    /// the server read-only (every such request is 403, contract §3.1).
    pub token: Option<String>,
    /// The CPU model reported by `status`.
    pub model: String,
    /// The program files as ladder rungs (see [`ladder::load`]).
    pub ladder: Vec<ladder::LadderProgram>,
    /// Connections and timeouts of the door.
    pub limits: door::Limits,
}

/// Shared by every request handler.
pub struct App {
    pub cfg: HttpConfig,
    pub engine: EngineHandle,
    pub snapshots: tokio::sync::watch::Receiver<Arc<monitor::Snapshot>>,
    /// Open event streams (at most [`MAX_STREAMS`]).
    pub streams: std::sync::atomic::AtomicUsize,
    /// What device names mean for the served CPU (its dialect and global
    /// names), read once at start.
    pub names: softplc_core::names::Names,
}

/// Most event streams open at once; more are 503.
pub const MAX_STREAMS: usize = 128;

/// The web monitor as a `softplc-serve` listener on `addr`.
pub fn listener(addr: SocketAddr, cfg: HttpConfig) -> Listener {
    Listener::tcp_with(addr, move |tcp, engine| {
        tokio::spawn(async move {
            let limits = cfg.limits;
            let Ok(app) = start(cfg, engine).await else {
                eprintln!("softplc: --http: the engine stopped before the web monitor started");
                return;
            };
            door::serve(tcp, api::router(app), limits).await;
        })
    })
}

/// Installs the END hook and builds the shared state.
pub async fn start(cfg: HttpConfig, engine: EngineHandle) -> Result<Arc<App>, softplc_serve::Busy> {
    let (tx, rx) = tokio::sync::watch::channel(Arc::new(monitor::Snapshot::default()));
    engine.at_end(move |s| monitor::install(s, tx)).await?;
    let names = engine
        .at_end(|s| softplc_core::names::Names::of(&s.cpu))
        .await?;
    Ok(Arc::new(App {
        cfg,
        engine,
        snapshots: rx,
        streams: Default::default(),
        names,
    }))
}
