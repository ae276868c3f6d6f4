//! The JSON API of contract §3.1 under `/api/v1`, and the routes of the pages.
//!
//! Every answer is computed by an `at_end` job on the engine thread, so all
//! values of one response come from the same END and writes land between two
//! scans. Writes, forcing, `cpu/*` and breakpoints need `Authorization: Bearer
//! TOKEN` (cookies are never read); without a configured token they are 403,
//! with one a missing or wrong token is 401. Every 400 is `{"error": "..."}`
//! naming the bad name or value, and nothing of a rejected request is written.
//!
//! A multi-CPU system (contract §6): device names take `CPUn/` prefixes
//! (none: CPU 1), `status` adds `"cpus"`, and `cpu/*`, `rack` and the
//! ladder pages take `?cpu=N` (1-based, default 1).

// Handlers answer with a `Response` either way; the error side is the reply.
#![allow(clippy::result_large_err)]

use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;

use axum::body::Bytes;
use axum::extract::{DefaultBodyLimit, Query, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde_json::{json, Map, Value as Json_};
use softplc_core::access::Value;
use softplc_core::names::Names;
use softplc_serve::ServeState;

use crate::monitor::{self, Breakpoint, Monitor};
use crate::values::{self, cpu_prefix, io_dev, io_name, to_json, Dev};
use crate::App;

type Shared = State<Arc<App>>;
type Q = Query<std::collections::HashMap<String, String>>;

/// Most scans one step request executes.
pub const MAX_STEP: u64 = 10_000;

/// The router: pages and `/api/v1`.
pub fn router(app: Arc<App>) -> Router {
    Router::new()
        .route("/", get(crate::pages::ladder))
        .route("/ladder.txt", get(crate::pages::ladder_text))
        .route("/overview", get(crate::pages::overview))
        .route("/devices", get(crate::pages::devices))
        .route("/trend", get(crate::pages::trend))
        .route("/loops", get(crate::loops::page))
        .route("/monitor.js", get(crate::pages::script))
        .route("/monitor.css", get(crate::pages::style))
        .route("/api/v1/status", get(status))
        .route("/api/v1/devices", get(read_devices).post(write_devices))
        .route(
            "/api/v1/force",
            get(list_forces).post(force).delete(release),
        )
        .route("/api/v1/cpu/run", post(cpu_run))
        .route("/api/v1/cpu/stop", post(cpu_stop))
        .route("/api/v1/cpu/pause", post(cpu_pause))
        .route("/api/v1/cpu/reset", post(cpu_reset))
        .route("/api/v1/cpu/step", post(cpu_step))
        .route(
            "/api/v1/breakpoint",
            get(get_breakpoint)
                .post(set_breakpoint)
                .delete(clear_breakpoint),
        )
        .route("/api/v1/events", get(events))
        .route("/api/v1/rack", get(crate::rack::rack))
        .route("/api/v1/timing", get(crate::timing::get))
        .route("/api/v1/timing/reset", post(crate::timing::reset))
        .route("/api/v1/sim/advance", post(crate::sim::advance))
        .route(
            "/api/v1/program",
            axum::routing::put(crate::program::put)
                .layer(DefaultBodyLimit::max(crate::program::PROGRAM_BODY_LIMIT)),
        )
        .route(
            "/api/v1/snapshot",
            get(crate::snapshot::get)
                .put(crate::snapshot::put)
                .layer(DefaultBodyLimit::max(crate::snapshot::SNAPSHOT_LIMIT)),
        )
        .fallback(not_found)
        .layer(DefaultBodyLimit::max(crate::BODY_LIMIT))
        .with_state(app)
}

/// `{"error": msg}` with `code`.
pub fn error(code: StatusCode, msg: impl Into<String>) -> Response {
    (code, Json(json!({ "error": msg.into() }))).into_response()
}

pub(crate) fn bad(msg: impl Into<String>) -> Response {
    error(StatusCode::BAD_REQUEST, msg)
}

fn busy() -> Response {
    error(
        StatusCode::SERVICE_UNAVAILABLE,
        softplc_serve::Busy.to_string(),
    )
}

async fn not_found() -> Response {
    error(StatusCode::NOT_FOUND, "no such page or API route")
}

/// Longest a request waits for an END (a scan stuck in an endless loop).
pub const END_WAIT: Duration = Duration::from_secs(10);

/// Runs `f` at the next END; a full queue, or no END within [`END_WAIT`], is 503.
pub(crate) async fn at_end<R: Send + 'static>(
    app: &App,
    f: impl FnOnce(&mut ServeState) -> R + Send + 'static,
) -> Result<R, Response> {
    match tokio::time::timeout(END_WAIT, app.engine.at_end(f)).await {
        Ok(r) => r.map_err(|_| busy()),
        Err(_) => Err(error(
            StatusCode::SERVICE_UNAVAILABLE,
            "the CPU did not reach END in time (a scan that does not end?)",
        )),
    }
}

