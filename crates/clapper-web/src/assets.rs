//! The page, compiled into the binary.

use axum::http::{header, HeaderMap};
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

/// `GET /player.js`: the animation player, the same file `clapper
/// animate` puts in its pages.
pub(crate) async fn player() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        clapper_plot::animation::PLAYER_JS,
    )
}

/// `GET /app.css`.
pub(crate) async fn style() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/css; charset=utf-8")],
        include_str!("../assets/app.css"),
    )
}

/// `GET /api`: the API, described with examples. The examples name the
/// host and port the page was asked for (the server may run on any port),
/// `localhost:8080` when the request does not say or names an odd host.
pub(crate) async fn api_page(headers: HeaderMap) -> Html<String> {
    const PAGE: &str = include_str!("../assets/api.html");
    let host = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        // The host goes into HTML and shell lines: only what a host and port are made of.
        .filter(|h| {
            !h.is_empty() && h.len() <= 255 && h.bytes().all(|b| b.is_ascii_alphanumeric() || b".-:[]".contains(&b))
        })
        .unwrap_or("localhost:8080");
    Html(PAGE.replace("localhost:8080", host))
}
