//! A program's local devices over HTTP (QCPU manual §10.13.1, the monitor
//! with a chosen program): `D0@FILE` reads and writes that program's own
//! copy through `/api/v1/devices` and `/api/v1/events`, and each program's
//! ladder page watches its own local devices.
//!
//! a.il moves 3 and b.il 30 into the local D0 every scan; b.il runs last,
//! so device memory (a name without `@`) holds b's 30.

mod common;

use common::*;
use serde_json::json;

const A: &str = "LD SM400\nMOV K3 D0\nMOV D0 D100\nEND\n";
const B: &str = "LD SM400\nMOV K30 D0\nMOV D0 D101\nEND\n";

struct Project {
    server: Server,
    _dir: tempfile::TempDir,
}

fn start_two_programs() -> Project {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("plc.toml"),
        "[devices]\nlocal = [\"D0-D9\"]\n[[program]]\nfile = \"a.il\"\n[[program]]\nfile = \"b.il\"\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("a.il"), A).unwrap();
    std::fs::write(dir.path().join("b.il"), B).unwrap();
    Project {
        server: common::start_project(dir.path()),
        _dir: dir,
    }
}

/// The device names a page watches (its `data-names`).
fn page_names(body: &str) -> Vec<String> {
    body.split("data-names=\"")
        .nth(1)
        .and_then(|t| t.split('"').next())
        .unwrap_or_default()
        .split(',')
        .map(str::to_string)
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn each_programs_local_devices_read_and_written_by_name() {
    let p = start_two_programs();
    let addr = p.server.addr;
    let r = get(
        addr,
        "/api/v1/devices?names=D0@a,D0@b.il,D0,D100,D101,D100@a",
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    assert_eq!(
        r.json()["devices"],
        json!({"D0@a": 3, "D0@b.il": 30, "D0": 30, "D100": 3, "D101": 30, "D100@a": 3})
    );
    // A write lands in that program's copy only: a.il's D5 is 7, b.il's
    // (in device memory) stays 0.
    let w = send(addr, "POST", "/api/v1/devices", Some(r#"{"D5@A.IL": 7}"#)).await;
    assert_eq!(w.status, 200, "{}", w.body);
    let r = get(addr, "/api/v1/devices?names=D5@a,D5@b,D5").await;
    assert_eq!(r.json()["devices"], json!({"D5@a": 7, "D5@b": 0, "D5": 0}));
    // The live stream takes the same names.
    let (_, events) = sse(addr, "/api/v1/events?names=D0@a,D0", 1).await;
    assert_eq!(events[0].1["devices"], json!({"D0@a": 3, "D0": 30}));
    // An unknown program or an empty one: 400 naming it.
    let bad = get(addr, "/api/v1/devices?names=D0@c").await;
    assert_eq!(bad.status, 400);
    assert!(
        bad.body
            .contains("no program file `c` (the programs: a.il, b.il)"),
        "{}",
        bad.body
    );
    assert_eq!(get(addr, "/api/v1/devices?names=D0@").await.status, 400);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_programs_ladder_watches_its_own_local_devices() {
    let p = start_two_programs();
    let a = get(p.server.addr, "/?prog=0").await;
    assert_eq!(a.status, 200);
    let names = page_names(&a.body);
    assert!(names.contains(&"D0@a.il".to_string()), "{names:?}");
    assert!(names.contains(&"D100".to_string()), "{names:?}");
    assert!(names.contains(&"SM400".to_string()), "{names:?}");
    let b = page_names(&get(p.server.addr, "/?prog=1").await.body);
    assert!(b.contains(&"D0@b.il".to_string()), "{b:?}");
    // The names read as the programs see them.
    let q = format!("/api/v1/devices?names={}", names.join(","));
    let r = get(p.server.addr, &q).await;
    assert_eq!(r.json()["devices"]["D0@a.il"], 3, "{}", r.body);
}
