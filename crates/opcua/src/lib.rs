//! softplc-opcua: `softplc serve --opcua ADDR`, the OPC UA server of
//! contract §3.2 on async-opcua.
//!
//! - [`points`]: which devices the program uses and their typed nodes, and
//!   the control loops' fields;
//! - [`space`]: the address space (`Objects/softplc/Devices`, `Diagnostics`,
//!   `Loops`; a multi-CPU system's in a folder per CPU, `CPU1`, `CPU2` …)
//!   and its node manager, which checks writes and applies them at END
//!   through `softplc-serve`'s queue;
//! - [`publish`]: values published at END, changed points only;
//! - [`config`]: the `[opcua]` table and the command line.
//!
//! Security None is offered only on a loopback address; every endpoint also
//! offers Basic256Sha256 (Sign, SignAndEncrypt) with a self-signed
//! certificate made in the pki directory on first start.

#![forbid(unsafe_code)]

pub mod config;
pub mod points;
pub mod publish;
pub mod space;

use std::net::SocketAddr;
use std::sync::Arc;

use opcua::crypto::SecurityPolicy;
use opcua::server::node_manager::memory::{InMemoryNodeManager, InMemoryNodeManagerBuilder};
use opcua::server::{ServerBuilder, ServerUserToken, ANONYMOUS_USER_TOKEN_ID};
use opcua::types::MessageSecurityMode;
use softplc_core::engine::Cpu;
use softplc_ir::listing::LoopUse;
use softplc_serve::{EngineHandle, Listener};

pub use config::{Flags, OpcuaConfig};

use points::Point;
use space::{SoftplcNodes, Space, WriteRule};

/// Why the programs of a model without the OPC UA door (the APLC-TCP) are
/// not served (COMPATIBILITY.md).
pub fn refused(model: &str) -> String {
    format!(
        "--opcua: {model} programs are not served over OPC UA yet: its compiler does not \
         record the devices programs use (Program::used_devices), so the Devices folder \
         would be empty; use --modbus or --http"
    )
}

/// The user token id of the configured user.
const USER_TOKEN_ID: &str = "user";

/// Everything the server needs from the loaded CPU, taken before it runs.
pub struct Prepared {
    pub cfg: OpcuaConfig,
    pub devices: Vec<Point>,
    /// The loop memories of each program, (file, loops), where the loops
    /// are found ([`points::program_loops`]).
    pub loops: Vec<(String, Vec<LoopUse>)>,
}

impl Prepared {
    /// The device variables of `cpu` (an error names a bad `[opcua] nodes`
    /// entry) and its programs' loop memories.
    pub fn new(cfg: OpcuaConfig, cpu: &Cpu) -> Result<Prepared, String> {
        if !cpu.profile().doors.opcua {
            return Err(refused(cpu.profile().model));
        }
        let devices = points::devices(cpu, &cfg.nodes)?;
        Ok(Prepared {
            cfg,
            devices,
            loops: points::program_loops(cpu),
        })
    }

    /// The device variables of every CPU of a multi-CPU system, CPU 1's
    /// first, with NodeIds `CPUn/<name>`; `[opcua] nodes` entries name their
    /// CPU as `CPU2/D100` (none: CPU 1). The loops are found at the first END.
    pub fn system(cfg: OpcuaConfig, cpus: &[&Cpu]) -> Result<Prepared, String> {
        let mut devices = Vec::new();
        for (i, cpu) in cpus.iter().enumerate() {
            if !cpu.profile().doors.opcua {
                return Err(refused(cpu.profile().model));
            }
            let mut extra = Vec::new();
            for t in &cfg.nodes {
                let (k, rest) = softplc_core::system::names::split(t.trim(), cpus.len())
                    .map_err(|e| format!("[opcua] nodes: {e}"))?;
                if k == i {
                    extra.push(rest.to_string());
                }
            }
            let prefix = format!("CPU{}/", i + 1);
            devices.extend(points::devices_at(cpu, i, &prefix, &extra)?);
        }
        Ok(Prepared {
            cfg,
            devices,
            loops: Vec::new(),
        })
    }

    /// The OPC UA server as a `softplc-serve` listener.
    pub fn listener(self) -> Listener {
        Listener::tcp_with(self.cfg.addr, move |tcp, engine| {
            tokio::spawn(async move {
                if let Err(e) = serve(self, tcp, engine).await {
                    eprintln!("softplc: --opcua: {e}");
                }
            })
        })
    }
}