/// Contract §3.1: no token configured → 403; a missing or wrong bearer → 401.
pub(crate) fn authorize(app: &App, headers: &HeaderMap) -> Result<(), Response> {
    let Some(token) = &app.cfg.token else {
        return Err(error(
            StatusCode::FORBIDDEN,
            "the web monitor is read-only: start serve with --http-token (or [http] token) to allow writes",
        ));
    };
    let given = headers
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(str::trim);
    match given {
        Some(g) if equal(g.as_bytes(), token.as_bytes()) => Ok(()),
        _ => {
            let mut r = error(
                StatusCode::UNAUTHORIZED,
                "a valid `Authorization: Bearer TOKEN` header is required",
            );
            r.headers_mut().insert(
                header::WWW_AUTHENTICATE,
                header::HeaderValue::from_static("Bearer"),
            );
            Err(r)
        }
    }
}

/// Compares in time independent of where the first difference is.
fn equal(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// A request body, or why it was refused (413 over [`crate::BODY_LIMIT`]).
pub(crate) type Body = Result<Bytes, axum::extract::rejection::BytesRejection>;

/// Parses a JSON body; malformed JSON is 400, an oversized body 413, both
/// with `{"error": ...}`.
pub(crate) fn body<T: serde::de::DeserializeOwned>(
    bytes: &Body,
    what: &str,
) -> Result<T, Response> {
    let bytes = bytes.as_ref().map_err(|r| {
        error(
            r.status(),
            format!("request body refused: {}", r.body_text()),
        )
    })?;
    serde_json::from_slice(bytes).map_err(|e| bad(format!("malformed JSON body ({what}): {e}")))
}

/// The device names of CPU `cpu` (0-based).
fn names(s: &ServeState, cpu: usize) -> Names {
    Names::plain(s.cpu_at(cpu).profile())
}

/// The CPU a request's `?cpu=N` (1-based) names: 0-based, CPU 1 without
/// one; 400 for a CPU the server does not run.
pub(crate) fn cpu_param(
    app: &App,
    q: &std::collections::HashMap<String, String>,
) -> Result<usize, Response> {
    let Some(v) = q.get("cpu") else {
        return Ok(0);
    };
    let n = app.names.len();
    match v.trim().parse::<usize>() {
        Ok(k) if (1..=n).contains(&k) => Ok(k - 1),
        _ => Err(bad(format!(
            "`cpu={v}`: there is no such CPU (the server runs CPU 1{})",
            if n > 1 {
                format!("-{n}")
            } else {
                String::new()
            }
        ))),
    }
}

/// CPU `cpu`'s error as in contract §2 (the APLC has no step numbers).
fn error_json(s: &ServeState, cpu: usize) -> Json_ {
    let c = s.cpu_at(cpu);
    let steps = c.profile().step_numbers;
    c.error().map_or(Json_::Null, |e| {
        json!({
            "code": e.code.0,
            "message": c.error_message(e.code),
            "step": if steps { e.step } else { None },
            "file": e.file,
            "line": e.line,
        })
    })
}

/// The forced points of every CPU, named with their CPU prefixes.
fn forced_json(s: &ServeState) -> Json_ {
    let mut m = Map::new();
    for i in 0..s.cpu_count() {
        let d = names(s, i);
        let p = cpu_prefix(i);
        for (k, n, on) in s.cpu_at(i).forced() {
            m.insert(format!("{p}{}", io_name(k, n, &d)), Json_::Bool(on));
        }
    }
    Json_::Object(m)
}

fn breakpoint_json(s: &mut ServeState) -> Json_ {
    s.ext::<Monitor>()
        .breakpoint
        .as_ref()
        .map_or(Json_::Null, |b| json!({ "when": b.text(), "hit": b.hit }))
}

/// Each CPU of a multi-CPU system: number, model, state, error, scans and
/// scan times.
fn cpus_json(s: &ServeState) -> Json_ {
    (0..s.cpu_count())
        .map(|i| {
            let c = s.cpu_at(i);
            let t = s.stats.cpus.get(i).cloned().unwrap_or_default();
            json!({
                "cpu": i + 1,
                "model": c.profile().model,
                "state": c.state().as_str(),
                "error": error_json(s, i),
                "scans": c.scans(),
                "time_ms": c.since_power_on_us() as f64 / 1000.0,
                "scan_time_us": {"last": t.exec_us, "min": t.exec_min_us, "max": t.exec_max_us},
                "overruns": t.overruns,
            })
        })
        .collect()
}

async fn status(State(app): Shared) -> Response {
    let model = app.cfg.model.clone();
    let r = at_end(&app, move |s| {
        let st = &s.stats;
        let cpu = s.cpu();
        let history: Vec<Json_> = cpu
            .history()
            .map(|h| {
                json!({"code": h.code.0, "message": cpu.error_message(h.code), "time": h.time, "detail": h.detail})
            })
            .collect();
        let mut j = json!({
            "state": cpu.state().as_str(),
            "scan": cpu.scans(),
            "time_ms": cpu.since_power_on_us() as f64 / 1000.0,
            "scan_time_us": {"last": st.exec_us, "min": st.exec_min_us, "max": st.exec_max_us},
            "error": error_json(s, 0),
            "model": model,
            "history": history,
            "forced": forced_json(s),
            "breakpoint": breakpoint_json(s),
            "overruns": s.stats.overruns,
            "watched": s.ext::<Monitor>().watched(),
            "rack": crate::rack::summary(s.cpu().rack()),
        });
        if s.cpu_count() > 1 {
            j["cpus"] = cpus_json(s);
        }
        j
    })
    .await;
    match r {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}

/// Reads `specs` now: `{"scan": N, "devices": {...}}`, or the first error.
fn read_all(s: &mut ServeState, specs: &[Dev]) -> Result<Json_, String> {
    let mut m = Map::new();
    for d in specs {
        let v = d.read(s)?;
        m.insert(d.text().to_string(), to_json(&v));
    }
    Ok(json!({"scan": s.cpu().scans(), "devices": m}))
}

async fn read_devices(State(app): Shared, Query(q): Q) -> Response {
    let specs = match values::dev_list(q.get("names").map(String::as_str), &app.names) {
        Ok(s) => s,
        Err(e) => return bad(e),
    };
    match at_end(&app, move |s| read_all(s, &specs)).await {
        Ok(Ok(j)) => Json(j).into_response(),
        Ok(Err(e)) => bad(e),
        Err(e) => e,
    }
}

/// Writes every `(device, value)` or none: on a failure the ones written are
/// put back before the END ends, so no scan sees a part.
fn write_all(s: &mut ServeState, writes: &[(Dev, Value)]) -> Result<u64, String> {
    let mut done: Vec<(&Dev, Value)> = Vec::with_capacity(writes.len());
    let mut fail = None;
    for (d, v) in writes {
        let old = match d.read(s) {
            Ok(o) => o,
            Err(e) => {
                fail = Some(e);
                break;
            }
        };
        if let Err(e) = d.write_value(s, v) {
            fail = Some(e);
            break;
        }
        done.push((d, old));
    }
    if let Some(e) = fail {
        for (d, old) in done.into_iter().rev() {
            let _ = d.write_value(s, &old);
        }
        return Err(e);
    }
    for (d, _) in writes {
        s.mark_wrote(d.cpu);
    }
    Ok(s.cpu().scans())
}

async fn write_devices(State(app): Shared, headers: HeaderMap, bytes: Body) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let obj: Map<String, Json_> = match body(&bytes, "expected an object {\"D0\": 5}") {
        Ok(o) => o,
        Err(r) => return r,
    };
    if obj.len() > values::MAX_NAMES {
        return bad(format!(
            "at most {} devices in one write",
            values::MAX_NAMES
        ));
    }
    let mut writes = Vec::with_capacity(obj.len());
    for (name, v) in &obj {
        let d = match values::dev(name, &app.names) {
            Ok(d) => d,
            Err(e) => return bad(e),
        };
        match d.value(v) {
            Ok(v) => writes.push((d, v)),
            Err(e) => return bad(e),
        }
    }
    match at_end(&app, move |s| write_all(s, &writes)).await {
        Ok(Ok(scan)) => Json(json!({ "scan": scan })).into_response(),
        Ok(Err(e)) => bad(e),
        Err(e) => e,
    }
}

async fn list_forces(State(app): Shared) -> Response {
    match at_end(&app, |s| json!({ "forced": forced_json(s) })).await {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}

async fn force(State(app): Shared, headers: HeaderMap, bytes: Body) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let obj: Map<String, Json_> = match body(&bytes, "expected an object {\"X0\": true}") {
        Ok(o) => o,
        Err(r) => return r,
    };
    let mut forces = Vec::with_capacity(obj.len());
    for (name, v) in &obj {
        let (cpu, k, n) = match io_dev(name, &app.names) {
            Ok(p) => p,
            Err(e) => return bad(e),
        };
        let Some(on) = v.as_bool() else {
            return bad(format!("`{name}`: a force is true or false, not `{v}`"));
        };
        forces.push((cpu, k, n, on));
    }
    let r = at_end(&app, move |s| {
        // Check every point first: nothing is forced when one is refused.
        for i in 0..s.cpu_count() {
            let c = s.cpu_at(i);
            let limit = c.max_forces();
            let known = c.forced().count();
            let fresh = forces
                .iter()
                .filter(|(cpu, k, n, _)| {
                    *cpu == i && !c.forced().any(|(fk, fn_, _)| fk == *k && fn_ == *n)
                })
                .count();
            if known + fresh > limit {
                return Err(format!(
                    "at most {limit} devices can be forced on a {}",
                    c.profile().model
                ));
            }
        }
        for (cpu, k, n, _) in &forces {
            if *n >= s.cpu_at(*cpu).memory().map.points(*k) {
                let name = io_name(*k, *n, &names(s, *cpu));
                return Err(format!(
                    "`{}{name}` is beyond the CPU's points",
                    cpu_prefix(*cpu)
                ));
            }
        }
        for (cpu, k, n, on) in forces {
            s.cpu_mut_at(cpu).force(k, n, on)?;
            s.mark_wrote(cpu);
        }
        Ok(json!({ "forced": forced_json(s) }))
    })
    .await;
    match r {
        Ok(Ok(j)) => Json(j).into_response(),
        Ok(Err(e)) => bad(e),
        Err(e) => e,
    }
}

async fn release(State(app): Shared, headers: HeaderMap, bytes: Body) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let names: Vec<String> = match body(&bytes, "expected a list [\"X0\"]") {
        Ok(o) => o,
        Err(r) => return r,
    };
    let mut points = Vec::with_capacity(names.len());
    for name in &names {
        match io_dev(name, &app.names) {
            Ok(p) => points.push(p),
            Err(e) => return bad(e),
        }
    }
    let r = at_end(&app, move |s| {
        for (cpu, k, n) in points {
            s.cpu_mut_at(cpu).release(k, n);
            s.mark_wrote(cpu);
        }
        json!({ "forced": forced_json(s) })
    })
    .await;
    match r {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}

/// A remote operation of the CPU `?cpu=N` names, answering `{"state":
/// ...}` with that CPU's state; a refused one is 409.
async fn cpu_op(
    app: Arc<App>,
    headers: HeaderMap,
    q: &std::collections::HashMap<String, String>,
    op: fn(&mut ServeState, usize) -> Result<(), String>,
) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let cpu = match cpu_param(&app, q) {
        Ok(c) => c,
        Err(r) => return r,
    };
    let r = at_end(&app, move |s| {
        let r = op(s, cpu);
        // A system's RESET may change every CPU.
        (0..s.cpu_count()).for_each(|i| s.mark_wrote(i));
        r.map(|_| s.cpu_at(cpu).state().as_str())
    })
    .await;
    match r {
        Ok(Ok(state)) => Json(json!({ "state": state })).into_response(),
        Ok(Err(e)) => error(StatusCode::CONFLICT, e),
        Err(e) => e,
    }
}

