//! Measurement commands through the built binary, on synthetic recordings
//! of known truth (no real recordings come with the project).

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

mod common;
use common::{clapper, json};

/// A uniform number in [-1, 1) (PCG: the same on every machine).
fn uniform(rng: &mut Pcg64) -> f64 {
    rng.random_range(-1.0..1.0)
}

fn write_wav(path: &Path, rate: u32, x: &[f64]) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    let max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for v in x {
        w.write_sample((v / max * 0.9) as f32).unwrap();
    }
    w.finalize().unwrap();
}

fn strike_wav(dir: &Path) -> PathBuf {
    let rate = 22050;
    let mut seed = Pcg64::seed_from_u64(5);
    let x: Vec<f64> = (0..rate * 4)
        .map(|i| {
            let t = i as f64 / rate as f64;
            let p = |f: f64, q: f64, a: f64| a * (-PI * f * t / q).exp() * (2.0 * PI * f * t).sin();
            p(624.0, 1300.0, 1.0) + p(981.0, 1000.0, 0.6) + p(1310.0, 2000.0, 0.4) + 1e-4 * uniform(&mut seed)
        })
        .collect();
    let p = dir.join("strike.wav");
    write_wav(&p, rate, &x);
    p
}

#[test]
fn restitution_from_jumps() {
    let v = json(&["restitution", "--jumps", "1.0,0.35"]);
    assert!((v["ratios"][0][0].as_f64().unwrap() - 0.35).abs() < 1e-12);
    assert!((v["r_equal_loss"].as_f64().unwrap() - 0.1225).abs() < 1e-9);
    assert!((v["r_lossless_later"].as_f64().unwrap() - 0.045).abs() < 5e-4);
}

#[test]
fn restitution_from_a_noisy_accelerometer_drop() {
    let dir = tempfile::tempdir().unwrap();
    let r: f64 = 0.1;
    let (rate, e, g, pulse) = (50000.0, r.sqrt(), 5.0, 4e-4);
    let (mut v, mut t, mut impacts) = (0.5, 0.05, vec![]);
    for _ in 0..5 {
        impacts.push((t, v * (1.0 + e)));
        t += 2.0 * e * v / g;
        v *= e;
    }
    let mut seed = Pcg64::seed_from_u64(9);
    let x: Vec<f64> = (0..((t + 0.05) * rate) as usize)
        .map(|i| {
            let tt = i as f64 / rate;
            let mut a = 0.3 + 0.2 * tt + 30.0 * uniform(&mut seed);
            for &(ti, dv) in &impacts {
                if tt >= ti && tt < ti + pulse {
                    a += dv * PI / (2.0 * pulse) * (PI * (tt - ti) / pulse).sin();
                }
            }
            a
        })
        .collect();
    let p = dir.path().join("drop.wav");
    write_wav(&p, rate as u32, &x);
    let out = json(&["restitution", "--accel", p.to_str().unwrap()]);
    let got = out["r_equal_loss"].as_f64().unwrap();
    assert!((got - r).abs() / r < 0.1, "R {got}");
}

#[test]
fn contacts_within_one_sample() {
    let dir = tempfile::tempdir().unwrap();
    let rate = 10000.0;
    let truth = [(1000usize, 1004usize), (2500, 2504), (3300, 3303), (3700, 9000)];
    let mut seed = Pcg64::seed_from_u64(1);
    let mut csv = String::from("t_s,contact_v\n");
    for i in 0..12000usize {
        let inside = truth.iter().any(|&(a, b)| i >= a && i < b);
        let v = if inside { 0.1 } else { 3.3 } + 0.2 * uniform(&mut seed);
        csv.push_str(&format!("{},{v}\n", i as f64 / rate));
    }
    let p = dir.path().join("contact.csv");
    std::fs::write(&p, csv).unwrap();
    let v = json(&["contacts", p.to_str().unwrap()]);
    let c = v["contacts"].as_array().unwrap();
    assert_eq!(c.len(), 4);
    for (got, &(a, b)) in c.iter().zip(&truth) {
        assert!((got["contact_s"].as_f64().unwrap() - a as f64 / rate).abs() <= 1.0 / rate + 1e-9);
        assert!((got["separation_s"].as_f64().unwrap() - b as f64 / rate).abs() <= 1.0 / rate + 1e-9);
    }
    assert_eq!(v["bounces"], 3);
    assert!((v["time_to_rest_s"].as_f64().unwrap() - 0.27).abs() <= 1.0 / rate + 1e-9);
    assert!((v["liftoff_s"].as_f64().unwrap() - 0.9).abs() <= 1.0 / rate + 1e-9);
}

