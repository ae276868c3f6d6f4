//! The rack over HTTP: `GET /api/v1/rack`, the summary in `status`, buffer
//! memory `U<n>\G<addr>` read and written through `/api/v1/devices`, and
//! the ladder monitor showing `MOV U2\G11 D0` live. The project is
//! tests/python/rack (a generic module of 100 words at X/Y20, another of
//! 4096 words at X/Y40).

mod common;

use common::*;
use serde_json::json;
use softplc_core::engine::MonotonicClock;
use softplc_http::HttpConfig;

/// The device names a page watches (its `data-names`), comma-separated.
fn page_names(body: &str) -> String {
    body.split("data-names=\"")
        .nth(1)
        .and_then(|t| t.split('"').next())
        .unwrap_or_default()
        .to_string()
}

fn start_rack() -> Server {
    start_project(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/rack"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_rack_route_lists_every_slot() {
    let s = start_rack();
    let r = get(s.addr, "/api/v1/rack").await;
    assert_eq!(r.status, 200, "{}", r.body);
    let slots = r.json()["slots"].clone();
    assert_eq!(slots.as_array().map(Vec::len), Some(5), "{slots}");
    assert_eq!(
        slots[0],
        json!({"index": 0, "type": "input", "points": 16, "start": "0000", "end": "000F",
               "module": null, "unit": null, "buffer_words": 0, "interrupts": []})
    );
    assert_eq!(slots[1]["type"], "output");
    assert_eq!(
        (slots[1]["start"].clone(), slots[1]["end"].clone()),
        (json!("0010"), json!("001F"))
    );
    assert_eq!(
        slots[2],
        json!({"index": 2, "type": "intelligent", "points": 16, "start": "0020", "end": "002F",
               "module": "generic", "unit": "U2", "buffer_words": 100, "interrupts": []})
    );
    // The empty slot takes the default 16 points (30-3F).
    assert_eq!(slots[3]["type"], "empty");
    assert_eq!(slots[3]["start"], "0030");
    assert_eq!(slots[3]["unit"], json!(null));
    assert_eq!(slots[4]["unit"], "U4");
    assert_eq!(slots[4]["buffer_words"], 4096);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn status_carries_a_rack_summary() {
    let s = start_rack();
    let j = get(s.addr, "/api/v1/status").await.json();
    assert_eq!(
        j["rack"],
        json!({"slots": 5, "modules": {"2": "generic", "4": "generic"}})
    );
    // Without a rack: null.
    let plain = start(None);
    assert_eq!(
        get(plain.addr, "/api/v1/status").await.json()["rack"],
        json!(null)
    );
    assert_eq!(
        get(plain.addr, "/api/v1/rack").await.json(),
        json!({"slots": []})
    );
}

/// `U2\G11` written over HTTP is what the program copies to D0; the names
/// are keys as given (`U2\G11`, its backslash URL-encoded in a query).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn buffer_memory_is_read_and_written_by_name() {
    let s = start_rack();
    let r = send(
        s.addr,
        "POST",
        "/api/v1/devices",
        Some(r#"{"U2\\G11": 4321, "U4\\G4095": -1}"#),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    let mut seen = json!(null);
    for _ in 0..200 {
        let j = get(
            s.addr,
            "/api/v1/devices?names=U2%5CG11,D0,U4%5CG4095,U2%5CG13",
        )
        .await
        .json();
        seen = j["devices"].clone();
        if seen["D0"] == 4321 {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(10)).await;
    }
    assert_eq!(seen["U2\\G11"], 4321, "{seen}");
    assert_eq!(seen["D0"], 4321, "{seen}");
    assert_eq!(seen["U4\\G4095"], -1, "{seen}");
    assert!(
        seen["U2\\G13"].as_i64().unwrap_or(0) > 0,
        "the program counts scans there: {seen}"
    );
    // A unit with no module, an address past the module: 400 naming them.
    for name in ["U3%5CG0", "U2%5CG100"] {
        let r = get(s.addr, &format!("/api/v1/devices?names={name}")).await;
        assert_eq!(r.status, 400, "{name}: {}", r.body);
        assert!(r.body.contains("U") && r.body.contains("G"), "{}", r.body);
    }
    let r = send(s.addr, "POST", "/api/v1/devices", Some(r#"{"U3\\G0": 1}"#)).await;
    assert_eq!(r.status, 400, "{}", r.body);
}

/// The ladder shows `MOV U2\G11 D0` with U2\G11 among its live names, and
/// the event stream carries its value.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_ladder_shows_buffer_memory_live() {
    let s = start_rack();
    let r = get(s.addr, "/").await;
    assert_eq!(r.status, 200);
    let names = page_names(&r.body);
    for n in [
        "U2\\G11", "D0", "D1", "U2\\G12", "U2\\G13", "U2\\G10", "U4\\G0",
    ] {
        assert!(names.split(',').any(|x| x == n), "{n} in {names}");
    }
    assert!(r.body.contains("U2\\G11"), "the operand is drawn");
    send(
        s.addr,
        "POST",
        "/api/v1/devices",
        Some(r#"{"U2\\G11": 77}"#),
    )
    .await;
    let (_, ev) = sse(s.addr, "/api/v1/events?names=U2%5CG11,D0,U2%5CG13", 3).await;
    let last = &ev.last().unwrap().1["devices"];
    assert_eq!(last["U2\\G11"], 77, "{last}");
    assert_eq!(last["D0"], 77, "{last}");
    assert!(last["U2\\G13"].is_i64(), "{last}");
    // The device monitor page lists buffer memory by name.
    let r = get(s.addr, "/devices?names=U2%5CG11,U4%5CG0").await;
    assert_eq!(r.status, 200, "{}", r.body);
    assert!(r.body.contains(r#"data-v="U2\G11""#), "{}", r.body);
}

/// The device monitor's batch view counts buffer-memory addresses from a
/// `U<n>\G<addr>` start.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_device_monitor_counts_buffer_memory() {
    let s = start_rack();
    let r = get(s.addr, "/devices?start=U2%5CG10&count=3").await;
    assert_eq!(r.status, 200, "{}", r.body);
    for n in ["U2\\G10", "U2\\G11", "U2\\G12"] {
        assert!(
            r.body.contains(&format!(r#"data-v="{n}""#)),
            "{n}: {}",
            r.body
        );
    }
    let r = get(s.addr, "/devices?start=U2%5CG10&count=2&fmt=float").await;
    assert!(r.body.contains(r#"data-v="U2\G12:f32""#), "{}", r.body);
}

/// A program that names buffer memory of a unit with no module (it would
/// stop with SP.UNIT ERROR 2110 when that instruction runs): its ladder
/// draws the operand but does not watch it, so the page's other names stay
/// live instead of the whole event list being refused.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_unit_without_a_module_does_not_silence_the_ladder() {
    let rack = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/rack");
    let dir = std::env::temp_dir().join(format!("softplc-rack-ladder-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(rack.join("plc.toml"), dir.join("plc.toml")).unwrap();
    std::fs::write(
        dir.join("main.il"),
        "LD X0\nMOV U9\\G0 D5\nLD SM400\nMOV U2\\G11 D0\nEND\n",
    )
    .unwrap();
    let cpu = softplc_core::project::load_project(&dir)
        .and_then(|p| p.build_cpu(Box::new(MonotonicClock::default())))
        .unwrap_or_else(|d| panic!("{:?}", d.0));
    let _ = std::fs::remove_dir_all(&dir);
    let cfg = HttpConfig {
        token: Some(TOKEN.into()),
        model: "Q06HCPU".into(),
        ladder: softplc_http::ladder::load_programs(&cpu),
        limits: Default::default(),
        online: None,
    };
    let s = start_cpu(cpu, cfg);
    let r = get(s.addr, "/").await;
    assert_eq!(r.status, 200);
    assert!(r.body.contains("U9\\G0"), "the operand is drawn");
    let names = page_names(&r.body);
    assert!(!names.split(',').any(|x| x == "U9\\G0"), "{names}");
    for n in ["U2\\G11", "D0", "D5", "X0"] {
        assert!(names.split(',').any(|x| x == n), "{n} in {names}");
    }
    let query = names.replace('\\', "%5C");
    let (_, ev) = sse(s.addr, &format!("/api/v1/events?names={query}"), 1).await;
    assert!(ev.last().unwrap().1["devices"]["U2\\G11"].is_i64());
}
