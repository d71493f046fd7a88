//! A chart whose client leaves stops computing (docs/reliability.md). In
//! a test binary of its own: it reads the process's CPU time, which other
//! tests running beside it would add to.

mod common;

use common::{post, start};
use std::time::{Duration, Instant};

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

/// The process's CPU time so far (s), user and system, from /proc.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap();
    // Fields after the command's closing parenthesis; utime and stime are
    // the 14th and 15th of the line.
    let rest = &stat[stat.rfind(')').unwrap() + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap();
    ticks / 100.0
}

/// A chart that is one block of 80,000 slow strokes (the penalty law at
/// k = 1e9 with Dormand-Prince at 1e-14: tens of minutes of both cores)
/// stops computing within 2 s of its client leaving.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_chart_stops_when_its_client_leaves() {
    let addr = start().await;
    let heavy =
        r#"{"grid": [40000, 1], "contact": "penalty", "stiffness": 1e9, "integrator": "dopri5", "rtol": 1e-14}"#;
    let mut s = TcpStream::connect(addr).await.unwrap();
    s.write_all(post(addr, "/api/chart", heavy).as_bytes()).await.unwrap();
    let mut first = [0u8; 256];
    let n = s.read(&mut first).await.unwrap();
    assert!(
        String::from_utf8_lossy(&first[..n]).contains("200"),
        "{}",
        String::from_utf8_lossy(&first[..n])
    );
    tokio::time::sleep(Duration::from_millis(500)).await;
    let busy = cpu_seconds();
    drop(s);
    let left = Instant::now();
    tokio::time::sleep(Duration::from_secs(2)).await;
    let after = cpu_seconds();
    tokio::time::sleep(Duration::from_secs(1)).await;
    let idle = cpu_seconds() - after;
    println!(
        "CPU while computing: {:.2} s before the client left; {:.2} s in the 2 s after; {idle:.2} s in the second after that ({:.1} s since it left)",
        busy,
        after - busy,
        left.elapsed().as_secs_f64()
    );
    assert!(
        idle < 0.2,
        "still computing: {idle:.2} s of CPU in one second, 2 s after the client left"
    );
}
