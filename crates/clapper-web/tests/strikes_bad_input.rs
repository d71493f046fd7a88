//! `POST /api/strikes` over a real socket on what is not a ring (issue 43's
//! acceptance): silence, one bell and speech are answered 200 with the
//! same clear warning first that `clapper strikes` gives
//! (crates/clapper-cli/tests/strikes_bad_input.rs), a nominal the recording
//! cannot hold 400 with the reason; never a panic, and the server answers
//! after.

mod common;

use std::time::Duration;

use clapper_signal::tower::*;
use clapper_signal::Signal;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use serde_json::Value;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

const RATE: f64 = 22_050.0;
const EIGHT: &str = "1400,1247.3,1111.2,1048.8,934.4,832.4,741.6,700";

/// (status, JSON body) of a recording posted to `/api/strikes` with its
/// bells' `nominals` (Hz, treble first, and any further query).
async fn post_wav(addr: std::net::SocketAddr, nominals: &str, sig: &Signal) -> (u16, Value) {
    post_query(addr, &format!("nominals={nominals}"), sig).await
}

/// (status, JSON body) of a recording posted to `/api/strikes?QUERY`.
async fn post_query(addr: std::net::SocketAddr, query: &str, sig: &Signal) -> (u16, Value) {
    let wav = clapper_io::signal_file::wav_bytes(sig, 0.8).unwrap();
    let mut s = TcpStream::connect(addr).await.unwrap();
    let head = format!(
        "POST /api/strikes?{query} HTTP/1.1\r\nHost: localhost\r\nContent-Type: audio/wav\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        wav.len()
    );
    s.write_all(head.as_bytes()).await.unwrap();
    s.write_all(&wav).await.unwrap();
    let mut out = Vec::new();
    // Bounded only to turn a hang into a failure.
    tokio::time::timeout(Duration::from_secs(300), s.read_to_end(&mut out))
        .await
        .unwrap()
        .unwrap();
    let text = String::from_utf8_lossy(&out);
    let status: u16 = text.split(' ').nth(1).unwrap().parse().unwrap();
    let body = text.split("\r\n\r\n").nth(1).unwrap_or("");
    let v = serde_json::from_str(body).unwrap_or_else(|e| panic!("not JSON ({e}): {text}"));
    (status, v)
}

