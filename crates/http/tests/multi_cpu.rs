//! The JSON API and the web monitor of a multi-CPU system (contract §6,
//! §3.1): a real two-CPU system built in a temporary directory. Names take
//! `CPUn/` prefixes (none: CPU 1), `status` lists every CPU, remote
//! operations and the ladder take `?cpu=N`.

mod common;

use std::time::Duration;

use common::*;
use serde_json::json;
use softplc_core::engine::{Clock, MonotonicClock};
use softplc_core::system::System;
use softplc_http::HttpConfig;
use softplc_serve::ServeState;

/// CPU 1 puts 11 in D1; CPU 2 puts 22 in D1 and counts its scans in D0; in
/// both X0 drives Y0.
const CPU1: &str = "LD SM400\nMOV K11 D1\nLD X0\nOUT Y0\nEND\n";
const CPU2: &str = "LD SM400\nMOV K22 D1\nINC D0\nLD X0\nOUT Y0\nEND\n";

struct Sys {
    server: Server,
    _dir: tempfile::TempDir,
}

fn start_system(token: Option<&str>) -> Sys {
    let dir = tempfile::tempdir().unwrap();
    for (i, il) in [CPU1, CPU2].iter().enumerate() {
        let d = dir.path().join(format!("cpu{}", i + 1));
        std::fs::create_dir(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            "[[program]]\nfile = \"main.il\"\n[multi_cpu]\ncpus = 2\n[ras]\nremote_reset = true\n",
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
    let cfg = HttpConfig {
        token: token.map(str::to_string),
        model: sys.cpu(0).profile().model.to_string(),
        ladder: softplc_http::ladder::load_programs(sys.cpu(0)),
        limits: Default::default(),
        online: None,
    };
    Sys {
        server: start_state(ServeState::system(sys, Vec::new()), cfg),
        _dir: dir,
    }
}

async fn until(addr: std::net::SocketAddr, path: &str, ok: impl Fn(&serde_json::Value) -> bool) {
    for _ in 0..300 {
        let j = get(addr, path).await.json();
        if ok(&j) {
            return;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    panic!(
        "{path} never became as expected: {}",
        get(addr, path).await.body
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn status_keeps_cpu1_at_the_top_and_lists_every_cpu() {
    let s = start_system(None);
    let a = s.server.addr;
    until(a, "/api/v1/status", |j| {
        j["cpus"][1]["scans"].as_u64() > Some(0)
    })
    .await;
    let j = get(a, "/api/v1/status").await.json();
    assert_eq!(j["state"], "RUN");
    assert_eq!(j["model"], "Q06HCPU");
    assert!(j["scan"].as_u64().unwrap() >= 1);
    let cpus = j["cpus"].as_array().unwrap();
    assert_eq!(cpus.len(), 2);
    for (i, c) in cpus.iter().enumerate() {
        assert_eq!(c["cpu"], i + 1);
        assert_eq!(c["state"], "RUN");
        assert_eq!(c["error"], serde_json::Value::Null);
        assert_eq!(c["model"], "Q06HCPU");
        assert!(c["scan_time_us"]["max"].is_u64());
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn names_take_their_cpu_prefix() {
    let s = start_system(Some(TOKEN));
    let a = s.server.addr;
    until(a, "/api/v1/devices?names=D1,CPU2/D1", |j| {
        j["devices"] == json!({"D1": 11, "CPU2/D1": 22})
    })
    .await;
    // CPU1/ is CPU 1 too.
    let j = get(a, "/api/v1/devices?names=CPU1/D1,cpu2/D1").await.json();
    assert_eq!(j["devices"], json!({"CPU1/D1": 11, "cpu2/D1": 22}));
    // A CPU the system does not have, or a bad device behind a prefix: 400.
    let r = get(a, "/api/v1/devices?names=CPU3/D0").await;
    assert_eq!(r.status, 400);
    assert!(r.json()["error"].as_str().unwrap().contains("no CPU 3"));
    let r = get(a, "/api/v1/devices?names=CPU2/QQ1").await;
    assert_eq!(r.status, 400);
    assert!(r.json()["error"].as_str().unwrap().contains("CPU2/QQ1"));
    // A write reaches its CPU only; a bad value names the device as given.
    let r = send(a, "POST", "/api/v1/devices", Some(r#"{"CPU2/D10": 5}"#)).await;
    assert_eq!(r.status, 200, "{}", r.body);
    let j = get(a, "/api/v1/devices?names=D10,CPU2/D10").await.json();
    assert_eq!(j["devices"], json!({"D10": 0, "CPU2/D10": 5}));
    let r = send(a, "POST", "/api/v1/devices", Some(r#"{"CPU2/D10": true}"#)).await;
    assert_eq!(r.status, 400);
    assert!(r.json()["error"].as_str().unwrap().contains("`CPU2/D10`"));
    // Live values too.
    let (_, ev) = sse(a, "/api/v1/events?names=CPU2/D0,D1", 2).await;
    let (_, e) = &ev[1];
    assert!(e["devices"]["CPU2/D0"].as_i64().unwrap() > 0);
    assert_eq!(e["devices"]["D1"], 11);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn forcing_names_the_cpu() {
    let s = start_system(Some(TOKEN));
    let a = s.server.addr;
    let r = send(a, "POST", "/api/v1/force", Some(r#"{"CPU2/X0": true}"#)).await;
    assert_eq!(r.status, 200, "{}", r.body);
    assert_eq!(r.json()["forced"], json!({"CPU2/X0": true}));
    until(a, "/api/v1/devices?names=Y0,CPU2/Y0", |j| {
        j["devices"] == json!({"Y0": false, "CPU2/Y0": true})
    })
    .await;
    assert_eq!(
        get(a, "/api/v1/status").await.json()["forced"],
        json!({"CPU2/X0": true})
    );
    let r = send(a, "DELETE", "/api/v1/force", Some(r#"["CPU2/X0"]"#)).await;
    assert_eq!(r.json()["forced"], json!({}));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn remote_operations_take_the_cpu() {
    let s = start_system(Some(TOKEN));
    let a = s.server.addr;
    let r = send(a, "POST", "/api/v1/cpu/stop?cpu=2", None).await;
    assert_eq!(r.json(), json!({"state": "STOP"}));
    let j = get(a, "/api/v1/status").await.json();
    assert_eq!(j["state"], "RUN");
    assert_eq!(j["cpus"][0]["state"], "RUN");
    assert_eq!(j["cpus"][1]["state"], "STOP");
    // No CPU 3: 400; CPU 1's RESET is refused in RUN (409).
    let r = send(a, "POST", "/api/v1/cpu/run?cpu=3", None).await;
    assert_eq!(r.status, 400);
    assert_eq!(send(a, "POST", "/api/v1/cpu/reset", None).await.status, 409);
    // RESET of CPU 2 alone brings the others down: MULTI CPU DOWN (7000)
    // in CPU 1 (004 ch. 13; the system's rule).
    let r = send(a, "POST", "/api/v1/cpu/reset?cpu=2", None).await;
    assert_eq!(r.status, 200, "{}", r.body);
    until(a, "/api/v1/status", |j| {
        j["cpus"][0]["error"]["code"] == 7000
    })
    .await;
    let j = get(a, "/api/v1/status").await.json();
    assert_eq!(j["error"]["code"], 7000);
    assert_eq!(j["state"], "STOP");
    // CPU 1's RESET (in STOP now) resets the whole system.
    let r = send(a, "POST", "/api/v1/cpu/reset?cpu=1", None).await;
    assert_eq!(r.status, 200, "{}", r.body);
    let j = get(a, "/api/v1/status").await.json();
    assert_eq!(j["cpus"][0]["error"], serde_json::Value::Null);
    assert_eq!(j["cpus"][1]["error"], serde_json::Value::Null);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_breakpoint_pauses_its_cpu_and_a_step_steps_it() {
    let s = start_system(Some(TOKEN));
    let a = s.server.addr;
    let r = send(
        a,
        "POST",
        "/api/v1/breakpoint",
        Some(r#"{"when": "CPU2/D0 >= 20"}"#),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    until(a, "/api/v1/status", |j| j["cpus"][1]["state"] == "PAUSE").await;
    let j = get(a, "/api/v1/status").await.json();
    assert_eq!(j["state"], "RUN");
    assert_eq!(j["breakpoint"]["when"], "CPU2/D0 >= 20");
    let hit = j["breakpoint"]["hit"].as_u64().unwrap();
    let d0 = get(a, "/api/v1/devices?names=CPU2/D0").await.json()["devices"]["CPU2/D0"].clone();
    assert_eq!(d0, 20);
    assert_eq!(j["cpus"][1]["scans"], hit);
    send(a, "DELETE", "/api/v1/breakpoint", None).await;
    // Step CPU 2 by 3 scans.
    let r = send(a, "POST", "/api/v1/cpu/step?scans=3&cpu=2", None).await;
    assert_eq!(r.json(), json!({"state": "PAUSE", "scan": hit + 3}));
    let d0 = get(a, "/api/v1/devices?names=CPU2/D0").await.json()["devices"]["CPU2/D0"].clone();
    assert_eq!(d0, 23);
    // CPU 1 is running: its step is refused.
    assert_eq!(send(a, "POST", "/api/v1/cpu/step", None).await.status, 409);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_monitor_shows_every_cpu() {
    let s = start_system(None);
    let a = s.server.addr;
    // CPU 1's page: a tab per CPU, its names without a prefix.
    let r = get(a, "/").await;
    assert_eq!(r.status, 200);
    assert!(r.body.contains(r#"id="cpu-state-1""#));
    assert!(r.body.contains(r#"href="/?cpu=2""#));
    assert!(r.body.contains(r#"data-cpu="1" data-prefix="""#));
    assert!(r.body.contains("data-names=\"SM400,"), "{}", r.body);
    // CPU 2's page: its ladder (INC), its names with its prefix.
    let r = get(a, "/?cpu=2").await;
    assert_eq!(r.status, 200);
    assert!(r.body.contains(r#"data-cpu="2" data-prefix="CPU2/""#));
    assert!(r.body.contains("CPU2/D0"));
    assert!(r.body.contains("INC"));
    let t = get(a, "/ladder.txt?cpu=2").await;
    assert!(t.body.contains("INC D0"), "{}", t.body);
    assert!(!get(a, "/ladder.txt").await.body.contains("INC"));
    assert_eq!(get(a, "/?cpu=5").await.status, 400);
    // The devices page and the rack take prefixed names and the CPU.
    let r = get(a, "/devices?start=CPU2/D0&count=2").await;
    assert!(r.body.contains(r#"data-v="CPU2/D1""#));
    assert_eq!(
        get(a, "/api/v1/rack?cpu=2").await.json(),
        json!({"slots": []})
    );
}
