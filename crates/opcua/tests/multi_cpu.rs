//! OPC UA of a multi-CPU system (contract §6, §3.2): a folder per CPU
//! (`CPU1`, `CPU2`) with its Devices, Diagnostics and Loops; NodeIds carry
//! the CPU prefix; a write reaches its CPU. async-opcua's client against a
//! real two-CPU system built in a temporary directory.

use std::sync::Arc;
use std::time::Duration;

use opcua::client::{ClientBuilder, IdentityToken, Session};
use opcua::crypto::SecurityPolicy;
use opcua::types::{
    AttributeId, BrowseDescription, BrowseDirection, BrowseResultMask, DataValue,
    MessageSecurityMode, NodeId, ReadValueId, ReferenceTypeId, StatusCode, TimestampsToReturn,
    Variant, WriteValue,
};
use softplc_core::engine::{Clock, MonotonicClock};
use softplc_core::system::System;
use softplc_opcua::{OpcuaConfig, Prepared};
use softplc_serve::{Background, EngineConfig, ServeState};

/// CPU 1 puts 11 in D1; CPU 2 puts 22 in D1 and copies D5 to D6.
const CPU1: &str = "LD SM400\nMOV K11 D1\nEND\n";
const CPU2: &str = "LD SM400\nMOV K22 D1\nMOV D5 D6\nEND\n";

struct Server {
    url: String,
    bg: Option<Background>,
    pki: tempfile::TempDir,
    _dir: tempfile::TempDir,
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Some(bg) = self.bg.take() {
            let _ = bg.stop();
        }
    }
}

fn start(nodes: &[&str]) -> Result<Server, String> {
    let dir = tempfile::tempdir().unwrap();
    for (i, il) in [CPU1, CPU2].iter().enumerate() {
        let d = dir.path().join(format!("cpu{}", i + 1));
        std::fs::create_dir(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            "[[program]]\nfile = \"main.il\"\n[multi_cpu]\ncpus = 2\n",
        )
        .unwrap();
        std::fs::write(d.join("main.il"), il).unwrap();
    }
    std::fs::write(
        dir.path().join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    let time = MonotonicClock::default();
    let mut clock = || -> Box<dyn Clock> { Box::new(time.clone()) };
    let sys = System::load(dir.path(), &mut clock).unwrap();
    let pki = tempfile::tempdir().unwrap();
    let cfg = OpcuaConfig {
        addr: "127.0.0.1:0".parse().unwrap(),
        read_only: false,
        user: None,
        pki: pki.path().to_path_buf(),
        trust_client_certs: true,
        nodes: nodes.iter().map(|n| n.to_string()).collect(),
        scan: Duration::from_millis(5),
        max_sessions: softplc_opcua::config::MAX_SESSIONS,
        max_sessions_per_client: softplc_opcua::config::MAX_SESSIONS_PER_CLIENT,
    };
    let prepared = Prepared::system(cfg, &[sys.cpu(0), sys.cpu(1)])?;
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
        ServeState::system(sys, Vec::new()),
        engine,
        vec![prepared.listener()],
        vec![],
    )
    .unwrap();
    Ok(Server {
        url: format!("opc.tcp://127.0.0.1:{}/", bg.addrs[0].port()),
        bg: Some(bg),
        pki,
        _dir: dir,
    })
}

async fn connect(srv: &Server) -> Arc<Session> {
    let mut client = ClientBuilder::new()
        .application_name("softplc test client")
        .application_uri("urn:softplc:test-client")
        .pki_dir(srv.pki.path().join("client"))
        .create_sample_keypair(false)
        .trust_server_certs(true)
        .session_retry_limit(3)
        .client()
        .unwrap();
    let endpoint = (
        srv.url.as_str(),
        SecurityPolicy::None.to_str(),
        MessageSecurityMode::None,
    );
    for _ in 0..300 {
        if let Ok((session, lp)) = client
            .connect_to_matching_endpoint(endpoint, IdentityToken::Anonymous)
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
    panic!("no session on {}", srv.url);
}

fn node(ns: u16, id: &str) -> NodeId {
    NodeId::new(ns, id.to_string())
}

async fn read(s: &Session, ns: u16, id: &str) -> Option<Variant> {
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
    r.into_iter().next().unwrap().value
}

async fn wait_for(s: &Session, ns: u16, id: &str, want: Variant) {
    let mut last = None;
    for _ in 0..300 {
        let v = read(s, ns, id).await;
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
async fn each_cpu_has_its_folder() {
    let srv = start(&["CPU2/D100:u16", "D200"]).unwrap();
    let s = connect(&srv).await;
    let ns = s.get_namespace_index("urn:softplc").await.unwrap();
    assert_eq!(
        browse_names(&s, node(ns, "/softplc")).await,
        ["CPU1", "CPU2"]
    );
    for cpu in ["CPU1", "CPU2"] {
        assert_eq!(
            browse_names(&s, node(ns, &format!("/softplc/{cpu}"))).await,
            ["Devices", "Diagnostics", "Loops"]
        );
    }
    // Each CPU's devices, browse names as written, NodeIds with the prefix.
    assert_eq!(
        browse_names(&s, node(ns, "/softplc/CPU1/Devices")).await,
        ["D1", "D200", "SM400"]
    );
    assert_eq!(
        browse_names(&s, node(ns, "/softplc/CPU2/Devices")).await,
        ["D1", "D100:u16", "D5", "D6", "SM400"]
    );
    wait_for(&s, ns, "CPU1/D1", Variant::Int16(11)).await;
    wait_for(&s, ns, "CPU2/D1", Variant::Int16(22)).await;
    for cpu in ["CPU1", "CPU2"] {
        let state = read(&s, ns, &format!("/softplc/{cpu}/Diagnostics/State")).await;
        assert_eq!(state, Some(Variant::from("RUN")));
    }
    // A write reaches its CPU only.
    let r = s
        .write(&[WriteValue {
            node_id: node(ns, "CPU2/D5"),
            attribute_id: AttributeId::Value as u32,
            value: DataValue::value_only(Variant::Int16(-9)),
            ..Default::default()
        }])
        .await
        .unwrap();
    assert_eq!(r[0], StatusCode::Good);
    wait_for(&s, ns, "CPU2/D6", Variant::Int16(-9)).await;
    // No single-CPU folders, no unprefixed device nodes.
    assert_eq!(
        read(&s, ns, "D1").await,
        None,
        "a system's device nodes carry their CPU"
    );
}

#[test]
fn nodes_of_an_absent_cpu_are_refused() {
    let e = start(&["CPU3/D0"]).err().unwrap();
    assert!(e.contains("[opcua] nodes") && e.contains("no CPU 3"), "{e}");
}
