//! async-opcua's own client against `serve --opcua` on 127.0.0.1:0
//! (contract §3.2): browse, read, write at END, subscriptions, and the
//! BadNodeIdUnknown / BadTypeMismatch / BadNotWritable / BadUserAccessDenied
//! answers.

use std::sync::Arc;
use std::time::Duration;

use opcua::client::{ClientBuilder, DataChangeCallback, IdentityToken, Session};
use opcua::crypto::SecurityPolicy;
use opcua::types::{
    AttributeId, BrowseDescription, BrowseDirection, BrowseResultMask, DataValue,
    MessageSecurityMode, MonitoredItemCreateRequest, MonitoringMode, MonitoringParameters, NodeId,
    ObjectId, ReadValueId, ReferenceTypeId, StatusCode, TimestampsToReturn, Variant, WriteValue,
};
use softplc_core::device::DeviceConfig;
use softplc_core::engine::{Cpu, MonotonicClock};
use softplc_opcua::{points, OpcuaConfig, Prepared};
use softplc_serve::{Background, EngineConfig, ServeState};

/// X0 → Y0; D100 counts executed scans; D0 is copied to D1 every scan;
/// DMOV makes D20/D22 32-bit operands, EMOV D30/D32 reals.
const PROGRAM: &str =
    "LD X0\nOUT Y0\nLD SM400\nINC D100\nMOV D0 D1\nDMOV D20 D22\nEMOV D30 D32\nEND\n";

/// Two PID loops (D500 = 2) of the PIDCONT at D600, in manual, with the
/// data of 001 §5.1 Table 5.2 (Ts 10 ms, Kp 1.00) set in the first scan.
const PID_PROGRAM: &str = "LD SM402\nMOV K2 D500\nMOV K2 D501\n\
    MOV K1 D502\nMOV K1 D503\nMOV K100 D504\nMOV K32767 D505\nMOV K2000 D509\nMOV K2000 D510\nMOV K2000 D511\n\
    MOV K1 D512\nMOV K1 D513\nMOV K100 D514\nMOV K32767 D515\nMOV K2000 D519\nMOV K2000 D520\nMOV K2000 D521\n\
    PIDINIT D500\nLD SM400\nPIDCONT D600\nEND\n";

struct Server {
    url: String,
    bg: Option<Background>,
    /// The server's certificate store, made on start.
    pki: tempfile::TempDir,
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Some(bg) = self.bg.take() {
            let _ = bg.stop();
        }
    }
}

fn config(read_only: bool, user: Option<(&str, &str)>) -> OpcuaConfig {
    OpcuaConfig {
        addr: "127.0.0.1:0".parse().unwrap(),
        read_only,
        user: user.map(|(u, p)| (u.to_string(), p.to_string())),
        // Set by `start`.
        pki: std::path::PathBuf::new(),
        trust_client_certs: true,
        nodes: vec!["D40:u16".into(), "D42:u32".into()],
        scan: Duration::from_millis(5),
        max_sessions: softplc_opcua::config::MAX_SESSIONS,
        max_sessions_per_client: softplc_opcua::config::MAX_SESSIONS_PER_CLIENT,
    }
}