fn warnings(v: &Value) -> Vec<String> {
    v["report"]["summary"]["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect()
}

/// A uniform number in [0, 1) (PCG: the same on every machine).
fn uniform(s: &mut Pcg64) -> f64 {
    s.random()
}

/// Speech-like sound: a glottal pulse train at 100-200 Hz, its pitch
/// gliding, through three vowel formant resonators per syllable; pauses;
/// noise bursts as consonants (the CLI test's generator).
fn speech(seconds: f64, seed: u64) -> Signal {
    const VOWELS: [[f64; 3]; 5] = [
        [730.0, 1090.0, 2440.0],
        [270.0, 2290.0, 3010.0],
        [300.0, 870.0, 2240.0],
        [530.0, 1840.0, 2480.0],
        [570.0, 840.0, 2410.0],
    ];
    let mut s = Pcg64::seed_from_u64(seed);
    let mut out = vec![0.0; (seconds * RATE) as usize];
    let mut t = 0.3;
    while t < seconds - 0.6 {
        let syl = 0.12 + 0.18 * uniform(&mut s);
        let (i0, i1) = ((t * RATE) as usize, ((t + syl) * RATE) as usize);
        if uniform(&mut s) < 0.6 {
            let b = ((0.02 + 0.04 * uniform(&mut s)) * RATE) as usize;
            for v in &mut out[i0 - b..i0] {
                *v += 0.3 * (2.0 * uniform(&mut s) - 1.0);
            }
        }
        let (f0, glide) = (100.0 + 100.0 * uniform(&mut s), 1.0 + 2.0 * uniform(&mut s));
        let vowel = VOWELS[(uniform(&mut s) * 5.0) as usize];
        let len = i1 - i0;
        let mut src = vec![0.0; len];
        let mut phase = 0.0f64;
        for k in 0..len {
            let next = phase + f0 * (1.0 + 0.2 * (glide * k as f64 / len as f64).sin()) / RATE;
            if next.floor() > phase.floor() {
                for (j, v) in src[k..len.min(k + 40)].iter_mut().enumerate() {
                    *v += (-(j as f64) / 8.0).exp();
                }
            }
            phase = next;
        }
        for (f, bw) in vowel.iter().zip([80.0, 100.0, 120.0]) {
            let r = (-std::f64::consts::PI * bw / RATE).exp();
            let c = 2.0 * r * (2.0 * std::f64::consts::PI * f / RATE).cos();
            let (mut z1, mut z2) = (0.0, 0.0);
            let y: Vec<f64> = src
                .iter()
                .map(|x| {
                    let v = x + c * z1 - r * r * z2;
                    z2 = z1;
                    z1 = v;
                    v
                })
                .collect();
            let peak = y.iter().fold(1e-9f64, |m, v| m.max(v.abs()));
            for (k, v) in y.iter().enumerate() {
                let hann = 0.5 - 0.5 * (2.0 * std::f64::consts::PI * k as f64 / (len - 1) as f64).cos();
                out[i0 + k] += v / peak * hann;
            }
        }
        t += syl
            + if uniform(&mut s) < 0.3 {
                0.2 + 0.4 * uniform(&mut s)
            } else {
                0.02 + 0.06 * uniform(&mut s)
            };
    }
    for v in &mut out {
        *v += 0.003 * (2.0 * uniform(&mut s) - 1.0);
    }
    Signal {
        rate: RATE,
        samples: out,
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn silence_one_bell_and_speech_are_answered_with_a_warning_first() {
    let addr = common::start().await;
    let silence = Signal {
        rate: RATE,
        samples: vec![0.0; 10 * RATE as usize],
    };
    // wav_bytes scales to its peak: silence is sent as it is, all zeros.
    let (status, v) = post_wav(addr, EIGHT, &silence).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(warnings(&v)[0], "the recording is silent");
    // Nothing to learn the bells from: a report of none, as the CLI's
    // (session 19: an error here).
    let (status, v) = post_query(addr, "bells=6", &silence).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["report"]["summary"]["strikes"], 0);
    assert_eq!(warnings(&v)[0], "the recording is silent");

    for seed in [7, 8] {
        let (status, v) = post_wav(addr, EIGHT, &speech(12.0, seed)).await;
        assert_eq!(status, 200, "{v}");
        let said = warnings(&v);
        let no_strikes = v["report"]["summary"]["strikes"] == 0 && said[0].starts_with("no strikes heard");
        assert!(
            no_strikes || said[0].starts_with("this does not sound like a recording of bells"),
            "seed {seed}: {said:?}"
        );
    }

    // One bell, struck every second: its strikes listed, and warned of.
    let spec = TowerSpec {
        rate: RATE,
        rows: 12,
        interval: 1.0,
        snr_db: Some(30.0),
        ..TowerSpec::new(major_scale(1, 1400.0).unwrap())
    };
    let (one, _) = tower_recording(&spec).unwrap();
    let (status, v) = post_wav(addr, "1400", &one).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["report"]["summary"]["strikes"], 12);
    assert!(
        warnings(&v)
            .iter()
            .any(|w| w.starts_with("one bell: its strikes are listed")),
        "{:?}",
        warnings(&v)
    );

    // A nominal above what the recording holds: refused, with the reason.
    let low = Signal {
        rate: 8000.0,
        samples: speech(3.0, 1).samples,
    };
    let (status, v) = post_wav(addr, "1400,5000", &low).await;
    assert_eq!(status, 400, "{v}");
    assert!(
        v["error"]
            .as_str()
            .unwrap()
            .contains("bell 2's strongest partial, 5000 Hz"),
        "{v}"
    );

    // A channel the recording lacks, or not a channel: refused, as `--channel`.
    let (status, v) = post_wav(addr, "1400&channel=2", &one).await;
    assert_eq!(status, 400, "{v}");
    assert!(
        v["error"]
            .as_str()
            .unwrap()
            .contains("channel 2 asked, the recording has 1"),
        "{v}"
    );
    let (status, v) = post_wav(addr, "1400&channel=left", &one).await;
    assert_eq!(status, 400, "{v}");
    assert_eq!(
        post_wav(addr, "1400&channel=1", &one).await.1["report"]["summary"]["strikes"],
        12
    );
}
