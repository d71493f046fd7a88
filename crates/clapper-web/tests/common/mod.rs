//! What the socket tests share: a server on a free loopback port, and a
//! request's bytes.

#![allow(dead_code)]

/// Serve with the default limits on a free loopback port; its address.
pub async fn start() -> std::net::SocketAddr {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(clapper_web::serve(
        listener,
        clapper_web::Limits::default(),
        clapper_web::AllowedHosts::loopback(),
        std::future::pending(),
    ));
    addr
}

/// A JSON POST to `path` on `addr`, closing the connection after.
pub fn post(addr: std::net::SocketAddr, path: &str, body: &str) -> String {
    format!(
        "POST {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
}

/// A WAV file `wav` POSTed to `uri` on the router `app` (no socket): the
/// answer's status and body.
pub async fn send_wav(app: &axum::Router, uri: &str, wav: Vec<u8>) -> (axum::http::StatusCode, Vec<u8>) {
    use http_body_util::BodyExt;
    use tower::ServiceExt;
    let req = axum::http::Request::builder()
        .method("POST")
        .uri(uri)
        .header("content-type", "audio/wav")
        .body(axum::body::Body::from(wav))
        .unwrap();
    let res = app.clone().oneshot(req).await.unwrap();
    let status = res.status();
    (status, res.into_body().collect().await.unwrap().to_bytes().to_vec())
}