/// Builds the address space at one END (after the first scan, so PIDINIT
/// has set its loop counts), installs the publisher and runs the server on
/// `tcp` until the runtime stops.
pub async fn serve(
    p: Prepared,
    tcp: tokio::net::TcpListener,
    engine: EngineHandle,
) -> Result<(), String> {
    let addr = tcp.local_addr().map_err(|e| e.to_string())?;
    let Prepared {
        cfg,
        devices,
        loops,
    } = p;
    let feed = engine
        .at_end(move |s| {
            let space = if s.cpu_count() == 1 {
                Space::new(devices, points::loops(s.cpu(), &loops))
            } else {
                // A system's loops, each CPU's from its programs' listings.
                let loops = (0..s.cpu_count())
                    .flat_map(|i| {
                        let cpu = s.cpu_at(i);
                        let folder = format!("{}/Loops", space::cpu_folder(i));
                        points::loops_at(cpu, i, &folder, &points::program_loops(cpu))
                    })
                    .collect();
                Space::with_cpus(devices, loops, s.cpu_count())
            };
            let space = Arc::new(space);
            let raw: Vec<u64> = space
                .points
                .iter()
                .map(|p| p.name.raw(s.cpu_at(p.cpu).memory()).unwrap_or(0))
                .collect();
            let diags = (0..space.cpus()).map(|i| publish::Diag::at(s, i)).collect();
            let feed = publish::Feed::with_diags(space, raw, diags);
            publish::install(s, feed.clone());
            feed
        })
        .await
        .map_err(|_| "the engine stopped before the OPC UA server started".to_string())?;
    let rule = WriteRule {
        read_only: cfg.read_only,
        needs_user: cfg.user.is_some(),
    };
    let nm_feed = feed.clone();
    // Making the certificate on first start is CPU work: off the runtime's
    // worker threads.
    let (server, handle) = tokio::task::spawn_blocking(move || {
        let nodes = InMemoryNodeManagerBuilder::new(move |ctx, asp: &mut _| {
            SoftplcNodes::build(&ctx, asp, engine, rule, nm_feed)
        });
        server_builder(&cfg, addr).with_node_manager(nodes).build()
    })
    .await
    .map_err(|e| e.to_string())??;
    let nm = handle
        .node_managers()
        .get_of_type::<InMemoryNodeManager<SoftplcNodes>>()
        .ok_or("the softplc node manager is missing")?;
    let ns = nm.inner().namespace();
    tokio::spawn(publish::run(feed, nm, handle.subscriptions().clone(), ns));
    server.run_with(tcp).await
}

/// The host part of the endpoint URL for a server on `addr`: the machine's
/// name for an unspecified address, else the address itself, an IPv6 one in
/// brackets (`opc.tcp://[::1]:4840/`, RFC 3986 §3.2.2) so that the port is
/// not read as part of it.
fn endpoint_host(addr: SocketAddr) -> String {
    match addr.ip() {
        ip if ip.is_unspecified() => opcua::crypto::X509Data::computer_hostnames()
            .into_iter()
            .next()
            .unwrap_or_else(|| "localhost".to_string()),
        std::net::IpAddr::V4(ip) => ip.to_string(),
        std::net::IpAddr::V6(ip) => format!("[{ip}]"),
    }
}

/// The endpoint `opc.tcp://ADDR/` with its security and limits.
fn server_builder(cfg: &OpcuaConfig, addr: SocketAddr) -> ServerBuilder {
    let host = endpoint_host(addr);
    let mut users = vec![ANONYMOUS_USER_TOKEN_ID];
    let mut b = ServerBuilder::new()
        .application_name("softplc")
        .application_uri("urn:softplc:server")
        .product_uri("urn:softplc")
        .host(host.clone())
        .port(addr.port())
        .discovery_urls(vec![format!("opc.tcp://{host}:{}/", addr.port())])
        .pki_dir(cfg.pki.clone())
        .certificate_path("own/cert.der")
        .private_key_path("private/private.pem")
        .create_sample_keypair(true)
        .trust_client_certs(cfg.trust_client_certs)
        .diagnostics_enabled(false);
    if let Some((user, pass)) = &cfg.user {
        b = b.add_user_token(
            USER_TOKEN_ID,
            ServerUserToken::user_pass(user.as_str(), pass.as_str()),
        );
        users.push(USER_TOKEN_ID);
    }
    if cfg.allows_none() {
        b = b.add_endpoint(
            "none",
            (
                "/",
                SecurityPolicy::None,
                MessageSecurityMode::None,
                &users as &[&str],
            ),
        );
    }
    for (id, mode) in [
        ("basic256sha256_sign", MessageSecurityMode::Sign),
        (
            "basic256sha256_sign_encrypt",
            MessageSecurityMode::SignAndEncrypt,
        ),
    ] {
        b = b.add_endpoint(
            id,
            ("/", SecurityPolicy::Basic256Sha256, mode, &users as &[&str]),
        );
    }
    // Every END can change a value: sample as fast as the scan, publish as
    // often as a client asks down to one scan (at least 10 ms).
    let scan_ms = (cfg.scan.as_secs_f64() * 1000.0).max(1.0);
    let tick = scan_ms.clamp(10.0, 100.0);
    b = b.subscription_poll_interval_ms(tick as u64);
    let limits = b.limits_mut();
    // A client that goes away without closing its session leaves it open
    // for its timeout (OPC UA lets it come back to it): such sessions, and
    // those never activated, make room for new ones; one client address
    // cannot take every session or connection (docs/opcua.md, Limits).
    limits.max_sessions = cfg.max_sessions;
    limits.max_sessions_per_client = cfg.max_sessions_per_client;
    limits.max_connections = 2 * cfg.max_sessions;
    limits.max_connections_per_client = 2 * cfg.max_sessions_per_client;
    limits.subscriptions.min_sampling_interval_ms = scan_ms;
    limits.subscriptions.min_publishing_interval_ms = tick;
    limits.subscriptions.max_monitored_items_per_sub = 100_000;
    // A publish response carries at most 1000 data changes, the array
    // length clients decode by default (async-opcua's limit); the rest go in
    // the next responses.
    limits.subscriptions.max_notifications_per_publish = 1000;
    limits.operational.max_monitored_items_per_call = 100_000;
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoint_hosts_bracket_ipv6_addresses() {
        let host = |a: &str| endpoint_host(a.parse().unwrap());
        assert_eq!(host("127.0.0.1:4840"), "127.0.0.1");
        assert_eq!(host("[::1]:4840"), "[::1]");
        assert_eq!(host("[fe80::1]:4840"), "[fe80::1]");
        let url = format!("opc.tcp://{}:{}/", host("[::1]:4840"), 4840);
        assert_eq!(url, "opc.tcp://[::1]:4840/");
    }
}
