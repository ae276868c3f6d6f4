//! Writing a program during RUN over HTTP and with `serve --watch`
//! (contract §7): `PUT /api/v1/program` replaces a project's file at an
//! END with device memory and the unchanged instructions' state kept,
//! rewrites it on disk and the ladder shows it; a text that does not
//! compile is 400 with its diagnostics and changes nothing; a rewritten
//! file is picked up by the watcher.

mod common;

use std::sync::Arc;
use std::time::{Duration, Instant};

use common::*;
use serde_json::json;
use softplc_core::engine::MonotonicClock;
use softplc_http::HttpConfig;
use softplc_serve::online::Online;
use softplc_serve::ServeState;

const V1: &str = "LD M0\nOUT C0 K100\nLD SM400\nINC D100\nEND\n";
/// V1 with a falling-edge rung whose condition (M5) is OFF.
const V2: &str = "LD M0\nOUT C0 K100\nLDF M5\nINC D5\nLD SM400\nINC D100\nEND\n";

struct Project {
    server: Server,
    dir: tempfile::TempDir,
}

/// A project of main.il (`text`) served with the token; with `watch`, the
/// watcher of `serve --watch` runs too.
fn serve(text: &str, watch: bool) -> (Project, Option<softplc_serve::online::Watcher>) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("plc.toml"),
        "[[program]]\nfile = \"main.il\"\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("main.il"), text).unwrap();
    let mut cpu = softplc_core::project::load_project(dir.path())
        .and_then(|p| p.build_cpu(Box::new(MonotonicClock::default())))
        .unwrap_or_else(|d| panic!("{d}"));
    softplc_core::tier::apply_env(&mut cpu);
    let ladder = softplc_http::ladder::load_programs(&cpu);
    let mut state = ServeState::new(cpu);
    let sources = softplc_core::online::Sources::load(dir.path(), &state.cpus).unwrap();
    let online = Arc::new(Online::new(sources));
    let watcher = watch.then(|| {
        let w = softplc_serve::online::watch(online.clone(), vec![dir.path().join("plc.toml")])
            .unwrap();
        state.add_hook(w.hook);
        w.watcher
    });
    let cfg = HttpConfig {
        token: Some(TOKEN.into()),
        model: "Q06HCPU".into(),
        ladder,
        limits: Default::default(),
        online: Some(online),
    };
    (
        Project {
            server: start_state(state, cfg),
            dir,
        },
        watcher,
    )
}

async fn devices(addr: std::net::SocketAddr, names: &str) -> serde_json::Value {
    let r = get(addr, &format!("/api/v1/devices?names={names}")).await;
    assert_eq!(r.status, 200, "{}", r.body);
    r.json()["devices"].clone()
}

