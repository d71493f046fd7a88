//! One ring built from real recorded strikes (issue 43's ring builder,
//! `clapper_signal::sampled_ring`), written out as files so that any
//! listener (clapper's CLI, a peer) hears the same recording:
//! `OUT/ring.wav` (16-bit), `OUT/truth.csv` (the columns `clapper
//! synth-ring --truth` writes), `OUT/templates/1.wav ..` (each bell's
//! recorded strike, treble first, for `--templates`) and
//! `OUT/nominals.txt` (each bell's nominal, Hz, comma separated, for
//! `--nominals`). Used by `bench/strikes`.
//!
//! cargo run --release -p clapper-app --example ring_files -- FOLDER OUT [--bells N] [--order pitch|name] [--nominals F1,F2,..] [--method rounds|plain-hunt] [--rows R] [--rt60 S] [--dark-tail D] [--drr DB] [--reflections MS:GAIN,..] [--snr DB] [--seed S]
//!
//! The ring is `real_rings`'s: a 2 s row, striking errors within ±20 ms,
//! bell 3 25 ms odd-struck, six doubles of 45-90 ms and ratio 0.5-1.0.
//! `--reflections 7:0.5,13:0.35,21:0.3` adds discrete early reflections
//! (delay ms, gain against the direct sound; at most four) to the room,
//! with or without its diffuse tail (`--rt60 0`).
//! No recordings ship with the project: docs/strikes.md names the ones
//! measured.

use std::path::{Path, PathBuf};

use clapper_signal::sampled_ring::{sample_onset, sampled_ring};
use clapper_signal::strikes::BellVoice;
use clapper_signal::tower::*;
use clapper_signal::Signal;

fn main() {
    let v: Vec<String> = std::env::args().skip(1).collect();
    let get = |k: &str| v.iter().position(|a| a == k).and_then(|i| v.get(i + 1)).cloned();
    let num = |k: &str, d: f64| get(k).map_or(d, |s| s.parse().expect("a number"));
    let folder = PathBuf::from(v.first().expect("FOLDER: WAV files, one recorded strike per bell"));
    let out = PathBuf::from(v.get(1).expect("OUT: the folder to write the ring to"));
    let n = num("--bells", 8.0) as usize;
    let method = match get("--method").as_deref() {
        Some("plain-hunt") => Method::PlainHunt,
        _ => Method::Rounds,
    };
    let seed = num("--seed", 1.0) as u64;
    let room = room_of(&get, &num);
    let snr = num("--snr", 25.0);

    let mut keyed: Vec<(f64, String, Signal)> = load(&folder)
        .into_iter()
        .map(|(name, s)| (strongest_hz(&s), name, s))
        .collect();
    if get("--order").as_deref() == Some("name") {
        keyed.sort_by_key(|x| first_number(&x.1));
    } else {
        keyed.sort_by(|x, y| y.0.total_cmp(&x.0));
    }
    keyed.truncate(n);
    assert_eq!(keyed.len(), n, "not enough recordings in the folder");
    let strikes: Vec<Signal> = keyed.iter().map(|k| k.2.clone()).collect();
    // Nominals given (each moved to the strike's spectral peak within 2 %),
    // else each bell's strongest partial: what `real_rings` gives.
    let nominals: Vec<f64> = match get("--nominals") {
        Some(s) => s
            .split(',')
            .zip(&strikes)
            .map(|(f, s)| peak_near(s, f.parse().expect("a nominal")))
            .collect(),
        None => keyed.iter().map(|k| k.0).collect(),
    };

    let mut bells = major_scale(n, 1000.0).expect("at most 16 bells");
    bells[2].odd_struck_ms = 25.0;
    let spec = TowerSpec {
        rate: strikes[0].rate,
        rows: num("--rows", 24.0) as usize,
        interval: 2.0 / (n as f64 + 1.0),
        jitter: 0.02,
        seed,
        doubles: (0..6)
            .map(|k| DoubleStrikeSpec {
                bell: 1 + (k * 3 + seed as usize) % n,
                row: 2 + k * 4 - (k % 2),
                delay_ms: 45.0 + 9.0 * k as f64,
                amplitude_ratio: 0.5 + 0.1 * k as f64,
            })
            .collect(),
        method,
        room,
        snr_db: Some(snr),
        ..TowerSpec::new(bells)
    };
    let (sig, truth) = sampled_ring(&spec, &strikes).expect("a ring");

    write_ring(&out, &sig, &strikes, &truth, &nominals);
    println!(
        "wrote {} ({:.1} s, {} strikes of {n} bells: {})",
        out.display(),
        sig.duration(),
        truth.len(),
        keyed.iter().map(|k| k.1.as_str()).collect::<Vec<_>>().join(" ")
    );
}

