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
/// stops computing once its client has left: some second after it uses
/// next to no CPU. The effect is tested, not how soon: on a busy machine
/// the server may notice later, and the bound (60 s) only stops a hang.
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
    // One-second windows until one is idle (the sweep would keep both
    // cores busy for tens of minutes).
    let mut idle = f64::MAX;
    for _ in 0..60 {
        let before = cpu_seconds();
        tokio::time::sleep(Duration::from_secs(1)).await;
        idle = cpu_seconds() - before;
        if idle < 0.2 {
            break;
        }
    }
    println!(
        "CPU while computing: {busy:.2} s before the client left; {idle:.2} s in the first idle second, {:.1} s after it left",
        left.elapsed().as_secs_f64()
    );
    assert!(
        idle < 0.2,
        "still computing: {idle:.2} s of CPU in a second, 60 s after the client left"
    );
}
