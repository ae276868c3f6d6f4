//! The web monitor's door: the accept loop and the connections, with the
//! limits MC and Modbus TCP have (docs/limits.md).
//!
//! - **Connections**: the door's [`Conns`] table (shared with MC and Modbus
//!   TCP): at most [`Limits::max_connections`]; at the limit a new connection
//!   replaces one that never completed a request head (a half-sent request),
//!   else one idle for 10 s; with only active clients (a request being
//!   answered, an event stream open) it is refused. Accept errors (EMFILE)
//!   back off.
//! - **Header timeout**: a request head must arrive within
//!   [`Limits::header_timeout`] of the connection opening, or of the previous
//!   answer on a kept-alive connection; otherwise the connection is closed
//!   (slow or idle clients do not hold a place).
//! - **Body timeout**: a request body must arrive whole within
//!   [`Limits::body_timeout`] (408 otherwise), and at most [`crate::BODY_LIMIT`]
//!   bytes of it (a program written during RUN:
//!   [`crate::program::PROGRAM_BODY_LIMIT`]; a state file put to
//!   `/api/v1/snapshot`: [`crate::snapshot::SNAPSHOT_LIMIT`]; 413 otherwise),
//!   before the request reaches the router.
//! - Heads are read into a buffer of at most [`MAX_HEAD`] bytes.

use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;

use axum::body::{Body, Bytes, HttpBody};
use axum::http::{header, Request, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Router;
use futures_util::StreamExt;
use hyper_util::rt::{TokioIo, TokioTimer};
use softplc_serve::conns::Slot;
use tower::ServiceExt;

/// The HTTP door's limits (`[http]` in plc.toml, `--http-*` options).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Connections open at once.
    pub max_connections: usize,
    /// Longest wait for a request head (also between requests on a kept-alive
    /// connection).
    pub header_timeout: Duration,
    /// Longest wait for a whole request body.
    pub body_timeout: Duration,
}

/// Defaults for a PLC on a plant network: a few operator and engineering
/// stations, each browser with up to 6 connections and an event stream per
/// page, and requests that arrive in well under a second.
impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_connections: 64,
            header_timeout: Duration::from_secs(10),
            body_timeout: Duration::from_secs(10),
        }
    }
}

/// Largest request head (request line and headers) read, bytes: 1,024 device
/// names in a query fit.
pub const MAX_HEAD: usize = 64 * 1024;

/// Serves `router` on `listener` until the task is dropped.
pub async fn serve(listener: tokio::net::TcpListener, router: Router, limits: Limits) {
    let mut http = hyper::server::conn::http1::Builder::new();
    http.timer(TokioTimer::new())
        .header_read_timeout(limits.header_timeout)
        .max_buf_size(MAX_HEAD);
    let http = Arc::new(http);
    let max = limits.max_connections;
    softplc_serve::conns::serve(listener, "web monitor", max, |stream, _, slot| {
        let (http, router) = (http.clone(), router.clone());
        tokio::spawn(async move {
            let service = hyper::service::service_fn(move |req| {
                request(req.map(Body::new), router.clone(), slot.clone(), limits)
            });
            let _ = http.serve_connection(TokioIo::new(stream), service).await;
        })
    })
    .await
}

/// One request: its body read whole within the body timeout, then the router.
/// The connection is busy (not evicted) until the answer is complete, an
/// event stream's until the stream ends.
async fn request(
    req: Request<Body>,
    router: Router,
    slot: Arc<Slot>,
    limits: Limits,
) -> Result<Response, Infallible> {
    let busy = slot.busy();
    let (parts, body) = req.into_parts();
    let limit = body_limit(&parts);
    let body = match tokio::time::timeout(limits.body_timeout, whole(body, limit)).await {
        Ok(Ok(b)) => b,
        Ok(Err(r)) => return Ok(r),
        Err(_) => {
            return Ok(closing(
                StatusCode::REQUEST_TIMEOUT,
                format!(
                    "the request body did not arrive within {:?}",
                    limits.body_timeout
                ),
            ))
        }
    };
    let req = Request::from_parts(parts, Body::from(body));
    let Ok(resp) = router.oneshot(req).await;
    if resp.body().size_hint().exact().is_some() {
        return Ok(resp);
    }
    // A stream: the connection stays busy while it is sent.
    let (parts, body) = resp.into_parts();
    let held = body.into_data_stream().map(move |chunk| {
        let _ = &busy;
        chunk
    });
    Ok(Response::from_parts(parts, Body::from_stream(held)))
}

/// The largest body of a request: a program's text put to
/// `/api/v1/program` may be [`crate::program::PROGRAM_BODY_LIMIT`] bytes, a
/// state file put to `/api/v1/snapshot` [`crate::snapshot::SNAPSHOT_LIMIT`],
/// anything else [`crate::BODY_LIMIT`].
fn body_limit(parts: &axum::http::request::Parts) -> usize {
    if parts.method != axum::http::Method::PUT {
        return crate::BODY_LIMIT;
    }
    match parts.uri.path() {
        "/api/v1/program" => crate::program::PROGRAM_BODY_LIMIT,
        "/api/v1/snapshot" => crate::snapshot::SNAPSHOT_LIMIT,
        _ => crate::BODY_LIMIT,
    }
}

/// The body's bytes, at most `limit` of them.
async fn whole(body: Body, limit: usize) -> Result<Bytes, Response> {
    if body.size_hint().exact() == Some(0) {
        return Ok(Bytes::new());
    }
    let mut data = body.into_data_stream();
    let mut buf = Vec::new();
    while let Some(chunk) = data.next().await {
        let chunk = chunk.map_err(|e| {
            closing(
                StatusCode::BAD_REQUEST,
                format!("request body refused: {e}"),
            )
        })?;
        if buf.len() + chunk.len() > limit {
            return Err(closing(
                StatusCode::PAYLOAD_TOO_LARGE,
                format!("request body refused: larger than {limit} bytes"),
            ));
        }
        buf.extend_from_slice(&chunk);
    }
    Ok(Bytes::from(buf))
}

/// `{"error": msg}` with `code`, closing the connection (the rest of the
/// request may still be on its way).
fn closing(code: StatusCode, msg: String) -> Response {
    let mut r = crate::api::error(code, msg).into_response();
    r.headers_mut().insert(
        header::CONNECTION,
        header::HeaderValue::from_static("close"),
    );
    r
}
