//! `POST /api/v1/sim/advance` (contract §7): a `serve --lockstep` CPU runs
//! from its held END — body `{"scans": N}`, or `{"ms": T}` rounded up to
//! whole scans of CPU 1's period — and the answer `{"scan": S, "time_ms": T}`
//! comes after the last of those ENDs (the engine's side is
//! [`softplc_serve::ServeState::advance`]). It needs the token like every
//! write. A server not in lockstep, or an advance while another runs, is 409;
//! a bad body is 400 with `{"error"}`.

use std::sync::Arc;

use axum::extract::State;
use axum::http::{HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::{json, Map, Value};
use softplc_serve::sim::MAX_ADVANCE;
use softplc_serve::{Advance, AdvanceRefused};

use crate::api::{at_end, authorize, bad, body, error, Body};
use crate::App;

const FORM: &str = "expected {\"scans\": N} or {\"ms\": T}";

pub async fn advance(State(app): State<Arc<App>>, headers: HeaderMap, bytes: Body) -> Response {
    if let Err(r) = authorize(&app, &headers) {
        return r;
    }
    let obj: Map<String, Value> = match body(&bytes, FORM) {
        Ok(o) => o,
        Err(r) => return r,
    };
    let a = match parse(&obj) {
        Ok(a) => a,
        Err(e) => return bad(e),
    };
    let rx = match at_end(&app, move |s| s.advance(a)).await {
        Ok(Ok(rx)) => rx,
        Ok(Err(e @ AdvanceRefused::Scans(_))) => return bad(e.to_string()),
        Ok(Err(e)) => return error(StatusCode::CONFLICT, e.to_string()),
        Err(r) => return r,
    };
    // However long the scans take (an advance has no time limit, as a step).
    match rx.await {
        Ok(done) => Json(json!({
            "scan": done.scan,
            "time_ms": done.time_us as f64 / 1000.0,
        }))
        .into_response(),
        Err(_) => error(
            StatusCode::SERVICE_UNAVAILABLE,
            "the advance did not complete: the server stopped, or its last END could not be saved",
        ),
    }
}

/// The body: exactly one of `scans` (a whole number, 1 to [`MAX_ADVANCE`])
/// and `ms` (more than 0).
fn parse(obj: &Map<String, Value>) -> Result<Advance, String> {
    let mut keys = obj.iter();
    let (Some((k, v)), None) = (keys.next(), keys.next()) else {
        return Err(format!("{FORM}: one key"));
    };
    match k.as_str() {
        "scans" => match v.as_u64() {
            Some(n) if (1..=MAX_ADVANCE).contains(&n) => Ok(Advance::Scans(n)),
            _ => Err(format!(
                "`scans`: expected a whole number of scans from 1 to {MAX_ADVANCE}, not `{v}`"
            )),
        },
        "ms" => match v.as_f64() {
            // To the nanosecond first, so that 0.3 ms is 300 µs, not 301.
            Some(t) if t > 0.0 && t <= 1e12 => {
                Ok(Advance::Us(((t * 1e6).round() as u64).div_ceil(1000)))
            }
            _ => Err(format!(
                "`ms`: expected a virtual time in ms more than 0, not `{v}`"
            )),
        },
        _ => Err(format!("`{k}`: unknown key; {FORM}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(text: &str) -> Result<Advance, String> {
        parse(&serde_json::from_str(text).unwrap())
    }

    #[test]
    fn bodies() {
        assert_eq!(parsed(r#"{"scans": 3}"#), Ok(Advance::Scans(3)));
        assert_eq!(parsed(r#"{"ms": 25}"#), Ok(Advance::Us(25_000)));
        assert_eq!(parsed(r#"{"ms": 0.3}"#), Ok(Advance::Us(300)));
        assert_eq!(parsed(r#"{"ms": 0.0004}"#), Ok(Advance::Us(1)));
        for bad in [
            r#"{}"#,
            r#"{"scans": 0}"#,
            r#"{"scans": -1}"#,
            r#"{"scans": 1.5}"#,
            r#"{"scans": "2"}"#,
            r#"{"scans": 10000001}"#,
            r#"{"ms": 0}"#,
            r#"{"ms": -5}"#,
            r#"{"ms": "5"}"#,
            r#"{"scans": 1, "ms": 10}"#,
            r#"{"seconds": 1}"#,
        ] {
            assert!(parsed(bad).is_err(), "{bad}");
        }
    }
}
