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
pub mod program;
pub mod rack;
pub mod sim;
pub mod snapshot;
pub mod timing;
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
    /// The program files as ladder rungs (see [`ladder::load`]); CPU 1's
    /// in a multi-CPU system (the others' come from their listings).
    pub ladder: Vec<ladder::LadderProgram>,
    /// Connections and timeouts of the door.
    pub limits: door::Limits,
    /// The program files `PUT /api/v1/program` may write; `None`: none.
    pub online: Option<Arc<softplc_serve::online::Online>>,
}

/// Shared by every request handler.
pub struct App {
    pub cfg: HttpConfig,
    pub engine: EngineHandle,
    pub snapshots: tokio::sync::watch::Receiver<Arc<monitor::Snapshot>>,
    /// Open event streams (at most [`MAX_STREAMS`]).
    pub streams: std::sync::atomic::AtomicUsize,
    /// What device names mean for each served CPU, CPU 1's first (its
    /// dialect and global names), read once at start.
    pub names: Vec<softplc_core::names::Names>,
    /// Each CPU's ladders and the CPU's program writes they were drawn
    /// after (a program written during RUN is drawn again).
    ladders: std::sync::Mutex<Vec<(u64, Arc<Vec<ladder::LadderProgram>>)>>,
}

impl App {
    /// Number of CPUs served.
    pub fn cpus(&self) -> usize {
        self.names.len()
    }

    /// The programs of CPU `cpu` (0-based) as ladder rungs, as last drawn.
    pub fn ladder(&self, cpu: usize) -> Arc<Vec<ladder::LadderProgram>> {
        let ladders = self.ladders.lock().unwrap_or_else(|e| e.into_inner());
        ladders.get(cpu).map(|l| l.1.clone()).unwrap_or_default()
    }

    /// [`App::ladder`], drawn again at this END when a program of the CPU
    /// was written during RUN since (through the API or `serve --watch`).
    pub async fn ladder_now(&self, cpu: usize) -> Arc<Vec<ladder::LadderProgram>> {
        let seen = {
            let ladders = self.ladders.lock().unwrap_or_else(|e| e.into_inner());
            ladders.get(cpu).map_or(0, |l| l.0)
        };
        let fresh = api::at_end(self, move |s| {
            let c = (cpu < s.cpu_count()).then(|| s.cpu_at(cpu))?;
            (c.program_writes() != seen).then(|| (c.program_writes(), ladder::load_programs(c)))
        })
        .await;
        if let Ok(Some((writes, programs))) = fresh {
            let mut ladders = self.ladders.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(l) = ladders.get_mut(cpu) {
                *l = (writes, Arc::new(programs));
            }
        }
        self.ladder(cpu)
    }
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
        .at_end(|s| {
            (0..s.cpu_count())
                .map(|i| softplc_core::names::Names::of(s.cpu_at(i)))
                .collect()
        })
        .await?;
    // A system's CPUs are MELSEC CPUs: their ladders come from the programs'
    // listings, no file is read on the engine thread.
    let others: Vec<Vec<ladder::LadderProgram>> = engine
        .at_end(|s| {
            (1..s.cpu_count())
                .map(|i| ladder::load_programs(s.cpu_at(i)))
                .collect()
        })
        .await?;
    let ladders = std::iter::once(cfg.ladder.clone())
        .chain(others)
        .map(|l| (0, Arc::new(l)))
        .collect();
    Ok(Arc::new(App {
        cfg,
        engine,
        snapshots: rx,
        streams: Default::default(),
        names,
        ladders: std::sync::Mutex::new(ladders),
    }))
}
