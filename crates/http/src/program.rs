//! `PUT /api/v1/program` (contract §7): writing a program file during RUN.
//! Body `{"file": "main.il", "text": "…"}`: the file relative to the served
//! directory (or a single program's file name). At the next END the CPU
//! runs the new program with device memory and the state of unchanged
//! instructions kept, and the file is rewritten on disk; the answer is
//! `{"scan": S}` of that END with what was kept. A text that does not
//! compile is 400 with its diagnostics and nothing changes; an unknown file
//! is 404. The ladder pages draw the new program from then on
//! ([`crate::App::ladder_now`]).

use std::sync::Arc;

use axum::extract::State;
use axum::http::{HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::json;
use softplc_core::online::Refused;
use softplc_serve::online::{self, WriteError};

use crate::api::{authorize, body, error, Body};
use crate::App;

/// Largest program text accepted, bytes (as a program file read at load).
pub const PROGRAM_BODY_LIMIT: usize = softplc_core::program::MAX_IL_BYTES as usize + 64 * 1024;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Put {
    file: String,
    text: String,
}

pub async fn put(State(app): State<Arc<App>>, headers: HeaderMap, bytes: Body) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let req: Put = match body(&bytes, "expected {\"file\": \"main.il\", \"text\": \"…\"}") {
        Ok(r) => r,
        Err(r) => return r,
    };
    let Some(online) = app.cfg.online.clone() else {
        return error(
            StatusCode::NOT_FOUND,
            "this server has no program files to write (it was not started on a program file, project or system)",
        );
    };
    let result = tokio::time::timeout(
        crate::api::END_WAIT,
        online::write(&app.engine, online, &req.file, req.text),
    )
    .await;
    match result {
        Ok(Ok(w)) => {
            eprintln!("softplc: --http: {}", online::summary(&req.file, &w));
            Json(json!({
                "scan": w.scan,
                "kept": w.kept,
                "added": w.added,
                "removed": w.removed,
                "steps_written": w.steps_written,
                "steps": w.steps,
            }))
            .into_response()
        }
        Ok(Err(WriteError::Refused(Refused::UnknownFile(e)))) => error(StatusCode::NOT_FOUND, e),
        Ok(Err(WriteError::Refused(Refused::Program(d)))) => {
            let diagnostics: Vec<String> = d.0.iter().map(ToString::to_string).collect();
            (
                StatusCode::BAD_REQUEST,
                Json(json!({
                    "error": format!("{} does not compile; the running program is unchanged", req.file),
                    "diagnostics": diagnostics,
                })),
            )
                .into_response()
        }
        Ok(Err(WriteError::Refused(Refused::Cpu(e)))) => error(
            StatusCode::BAD_REQUEST,
            format!("{e}; the running program is unchanged"),
        ),
        Ok(Err(WriteError::NotSaved(w, e))) => error(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!(
                "the CPU runs the new program since scan {}, but the file could not be rewritten: {e}",
                w.scan
            ),
        ),
        Ok(Err(WriteError::Busy)) => error(
            StatusCode::SERVICE_UNAVAILABLE,
            softplc_serve::Busy.to_string(),
        ),
        Err(_) => error(
            StatusCode::SERVICE_UNAVAILABLE,
            "the CPU did not reach END in time (a scan that does not end?)",
        ),
    }
}