fn start(src: &str, mut cfg: OpcuaConfig) -> Server {
    let pki = tempfile::tempdir().unwrap();
    cfg.pki = pki.path().to_path_buf();
    let p = softplc_core::program::compile_il("main.il", src, &DeviceConfig::default()).unwrap();
    let cpu = Cpu::new(
        p,
        softplc_core::profile::default_config(),
        Box::new(MonotonicClock::default()),
    );
    let prepared = Prepared {
        devices: points::devices(&cpu, &cfg.nodes).unwrap(),
        loops: points::program_loops(&cpu),
        cfg,
    };
    let engine = EngineConfig {
        period: Duration::from_millis(5),
        end_budget: Duration::from_millis(2),
        queue: 256,
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
    .unwrap();
    Server {
        url: format!("opc.tcp://127.0.0.1:{}/", bg.addrs[0].port()),
        bg: Some(bg),
        pki,
    }
}

/// A session on `srv` (it may still be making its certificate).
async fn connect(
    srv: &Server,
    policy: SecurityPolicy,
    mode: MessageSecurityMode,
    who: IdentityToken,
) -> Arc<Session> {
    static CLIENTS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    let n = CLIENTS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let url = srv.url.as_str();
    let mut client = ClientBuilder::new()
        .application_name("softplc test client")
        .application_uri("urn:softplc:test-client")
        .pki_dir(srv.pki.path().join(format!("client-{n}")))
        .create_sample_keypair(policy != SecurityPolicy::None)
        .trust_server_certs(true)
        .session_retry_limit(3)
        .client()
        .unwrap();
    for _ in 0..300 {
        if let Ok((session, lp)) = client
            .connect_to_matching_endpoint((url, policy.to_str(), mode), who.clone())
            .await
        {
            lp.spawn();
            tokio::time::timeout(Duration::from_secs(20), session.wait_for_connection())
                .await
                .unwrap();
            return session;
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    panic!("no session on {url}");
}

async fn anonymous(srv: &Server) -> Arc<Session> {
    connect(
        srv,
        SecurityPolicy::None,
        MessageSecurityMode::None,
        IdentityToken::Anonymous,
    )
    .await
}

async fn ns(s: &Session) -> u16 {
    s.get_namespace_index("urn:softplc").await.unwrap()
}

fn node(ns: u16, id: &str) -> NodeId {
    NodeId::new(ns, id.to_string())
}

async fn read(s: &Session, ns: u16, id: &str) -> DataValue {
    let r = s
        .read(
            &[ReadValueId {
                node_id: node(ns, id),
                attribute_id: AttributeId::Value as u32,
                ..Default::default()
            }],
            TimestampsToReturn::Both,
            0.0,
        )
        .await
        .unwrap();
    r.into_iter().next().unwrap()
}

async fn write(s: &Session, ns: u16, id: &str, v: Variant) -> StatusCode {
    let r = s
        .write(&[WriteValue {
            node_id: node(ns, id),
            attribute_id: AttributeId::Value as u32,
            value: DataValue::value_only(v),
            ..Default::default()
        }])
        .await
        .unwrap();
    r[0]
}

/// Reads `id` until it is `want` (values are published at END).
async fn wait_for(s: &Session, ns: u16, id: &str, want: Variant) {
    let mut last = None;
    for _ in 0..200 {
        let v = read(s, ns, id).await.value;
        if v.as_ref() == Some(&want) {
            return;
        }
        last = v;
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    panic!("{id} never became {want:?} (last {last:?})");
}

async fn browse_names(s: &Session, id: NodeId) -> Vec<String> {
    let r = s
        .browse(
            &[BrowseDescription {
                node_id: id,
                browse_direction: BrowseDirection::Forward,
                reference_type_id: ReferenceTypeId::HierarchicalReferences.into(),
                include_subtypes: true,
                node_class_mask: 0,
                result_mask: BrowseResultMask::All as u32,
            }],
            1000,
            None,
        )
        .await
        .unwrap();
    // References come in no set order.
    let mut names: Vec<String> = r[0]
        .references
        .clone()
        .unwrap_or_default()
        .iter()
        .map(|r| r.browse_name.name.to_string())
        .collect();
    names.sort();
    names
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn browse_shows_devices_diagnostics_and_loops() {
    let srv = start(PROGRAM, config(false, None));
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    let objects = browse_names(&s, ObjectId::ObjectsFolder.into()).await;
    assert!(objects.contains(&"softplc".to_string()), "{objects:?}");
    let top = browse_names(&s, node(ns, "/softplc")).await;
    assert_eq!(top, ["Devices", "Diagnostics", "Loops"]);
    let devices = browse_names(&s, node(ns, "/softplc/Devices")).await;
    // Every device operand once, its 32-bit and real nodes where DMOV and
    // EMOV use it, and the [opcua] nodes.
    assert_eq!(
        devices,
        [
            "D0", "D1", "D100", "D20", "D20:i32", "D22", "D22:i32", "D30", "D30:f32", "D32",
            "D32:f32", "D40:u16", "D42:u32", "SM400", "X0", "Y0"
        ]
    );
    let diag = browse_names(&s, node(ns, "/softplc/Diagnostics")).await;
    assert_eq!(diag, ["ErrorCode", "Scan", "ScanTimeUs", "State"]);
    // This program has no loop.
    assert!(browse_names(&s, node(ns, "/softplc/Loops"))
        .await
        .is_empty());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn reads_are_typed_and_diagnostics_follow_the_scan() {
    let srv = start(PROGRAM, config(false, None));
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    assert_eq!(
        read(&s, ns, "Y0").await.value,
        Some(Variant::Boolean(false))
    );
    assert_eq!(read(&s, ns, "D20:i32").await.value, Some(Variant::Int32(0)));
    assert_eq!(
        read(&s, ns, "D30:f32").await.value,
        Some(Variant::Float(0.0))
    );
    assert_eq!(
        read(&s, ns, "D40:u16").await.value,
        Some(Variant::UInt16(0))
    );
    assert_eq!(
        read(&s, ns, "D42:u32").await.value,
        Some(Variant::UInt32(0))
    );
    assert_eq!(
        read(&s, ns, "/softplc/Diagnostics/State").await.value,
        Some(Variant::from("RUN"))
    );
    assert_eq!(
        read(&s, ns, "/softplc/Diagnostics/ErrorCode").await.value,
        Some(Variant::UInt16(0))
    );
    // D100 counts executed scans, so it is Scan as an Int16 at one END.
    let Some(Variant::Int16(d100)) = read(&s, ns, "D100").await.value else {
        panic!("D100 is Int16")
    };
    let Some(Variant::UInt64(scan)) = read(&s, ns, "/softplc/Diagnostics/Scan").await.value else {
        panic!("Scan is UInt64")
    };
    assert!(d100 > 0 && scan >= d100 as u64, "D100 {d100}, Scan {scan}");
    assert!(matches!(
        read(&s, ns, "/softplc/Diagnostics/ScanTimeUs").await.value,
        Some(Variant::UInt32(_))
    ));
    // Not a device the program uses, and not a device at all.
    for id in ["D999", "NOPE"] {
        assert_eq!(
            read(&s, ns, id).await.status,
            Some(StatusCode::BadNodeIdUnknown),
            "{id}"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn writes_land_at_end_and_the_program_sees_them() {
    let srv = start(PROGRAM, config(false, None));
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    assert_eq!(
        write(&s, ns, "D0", Variant::Int16(-1234)).await,
        StatusCode::Good
    );
    // The reply comes after the END that wrote: D0 reads back at once; the
    // program copies it to D1 in the next scan.
    assert_eq!(read(&s, ns, "D0").await.value, Some(Variant::Int16(-1234)));
    wait_for(&s, ns, "D1", Variant::Int16(-1234)).await;
    // X0 goes to the input image: Y0 follows.
    assert_eq!(
        write(&s, ns, "X0", Variant::Boolean(true)).await,
        StatusCode::Good
    );
    wait_for(&s, ns, "Y0", Variant::Boolean(true)).await;
    // 32-bit and real nodes write both words (MELSEC: low word first).
    assert_eq!(
        write(&s, ns, "D20:i32", Variant::Int32(0x0001_0002)).await,
        StatusCode::Good
    );
    wait_for(&s, ns, "D20", Variant::Int16(2)).await;
    wait_for(&s, ns, "D22:i32", Variant::Int32(0x0001_0002)).await;
    assert_eq!(
        write(&s, ns, "D30:f32", Variant::Float(1.5)).await,
        StatusCode::Good
    );
    wait_for(&s, ns, "D32:f32", Variant::Float(1.5)).await;
    // 1.5f32 is 0x3FC0_0000: the high word D31 = 0x3FC0, the low D30 = 0.
    wait_for(&s, ns, "D30", Variant::Int16(0)).await;
    assert_eq!(
        write(&s, ns, "D40:u16", Variant::UInt16(65535)).await,
        StatusCode::Good
    );
    wait_for(&s, ns, "D40:u16", Variant::UInt16(65535)).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_writes_get_their_status_and_write_nothing() {
    let srv = start(PROGRAM, config(false, None));
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    assert_eq!(
        write(&s, ns, "D0", Variant::Int32(5)).await,
        StatusCode::BadTypeMismatch
    );
    assert_eq!(
        write(&s, ns, "Y0", Variant::Int16(1)).await,
        StatusCode::BadTypeMismatch
    );
    assert_eq!(
        write(&s, ns, "D30:f32", Variant::Double(1.0)).await,
        StatusCode::BadTypeMismatch
    );
    assert_eq!(
        write(&s, ns, "NOPE", Variant::Int16(1)).await,
        StatusCode::BadNodeIdUnknown
    );
    assert_eq!(
        write(&s, ns, "/softplc/Diagnostics/Scan", Variant::UInt64(1)).await,
        StatusCode::BadNotWritable
    );
    assert_eq!(read(&s, ns, "D0").await.value, Some(Variant::Int16(0)));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn read_only_refuses_every_write() {
    let srv = start(PROGRAM, config(true, None));
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    assert_eq!(
        write(&s, ns, "D0", Variant::Int16(7)).await,
        StatusCode::BadNotWritable
    );
    assert_eq!(read(&s, ns, "D0").await.value, Some(Variant::Int16(0)));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_a_user_anonymous_only_reads() {
    let srv = start(PROGRAM, config(false, Some(("operator", "s3cret"))));
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    assert_eq!(
        write(&s, ns, "D0", Variant::Int16(7)).await,
        StatusCode::BadUserAccessDenied
    );
    let user = connect(
        &srv,
        SecurityPolicy::None,
        MessageSecurityMode::None,
        IdentityToken::UserName("operator".into(), "s3cret".into()),
    )
    .await;
    assert_eq!(
        write(&user, ns, "D0", Variant::Int16(7)).await,
        StatusCode::Good
    );
    assert_eq!(read(&s, ns, "D0").await.value, Some(Variant::Int16(7)));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn subscriptions_get_every_change_published_at_end() {
    let srv = start(PROGRAM, config(false, None));
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel::<(String, Variant)>();
    let sub = s
        .create_subscription(
            Duration::from_millis(20),
            100,
            10,
            0,
            0,
            true,
            DataChangeCallback::new(move |dv, item| {
                let id = item.item_to_monitor().node_id.to_string();
                if let Some(v) = dv.value {
                    let _ = tx.send((id, v));
                }
            }),
        )
        .await
        .unwrap();
    let items: Vec<MonitoredItemCreateRequest> = ["D100", "Y0"]
        .iter()
        .map(|id| MonitoredItemCreateRequest {
            item_to_monitor: ReadValueId {
                node_id: node(ns, id),
                attribute_id: AttributeId::Value as u32,
                ..Default::default()
            },
            monitoring_mode: MonitoringMode::Reporting,
            requested_parameters: MonitoringParameters {
                sampling_interval: 0.0,
                queue_size: 100,
                discard_oldest: true,
                ..Default::default()
            },
        })
        .collect();
    let r = s
        .create_monitored_items(sub, TimestampsToReturn::Both, items)
        .await
        .unwrap();
    assert!(r.iter().all(|i| i.result.status_code.is_good()));
    assert_eq!(
        write(&s, ns, "X0", Variant::Boolean(true)).await,
        StatusCode::Good
    );
    let d100 = node(ns, "D100").to_string();
    let y0 = node(ns, "Y0").to_string();
    let (mut counts, mut y0_on) = (Vec::new(), false);
    let end = tokio::time::Instant::now() + Duration::from_secs(20);
    while (counts.len() < 20 || !y0_on) && tokio::time::Instant::now() < end {
        match tokio::time::timeout(Duration::from_secs(5), rx.recv()).await {
            Ok(Some((id, Variant::Int16(n)))) if id == d100 => counts.push(n),
            Ok(Some((id, Variant::Boolean(b)))) if id == y0 => y0_on |= b,
            Ok(Some(_)) => {}
            _ => break,
        }
    }
    assert!(y0_on, "Y0 turned on after X0 was written");
    assert!(counts.len() >= 20, "D100 notifications: {counts:?}");
    // Each notification is a later END: D100 only goes up (no wrap here).
    assert!(counts.windows(2).all(|w| w[0] < w[1]), "{counts:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn loops_have_named_fields_on_the_loop_words() {
    let mut cfg = config(false, None);
    cfg.nodes.push("D632".into());
    let srv = start(PID_PROGRAM, cfg);
    let s = anonymous(&srv).await;
    let ns = ns(&s).await;
    let loops = browse_names(&s, node(ns, "/softplc/Loops")).await;
    assert_eq!(loops, ["PIDCONT D600 loop 1", "PIDCONT D600 loop 2"]);
    let fields = browse_names(&s, node(ns, "/softplc/Loops/PIDCONT D600 loop 2")).await;
    assert_eq!(fields, ["ALARM", "MODE", "MV", "MVMAN", "PV", "SV"]);
    // Loop 2's I/O data start at D600 + 10 common words + 18 = D628; its
    // manual MV is word 4, D632 (001 §5.2(4)), kept in manual mode.
    let mvman = "/softplc/Loops/PIDCONT D600 loop 2/MVMAN";
    assert_eq!(
        write(&s, ns, mvman, Variant::Int16(500)).await,
        StatusCode::Good
    );
    assert_eq!(read(&s, ns, "D632").await.value, Some(Variant::Int16(500)));
    assert_eq!(read(&s, ns, mvman).await.value, Some(Variant::Int16(500)));
    assert_eq!(
        read(&s, ns, "/softplc/Diagnostics/State").await.value,
        Some(Variant::from("RUN"))
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn basic256sha256_sign_and_encrypt() {
    let srv = start(PROGRAM, config(false, None));
    let s = connect(
        &srv,
        SecurityPolicy::Basic256Sha256,
        MessageSecurityMode::SignAndEncrypt,
        IdentityToken::Anonymous,
    )
    .await;
    let ns = ns(&s).await;
    assert_eq!(
        write(&s, ns, "D0", Variant::Int16(42)).await,
        StatusCode::Good
    );
    wait_for(&s, ns, "D1", Variant::Int16(42)).await;
}
