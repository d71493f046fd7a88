//! `clapper strikes` on what is not a recording of bells (issue 46): a
//! 1400 Hz square wave gave "74 strikes, 8 doubles" without a word, and
//! noise is no ring either. Each is now said not to sound like bells
//! (text and JSON: `summary.plausibility` under 0.5 and the warning first),
//! or heard as no strikes at all; a synthetic ring is not warned of.

mod common;
use common::clapper;

const EIGHT: &str = "1400.0,1247.3,1111.2,1048.8,934.4,832.4,741.6,700.0";
const WARNING: &str = "this does not sound like a recording of bells";

/// A 16-bit mono WAV at 22.05 kHz of 30 s of `f(sample)`.
fn wav(path: &std::path::Path, mut f: impl FnMut(usize) -> f64) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 22_050,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for i in 0..30 * 22_050 {
        w.write_sample((f(i).clamp(-1.0, 1.0) * 32_767.0 * 0.3) as i16).unwrap();
    }
    w.finalize().unwrap();
}

/// (text, JSON) of `clapper strikes` on `path` for `nominals`.
fn heard(path: &std::path::Path, nominals: &str) -> (String, serde_json::Value) {
    let run = |json: bool| {
        let mut c = clapper();
        c.arg("strikes").arg(path).args(["--nominals", nominals]);
        if json {
            c.arg("--json");
        }
        let out = c.output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    (run(false), serde_json::from_str(&run(true)).unwrap())
}

fn strikes_of(j: &serde_json::Value) -> u64 {
    j["summary"]["strikes"].as_u64().unwrap()
}

#[test]
fn a_square_wave_is_said_not_to_sound_like_bells() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("square.wav");
    // As one makes it, by the sign of a sine: where the sine is 0 (every
    // 63 samples, four periods) rounding takes either sign, clicks the
    // finder hears as strikes (a square wave made exact gives none).
    let tau = std::f64::consts::TAU;
    wav(&p, |i| {
        if (tau * 1400.0 * i as f64 / 22_050.0).sin() >= 0.0 {
            1.0
        } else {
            -1.0
        }
    });
    for nominals in ["1400", "700,1400", "2800,1400"] {
        let (text, j) = heard(&p, nominals);
        // Strikes are heard (the square wave's level wanders)...
        assert!(strikes_of(&j) > 0, "{nominals}: {text}");
        // ... but said not to be bells'.
        assert!(text.contains(&format!("warning: {WARNING}")), "{nominals}: {text}");
        assert!(j["summary"]["plausibility"].as_f64().unwrap() < 0.5, "{nominals}: {j}");
        let first = j["summary"]["warnings"][0].as_str().unwrap();
        assert!(first.starts_with(WARNING), "{nominals}: {first}");
    }
}

#[test]
fn noise_gives_no_confident_strikes() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("noise.wav");
    // Gaussian noise (Box-Muller on a seeded PCG: the same every run).
    let mut rng = <rand_pcg::Pcg64 as rand::SeedableRng>::seed_from_u64(1);
    let mut uniform = move || 1.0 - rand::Rng::random::<f64>(&mut rng);
    wav(&p, |_| {
        let (u, v) = (uniform(), uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos() / 3.0
    });
    for nominals in ["1400", "700,1400", EIGHT] {
        let (text, j) = heard(&p, nominals);
        let warned = text.contains(WARNING) && j["summary"]["plausibility"].as_f64().unwrap() < 0.5;
        assert!(strikes_of(&j) == 0 || warned, "{nominals}: {text}");
    }
}

#[test]
fn a_synthetic_ring_is_not_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("ring.wav");
    clapper()
        .args(["synth-ring", "--rows", "16", "--rt60", "1.2", "--snr", "20", "--out"])
        .arg(&p)
        .assert()
        .success();
    let (text, j) = heard(&p, EIGHT);
    assert_eq!(strikes_of(&j), 128, "{text}");
    assert!(!text.contains(WARNING), "{text}");
    assert!(j["summary"]["plausibility"].as_f64().unwrap() >= 0.9, "{j}");
}
