//! Synthesis round trips and the listening test, through the built binary.

use std::path::Path;

mod common;
use common::{clapper, json};

fn read_wav(p: &Path) -> Vec<f64> {
    let mut r = hound::WavReader::open(p).unwrap();
    r.samples::<i16>().map(|s| f64::from(s.unwrap())).collect()
}

#[test]
fn synth_round_trip_recovers_modes_qs_and_the_moment_of_rest() {
    let dir = tempfile::tempdir().unwrap();
    let chime = dir.path().join("chime.wav");
    let full = dir.path().join("full.wav");
    let c = chime.to_str().unwrap();
    let f = full.to_str().unwrap();
    json(&["synth", "--preset", "lab", "--chime", "--out", c]);
    let v = json(&["modes", c]);
    let modes = v["modes"].as_array().unwrap();
    for (freq, q) in [(624.0, 1300.0), (981.0, 1000.0), (1310.0, 2000.0)] {
        // Each doublet shows as two members within 0.1 % of the mode.
        let near: Vec<&serde_json::Value> = modes
            .iter()
            .filter(|m| (m["freq_hz"].as_f64().unwrap() - freq).abs() < 1e-3 * freq)
            .collect();
        assert!(!near.is_empty(), "{freq} Hz missing from {v}");
        for m in near {
            let got = m["q"].as_f64().unwrap();
            assert!((got - q).abs() / q < 0.10, "{freq} Hz: Q {got} vs {q}");
        }
    }
    let s = json(&["synth", "--preset", "lab", "--strokes", "1", "--out", f]);
    let rest = s["rest_after_first_strike_s"][0].as_f64().unwrap();
    // A resting clapper damps every mode from the same moment; bounces just
    // before can only delay the change a partial shows: take the earliest.
    let found = [624.0, 981.0, 1310.0]
        .iter()
        .map(|fr| {
            let d = json(&["decay", f, "--freq", &fr.to_string(), "--window", "1024"]);
            d["rate_change"]["t_s"].as_f64().unwrap()
        })
        .fold(f64::INFINITY, f64::min);
    assert!((found - rest).abs() < 0.020, "rest at {rest} s, found {found} s");
}

#[test]
fn listening_stimuli_have_the_ratio_and_delay_they_claim() {
    let dir = tempfile::tempdir().unwrap();
    clapper()
        .args([
            "listening-test",
            "make",
            "--seed",
            "3",
            "--listeners",
            "2",
            "--rate",
            "22050",
            "--out",
        ])
        .arg(dir.path())
        .assert()
        .success();
    let reference = read_wav(&dir.path().join("reference.wav"));
    let index = std::fs::read_to_string(dir.path().join("stimuli.csv")).unwrap();
    let rows: Vec<Vec<String>> = index
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 100);
    for row in rows.iter().step_by(7) {
        let (ratio, delay_ms): (f64, f64) = (row[1].parse().unwrap(), row[2].parse().unwrap());
        let x = read_wav(&dir.path().join(&row[0]));
        // x = s + A s(t − Δ): for each Δ, A by least squares; keep the best Δ.
        let best = (0..2400usize)
            .map(|lag| {
                let (mut num, mut den, mut res0) = (0.0, 0.0, 0.0);
                for i in 0..x.len() {
                    let d = x[i] - reference[i];
                    let sh = if i >= lag { reference[i - lag] } else { 0.0 };
                    num += d * sh;
                    den += sh * sh;
                    res0 += d * d;
                }
                let a = num / den;
                (res0 - a * num, lag, a)
            })
            .min_by(|p, q| p.0.total_cmp(&q.0))
            .unwrap();
        let measured_ms = best.1 as f64 / 22050.0 * 1e3;
        assert!(
            (measured_ms - delay_ms).abs() <= 1.0 / 22.05 + 1e-9,
            "{row:?}: delay {measured_ms} ms"
        );
        assert!((best.2 - ratio).abs() < 0.01, "{row:?}: ratio {}", best.2);
    }
    // Every sheet holds the 100 stimuli once, each in its own order.
    let a = std::fs::read_to_string(dir.path().join("answers-listener01.csv")).unwrap();
    let b = std::fs::read_to_string(dir.path().join("answers-listener02.csv")).unwrap();
    assert_eq!(a.lines().count(), 101);
    assert_ne!(
        a.lines().nth(1),
        b.lines()
            .nth(1)
            .map(|l| l.replace("listener02", "listener01"))
            .as_deref()
    );
}

#[test]
fn listening_analysis_recovers_a_known_hyperbola() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, c, w) = (0.25, 18.0, 3.0, 1.2);
    let mut rng = <rand_pcg::Pcg64 as rand::SeedableRng>::seed_from_u64(42);
    let mut rnd = || rand::Rng::random::<f64>(&mut rng);
    let mut csv = String::from("listener,trial,stimulus,amplitude_ratio,delay_ms,answer\n");
    for l in 0..40 {
        for i in 1..=10 {
            for j in 1..=10 {
                let (r, d) = (0.1 * i as f64, 10.0 * j as f64);
                let p_double = 1.0 / (1.0 + (-((r - a) * (d - b) - c) / w).exp());
                let mut ans = if rnd() < p_double { -1 } else { 1 };
                if l >= 38 {
                    ans = -ans; // two listeners who hear it the other way round
                }
                csv.push_str(&format!("L{l},0,x,{r:.1},{d:.0},{ans}\n"));
            }
        }
    }
    let p = dir.path().join("answers.csv");
    std::fs::write(&p, csv).unwrap();
    let png = dir.path().join("fig13.png");
    let v = json(&[
        "listening-test",
        "analyse",
        p.to_str().unwrap(),
        "--plot",
        png.to_str().unwrap(),
    ]);
    assert_eq!(v["excluded"].as_array().unwrap().len(), 2);
    let fit = &v["fit"];
    for (key, sig, want) in [
        ("a", "sigma_a", a),
        ("b_ms", "sigma_b_ms", b),
        ("c_ms", "sigma_c_ms", c),
    ] {
        let (est, s) = (fit[key].as_f64().unwrap(), fit[sig].as_f64().unwrap());
        assert!((est - want).abs() <= 2.5 * s, "{key}: {est} +- {s} vs {want}");
    }
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    // Bad answer files.
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "listener,amplitude_ratio,delay_ms,answer\nx,0.15,10,1\n").unwrap();
    let out = clapper()
        .args(["listening-test", "analyse"])
        .arg(&bad)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("grid"));
}
