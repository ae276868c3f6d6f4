//! Monitored items per second at a 10 ms constant scan (docs/opcua.md):
//!
//! ```sh
//! cargo run --release -p softplc-opcua --example monitored_load -- --items 1000 --secs 10
//! ```
//!
//! Serves a program of `--items` word devices that all change every scan
//! (`INC D0` … `INC Dn`) over OPC UA on 127.0.0.1, subscribes to every one
//! with async-opcua's client (sampling at the scan, queue 10, publishing
//! every 50 ms), counts the data-change notifications for `--secs`, and
//! prints them per second with the serve statistics (overruns, scan times).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use opcua::client::{ClientBuilder, DataChangeCallback, IdentityToken};
use opcua::crypto::SecurityPolicy;
use opcua::types::{
    AttributeId, MessageSecurityMode, MonitoredItemCreateRequest, MonitoringMode,
    MonitoringParameters, NodeId, ReadValueId, TimestampsToReturn,
};
use softplc_core::device::DeviceConfig;
use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_opcua::{points, OpcuaConfig, Prepared};
use softplc_serve::{Background, EngineConfig, ServeState};

const SCAN: Duration = Duration::from_millis(10);

fn arg(name: &str, default: u64) -> u64 {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map(|v| {
            v.parse()
                .unwrap_or_else(|_| panic!("{name}: expected a number, not `{v}`"))
        })
        .unwrap_or(default)
}

fn main() {
    let items = arg("--items", 1000) as usize;
    let secs = arg("--secs", 10);
    let publish_ms = arg("--publish-ms", 50);
    let queue = arg("--queue", 10) as u32;
    let mut src = String::from("LD SM400\n");
    for k in 0..items {
        src.push_str(&format!("INC D{k}\n"));
    }
    src.push_str("END\n");
    let program = softplc_core::program::compile_il("load.il", &src, &DeviceConfig::default())
        .expect("the load program compiles");
    let cpu = Cpu::new(
        program,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let pki = tempfile::tempdir().expect("a temporary pki directory");
    let cfg = OpcuaConfig {
        addr: "127.0.0.1:0".parse().unwrap(),
        read_only: false,
        user: None,
        pki: pki.path().to_path_buf(),
        trust_client_certs: false,
        nodes: Vec::new(),
        scan: SCAN,
        max_sessions: softplc_opcua::config::MAX_SESSIONS,
        max_sessions_per_client: softplc_opcua::config::MAX_SESSIONS_PER_CLIENT,
    };
    let prepared = Prepared {
        devices: points::devices(&cpu, &[]).expect("the program's devices"),
        cfg,
        loops: Vec::new(),
    };
    let engine = EngineConfig {
        period: SCAN,
        end_budget: SCAN / 4,
        queue: 1024,
        battery: None,
        log_every: None,
        realtime: softplc_serve::RealTime::none(),
        ack_after_commit: true,
    };
    let bg = Background::start(
        ServeState::new(cpu),
        engine,
        vec![prepared.listener()],
        vec![],
    )
    .expect("the server starts");
    let url = format!("opc.tcp://127.0.0.1:{}/", bg.addrs[0].port());
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let count = Arc::new(AtomicU64::new(0));
    let c2 = count.clone();
    let counted = rt.block_on(async move {
        let mut client = ClientBuilder::new()
            .application_name("softplc monitored_load")
            .application_uri("urn:softplc:monitored-load")
            .pki_dir(pki.path().join("client"))
            .create_sample_keypair(false)
            .trust_server_certs(true)
            .client()
            .unwrap();
        let (session, lp) = loop {
            match client
                .connect_to_matching_endpoint(
                    (
                        url.as_str(),
                        SecurityPolicy::None.to_str(),
                        MessageSecurityMode::None,
                    ),
                    IdentityToken::Anonymous,
                )
                .await
            {
                Ok(s) => break s,
                Err(_) => tokio::time::sleep(Duration::from_millis(100)).await,
            }
        };
        lp.spawn();
        session.wait_for_connection().await;
        let ns = session.get_namespace_index("urn:softplc").await.unwrap();
        let sub = session
            .create_subscription(
                Duration::from_millis(publish_ms),
                600,
                20,
                0,
                0,
                true,
                DataChangeCallback::new(move |_, _| {
                    c2.fetch_add(1, Ordering::Relaxed);
                }),
            )
            .await
            .unwrap();
        let requests: Vec<MonitoredItemCreateRequest> = (0..items)
            .map(|k| MonitoredItemCreateRequest {
                item_to_monitor: ReadValueId {
                    node_id: NodeId::new(ns, format!("D{k}")),
                    attribute_id: AttributeId::Value as u32,
                    ..Default::default()
                },
                monitoring_mode: MonitoringMode::Reporting,
                requested_parameters: MonitoringParameters {
                    client_handle: k as u32,
                    sampling_interval: SCAN.as_secs_f64() * 1000.0,
                    queue_size: queue,
                    discard_oldest: true,
                    ..Default::default()
                },
            })
            .collect();
        // In requests of 1000 items, which fit a message.
        let mut good = 0;
        for chunk in requests.chunks(1000) {
            let created = session
                .create_monitored_items(sub, TimestampsToReturn::Both, chunk.to_vec())
                .await
                .unwrap();
            good += created
                .iter()
                .filter(|r| r.result.status_code.is_good())
                .count();
        }
        assert_eq!(good, items, "every monitored item is created");
        // Warm up (initial values), then count.
        tokio::time::sleep(Duration::from_secs(1)).await;
        let from = count.load(Ordering::Relaxed);
        let t0 = Instant::now();
        tokio::time::sleep(Duration::from_secs(secs)).await;
        let n = count.load(Ordering::Relaxed) - from;
        let elapsed = t0.elapsed().as_secs_f64();
        let _ = session.disconnect().await;
        (n, elapsed)
    });
    let state = bg.stop().expect("the server stops");
    let st = &state.stats;
    let (n, elapsed) = counted;
    let per_s = n as f64 / elapsed;
    let ideal = items as f64 * (1.0 / SCAN.as_secs_f64());
    println!(
        "items {items}, scan {} ms: {per_s:.0} notifications/s over {elapsed:.1} s \
         ({:.0}% of {ideal:.0}/s, one per item per scan); scans {}, overruns {}, \
         exec max {} us, scan+END max {} us, jitter max {} us",
        SCAN.as_millis(),
        100.0 * per_s / ideal,
        st.scans,
        st.overruns,
        st.exec_max_us,
        st.max_us,
        st.jitter_max_us
    );
}
