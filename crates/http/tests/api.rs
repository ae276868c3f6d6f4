//! Every route of contract §3.1 against a real server on 127.0.0.1:0,
//! including the 401, 403 and 400 cases.

mod common;

use std::time::Duration;

use common::*;
use serde_json::json;

async fn wait_for(addr: std::net::SocketAddr, name: &str, want: serde_json::Value) {
    for _ in 0..200 {
        let r = get(addr, &format!("/api/v1/devices?names={name}")).await;
        if r.json()["devices"][name] == want {
            return;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    panic!("{name} never became {want}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn status_reports_state_scan_times_and_model() {
    let s = start(None);
    let r = get(s.addr, "/api/v1/status").await;
    assert_eq!(r.status, 200);
    assert!(r.headers.to_ascii_lowercase().contains("application/json"));
    let j = r.json();
    assert_eq!(j["state"], "RUN");
    assert_eq!(j["model"], "Q06HCPU");
    assert_eq!(j["error"], serde_json::Value::Null);
    assert!(j["scan"].as_u64().unwrap() >= 1);
    let t = &j["scan_time_us"];
    assert!(t["min"].as_u64().unwrap() <= t["max"].as_u64().unwrap());
    assert!(t["last"].is_u64());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn devices_are_read_from_one_end() {
    let s = start(None);
    let r = get(s.addr, "/api/v1/devices?names=D100,Y0,D10:f32,SD520").await;
    assert_eq!(r.status, 200);
    let j = r.json();
    let scan = j["scan"].as_u64().unwrap();
    // D100 counts every executed scan: the same END as `scan`.
    assert_eq!(j["devices"]["D100"].as_u64().unwrap(), scan);
    assert_eq!(j["devices"]["Y0"], false);
    assert_eq!(j["devices"]["D10:f32"], 0.0);
    // Order of the names is kept.
    let keys: Vec<_> = j["devices"].as_object().unwrap().keys().cloned().collect();
    assert_eq!(keys, ["D100", "Y0", "D10:f32", "SD520"]);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unknown_names_are_400_naming_them() {
    let s = start(None);
    for q in [
        "names=D0,QX9",
        "names=D0:q16",
        "names=",
        "x=1",
        "names=D999999",
    ] {
        let r = get(s.addr, &format!("/api/v1/devices?{q}")).await;
        assert_eq!(r.status, 400, "{q}: {}", r.body);
        let e = r.json()["error"].as_str().unwrap().to_string();
        assert!(!e.is_empty());
        if q.contains("QX9") {
            assert!(e.contains("QX9"), "{e}");
        }
        if q.contains("D999999") {
            assert!(e.contains("D999999"), "{e}");
        }
    }
    let r = get(s.addr, "/api/v1/events?names=D0,NOPE1").await;
    assert_eq!(r.status, 400);
    assert!(r.json()["error"].as_str().unwrap().contains("NOPE1"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn without_a_token_every_write_is_403() {
    let s = start(None);
    let auth = bearer("anything");
    for (m, p, b) in [
        ("POST", "/api/v1/devices", r#"{"D0": 5}"#),
        ("POST", "/api/v1/force", r#"{"X0": true}"#),
        ("DELETE", "/api/v1/force", r#"["X0"]"#),
        ("POST", "/api/v1/cpu/run", ""),
        ("POST", "/api/v1/cpu/stop", ""),
        ("POST", "/api/v1/cpu/pause", ""),
        ("POST", "/api/v1/cpu/reset", ""),
        ("POST", "/api/v1/cpu/step?scans=1", ""),
        ("POST", "/api/v1/breakpoint", r#"{"when": "M0"}"#),
        ("DELETE", "/api/v1/breakpoint", ""),
    ] {
        for h in [vec![], vec![auth.as_str()]] {
            let r = request(s.addr, m, p, &h, Some(b)).await;
            assert_eq!(r.status, 403, "{m} {p}: {}", r.body);
            assert!(r.json()["error"].as_str().unwrap().contains("read-only"));
        }
    }
    let r = get(s.addr, "/api/v1/status").await;
    assert_eq!(r.json()["state"], "RUN", "nothing stopped the CPU");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_missing_or_wrong_token_is_401_and_cookies_never_authorise() {
    let s = start(Some(TOKEN));
    let wrong = bearer("not-the-token");
    let cookie = format!("Cookie: token={TOKEN}; Authorization=Bearer {TOKEN}");
    let basic = "Authorization: Basic czNjcmV0LXRva2Vu".to_string();
    for (m, p, b) in [
        ("POST", "/api/v1/devices", r#"{"D0": 5}"#),
        ("POST", "/api/v1/force", r#"{"X0": true}"#),
        ("DELETE", "/api/v1/force", r#"["X0"]"#),
        ("POST", "/api/v1/cpu/run", ""),
        ("POST", "/api/v1/cpu/stop", ""),
        ("POST", "/api/v1/cpu/pause", ""),
        ("POST", "/api/v1/cpu/reset", ""),
        ("POST", "/api/v1/cpu/step", ""),
        ("POST", "/api/v1/cpu/step?scans=2", ""),
        ("POST", "/api/v1/breakpoint", r#"{"when": "M0"}"#),
        ("DELETE", "/api/v1/breakpoint", ""),
    ] {
        for h in [
            vec![],
            vec![wrong.as_str()],
            vec![cookie.as_str()],
            vec![basic.as_str()],
        ] {
            let r = request(s.addr, m, p, &h, Some(b)).await;
            assert_eq!(r.status, 401, "{m} {p} {h:?}: {}", r.body);
            assert!(
                r.headers.contains("www-authenticate") || r.headers.contains("WWW-Authenticate")
            );
            assert!(r.json()["error"].is_string());
        }
    }
    let r = get(s.addr, "/api/v1/devices?names=D0").await;
    assert_eq!(r.json()["devices"]["D0"], 0, "nothing was written");
    assert_eq!(get(s.addr, "/api/v1/status").await.json()["state"], "RUN");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn writes_land_at_the_next_end() {
    let s = start(Some(TOKEN));
    let r = send(
        s.addr,
        "POST",
        "/api/v1/devices",
        Some(r#"{"D0": 5, "M0": true, "D10:f32": 2.5, "D20": "H1F", "X0": 1}"#),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    assert!(r.json()["scan"].is_u64());
    let j = get(s.addr, "/api/v1/devices?names=D0,M0,D10:f32,D20,X0")
        .await
        .json();
    assert_eq!(
        j["devices"],
        json!({"D0": 5, "M0": true, "D10:f32": 2.5, "D20": 31, "X0": true})
    );
    // The program sees them: M0 → Y1, X0 → Y0 (X kept in the input image).
    wait_for(s.addr, "Y1", json!(true)).await;
    wait_for(s.addr, "Y0", json!(true)).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_rejected_write_writes_nothing() {
    let s = start(Some(TOKEN));
    for body in [
        r#"{"D0": 7, "QQ1": 5}"#,
        r#"{"D0": 7, "M0": 2}"#,
        r#"{"D0": 7, "D1": 70000}"#,
        r#"{"D0": 7, "D99999": 1}"#,
        r#"{"D0": 7, "D2": "x"}"#,
        r#"{"D0": 7, "D3": true}"#,
        r#"{"D0": 7, "D4": null}"#,
        r#"{"D0": 7, "D10:f32": "nan"}"#,
        r#"{"D0": 7,"#,
        r#"[1, 2]"#,
        "not json",
    ] {
        let r = send(s.addr, "POST", "/api/v1/devices", Some(body)).await;
        assert_eq!(r.status, 400, "{body}: {}", r.body);
        assert!(r.json()["error"].is_string(), "{body}");
    }
    let r = send(
        s.addr,
        "POST",
        "/api/v1/devices",
        Some(r#"{"D0": 7, "QQ1": 5}"#),
    )
    .await;
    assert!(r.json()["error"].as_str().unwrap().contains("QQ1"));
    let r = send(
        s.addr,
        "POST",
        "/api/v1/devices",
        Some(r#"{"D0": 7, "D1": 70000}"#),
    )
    .await;
    let e = r.json()["error"].as_str().unwrap().to_string();
    assert!(e.contains("D1") && e.contains("70000"), "{e}");
    let j = get(s.addr, "/api/v1/devices?names=D0,D1").await.json();
    assert_eq!(j["devices"], json!({"D0": 0, "D1": 0}));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn oversized_bodies_are_refused() {
    let s = start(Some(TOKEN));
    let big = format!("{{\"D0\": 1, \"pad\": \"{}\"}}", "x".repeat(200_000));
    let r = send(s.addr, "POST", "/api/v1/devices", Some(&big)).await;
    assert_eq!(r.status, 413, "{}", r.body);
    assert!(r.json()["error"].as_str().unwrap().contains("body"));
    let j = get(s.addr, "/api/v1/devices?names=D0").await.json();
    assert_eq!(j["devices"]["D0"], 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn forcing_lists_wins_and_releases() {
    let s = start(Some(TOKEN));
    let r = send(
        s.addr,
        "POST",
        "/api/v1/force",
        Some(r#"{"X0": true, "Y1": true}"#),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    let f = get(s.addr, "/api/v1/force").await.json();
    assert_eq!(f, json!({"forced": {"X0": true, "Y1": true}}));
    wait_for(s.addr, "Y0", json!(true)).await;
    // M0 is OFF, so the program writes Y1 OFF every scan: the force wins.
    tokio::time::sleep(Duration::from_millis(30)).await;
    assert_eq!(
        get(s.addr, "/api/v1/devices?names=Y1").await.json()["devices"]["Y1"],
        true
    );
    // A write to a forced input is kept for the release.
    send(s.addr, "POST", "/api/v1/devices", Some(r#"{"X0": false}"#)).await;
    assert_eq!(
        get(s.addr, "/api/v1/devices?names=X0").await.json()["devices"]["X0"],
        true
    );
    let r = send(s.addr, "DELETE", "/api/v1/force", Some(r#"["X0", "Y1"]"#)).await;
    assert_eq!(r.status, 200, "{}", r.body);
    assert_eq!(r.json(), json!({"forced": {}}));
    wait_for(s.addr, "Y0", json!(false)).await;
    wait_for(s.addr, "Y1", json!(false)).await;
    // Status lists the forces too.
    assert_eq!(
        get(s.addr, "/api/v1/status").await.json()["forced"],
        json!({})
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_forces_are_400_and_force_nothing() {
    let s = start(Some(TOKEN));
    for body in [
        r#"{"X0": true, "M0": true}"#,
        r#"{"X0": true, "Y0": 1}"#,
        r#"{"X0": true, "X2000": true}"#,
        r#"{"X0": true, "K4X0": true}"#,
        r#"{"X0": true, "Q": true}"#,
        r#"["X0"]"#,
    ] {
        let r = send(s.addr, "POST", "/api/v1/force", Some(body)).await;
        assert_eq!(r.status, 400, "{body}: {}", r.body);
        assert!(r.json()["error"].is_string());
    }
    let r = send(
        s.addr,
        "POST",
        "/api/v1/force",
        Some(r#"{"X0": true, "M0": true}"#),
    )
    .await;
    assert!(r.json()["error"].as_str().unwrap().contains("M0"));
    for body in [r#"{"X0": true}"#, r#"["M0"]"#, "["] {
        let r = send(s.addr, "DELETE", "/api/v1/force", Some(body)).await;
        assert_eq!(r.status, 400, "{body}");
    }
    assert_eq!(
        get(s.addr, "/api/v1/force").await.json(),
        json!({"forced": {}})
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn remote_operations_and_the_scan_counter() {
    let s = start_remote_reset(Some(TOKEN));
    let r = send(s.addr, "POST", "/api/v1/cpu/stop", None).await;
    assert_eq!(r.json(), json!({"state": "STOP"}));
    let a = get(s.addr, "/api/v1/status").await.json()["scan"]
        .as_u64()
        .unwrap();
    tokio::time::sleep(Duration::from_millis(40)).await;
    let b = get(s.addr, "/api/v1/status").await.json()["scan"]
        .as_u64()
        .unwrap();
    assert_eq!(a, b, "scan stands still in STOP");
    // Writes are served in STOP too.
    assert_eq!(
        send(s.addr, "POST", "/api/v1/devices", Some(r#"{"D5": 9}"#))
            .await
            .status,
        200
    );
    // PAUSE only from RUN: 409 with an error.
    let r = send(s.addr, "POST", "/api/v1/cpu/pause", None).await;
    assert_eq!(r.status, 409);
    assert!(r.json()["error"].is_string());
    let r = send(s.addr, "POST", "/api/v1/cpu/reset", None).await;
    assert_eq!(r.json(), json!({"state": "RUN"}), "{}", r.body);
    let r = send(s.addr, "POST", "/api/v1/cpu/pause", None).await;
    assert_eq!(r.json(), json!({"state": "PAUSE"}));
    let a = get(s.addr, "/api/v1/status").await.json();
    tokio::time::sleep(Duration::from_millis(40)).await;
    let b = get(s.addr, "/api/v1/status").await.json();
    assert_eq!(a["scan"], b["scan"], "scan stands still in PAUSE");
    assert_eq!(b["state"], "PAUSE");
    // RESET is refused outside STOP.
    assert_eq!(
        send(s.addr, "POST", "/api/v1/cpu/reset", None).await.status,
        409
    );
    let r = send(s.addr, "POST", "/api/v1/cpu/run", None).await;
    assert_eq!(r.json(), json!({"state": "RUN"}));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn step_adds_exactly_n_scans_and_pauses_again() {
    let s = start(Some(TOKEN));
    // Step is only from PAUSE.
    let r = send(s.addr, "POST", "/api/v1/cpu/step?scans=1", None).await;
    assert_eq!(r.status, 409, "{}", r.body);
    send(s.addr, "POST", "/api/v1/cpu/pause", None).await;
    let before = get(s.addr, "/api/v1/devices?names=D100").await.json();
    for n in [1u64, 5, 3] {
        let r = send(s.addr, "POST", &format!("/api/v1/cpu/step?scans={n}"), None).await;
        assert_eq!(r.status, 200, "{}", r.body);
        assert_eq!(r.json()["state"], "PAUSE");
    }
    let after = get(s.addr, "/api/v1/devices?names=D100").await.json();
    assert_eq!(
        after["scan"].as_u64().unwrap(),
        before["scan"].as_u64().unwrap() + 9
    );
    assert_eq!(
        after["devices"]["D100"].as_u64().unwrap(),
        before["devices"]["D100"].as_u64().unwrap() + 9
    );
    // Without scans= it is one scan.
    let r = send(s.addr, "POST", "/api/v1/cpu/step", None).await;
    assert_eq!(
        r.json()["scan"].as_u64().unwrap(),
        after["scan"].as_u64().unwrap() + 1
    );
    for q in ["scans=0", "scans=-1", "scans=x", "scans=10001"] {
        let r = send(s.addr, "POST", &format!("/api/v1/cpu/step?{q}"), None).await;
        assert_eq!(r.status, 400, "{q}");
        assert!(r.json()["error"].as_str().unwrap().contains("scans"));
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_breakpoint_pauses_at_the_end_where_it_becomes_true() {
    let s = start(Some(TOKEN));
    let now = get(s.addr, "/api/v1/devices?names=D100").await.json()["devices"]["D100"]
        .as_u64()
        .unwrap();
    let at = now + 20;
    let r = send(
        s.addr,
        "POST",
        "/api/v1/breakpoint",
        Some(&format!(r#"{{"when": "D100 >= {at}"}}"#)),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    for _ in 0..200 {
        if get(s.addr, "/api/v1/status").await.json()["state"] == "PAUSE" {
            break;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let j = get(s.addr, "/api/v1/devices?names=D100").await.json();
    assert_eq!(
        j["devices"]["D100"].as_u64().unwrap(),
        at,
        "paused at that END"
    );
    let b = get(s.addr, "/api/v1/breakpoint").await.json();
    assert_eq!(b["breakpoint"]["when"], format!("D100 >= {at}"));
    assert_eq!(b["breakpoint"]["hit"], j["scan"]);
    // Still true: stepping does not pause again on it (rising edge only).
    let r = send(s.addr, "POST", "/api/v1/cpu/step?scans=2", None).await;
    assert_eq!(r.json()["state"], "PAUSE");
    for body in [
        r#"{"when": "D0"}"#,
        r#"{"when": "ZZ9 > 1"}"#,
        r#"{"x": 1}"#,
        "{",
    ] {
        let r = send(s.addr, "POST", "/api/v1/breakpoint", Some(body)).await;
        assert_eq!(r.status, 400, "{body}");
    }
    let r = send(s.addr, "DELETE", "/api/v1/breakpoint", None).await;
    assert_eq!(r.json(), json!({"breakpoint": null}));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn events_stream_only_the_requested_names_2_to_10_per_second() {
    let s = start(Some(TOKEN));
    let (head, ev) = sse(s.addr, "/api/v1/events?names=D100,Y0", 6).await;
    assert!(
        head.to_ascii_lowercase().contains("text/event-stream"),
        "{head}"
    );
    let mut last = 0;
    for (_, e) in &ev {
        let keys: Vec<_> = e["devices"].as_object().unwrap().keys().cloned().collect();
        assert_eq!(keys, ["D100", "Y0"]);
        let scan = e["scan"].as_u64().unwrap();
        assert_eq!(e["devices"]["D100"].as_u64().unwrap(), scan, "one END");
        assert!(scan > last);
        last = scan;
    }
    // 6 events: 5 intervals of 100 ms or more, well under 2.5 s.
    let span = ev[5].0 - ev[0].0;
    assert!(span >= Duration::from_millis(450), "at most 10/s: {span:?}");
    assert!(
        span <= Duration::from_millis(2500),
        "at least 2/s: {span:?}"
    );
    // The stream closed: its names are no longer read at END.
    let mut watched = 1;
    for _ in 0..100 {
        watched = get(s.addr, "/api/v1/status").await.json()["watched"]
            .as_u64()
            .unwrap();
        if watched == 0 {
            break;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    assert_eq!(watched, 0, "unsubscribed when the client went away");
    // A write shows in the stream.
    send(s.addr, "POST", "/api/v1/force", Some(r#"{"X0": true}"#)).await;
    let (_, ev) = sse(s.addr, "/api/v1/events?names=Y0", 2).await;
    assert_eq!(ev[1].1["devices"]["Y0"], true);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pages_and_unknown_routes() {
    let s = start(None);
    let r = get(s.addr, "/").await;
    assert_eq!(r.status, 200);
    assert!(r.headers.to_ascii_lowercase().contains("text/html"));
    for p in [
        "/overview",
        "/devices",
        "/devices?start=X0&count=16",
        "/trend?names=D100",
        "/loops",
        "/monitor.js",
        "/monitor.css",
    ] {
        assert_eq!(get(s.addr, p).await.status, 200, "{p}");
    }
    let r = get(s.addr, "/api/v1/nope").await;
    assert_eq!(r.status, 404);
    assert!(r.json()["error"].is_string());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_page_requests_are_400() {
    let s = start(None);
    for p in [
        "/devices?start=zz",
        "/devices?names=D0,QQ",
        "/trend?names=QQ",
    ] {
        let r = get(s.addr, p).await;
        assert_eq!(r.status, 400, "{p}");
        assert!(
            r.body.contains("QQ") || r.body.contains("zz"),
            "{p}: the page names it"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn ladder_and_loop_pages_carry_element_ids_and_names() {
    let s = start_program(
        "LD X0\nOUT Y0\nLD SM400\nMOV K2 D500\nPIDINIT D500\nPIDCONT D600\nEND\n",
        None,
    );
    let r = get(s.addr, "/").await;
    assert!(r.body.contains(r#"id="e0-0" data-dev="X0""#), "{}", r.body);
    assert!(
        r.body.contains(r#"data-names="X0,Y0,SM400,D500,D600""#),
        "{}",
        r.body
    );
    let r = get(s.addr, "/loops").await;
    assert_eq!(r.status, 200);
    // Two loops (D500 = 2): loop 2's SV is D600 + 10 + 18.
    assert!(r.body.contains("PIDCONT D600 loop 2"), "{}", r.body);
    assert!(r.body.contains(r#"data-v="D628""#));
    assert!(r.body.contains(r#"data-v="D512""#), "loop 2's action word");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_33rd_force_is_refused_and_nothing_of_the_request_is_forced() {
    // A Q06HCPU registers 32 forces (QCPU manual, forced ON/OFF of I/O).
    let s = start(Some(TOKEN));
    let first: serde_json::Map<String, serde_json::Value> =
        (0..32).map(|n| (format!("Y{n:X}"), json!(true))).collect();
    let r = send(
        s.addr,
        "POST",
        "/api/v1/force",
        Some(&serde_json::Value::Object(first).to_string()),
    )
    .await;
    assert_eq!(r.status, 200, "{}", r.body);
    let r = send(
        s.addr,
        "POST",
        "/api/v1/force",
        Some(r#"{"Y0": false, "X0": true}"#),
    )
    .await;
    assert_eq!(r.status, 400, "{}", r.body);
    assert_eq!(
        r.json()["error"],
        "at most 32 devices can be forced on a Q06HCPU"
    );
    let f = get(s.addr, "/api/v1/force").await.json();
    assert_eq!(f["forced"].as_object().unwrap().len(), 32);
    assert_eq!(f["forced"]["Y0"], true);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn remote_reset_is_409_unless_the_parameter_allows_it() {
    // 004 §7.6.3: remote RESET is not allowed by default.
    let s = start(Some(TOKEN));
    send(s.addr, "POST", "/api/v1/cpu/stop", None).await;
    let r = send(s.addr, "POST", "/api/v1/cpu/reset", None).await;
    assert_eq!(r.status, 409);
    let why = r.json()["error"].as_str().unwrap().to_string();
    assert!(why.contains("remote_reset"), "{why}");
    assert_eq!(get(s.addr, "/api/v1/status").await.json()["state"], "STOP");
}
