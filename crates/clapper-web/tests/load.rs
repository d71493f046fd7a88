//! The server under load on loopback: many concurrent simulate and chart
//! requests over real sockets. Every request must be answered 200 (none
//! lost, none refused: they queue for the computation slots), and the
//! process's memory must stay bounded. Prints requests per second and
//! latency percentiles. LOAD_REQUESTS (default 400) and LOAD_CONCURRENCY
//! (default 200) set the size:
//!
//!     LOAD_REQUESTS=4000 LOAD_CONCURRENCY=500 cargo test --release -p clapper-web --test load -- --nocapture

use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::sync::Semaphore;

fn env(name: &str, default: usize) -> usize {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<f64>().ok())
        })
        .map_or(0.0, |kb| kb / 1024.0)
}

async fn request(addr: std::net::SocketAddr, path: &str, body: &str) -> std::io::Result<(u16, usize)> {
    let mut s = tokio::net::TcpStream::connect(addr).await?;
    let req = format!(
        "POST {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    s.write_all(req.as_bytes()).await?;
    let mut buf = Vec::new();
    s.read_to_end(&mut buf).await?;
    let status = std::str::from_utf8(&buf[9..12])
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    Ok((status, buf.len()))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_server_keeps_answering_under_load() {
    let total = env("LOAD_REQUESTS", 400);
    let concurrency = env("LOAD_CONCURRENCY", 200);
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let limits = clapper_web::Limits {
        queue_wait: Duration::from_secs(120),
        ..clapper_web::Limits::default()
    };
    tokio::spawn(clapper_web::serve(
        listener,
        limits,
        clapper_web::AllowedHosts::loopback(),
        std::future::pending(),
    ));
    // Warm up (first allocations, thread pools), then measure memory.
    request(addr, "/api/simulate", "{}").await.unwrap();
    let rss_before = rss_mib();

    let gate = Arc::new(Semaphore::new(concurrency));
    let start = Instant::now();
    let mut tasks = vec![];
    for k in 0..total {
        let gate = gate.clone();
        tasks.push(tokio::spawn(async move {
            let _p = gate.acquire_owned().await.unwrap();
            let (path, body) = match k % 4 {
                0 => ("/api/chart", r#"{"grid": [10, 10]}"#.to_string()),
                1 => (
                    "/api/simulate",
                    format!(
                        r#"{{"chart_point": [{}, 1.5], "style": "wrong"}}"#,
                        0.01 * (k % 50) as f64
                    ),
                ),
                2 => (
                    "/api/simulate",
                    r#"{"preset": "gsm-tenor", "strokes": 4, "protocol": "free"}"#.to_string(),
                ),
                _ => ("/api/stroke", r#"{"preset": "lab"}"#.to_string()),
            };
            let t = Instant::now();
            let r = request(addr, path, &body).await;
            (r, t.elapsed())
        }));
    }
    let mut latencies = vec![];
    let mut bad = vec![];
    for t in tasks {
        let (r, dt) = t.await.unwrap();
        match r {
            Ok((200, len)) if len > 100 => latencies.push(dt),
            other => bad.push(format!("{other:?}")),
        }
    }
    let secs = start.elapsed().as_secs_f64();
    let rss_after = rss_mib();
    latencies.sort();
    let pct = |p: f64| latencies[((latencies.len() - 1) as f64 * p) as usize].as_secs_f64() * 1e3;
    println!(
        "load: {total} requests, {concurrency} at once: {} answered 200 in {secs:.2} s ({:.0} requests/s); latency p50 {:.0} ms, p90 {:.0} ms, p99 {:.0} ms, max {:.0} ms; RSS {rss_before:.0} MiB before, {rss_after:.0} MiB after",
        latencies.len(),
        total as f64 / secs,
        pct(0.5),
        pct(0.9),
        pct(0.99),
        pct(1.0)
    );
    assert!(
        bad.is_empty(),
        "{} requests not answered 200: {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    // Bounded: the growth is the in-flight work, not something per request.
    assert!(
        rss_after - rss_before < 300.0,
        "memory grew by {:.0} MiB",
        rss_after - rss_before
    );
    // And it still answers.
    assert_eq!(request(addr, "/api/simulate", "{}").await.unwrap().0, 200);
}
