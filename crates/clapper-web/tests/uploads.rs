//! Request bodies bounded over real sockets (docs/reliability.md): a body
//! trickled to hold a connection is cut off, a length announced past the
//! limit is refused before any body is sent, recordings being received at
//! once share a budget of bytes, and a request has one Host header.
//! Every wait here is bounded only to turn a hang into a failure.

use std::net::SocketAddr;
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

async fn start_with(limits: clapper_web::Limits) -> SocketAddr {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(clapper_web::serve(
        listener,
        limits,
        clapper_web::AllowedHosts::loopback(),
        std::future::pending(),
    ));
    addr
}

/// The whole answer on `s`, or what came before `guard` ran out.
async fn answer(s: &mut TcpStream, guard: Duration) -> String {
    let mut out = Vec::new();
    let _ = tokio::time::timeout(guard, s.read_to_end(&mut out)).await;
    String::from_utf8_lossy(&out).into_owned()
}

fn head(path: &str, length: u64) -> String {
    format!(
        "POST {path} HTTP/1.1\r\nHost: localhost\r\nContent-Type: audio/wav\r\nContent-Length: {length}\r\nConnection: close\r\n\r\n"
    )
}

async fn health(addr: SocketAddr) -> String {
    let mut s = TcpStream::connect(addr).await.unwrap();
    s.write_all(b"GET /api/health HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n")
        .await
        .unwrap();
    answer(&mut s, Duration::from_secs(60)).await
}

/// More trickling uploads than the server holds connections: each sends a
/// byte every 300 ms, never pausing as long as the body timeout (1 s), so
/// only the least rate (1 KiB/s after 1 s) ends them. They are answered
/// 408 with the reason, and the health check, queued behind them, is
/// answered. Without the least rate they held every connection as long as
/// they kept trickling (here, longer than the 60 s guard).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn trickled_uploads_are_cut_off_and_the_server_answers_others() {
    let limits = clapper_web::Limits {
        body_timeout: Duration::from_secs(1),
        min_upload_rate: 1024,
        max_connections: 8,
        ..clapper_web::Limits::default()
    };
    let addr = start_with(limits).await;
    let mut tricklers = vec![];
    for _ in 0..16 {
        tricklers.push(tokio::spawn(async move {
            let mut s = TcpStream::connect(addr).await.unwrap();
            s.write_all(head("/api/strikes?nominals=400", 100_000).as_bytes())
                .await
                .unwrap();
            for _ in 0..200 {
                if s.write_all(b"x").await.is_err() {
                    break;
                }
                tokio::time::sleep(Duration::from_millis(300)).await;
                // The answer comes before the body is done: stop sending.
                let mut peek = [0u8; 1];
                if let Ok(Ok(n)) = tokio::time::timeout(Duration::from_millis(1), s.peek(&mut peek)).await {
                    if n > 0 {
                        break;
                    }
                }
            }
            answer(&mut s, Duration::from_secs(60)).await
        }));
    }
    tokio::time::sleep(Duration::from_millis(200)).await;
    let h = health(addr).await;
    assert!(h.starts_with("HTTP/1.1 200"), "health: {h}");
    let first = tricklers.remove(0).await.unwrap();
    assert!(first.starts_with("HTTP/1.1 408"), "{first}");
    assert!(
        first.contains("upload too slow") && first.contains("1 KiB/s"),
        "{first}"
    );
}

/// A recording announced at 10^12 bytes is refused (413) before its body:
/// the client sends none and is answered. Before, the server waited for
/// the body until the body timeout.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_length_past_the_limit_is_refused_before_the_body() {
    let addr = start_with(clapper_web::Limits::default()).await;
    for (path, kind) in [
        ("/api/strikes?nominals=400", "audio/wav"),
        ("/api/simulate", "application/json"),
    ] {
        let mut s = TcpStream::connect(addr).await.unwrap();
        let req = head(path, 1_000_000_000_000).replace("audio/wav", kind);
        s.write_all(req.as_bytes()).await.unwrap();
        let a = answer(&mut s, Duration::from_secs(60)).await;
        assert!(a.starts_with("HTTP/1.1 413"), "{path}: {a}");
        assert!(a.contains("1000000000000 bytes announced"), "{path}: {a}");
    }
}

/// With room for two recordings in flight, a third announced while two
/// are being received is answered 503 at once; the health check answers.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn recordings_in_flight_share_a_budget() {
    let limits = clapper_web::Limits {
        max_recording_bytes: 1 << 20,
        max_upload_bytes_in_flight: 2 << 20,
        // The two held uploads stall after their first bytes: a minute
        // before the least rate would cut them, however loaded the machine.
        body_timeout: std::time::Duration::from_secs(60),
        ..clapper_web::Limits::default()
    };
    let addr = start_with(limits).await;
    let mut held = vec![];
    for _ in 0..2 {
        let mut s = TcpStream::connect(addr).await.unwrap();
        s.write_all(head("/api/strikes?nominals=400", 1 << 20).as_bytes())
            .await
            .unwrap();
        s.write_all(&[0u8; 1000]).await.unwrap();
        held.push(s);
    }
    tokio::time::sleep(Duration::from_millis(300)).await;
    let mut third = TcpStream::connect(addr).await.unwrap();
    third
        .write_all(head("/api/strikes?nominals=400", 1 << 20).as_bytes())
        .await
        .unwrap();
    let a = answer(&mut third, Duration::from_secs(60)).await;
    assert!(a.starts_with("HTTP/1.1 503"), "{a}");
    assert!(a.contains("being received"), "{a}");
    let h = health(addr).await;
    assert!(h.starts_with("HTTP/1.1 200"), "health: {h}");
    drop(held);
}

/// Two Host headers are a malformed request (RFC 9112 §3.2): 400, whatever
/// the first one says.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_host_headers_are_refused() {
    let addr = start_with(clapper_web::Limits::default()).await;
    let mut s = TcpStream::connect(addr).await.unwrap();
    s.write_all(b"GET /api/health HTTP/1.1\r\nHost: localhost\r\nHost: evil.com\r\nConnection: close\r\n\r\n")
        .await
        .unwrap();
    let a = answer(&mut s, Duration::from_secs(60)).await;
    assert!(a.starts_with("HTTP/1.1 400"), "{a}");
    assert!(a.contains("one Host header"), "{a}");
}
