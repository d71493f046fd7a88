//! `POST /api/strikes` times the strikes as `clapper strikes` does (issue
//! 43): `timing=auto` by default, chosen from the recording by the one
//! function the CLI and Python call, so the three give the same strikes.

use axum::http::StatusCode;
use clapper_app::strikes::{choose_timing, opening, strike_options, StrikesReport, TimingAsked, Voice};
use clapper_signal::sampled_ring::{sampled_ring, UntunedStrike};
use clapper_signal::tower::{major_scale, Method, TowerSpec};
use clapper_web::{router, Limits};
use serde_json::Value;

mod common;
use common::send_wav;

#[tokio::test]
async fn the_api_chooses_the_timing_as_the_cli_does() {
    // Five bells at a recorded tower bell's ratios, each building up after
    // the blow by its own time: heard as a tuned bell's, each is late by
    // its own constant.
    let rate = 16_000.0;
    let bells = major_scale(5, 1000.0).unwrap();
    let nominals: Vec<f64> = bells.iter().map(|b| b.nominal_hz).collect();
    let strikes: Vec<_> = nominals
        .iter()
        .zip([0.01, 0.06, 0.02, 0.045, 0.03])
        .map(|(&f, r)| UntunedStrike::with_noisy_blow(f, r).signal(rate))
        .collect();
    let spec = TowerSpec {
        rate,
        rows: 24,
        interval: 0.3,
        method: Method::PlainHunt,
        snr_db: Some(25.0),
        ..TowerSpec::new(bells)
    };
    let sig = sampled_ring(&spec, &strikes).unwrap().0;
    let wav = clapper_io::signal_file::wav_bytes(&sig, 0.5).unwrap();
    // What the API hears is what the library hears in the WAV's samples.
    let sig = clapper_io::signal_file::recording_from_bytes(&wav, "ring").unwrap();
    let given: Vec<String> = nominals.iter().map(|f| format!("{f}")).collect();
    let app = router(Limits::default());
    let uri = format!("/api/strikes?nominals={}", given.join(","));
    let (status, body) = send_wav(&app, &uri, wav.clone()).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let v: Value = serde_json::from_slice(&body).unwrap();
    let report = &v["report"];
    assert_eq!(report["timing"]["choice"]["used"], "recording", "{}", report["timing"]);
    let opts = strike_options(0.3).unwrap();
    let c = choose_timing(&opening(&sig), &nominals, Voice::Tower, TimingAsked::Auto, &opts).unwrap();
    let mut lib = StrikesReport::timed(&sig, &c.voices, &opts, c.timing()).unwrap();
    lib.note_choice(c.choice);
    assert_eq!(*report, serde_json::to_value(&lib).unwrap());
    // Asked plain, plain; asked something else, refused.
    let (status, body) = send_wav(&app, &format!("{uri}&timing=plain"), wav.clone()).await;
    assert_eq!(status, StatusCode::OK);
    let v: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(v["report"]["timing"]["choice"]["used"], "plain");
    let (status, body) = send_wav(&app, &format!("{uri}&timing=sometimes"), wav).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(String::from_utf8_lossy(&body).contains("auto, plain or recording"));
}
