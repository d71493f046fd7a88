//! The page, compiled into the binary.

use axum::http::header;
use axum::response::{Html, IntoResponse};

/// `GET /`: the application page.
pub(crate) async fn index() -> Html<&'static str> {
    Html(include_str!("../assets/index.html"))
}

/// `GET /app.js`.
pub(crate) async fn script() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        include_str!("../assets/app.js"),
    )
}

/// `GET /app.css`.
pub(crate) async fn style() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/css; charset=utf-8")],
        include_str!("../assets/app.css"),
    )
}

/// `GET /api`: the API, described with examples.
pub(crate) async fn api_page() -> Html<&'static str> {
    Html(include_str!("../assets/api.html"))
}
