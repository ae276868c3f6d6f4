//! `GET /api/v1/snapshot` and `PUT /api/v1/snapshot` (contract §7): the
//! state file of `run --save-state`, taken at an END; a file put (token)
//! restores the CPU — every CPU of a system — at the next END, scan count
//! and time included, and is committed to the state directories like a
//! write. A refused file (another program or model, damaged) is 400 with
//! `{"error": …}` and nothing changes.

use std::sync::Arc;

use axum::extract::State;
use axum::http::{header, HeaderMap};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::json;
use softplc_core::snapshot::SnapshotError;

use crate::api::{at_end, authorize, bad, error, Body};
use crate::App;

/// Largest state file a `PUT` takes: a CPU's file is about two bytes per
/// word and one per bit of device memory (4 M words of file registers are
/// 8 MB).
pub const SNAPSHOT_LIMIT: usize = 32 << 20;

pub(crate) async fn get(State(app): State<Arc<App>>) -> Response {
    match at_end(&app, |s| s.cpus.save_state()).await {
        Ok(file) => (
            [
                (header::CONTENT_TYPE, "application/octet-stream"),
                (
                    header::CONTENT_DISPOSITION,
                    "attachment; filename=\"softplc.state\"",
                ),
            ],
            file,
        )
            .into_response(),
        Err(e) => e,
    }
}

pub(crate) async fn put(State(app): State<Arc<App>>, headers: HeaderMap, bytes: Body) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let file = match bytes {
        Ok(b) => b,
        Err(r) => {
            return error(
                r.status(),
                format!("request body refused: {}", r.body_text()),
            )
        }
    };
    let restored = at_end(&app, move |s| -> Result<(u64, u64), SnapshotError> {
        s.cpus.load_state(&file)?;
        for i in 0..s.cpus.len() {
            s.mark_wrote(i);
        }
        let cpu = s.cpus.get(0);
        Ok((cpu.scans(), cpu.now_us()))
    })
    .await;
    match restored {
        Ok(Ok((scan, us))) => {
            Json(json!({ "scan": scan, "time_ms": us as f64 / 1000.0 })).into_response()
        }
        Ok(Err(e)) => bad(e.to_string()),
        Err(e) => e,
    }
}