async fn cpu_run(State(app): Shared, h: HeaderMap, Query(q): Q) -> Response {
    cpu_op(app, h, &q, |s, i| s.cpu_mut_at(i).set_run()).await
}

async fn cpu_stop(State(app): Shared, h: HeaderMap, Query(q): Q) -> Response {
    cpu_op(app, h, &q, |s, i| {
        s.cpu_mut_at(i).set_stop();
        Ok(())
    })
    .await
}

async fn cpu_pause(State(app): Shared, h: HeaderMap, Query(q): Q) -> Response {
    cpu_op(app, h, &q, |s, i| s.cpu_mut_at(i).set_pause()).await
}

/// Remote RESET (in STOP, when `[ras] remote_reset` allows it; 409 with
/// the reason otherwise); in a multi-CPU system CPU 1's resets every CPU
/// and another's brings the others down (MULTI CPU DOWN).
async fn cpu_reset(State(app): Shared, h: HeaderMap, Query(q): Q) -> Response {
    cpu_op(app, h, &q, |s, i| {
        s.cpus.remote_reset(i).map_err(|r| r.to_string())
    })
    .await
}

/// `cpu/step?scans=N[&cpu=K]`: N scans from PAUSE, answered once the CPU
/// paused again (no time limit: 10,000 scans at a 100 ms period take 17
/// minutes).
async fn cpu_step(State(app): Shared, headers: HeaderMap, Query(q): Q) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let n = match q.get("scans").map(|s| s.trim().parse::<u64>()) {
        None => 1,
        Some(Ok(n)) if (1..=MAX_STEP).contains(&n) => n,
        Some(_) => {
            return bad(format!(
                "`scans={}`: expected a number of scans from 1 to {MAX_STEP}",
                q.get("scans").map_or("", |s| s.as_str())
            ))
        }
    };
    let cpu = match cpu_param(&app, &q) {
        Ok(c) => c,
        Err(r) => return r,
    };
    let rx = match at_end(&app, move |s| {
        s.mark_wrote(cpu);
        monitor::start_step(s, cpu, n)
    })
    .await
    {
        Ok(Ok(rx)) => rx,
        Ok(Err(e)) => return error(StatusCode::CONFLICT, e),
        Err(e) => return e,
    };
    step_answer(rx).await
}

