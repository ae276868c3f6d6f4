//! `GET /api/v1/timing`: how well the engine keeps its constant-scan period
//! (scan start lateness, period jitter, execution time; `softplc_serve::timing`),
//! and `POST /api/v1/timing/reset` to start the figures over (a token, as
//! other requests that change something). `serve --timing-report` writes the
//! same JSON at exit.

use std::sync::Arc;

use axum::extract::State;
use axum::http::HeaderMap;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::{json, Value};
use softplc_serve::{Dist, ServeState};

use crate::api::{at_end, authorize};
use crate::App;

/// The timing figures and the real-time setup they were taken with.
pub fn to_json(s: &ServeState) -> Value {
    let r = s.timing.report();
    let st = &s.stats;
    json!({
        "period_us": r.period_us,
        "seconds": (r.seconds * 1000.0).round() / 1000.0,
        "count": r.lateness.count,
        "overruns": r.overruns,
        "lateness_us": dist(&r.lateness),
        "period_jitter_us": dist(&r.period_jitter),
        "scan_time_us": dist(&r.exec),
        "realtime": {
            "sched_fifo": st.realtime,
            "memory_locked": st.memory_locked,
            "cpu": st.pinned,
            "spin_us": r.spin_us,
            "note": st.realtime_note,
        },
    })
}

fn dist(d: &Dist) -> Value {
    json!({
        "count": d.count,
        "p50": d.p50_us,
        "p99": d.p99_us,
        "p999": d.p999_us,
        "max": d.max_us,
        "mean": d.mean_us,
    })
}

pub async fn get(State(app): State<Arc<App>>) -> Response {
    match at_end(&app, |s| to_json(s)).await {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}

/// Starts the figures over; answers with those of before the reset.
pub async fn reset(State(app): State<Arc<App>>, headers: HeaderMap) -> Response {
    if let Err(e) = authorize(&app, &headers) {
        return e;
    }
    let r = at_end(&app, |s| {
        let j = to_json(s);
        s.timing.reset();
        j
    })
    .await;
    match r {
        Ok(j) => Json(j).into_response(),
        Err(e) => e,
    }
}
