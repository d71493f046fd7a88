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