/// The answer of a step once its scans are done, however long they take
/// (N scans at the constant-scan period; docs/web-monitor.md). A client that
/// goes away meanwhile does not stop the step.
async fn step_answer(rx: tokio::sync::oneshot::Receiver<monitor::StepDone>) -> Response {
    match rx.await {
        Ok(done) => Json(json!({"state": done.state.as_str(), "scan": done.scan})).into_response(),
        Err(_) => error(
            StatusCode::SERVICE_UNAVAILABLE,
            "the server stopped before the step completed",
        ),
    }
}

async fn get_breakpoint(State(app): Shared) -> Response {
    match at_end(&app, |s| json!({ "breakpoint": breakpoint_json(s) })).await {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}

/// Extension (docs/web-monitor.md): `{"when": "D0 >= 100"}` pauses the CPU
/// at the END where the condition becomes true.
async fn set_breakpoint(State(app): Shared, headers: HeaderMap, bytes: Body) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let obj: Map<String, Json_> = match body(&bytes, "expected {\"when\": \"D0 >= 100\"}") {
        Ok(o) => o,
        Err(r) => return r,
    };
    let Some(when) = obj.get("when").and_then(Json_::as_str) else {
        return bad("expected {\"when\": \"D0 >= 100\"} (or a bit device: \"M0\")");
    };
    let bp = match Breakpoint::parse_in(when, &app.names) {
        Ok(b) => b,
        Err(e) => return bad(e),
    };
    let r = at_end(&app, move |s| {
        bp.device.read(s)?;
        let mut bp = bp;
        // It pauses when the condition *becomes* true: from its value now.
        bp.prev = bp.holds(s);
        s.ext::<Monitor>().breakpoint = Some(bp);
        Ok::<_, String>(json!({ "breakpoint": breakpoint_json(s) }))
    })
    .await;
    match r {
        Ok(Ok(j)) => Json(j).into_response(),
        Ok(Err(e)) => bad(e),
        Err(e) => e,
    }
}

