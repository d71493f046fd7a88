//! `clapper serve` through the built binary and a socket.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

use common::json;

struct Server {
    child: Child,
    addr: String,
}

impl Server {
    fn start() -> Self {
        Self::start_with(&[])
    }

    fn start_with(extra: &[&str]) -> Self {
        let mut child = Command::new(assert_cmd::cargo::cargo_bin("clapper"))
            .args(["serve", "--port", "0"])
            .args(extra)
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let addr = line
            .split("http://")
            .nth(1)
            .and_then(|r| r.split('/').next())
            .unwrap_or_else(|| panic!("no address in {line:?}"))
            .to_string();
        Server { child, addr }
    }

    /// One HTTP/1.1 request; the status and the body.
    fn request(&self, method: &str, path: &str, body: &str) -> (u16, String) {
        self.request_as(&self.addr, "", method, path, body)
    }

    /// One HTTP/1.1 request with Host `host` and `headers` (lines ending
    /// in CRLF); the status and the body.
    fn request_as(&self, host: &str, headers: &str, method: &str, path: &str, body: &str) -> (u16, String) {
        let mut s = TcpStream::connect(&self.addr).unwrap();
        write!(
            s,
            "{method} {path} HTTP/1.1\r\nHost: {host}\r\n{headers}Content-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )
        .unwrap();
        let mut text = String::new();
        s.read_to_string(&mut text).unwrap();
        let status = text[9..12].parse().unwrap();
        let body = text.split_once("\r\n\r\n").map(|x| x.1.to_string()).unwrap_or_default();
        (status, body)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn api_simulate_answers_what_simulate_json_prints() {
    let server = Server::start();
    for (body, args) in [
        (
            r#"{"preset": "lab", "style": "right"}"#,
            vec!["simulate", "--preset", "lab", "--style", "right"],
        ),
        (
            r#"{"chart_point": [0.1, 1.2], "style": "wrong", "theta0": 150, "restitution": 0.3, "strokes": 3}"#,
            vec![
                "simulate",
                "--chart-point",
                "0.1,1.2",
                "--style",
                "wrong",
                "--theta0",
                "150",
                "--restitution",
                "0.3",
                "--strokes",
                "3",
            ],
        ),
        (
            r#"{"preset": "gsm-tenor", "contact": "penalty", "stiffness": 1e6, "protocol": "free"}"#,
            vec![
                "simulate",
                "--preset",
                "gsm-tenor",
                "--stiffness",
                "1e6",
                "--protocol",
                "free",
            ],
        ),
    ] {
        let (status, got) = server.request("POST", "/api/simulate", body);
        assert_eq!(status, 200, "{body}: {got}");
        let got: serde_json::Value = serde_json::from_str(&got).unwrap();
        assert_eq!(got, json(&args), "{body}");
    }
}

#[test]
fn bad_requests_do_not_stop_the_server() {
    let server = Server::start();
    for (method, path, body, code) in [
        ("POST", "/api/simulate", "{not json", 400),
        ("POST", "/api/chart", r#"{"grid": [1000, 1000]}"#, 400),
        ("POST", "/api/simulate", r#"{"bell": "bell_mass_kg = -1"}"#, 400),
        ("GET", "/no/such/route", "", 404),
    ] {
        let (status, text) = server.request(method, path, body);
        assert_eq!(status, code, "{method} {path}: {text}");
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(!v["error"].as_str().unwrap().is_empty());
    }
    let (status, _) = server.request("GET", "/api/health", "");
    assert_eq!(status, 200);
}

/// DNS rebinding: a request naming another site's host (or sent from a page
/// at another site) is refused with 403 and the reason; loopback names and
/// IP literals are served, and names given with `--allow-host`.
#[test]
fn other_sites_names_are_refused_and_loopback_served() {
    let server = Server::start_with(&["--allow-host", "bells.example"]);
    let port = server.addr.rsplit(':').next().unwrap().to_string();
    let (status, body) = server.request_as("evil.com", "", "POST", "/api/simulate", "{}");
    assert_eq!(status, 403, "{body}");
    let reason: serde_json::Value = serde_json::from_str(&body).unwrap();
    assert!(reason["error"].as_str().unwrap().contains("--allow-host"), "{body}");
    let (status, _) = server.request_as(&format!("evil.com:{port}"), "", "GET", "/", "");
    assert_eq!(status, 403);
    let origin = "Origin: http://evil.com\r\n";
    let (status, _) = server.request_as(&format!("localhost:{port}"), origin, "POST", "/api/simulate", "{}");
    assert_eq!(status, 403);
    for host in [
        format!("localhost:{port}"),
        server.addr.clone(),
        format!("bells.example:{port}"),
    ] {
        let (status, body) = server.request_as(&host, "", "POST", "/api/simulate", "{}");
        assert_eq!(status, 200, "{host}: {body}");
    }
    let own = format!("Origin: http://localhost:{port}\r\n");
    let (status, _) = server.request_as(&format!("localhost:{port}"), &own, "POST", "/api/simulate", "{}");
    assert_eq!(status, 200);
}

/// Ctrl-C (SIGINT) stops the server while clients hold
/// half-sent requests open (before, one such kept it running).
#[test]
fn ctrl_c_stops_the_server_with_half_sent_requests_open() {
    let mut server = Server::start();
    let mut half = vec![];
    for _ in 0..3 {
        let mut s = TcpStream::connect(&server.addr).unwrap();
        s.write_all(b"POST /api/chart HTTP/1.1\r\nHost: local").unwrap();
        half.push(s);
    }
    std::thread::sleep(std::time::Duration::from_millis(200));
    let t = std::time::Instant::now();
    let ok = Command::new("kill")
        .args(["-INT", &server.child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
    // Stopping at all while the clients still hold their requests is the
    // effect; the polls are a loop bound against a hang, not a timing.
    let mut stopped = None;
    for _ in 0..3000 {
        if let Some(status) = server.child.try_wait().unwrap() {
            stopped = Some(status);
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let status = stopped.expect("still running after 3000 polls since SIGINT");
    println!("stopped {:.2} s after SIGINT ({status})", t.elapsed().as_secs_f64());
    drop(half);
}