/// The room asked (`--rt60 S`, `--dark-tail D`, `--drr DB`,
/// `--reflections MS:GAIN,..`), none if dry and without reflections.
fn room_of(get: &dyn Fn(&str) -> Option<String>, num: &dyn Fn(&str, f64) -> f64) -> Option<Room> {
    let rt60 = num("--rt60", 0.0);
    // A darker tail (`Room::tail_darkening`) and its direct-to-reverberant
    // ratio (dB; the chamber's 3 dB unless given).
    let dark = num("--dark-tail", 0.0);
    let drr = num("--drr", Room::chamber(0.0).direct_to_reverb_db);
    let reflections: Vec<(f64, f64)> = get("--reflections").map_or(vec![], |s| {
        s.split(',')
            .map(|r| {
                let (d, g) = r.split_once(':').expect("a reflection as MS:GAIN");
                (d.parse().expect("a delay (ms)"), g.parse().expect("a gain"))
            })
            .collect()
    });
    assert!(
        reflections.len() <= MAX_REFLECTIONS,
        "at most {MAX_REFLECTIONS} reflections"
    );
    (rt60 > 0.0 || !reflections.is_empty()).then(|| {
        Room::chamber(rt60)
            .with_dark_tail(dark, drr)
            .with_reflections(&reflections)
    })
}

/// OUT/ring.wav, templates/N.wav (each bell's strike), truth.csv and
/// nominals.txt.
fn write_ring(out: &Path, sig: &Signal, strikes: &[Signal], truth: &[TrueStrike], nominals: &[f64]) {
    std::fs::create_dir_all(out.join("templates")).expect("a folder to write to");
    clapper_io::signal_file::write_wav(&out.join("ring.wav"), sig, 0.9).expect("ring.wav written");
    for (i, s) in strikes.iter().enumerate() {
        clapper_io::signal_file::write_wav(&out.join(format!("templates/{}.wav", i + 1)), s, 0.9)
            .expect("a template written");
    }
    let mut csv = String::from("bell,row,place,stroke,t_s,ideal_t_s,double_delay_ms,double_amplitude_ratio\n");
    for s in truth {
        csv += &format!(
            "{},{},{},{},{:.6},{:.6},{},{}\n",
            s.bell,
            s.row,
            s.place,
            if s.hand { "hand" } else { "back" },
            s.t,
            s.ideal_t,
            s.double.map_or(String::new(), |d| format!("{:.1}", d.0 * 1e3)),
            s.double.map_or(String::new(), |d| format!("{:.3}", d.1)),
        );
    }
    std::fs::write(out.join("truth.csv"), csv).expect("truth.csv written");
    let noms: Vec<String> = nominals.iter().map(|f| format!("{f:.1}")).collect();
    std::fs::write(out.join("nominals.txt"), noms.join(",") + "\n").expect("nominals.txt written");
}

/// The first run of digits in a name (d1, 15-d#1), 0 if none.
fn first_number(n: &str) -> u64 {
    n.chars()
        .skip_while(|c| !c.is_ascii_digit())
        .take_while(|c| c.is_ascii_digit())
        .collect::<String>()
        .parse()
        .unwrap_or(0)
}

/// The strongest spectral peak of a strike (Hz): a tuned bell's nominal.
fn strongest_hz(s: &Signal) -> f64 {
    BellVoice::from_template(s).expect("a usable strike").partials[0].freq_hz
}

/// The strongest spectral peak within 2 % of `f` (Hz) over the strike's
/// first second (Hann window, 0.1 Hz steps).
fn peak_near(s: &Signal, f: f64) -> f64 {
    let o = (sample_onset(s).expect("a strike with an onset") * s.rate) as usize;
    let n = ((s.rate as usize).min(s.samples.len() - o)).max(2);
    let x: Vec<f64> = (0..n)
        .map(|k| s.samples[o + k] * (std::f64::consts::PI * k as f64 / n as f64).sin().powi(2))
        .collect();
    let mut best = (f, 0.0);
    let mut g = 0.98 * f;
    while g <= 1.02 * f {
        let w = 2.0 * std::f64::consts::PI * g / s.rate;
        let (mut re, mut im) = (0.0, 0.0);
        for (k, v) in x.iter().enumerate() {
            re += v * (w * k as f64).cos();
            im += v * (w * k as f64).sin();
        }
        if re * re + im * im > best.1 {
            best = (g, re * re + im * im);
        }
        g += 0.1;
    }
    best.0
}

/// Every WAV file in `folder`: (file name, recording).
fn load(folder: &Path) -> Vec<(String, Signal)> {
    let mut out = vec![];
    for e in std::fs::read_dir(folder).expect("a readable folder") {
        let p = e.expect("a folder entry").path();
        let wav = p.extension().and_then(|x| x.to_str()).map(str::to_ascii_lowercase);
        if wav.as_deref() == Some("wav") {
            let s = clapper_io::signal_file::read_recording(&p).expect("a WAV file");
            out.push((p.file_name().unwrap_or_default().to_string_lossy().into_owned(), s));
        }
    }
    out
}