async fn clear_breakpoint(State(app): Shared, headers: HeaderMap) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    match at_end(&app, |s| {
        s.ext::<Monitor>().breakpoint = None;
        json!({ "breakpoint": null })
    })
    .await
    {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}

/// An open event stream: counted in [`App::streams`] and owning its
/// subscription ([`monitor::Owner`]) until it is dropped.
struct Subscription {
    app: Arc<App>,
    owner: monitor::Owner,
}

impl Drop for Subscription {
    fn drop(&mut self) {
        self.app.streams.fetch_sub(1, Ordering::Relaxed);
    }
}

/// `events?names=...`: one unnamed event per published snapshot (≤ 10/s).
async fn events(State(app): Shared, Query(q): Q) -> Response {
    let specs = match values::dev_list(q.get("names").map(String::as_str), &app.names) {
        Ok(s) => s,
        Err(e) => return bad(e),
    };
    let mut names: Vec<String> = specs.iter().map(|d| d.text().to_string()).collect();
    names.dedup();
    if app.streams.fetch_add(1, Ordering::Relaxed) >= crate::MAX_STREAMS {
        app.streams.fetch_sub(1, Ordering::Relaxed);
        return error(
            StatusCode::SERVICE_UNAVAILABLE,
            format!("at most {} event streams at once", crate::MAX_STREAMS),
        );
    }
    // From here the guard gives the stream back when dropped, and its names
    // with it: also when this request is abandoned before the job ran.
    let guard = Subscription {
        app: app.clone(),
        owner: monitor::Owner::default(),
    };
    let watcher = guard.owner.watcher();
    match at_end(&app, move |s| monitor::subscribe(s, &specs, watcher)).await {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return bad(e),
        Err(e) => return e,
    }
    let mut rx = app.snapshots.clone();
    rx.mark_unchanged();
    let stream =
        futures_util::stream::unfold((rx, guard, names), |(mut rx, guard, names)| async move {
            loop {
                rx.changed().await.ok()?;
                let snap = rx.borrow_and_update().clone();
                let mut m = Map::new();
                for n in &names {
                    match snap.values.get(n) {
                        Some(v) => {
                            m.insert(n.clone(), v.clone());
                        }
                        None => break,
                    }
                }
                if m.len() < names.len() {
                    // Published before this client's names were added.
                    continue;
                }
                let data = json!({"scan": snap.scan, "devices": m}).to_string();
                let ev: Result<Event, std::convert::Infallible> = Ok(Event::default().data(data));
                return Some((ev, (rx, guard, names)));
            }
        });
    Sse::new(stream)
        .keep_alive(KeepAlive::new().interval(Duration::from_secs(15)))
        .into_response()
}

