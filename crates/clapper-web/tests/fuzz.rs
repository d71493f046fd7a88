//! Fuzzing the server's JSON requests: valid bodies with bytes changed, cut
//! short or spliced, and arbitrary bytes, to every route that takes a body.
//! Every answer must be a 2xx or a 4xx with a one-line JSON message; never
//! a 5xx, a panic or a hang. FUZZ_CASES cases (default 256).

use axum::body::Body;
use axum::http::Request;
use clapper_web::{router, Limits};
use http_body_util::BodyExt;
use proptest::prelude::*;
use proptest::test_runner::Config;
use tower::ServiceExt;

const BODIES: [(&str, &str); 8] = [
    (
        "/api/animate",
        r#"{"bells": [{"preset": "lab", "strokes": 1}], "fps": 20}"#,
    ),
    (
        "/api/simulate",
        r#"{"preset": "lab", "style": "wrong", "theta0": 150, "restitution": 0.3, "strokes": 3}"#,
    ),
    (
        "/api/stroke",
        r#"{"chart_point": [0.45, 1.68], "contact": "penalty", "stiffness": 1e6}"#,
    ),
    (
        "/api/chart",
        r#"{"grid": [4, 3], "r_range": [-0.3, 0.7], "lb_range": [0.5, 2.5], "theta0": 171}"#,
    ),
    (
        "/api/diagnose",
        r#"{"csv": "name,bell_period_s,clapper_period_s,r_m,phi_max_deg\nA,2.0,1.5,0.1,26\n"}"#,
    ),
    (
        "/api/diagnose",
        r#"{"toml": "name = \"T\"\nbell_period_s = 2.33\nclapper_period_s = 1.76\nr_m = 0.179\nphi_max_deg = 32\n"}"#,
    ),
    (
        "/api/listening/analyse",
        r#"{"answers": [{"listener": "a", "amplitude_ratio": 0.5, "delay_ms": 40, "answer": -1}]}"#,
    ),
    (
        "/api/listening/parse",
        r#"{"csv": "listener,amplitude_ratio,delay_ms,answer\nA,0.5,30,1\n"}"#,
    ),
];

fn cases() -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

/// Digits changed for digits or signs: the request stays JSON, its numbers go anywhere.
fn number_edits(valid: Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    let len = valid.len();
    prop::collection::vec((0..len, any::<u8>()), 1..6).prop_map(move |edits| {
        let mut v = valid.clone();
        for (i, b) in edits {
            if v[i].is_ascii_digit() {
                const NUMERIC: &[u8] = b"0123456789-e.";
                v[i] = NUMERIC[b as usize % NUMERIC.len()];
            }
        }
        v
    })
}

/// Any bytes changed, then cut short or a tail repeated.
fn byte_edits(valid: Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    let len = valid.len();
    (
        prop::collection::vec((0..len, any::<u8>()), 0..5),
        0..=len,
        any::<bool>(),
        0..len,
    )
        .prop_map(move |(edits, cut, splice, at)| {
            let mut v = valid.clone();
            for (i, b) in edits {
                // Mostly JSON-ish bytes, so the mutation reaches the fields.
                const JSONISH: &[u8] = b"0123456789-.e,:[]{}\" truenlfa";
                v[i] = JSONISH[b as usize % JSONISH.len()];
            }
            if splice {
                let piece = v[at..].to_vec();
                v.splice(at..at, piece);
            } else {
                v.truncate(cut);
            }
            v
        })
}

/// A JSON object of the route's own keys (and a stranger), with values
/// from the edges: zero, negative, huge, tiny, wrong types, empty.
fn typed_object() -> impl Strategy<Value = Vec<u8>> {
    const KEYS: &[&str] = &[
        "preset",
        "bell",
        "chart_point",
        "style",
        "theta0",
        "restitution",
        "phi_max",
        "strokes",
        "protocol",
        "contact",
        "stiffness",
        "rtol",
        "grid",
        "r_range",
        "lb_range",
        "toml",
        "csv",
        "answers",
        "colour",
    ];
    const VALUES: &[&str] = &[
        "0",
        "-1",
        "1e308",
        "-1e308",
        "1e-320",
        "179.99999",
        "180",
        "1",
        "0.5",
        "1e9",
        "1e10",
        "2",
        "1000000",
        "\"lab\"",
        "\"gsm-tenor\"",
        "\"right\"",
        "\"wrong\"",
        "\"free\"",
        "\"penalty\"",
        "\"impact\"",
        "\"\"",
        "null",
        "true",
        "[]",
        "[0.45, 1.68]",
        "[-1e9, 1e9]",
        "[3, 2]",
        "[0, 5]",
        "[200, 201]",
        "[1, 2, 3]",
        "{}",
        "\"name,r_m\\nA,0.1\\n\"",
        "\"bell_period_s = -2\"",
        "[{\"listener\": \"a\", \"amplitude_ratio\": 2, \"delay_ms\": -5, \"answer\": 1}]",
    ];
    prop::collection::vec((0..KEYS.len(), 0..VALUES.len()), 0..6).prop_map(|kv| {
        let fields: Vec<String> = kv
            .iter()
            .map(|(k, v)| format!("\"{}\": {}", KEYS[*k], VALUES[*v]))
            .collect();
        format!("{{{}}}", fields.join(", ")).into_bytes()
    })
}

fn body() -> impl Strategy<Value = (usize, Vec<u8>)> {
    (0..BODIES.len()).prop_flat_map(|k| {
        let valid = BODIES[k].1.as_bytes().to_vec();
        (
            Just(k),
            prop_oneof![
                3 => number_edits(valid.clone()),
                3 => typed_object(),
                2 => byte_edits(valid),
                1 => prop::collection::vec(any::<u8>(), 0..200)
            ],
        )
    })
}

proptest! {
    #![proptest_config(Config { cases: cases(), ..Config::default() })]

    #[test]
    fn no_request_body_breaks_the_server((k, bytes) in body()) {
        // Small limits keep a mutated but valid request cheap.
        let app = router(Limits { max_chart_points: 400, max_strokes: 10, ..Limits::default() });
        let rt = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
        let (status, text) = rt.block_on(async {
            let req = Request::post(BODIES[k].0)
                .header("content-type", "application/json")
                .body(Body::from(bytes.clone()))
                .unwrap();
            let res = app.oneshot(req).await.unwrap();
            let status = res.status();
            let text = res.into_body().collect().await.unwrap().to_bytes();
            (status, String::from_utf8_lossy(&text).into_owned())
        });
        if std::env::var("FUZZ_VERBOSE").is_ok() {
            eprintln!("fuzz-status {} {}", BODIES[k].0, status.as_u16());
        }
        prop_assert!(status.is_success() || status.is_client_error(), "{} {}: {status} {text}", BODIES[k].0, String::from_utf8_lossy(&bytes));
        if status.is_client_error() {
            let v: serde_json::Value = serde_json::from_str(&text).unwrap();
            let m = v["error"].as_str().unwrap_or_default();
            prop_assert!(!m.is_empty() && !m.contains('\n'), "{m:?}");
        }
    }
}
