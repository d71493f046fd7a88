//! Issue 19's speed check: strikes found in ten minutes of a synthetic
//! 8-bell ring (plain hunt, 25 dB SNR, RT60 1.2 s) at 22.05 and 44.1 kHz.
//! The recording is made once, outside the timing; criterion runs on the
//! one thread the finder uses (it is not parallel).
//!
//! cargo bench -p clapper-signal --bench strikes
use clapper_signal::strikes::{find_strikes, BellVoice, StrikeOptions};
use clapper_signal::tower::*;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

/// Ten minutes of ringing: 8 bells, 0.22 s apart, 17 strikes a row pair
/// with the handstroke gap, so 326 rows.
fn ten_minutes(rate: f64) -> TowerSpec {
    TowerSpec {
        rate,
        rows: 326,
        jitter: 0.02,
        method: Method::PlainHunt,
        room: Some(Room::chamber(1.2)),
        snr_db: Some(25.0),
        ..TowerSpec::new(major_scale(8, 1400.0).expect("at most 16 bells"))
    }
}

fn strikes(c: &mut Criterion) {
    let mut g = c.benchmark_group("strikes in 10 minutes of 8 bells");
    g.sample_size(10);
    for rate in [22_050.0, 44_100.0] {
        let spec = ten_minutes(rate);
        let (sig, _) = tower_recording(&spec).expect("a valid spec");
        assert!(sig.duration() >= 600.0, "{} s", sig.duration());
        let voices: Vec<BellVoice> = spec
            .bells
            .iter()
            .map(|b| BellVoice::from_nominal(b.nominal_hz))
            .collect();
        g.bench_function(format!("{} kHz", rate / 1000.0), |b| {
            b.iter(|| find_strikes(black_box(&sig), black_box(&voices), &StrikeOptions::default()).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, strikes);
criterion_main!(benches);