fn put_body(file: &str, text: &str) -> String {
    json!({"file": file, "text": text}).to_string()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_put_program_keeps_the_count_fires_the_new_falling_edge_and_shows_the_rung() {
    let (p, _) = serve(V1, false);
    let addr = p.server.addr;
    // Two rising edges of M0: C0 counts 2.
    for on in [true, false, true, false] {
        let r = send(
            addr,
            "POST",
            "/api/v1/devices",
            Some(&json!({"M0": on}).to_string()),
        )
        .await;
        assert_eq!(r.status, 200, "{}", r.body);
    }
    assert_eq!(devices(addr, "CN0").await, json!({"CN0": 2}));
    let before = get(addr, "/ladder.txt?prog=0").await.body;
    assert!(!before.contains("M5"), "{before}");

    let r = send(
        addr,
        "PUT",
        "/api/v1/program",
        Some(&put_body("main.il", V2)),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    let j = r.json();
    assert!(j["scan"].as_u64().unwrap() > 0, "{j}");
    // LD M0, OUT C0, LD SM400, INC D100, END kept; LDF M5 and INC D5 added.
    assert_eq!(
        (&j["kept"], &j["added"], &j["removed"]),
        (&json!(5), &json!(2), &json!(0))
    );

    // The count is kept, and LDF M5 with M5 OFF acted once after the write.
    let d = devices(addr, "CN0,D5").await;
    assert_eq!(d, json!({"CN0": 2, "D5": 1}));
    let d = devices(addr, "CN0,D5").await;
    assert_eq!(d, json!({"CN0": 2, "D5": 1}));
    // The ladder shows the new rung; the file on disk is the new text.
    let after = get(addr, "/ladder.txt?prog=0").await.body;
    assert!(after.contains("M5") && after.contains("D5"), "{after}");
    let page = get(addr, "/").await.body;
    assert!(page.contains("M5"), "the ladder page watches M5");
    assert_eq!(
        std::fs::read_to_string(p.dir.path().join("main.il")).unwrap(),
        V2
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_program_that_does_not_compile_is_400_and_changes_nothing() {
    let (p, _) = serve(V1, false);
    let addr = p.server.addr;
    let bad = "LD M0\nFOO D0\nEND\n";
    let r = send(
        addr,
        "PUT",
        "/api/v1/program",
        Some(&put_body("main.il", bad)),
    )
    .await;
    assert_eq!(r.status, 400, "{}", r.body);
    let j = r.json();
    let diags = j["diagnostics"].as_array().unwrap();
    assert_eq!(diags.len(), 1, "{j}");
    let d = diags[0].as_str().unwrap();
    assert!(d.ends_with("main.il:2:1: unknown instruction `FOO`"), "{d}");
    assert!(j["error"].as_str().unwrap().contains("unchanged"), "{j}");
    // The old program runs: D100 counts on; the file is untouched.
    let a = devices(addr, "D100").await["D100"].as_i64().unwrap();
    let b = devices(addr, "D100").await["D100"].as_i64().unwrap();
    assert!(b > a, "{a} then {b}");
    assert_eq!(
        std::fs::read_to_string(p.dir.path().join("main.il")).unwrap(),
        V1
    );
    let ladder = get(addr, "/ladder.txt?prog=0").await.body;
    assert!(!ladder.contains("FOO"), "{ladder}");

    // An unknown file is 404 naming the files there are.
    let r = send(
        addr,
        "PUT",
        "/api/v1/program",
        Some(&put_body("nope.il", V2)),
    )
    .await;
    assert_eq!(r.status, 404, "{}", r.body);
    assert_eq!(
        r.json()["error"],
        json!("no program file \"nope.il\" is served (the program files: main.il)")
    );
    // Without the token: 401.
    let r = request(
        addr,
        "PUT",
        "/api/v1/program",
        &[],
        Some(&put_body("main.il", V2)),
    )
    .await;
    assert_eq!(r.status, 401, "{}", r.body);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn watch_writes_a_rewritten_file_during_run() {
    let (p, _watcher) = serve("LD SM400\nMOV K1 D0\nEND\n", true);
    let addr = p.server.addr;
    assert_eq!(devices(addr, "D0").await, json!({"D0": 1}));
    std::fs::write(p.dir.path().join("main.il"), "LD SM400\nMOV K2 D0\nEND\n").unwrap();
    // The watcher waits for the file to settle; give it ample time.
    let deadline = Instant::now() + Duration::from_secs(30);
    while devices(addr, "D0").await != json!({"D0": 2}) {
        assert!(
            Instant::now() < deadline,
            "the rewritten file was not picked up"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let ladder = get(addr, "/ladder.txt?prog=0").await.body;
    assert!(ladder.contains("K2"), "{ladder}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn each_cpu_of_a_system_is_written_by_its_path() {
    let dir = tempfile::tempdir().unwrap();
    for i in 1..=2 {
        let d = dir.path().join(format!("cpu{i}"));
        std::fs::create_dir(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            "[[program]]\nfile = \"main.il\"\n[multi_cpu]\ncpus = 2\n",
        )
        .unwrap();
        std::fs::write(d.join("main.il"), format!("LD SM400\nMOV K{i} D1\nEND\n")).unwrap();
    }
    std::fs::write(
        dir.path().join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    let time = MonotonicClock::default();
    let mut clock = || -> Box<dyn softplc_core::engine::Clock> { Box::new(time.clone()) };
    let sys = softplc_core::system::System::load(dir.path(), &mut clock).unwrap();
    let ladder = softplc_http::ladder::load_programs(sys.cpu(0));
    let state = ServeState::system(sys, Vec::new());
    let sources = softplc_core::online::Sources::load(dir.path(), &state.cpus).unwrap();
    let cfg = HttpConfig {
        token: Some(TOKEN.into()),
        model: "Q06HCPU".into(),
        ladder,
        limits: Default::default(),
        online: Some(Arc::new(Online::new(sources))),
    };
    let server = start_state(state, cfg);
    let addr = server.addr;
    assert_eq!(
        devices(addr, "D1,CPU2/D1").await,
        json!({"D1": 1, "CPU2/D1": 2})
    );
    // main.il is in both CPUs' projects: the name alone is ambiguous.
    let text = "LD SM400\nMOV K20 D1\nEND\n";
    let r = send(
        addr,
        "PUT",
        "/api/v1/program",
        Some(&put_body("main.il", text)),
    )
    .await;
    assert_eq!(r.status, 404, "{}", r.body);
    assert_eq!(
        r.json()["error"],
        json!(
            "\"main.il\" names several program files: give its path (cpu1/main.il, cpu2/main.il)"
        )
    );
    let r = send(
        addr,
        "PUT",
        "/api/v1/program",
        Some(&put_body("cpu2/main.il", text)),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    // Requests are served at either CPU's END: wait for CPU 2's next scan.
    let deadline = Instant::now() + Duration::from_secs(30);
    while devices(addr, "D1,CPU2/D1").await != json!({"D1": 1, "CPU2/D1": 20}) {
        assert!(
            Instant::now() < deadline,
            "CPU 2 does not run the new program"
        );
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let ladder = get(addr, "/ladder.txt?cpu=2&prog=0").await.body;
    assert!(ladder.contains("K20"), "{ladder}");
    assert_eq!(
        std::fs::read_to_string(dir.path().join("cpu2/main.il")).unwrap(),
        text
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_large_program_is_written_past_the_apis_64_kib_body_limit() {
    // 5000 rungs (about 80 KB, 10001 steps): the door takes a program's
    // text although other bodies stop at 64 KiB; one rung changes.
    let rungs = |last: &str| {
        let mut t: String = (0..4999).map(|i| format!("LD M{i}\nOUT L{i}\n")).collect();
        t.push_str(last);
        t.push_str("END\n");
        t
    };
    let (p, _) = serve(&rungs("LD M4999\nOUT L4999\n"), false);
    let addr = p.server.addr;
    let body = put_body("main.il", &rungs("LD SM400\nOUT L4999\n"));
    assert!(body.len() > 64 * 1024);
    let r = send(addr, "PUT", "/api/v1/program", Some(&body)).await;
    assert_eq!(r.status, 200, "{}", r.body);
    let j = r.json();
    assert_eq!(
        (&j["kept"], &j["added"], &j["removed"]),
        (&json!(10000), &json!(1), &json!(1))
    );
    assert_eq!(devices(addr, "L4999").await, json!({"L4999": true}));
}