#[test]
fn modes_spectrogram_and_decay_of_a_strike() {
    let dir = tempfile::tempdir().unwrap();
    let wav = strike_wav(dir.path());
    let v = json(&["modes", wav.to_str().unwrap()]);
    let m = v["modes"].as_array().unwrap();
    assert_eq!(m.len(), 3, "{v}");
    for (got, (f, q)) in m.iter().zip([(624.0, 1300.0), (981.0, 1000.0), (1310.0, 2000.0)]) {
        assert!((got["freq_hz"].as_f64().unwrap() - f).abs() < 0.1);
        assert!((got["q"].as_f64().unwrap() - q).abs() / q < 0.02);
        assert!(got["level_db"].as_f64().unwrap() <= 0.0);
    }
    let png = dir.path().join("s.png");
    clapper()
        .args(["spectrogram", wav.to_str().unwrap(), "--out"])
        .arg(&png)
        .assert()
        .success();
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    let out = clapper()
        .args(["decay", wav.to_str().unwrap(), "--freq", "624", "--csv", "-"])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    // Plain CSV that any reader takes: a header, then numbers only.
    assert_eq!(text.lines().next(), Some("t_s,level_db"));
    let both = clapper()
        .args(["decay", wav.to_str().unwrap(), "--freq", "624", "--csv", "-", "--json"])
        .output()
        .unwrap();
    assert!(!both.status.success());
    assert!(String::from_utf8_lossy(&both.stderr).contains("both want standard output"));
    let rows: Vec<(f64, f64)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let (a, b) = l.split_once(',').unwrap();
            (a.parse().unwrap(), b.parse().unwrap())
        })
        .collect();
    // Falls at 20 pi f / (Q ln 10) = 13.1 dB/s.
    let (a, b) = (rows[4], rows[40]);
    let slope = (b.1 - a.1) / (b.0 - a.0);
    assert!((slope + 13.1).abs() < 1.0, "{slope}");
}

#[test]
fn impulse_energy_into_vibration() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("modes.csv");
    // Five modes with m/M_n = 0.1 for a 1.65 kg clapper: the paper's K of about 0.5.
    std::fs::write(
        &p,
        "freq_hz,effective_mass_kg\n0.5,16.5\n624,16.5\n981,16.5\n1310,16.5\n1800,16.5\n",
    )
    .unwrap();
    let v = json(&["impulse", "--modes", p.to_str().unwrap(), "--clapper-mass", "1.65"]);
    assert!((v["k"].as_f64().unwrap() - 0.5).abs() < 1e-9);
    assert!((v["r"].as_f64().unwrap() - (1.0f64 / 3.0).powi(2)).abs() < 1e-9);
    assert_eq!(v["strongly_excited_modes"], 5);
    let v = json(&[
        "impulse",
        "--modes",
        p.to_str().unwrap(),
        "--clapper-mass",
        "5",
        "--pulse-ms",
        "0.5",
        "--hammer-fmax",
        "2000",
    ]);
    assert!(v["k"].as_f64().unwrap() < 5.0 / 16.5 * 5.0);
    assert!(v["shortest_clean_pulse_ms"].as_f64().unwrap() > 0.0);
    assert!(v["hammer"]["heaviest_clean_hammer_kg"].as_f64().unwrap() > 0.0);
}

#[test]
fn bad_recordings_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let put = |name: &str, bytes: &[u8]| {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        p.to_str().unwrap().to_string()
    };
    let not_wav = put("x.wav", b"RIFF nonsense");
    let empty = put("e.wav", b"");
    let cols = put("c.csv", b"only\n1\n2\n");
    let nan = put("n.csv", b"t,v\n0,1\n0.001,NaN\n0.002,1\n");
    let modes = put("m.csv", b"frequency,mass\n1,2\n");
    for (args, needle) in [
        (vec!["modes", not_wav.as_str()], "not a WAV"),
        (vec!["spectrogram", empty.as_str(), "--out", "x.png"], "not a WAV"),
        (vec!["contacts", cols.as_str()], "value column"),
        (vec!["decay", nan.as_str(), "--freq", "10"], "not finite"),
        (vec!["restitution", "--accel", nan.as_str()], "not finite"),
        (vec!["restitution", "--jumps", "1,x"], "not a number"),
        (vec!["restitution", "--jumps", "1"], "at least two"),
        (
            vec!["impulse", "--modes", modes.as_str(), "--clapper-mass", "1"],
            "row 1",
        ),
        (vec!["modes", "missing.wav"], "missing.wav"),
    ] {
        let out = clapper().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn the_shipped_sample_data_is_what_sample_data_writes() {
    let dir = tempfile::tempdir().unwrap();
    let out = clapper()
        .args(["sample-data", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data");
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert!(names.len() >= 8);
    for name in names {
        let made = std::fs::read(dir.path().join(&name)).unwrap();
        let committed = std::fs::read(shipped.join(&name)).unwrap_or_default();
        assert!(made == committed, "examples/data/{name:?} differs from what sample-data writes: run `clapper sample-data --out examples/data`");
    }
}
