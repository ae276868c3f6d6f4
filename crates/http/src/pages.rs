//! Pages (placeholder).
use axum::response::{Html, IntoResponse};
pub async fn ladder() -> impl IntoResponse {
    Html("ladder")
}
pub async fn overview() -> impl IntoResponse {
    Html("overview")
}
pub async fn devices() -> impl IntoResponse {
    Html("devices")
}
pub async fn script() -> impl IntoResponse {
    ""
}
pub async fn style() -> impl IntoResponse {
    ""
}