#[cfg(test)]
mod tests {
    use super::*;
    use softplc_core::engine::CpuState;

    /// Issue #31 defect 6: a step longer than any fixed wait (an hour of
    /// scans, in tokio's virtual time) is answered when it is done.
    #[tokio::test(start_paused = true)]
    async fn a_long_step_is_answered_when_done() {
        let (tx, rx) = tokio::sync::oneshot::channel();
        tokio::spawn(async move {
            tokio::time::sleep(Duration::from_secs(3600)).await;
            let _ = tx.send(monitor::StepDone {
                state: CpuState::Pause,
                scan: 10_000,
            });
        });
        let r = step_answer(rx).await;
        assert_eq!(r.status(), StatusCode::OK);
        let body = axum::body::to_bytes(r.into_body(), 1024).await.unwrap();
        let j: Json_ = serde_json::from_slice(&body).unwrap();
        assert_eq!(j, json!({"state": "PAUSE", "scan": 10_000}));
    }

    /// The engine stopped before the step ended: 503, at once.
    #[tokio::test(start_paused = true)]
    async fn a_step_the_engine_abandoned_is_503() {
        let (tx, rx) = tokio::sync::oneshot::channel::<monitor::StepDone>();
        drop(tx);
        let r = step_answer(rx).await;
        assert_eq!(r.status(), StatusCode::SERVICE_UNAVAILABLE);
    }
}
