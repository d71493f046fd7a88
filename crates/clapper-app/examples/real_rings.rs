//! Strike finding on rings built from real recorded strikes (issue 43,
//! docs/strikes.md): one WAV per bell in a folder (mono or stereo, all at
//! one rate), bells ordered by pitch (the highest is the treble), rung in
//! rounds and plain hunt in rooms and noise by
//! `clapper_signal::sampled_ring`, and scored against the truth.
//!
//! cargo run --release -p clapper-app --example real_rings -- FOLDER [--bells N] [--skip K] [--seeds A-B] [--mode templates|nominals|learned|both] [--conditions 1,2] [--show] [--order pitch|name|name-rev] [--nominals F1,F2,..] [--raw]
//!
//! `--skip K` leaves out the K highest bells (a ring of the next N).
//! `--mode nominals` times the strikes from the ring's own clean strikes
//! (`--self-calibrate`); with `--raw`, as heard through a tuned bell's ratios.
//! `--mode learned` learns the nominals from the ring (`--bells N`) and then
//! does the same about them (`--raw`: as heard about them).
//! No recordings ship with the project: docs/strikes.md names the ones
//! measured.

use std::path::{Path, PathBuf};

use clapper_app::strikes::{StrikesReport, Timing};
use clapper_signal::sampled_ring::{sample_onset, sampled_ring};
use clapper_signal::strikes::{BellVoice, StrikeOptions};
use clapper_signal::striking::{rhythm, Timed};
use clapper_signal::tower::*;
use clapper_signal::Signal;

struct Args {
    folder: PathBuf,
    bells: usize,
    skip: usize,
    seeds: (u64, u64),
    modes: Vec<&'static str>,
    conditions: Vec<usize>,
    show: bool,
    order: String,
    raw: bool,
    nominals: Option<Vec<f64>>,
}

fn args() -> Args {
    let v: Vec<String> = std::env::args().skip(1).collect();
    let get = |k: &str| v.iter().position(|a| a == k).and_then(|i| v.get(i + 1)).cloned();
    let seeds = get("--seeds").unwrap_or_else(|| "1-4".into());
    let (a, b) = seeds.split_once('-').unwrap_or((&seeds, &seeds));
    Args {
        folder: PathBuf::from(v.first().expect("a folder of WAV files, one strike per bell")),
        bells: get("--bells").and_then(|s| s.parse().ok()).unwrap_or(8),
        skip: get("--skip").and_then(|s| s.parse().ok()).unwrap_or(0),
        seeds: (a.parse().unwrap(), b.parse().unwrap()),
        modes: match get("--mode").as_deref() {
            Some("templates") => vec!["templates"],
            Some("nominals") => vec!["nominals"],
            Some("learned") => vec!["learned"],
            _ => vec!["templates", "nominals"],
        },
        conditions: get("--conditions")
            .map(|s| s.split(',').filter_map(|x| x.parse().ok()).collect())
            .unwrap_or_else(|| (1..=CONDITIONS.len()).collect()),
        show: v.iter().any(|a| a == "--show"),
        order: get("--order").unwrap_or_else(|| "pitch".into()),
        raw: v.iter().any(|a| a == "--raw"),
        nominals: get("--nominals").map(|s| s.split(',').map(|x| x.parse().unwrap()).collect()),
    }
}

/// (name, method, RT60 s, SNR dB)
const CONDITIONS: [(&str, Method, f64, f64); 6] = [
    ("rounds, dry, 25 dB", Method::Rounds, 0.0, 25.0),
    ("plain hunt, dry, 25 dB", Method::PlainHunt, 0.0, 25.0),
    ("rounds, RT60 0.6 s, 20 dB", Method::Rounds, 0.6, 20.0),
    ("plain hunt, RT60 0.6 s, 20 dB", Method::PlainHunt, 0.6, 20.0),
    ("plain hunt, RT60 1.2 s, 15 dB", Method::PlainHunt, 1.2, 15.0),
    ("rounds, RT60 1.2 s, 25 dB", Method::Rounds, 1.2, 25.0),
];

/// The strongest spectral peak of a strike over its first second: its
/// nominal in a ring's tuned bell (the partial heard as its pitch).
fn strongest_hz(s: &Signal) -> f64 {
    let v = BellVoice::from_template(s).expect("a usable strike");
    v.partials[0].freq_hz
}

/// The strongest spectral peak within 2 % of `f` over the strike's first
/// second (Hann window, 0.1 Hz steps).
fn peak_near(s: &Signal, f: f64) -> f64 {
    let o = (sample_onset(s).unwrap() * s.rate) as usize;
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
        let m = re * re + im * im;
        if m > best.1 {
            best = (g, m);
        }
        g += 0.1;
    }
    best.0
}

/// The nominals learned from the ring `sig` of `n` bells (`--bells N`),
/// printed with their worst error (%) against those given.
fn learn(sig: &Signal, n: usize, nominals: &[f64], name: &str, seed: u64) -> Vec<f64> {
    let l = clapper_signal::strikes::learn_nominals(sig, n).unwrap();
    let worst = (0..n)
        .map(|k| {
            l.bells
                .get(k)
                .map_or(f64::INFINITY, |b| 100.0 * (b.nominal_hz / nominals[k] - 1.0).abs())
        })
        .fold(0.0, f64::max);
    println!(
        "  {name} seed {seed}: learned {} (worst {worst:.2} %){}",
        l.bells
            .iter()
            .map(|b| format!("{:.1} ({:.2})", b.nominal_hz, b.confidence))
            .collect::<Vec<_>>()
            .join(", "),
        if l.warnings.is_empty() {
            String::new()
        } else {
            format!("; {}", l.warnings.join("; "))
        }
    );
    l.bells.iter().map(|b| b.nominal_hz).collect()
}

fn load(folder: &Path) -> Vec<(String, Signal)> {
    let mut out = vec![];
    for e in std::fs::read_dir(folder).expect("a readable folder") {
        let p = e.unwrap().path();
        if p.extension()
            .and_then(|x| x.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
            == Some("wav")
        {
            let s = clapper_io::signal_file::read_recording(&p).expect("a WAV file");
            out.push((p.file_name().unwrap().to_string_lossy().into_owned(), s));
        }
    }
    out
}

fn main() {
    let a = args();
    let mut all = load(&a.folder);
    let mut keyed: Vec<(f64, String, Signal)> = all.drain(..).map(|(n, s)| (strongest_hz(&s), n, s)).collect();
    // The number in a name (d1, 15-d#1): its first run of digits.
    let num = |n: &str| -> u64 {
        n.chars()
            .skip_while(|c| !c.is_ascii_digit())
            .take_while(|c| c.is_ascii_digit())
            .collect::<String>()
            .parse()
            .unwrap_or(0)
    };
    match a.order.as_str() {
        "name" => keyed.sort_by_key(|x| num(&x.1)),
        "name-rev" => keyed.sort_by_key(|x| std::cmp::Reverse(num(&x.1))),
        _ => keyed.sort_by(|x, y| y.0.total_cmp(&x.0)),
    }
    let ring: Vec<(f64, String, Signal)> = keyed.into_iter().skip(a.skip).take(a.bells).collect();
    assert_eq!(ring.len(), a.bells, "not enough recordings in the folder");
    let rate = ring[0].2.rate;
    for (i, (f, n, s)) in ring.iter().enumerate() {
        let v = BellVoice::from_template(s).unwrap();
        println!(
            "bell {}: {n}, {:.1} s, onset {:.1} ms, partials {}",
            i + 1,
            s.duration(),
            sample_onset(s).unwrap() * 1e3,
            v.partials
                .iter()
                .map(|p| format!("{:.1} ({:.2})", p.freq_hz, p.strength))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let _ = f;
    }
    let strikes: Vec<Signal> = ring.iter().map(|r| r.2.clone()).collect();
    // Nominals given (each refined to the template's spectral peak within 2 %),
    // else each bell's strongest partial.
    let nominals: Vec<f64> = match &a.nominals {
        Some(v) => v.iter().zip(&strikes).map(|(&f, s)| peak_near(s, f)).collect(),
        None => ring.iter().map(|r| r.0).collect(),
    };
    println!(
        "nominals: {}",
        nominals.iter().map(|f| format!("{f:.1}")).collect::<Vec<_>>().join(",")
    );
    let n = a.bells;
    let odd_bell = 3;
    println!();
    println!("| mode | condition | seeds | strikes | recall 10 ms | precision 10 ms | median / p95 abs err (ms) | worst bell mean err (ms) | doubles found | false doubles | odd-struck bell {odd_bell} (planted 25) err vs truth (ms) | others worst (ms) | recall / precision 100 ms |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for mode in &a.modes {
        let voices: Vec<BellVoice> = match *mode {
            "templates" => strikes.iter().map(|s| BellVoice::from_template(s).unwrap()).collect(),
            _ => nominals.iter().map(|&f| BellVoice::from_nominal(f)).collect(),
        };
        for &c in &a.conditions {
            let (name, method, rt60, snr) = CONDITIONS[c - 1];
            let mut tot = Score::default();
            let mut per_bell: Vec<Vec<f64>> = vec![vec![]; n];
            let mut odd_err = 0.0f64;
            let (mut wide_found, mut wide_false) = (0usize, 0usize);
            let mut others = 0.0f64;
            for seed in a.seeds.0..=a.seeds.1 {
                let mut bells = major_scale(n, 1000.0).unwrap();
                bells[odd_bell - 1].odd_struck_ms = 25.0;
                let spec = TowerSpec {
                    rate,
                    rows: 24,
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
                    room: (rt60 > 0.0).then(|| Room::chamber(rt60)),
                    snr_db: Some(snr),
                    ..TowerSpec::new(bells)
                };
                let (sig, truth) = sampled_ring(&spec, &strikes).unwrap();
                // --mode learned: the nominals learned from the ring itself
                // (`--bells N`), against those given (worst error, %).
                let learned: Option<Vec<f64>> = (*mode == "learned").then(|| learn(&sig, n, &nominals, name, seed));
                // --mode nominals: timed from the ring's own clean strikes
                // (`--raw`: as heard through the tuned-bell voices); --mode
                // learned: the same about the nominals learned.
                let calibrate_with = learned.as_ref().unwrap_or(&nominals);
                let calibration = (*mode != "templates" && !a.raw && calibrate_with.len() == n).then(|| {
                    clapper_app::strikes::calibrate_from_recording(&sig, calibrate_with, &StrikeOptions::default())
                        .unwrap()
                });
                let timing = match (*mode, a.raw, &calibration) {
                    (_, true, _) => Timing::AsHeard,
                    ("templates", _, _) => Timing::Templates(&strikes),
                    (_, _, Some(c)) => Timing::Recording(c),
                    _ => Timing::AsHeard,
                };
                let voices = if let (Some(l), None) = (&learned, &calibration) {
                    l.iter().map(|&f| BellVoice::from_nominal(f)).collect()
                } else if let Some(c) = &calibration {
                    if a.show {
                        for (b, v) in c.bells.iter().zip(&c.voices) {
                            println!(
                                "  bell {}: partials {} ({}), lateness {:?} ms from {} clean strikes",
                                b.bell,
                                if b.partials_learned { "learned" } else { "assumed" },
                                v.partials
                                    .iter()
                                    .map(|p| format!("{:.1} ({:.2})", p.freq_hz, p.strength))
                                    .collect::<Vec<_>>()
                                    .join(", "),
                                b.lateness_s.map(|l| (l * 1e4).round() / 10.0),
                                b.strikes
                            );
                        }
                    }
                    if a.show {
                        // How late the band finder heard each bell through
                        // the learned partials, against the truth (median,
                        // spread): what the calibration should find.
                        let h =
                            clapper_signal::strikes::find_strikes(&sig, &c.voices, &StrikeOptions::default()).unwrap();
                        for b in 1..=n {
                            let mut e: Vec<f64> = h
                                .strikes
                                .iter()
                                .filter(|s| s.bell == b)
                                .filter_map(|s| {
                                    truth
                                        .iter()
                                        .filter(|x| x.bell == b && (x.t - s.t).abs() < 0.15)
                                        .map(|x| (s.t - x.t) * 1e3)
                                        .min_by(|p, q| p.abs().total_cmp(&q.abs()))
                                })
                                .collect();
                            e.sort_by(f64::total_cmp);
                            let m = e.get(e.len() / 2).copied().unwrap_or(f64::NAN);
                            let mut d: Vec<f64> = e.iter().map(|v| (v - m).abs()).collect();
                            d.sort_by(f64::total_cmp);
                            println!(
                                "  bell {b}: heard late by {m:.1} ms (spread {:.1}, range {:.1} to {:.1}) at {} strikes",
                                d.get(d.len() / 2).copied().unwrap_or(f64::NAN),
                                e.first().copied().unwrap_or(f64::NAN),
                                e.last().copied().unwrap_or(f64::NAN),
                                e.len()
                            );
                        }
                    }
                    c.voices.clone()
                } else {
                    voices.clone()
                };
                let report = StrikesReport::timed(&sig, &voices, &StrikeOptions::default(), timing).unwrap();
                let heard: Vec<HeardTimes> = report
                    .strikes
                    .iter()
                    .map(|s| {
                        (
                            s.bell,
                            s.t_s,
                            s.double.as_ref().map(|d| (d.delay_ms * 1e-3, d.amplitude_ratio)),
                        )
                    })
                    .collect();
                let sc = score(&heard, &truth, 0.010);
                // Per bell error, from a wide match so a late bell shows.
                let wide = score(&heard, &truth, 0.1);
                for &(b, t, _) in &heard {
                    if let Some(x) = truth
                        .iter()
                        .filter(|x| x.bell == b && (x.t - t).abs() < 0.1)
                        .min_by(|p, q| (p.t - t).abs().total_cmp(&(q.t - t).abs()))
                    {
                        per_bell[b - 1].push((t - x.t) * 1e3);
                        if a.show && (t - x.t).abs() > 0.01 {
                            println!(
                                "    bell {b} row {} place {}: {:+.1} ms{}",
                                x.row,
                                x.place,
                                (t - x.t) * 1e3,
                                if x.double.is_some() { " (a double)" } else { "" }
                            );
                        }
                    }
                }
                if a.show {
                    if let Some(t) = &report.timing {
                        println!(
                            "  lateness learned / matched (ms): {}",
                            t.per_bell
                                .iter()
                                .map(|b| format!(
                                    "{:.1} ({}) / {:.1}",
                                    b.lateness_ms,
                                    b.learned_from,
                                    b.matched_ms.unwrap_or(f64::NAN)
                                ))
                                .collect::<Vec<_>>()
                                .join(", ")
                        );
                    }
                    show_missed(&sig, &voices, &heard, &truth);
                }
                wide_found += wide.found;
                wide_false += wide.false_strikes;
                let timed: Vec<Timed> = report
                    .strikes
                    .iter()
                    .map(|s| Timed { bell: s.bell, t: s.t_s })
                    .collect();
                let true_timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
                let r = rhythm(&timed, n);
                let tr = rhythm(&true_timed, n);
                if a.show {
                    let kept: Vec<Timed> = timed
                        .iter()
                        .copied()
                        .filter(|h| truth.iter().any(|x| x.bell == h.bell && (x.t - h.t).abs() < 0.01))
                        .collect();
                    let kr = rhythm(&kept, n);
                    println!(
                        "    odd-struck, outliers dropped: {}; strokes known {} / {}, full rows {} / {}",
                        (1..=n)
                            .map(|b| format!("{:.1}", kr.odd_struck(&kept, b).unwrap_or(f64::NAN) * 1e3))
                            .collect::<Vec<_>>()
                            .join(", "),
                        r.strokes_known,
                        tr.strokes_known,
                        r.full_rows,
                        tr.full_rows
                    );
                    println!(
                        "    odd-struck heard / true (ms): {}",
                        (1..=n)
                            .map(|b| format!(
                                "{:.1}/{:.1}",
                                r.odd_struck(&timed, b).unwrap_or(f64::NAN) * 1e3,
                                tr.odd_struck(&true_timed, b).unwrap_or(f64::NAN) * 1e3
                            ))
                            .collect::<Vec<_>>()
                            .join(", ")
                    );
                }
                for b in 1..=n {
                    let e = match (r.odd_struck(&timed, b), tr.odd_struck(&true_timed, b)) {
                        (Some(h), Some(t)) => (h - t).abs() * 1e3,
                        _ => f64::INFINITY,
                    };
                    if b == odd_bell {
                        odd_err = odd_err.max(e);
                    } else {
                        others = others.max(e);
                    }
                }
                if a.show {
                    println!(
                        "  seed {seed}: recall {:.3} precision {:.3} doubles {}/{} false {}",
                        sc.recall(),
                        sc.precision(),
                        sc.doubles_found,
                        sc.doubles_put,
                        sc.false_doubles
                    );
                    for w in &report.summary.warnings {
                        println!("  warning: {w}");
                    }
                }
                tot.found += sc.found;
                tot.missed += sc.missed;
                tot.false_strikes += sc.false_strikes;
                tot.onset_errors.extend(sc.onset_errors);
                tot.doubles_found += sc.doubles_found;
                tot.doubles_put += sc.doubles_put;
                tot.false_doubles += sc.false_doubles;
            }
            let mut e: Vec<f64> = tot.onset_errors.iter().map(|v| v.abs() * 1e3).collect();
            e.sort_by(f64::total_cmp);
            let pct = |p: f64| {
                e.get(((e.len().max(1) - 1) as f64 * p).round() as usize)
                    .copied()
                    .unwrap_or(f64::NAN)
            };
            let means: Vec<f64> = per_bell
                .iter()
                .map(|v| {
                    if v.is_empty() {
                        f64::NAN
                    } else {
                        v.iter().sum::<f64>() / v.len() as f64
                    }
                })
                .collect();
            let worst = means
                .iter()
                .fold(0.0f64, |m, v| if v.is_nan() { f64::INFINITY } else { m.max(v.abs()) });
            println!(
                "| {mode} | {name} | {}-{} | {} | {:.3} | {:.3} | {:.2} / {:.2} | {worst:.1} | {}/{} | {} ({:.2} %) | {odd_err:.1} | {others:.1} | {:.3} / {:.3} |",
                a.seeds.0,
                a.seeds.1,
                tot.found + tot.missed,
                tot.recall(),
                tot.precision(),
                pct(0.5),
                pct(0.95),
                tot.doubles_found,
                tot.doubles_put,
                tot.false_doubles,
                100.0 * tot.false_doubles as f64 / (tot.found.max(1)) as f64,
                wide_found as f64 / (tot.found + tot.missed).max(1) as f64,
                wide_found as f64 / (wide_found + wide_false).max(1) as f64,
            );
            if a.show {
                println!(
                    "  per bell mean err (ms): {}",
                    means.iter().map(|m| format!("{m:.1}")).collect::<Vec<_>>().join(", ")
                );
            }
        }
    }
}

/// `--show`: each true strike with no strike of its bell within 100 ms
/// (the nearest of its bell's strikes, and the band finder's alone,
/// signed), and each strike heard with no true strike of its bell within
/// 100 ms: where the misses come from.
fn show_missed(sig: &Signal, voices: &[BellVoice], heard: &[HeardTimes], truth: &[TrueStrike]) {
    let band = clapper_signal::strikes::find_strikes(sig, voices, &StrikeOptions::default()).unwrap();
    let nearest = |b: usize, t: f64, times: &mut dyn Iterator<Item = (usize, f64)>| -> String {
        times
            .filter(|h| h.0 == b)
            .map(|h| h.1 - t)
            .min_by(|p, q| p.abs().total_cmp(&q.abs()))
            .map_or("none".into(), |d| format!("{:+.1} ms", d * 1e3))
    };
    for x in truth {
        if heard.iter().any(|h| h.0 == x.bell && (h.1 - x.t).abs() < 0.1) {
            continue;
        }
        println!(
            "    missed bell {} row {} place {}{}: nearest {}, band finder's {}",
            x.bell,
            x.row,
            x.place,
            if x.double.is_some() { " (a double)" } else { "" },
            nearest(x.bell, x.t, &mut heard.iter().map(|h| (h.0, h.1))),
            nearest(x.bell, x.t, &mut band.strikes.iter().map(|s| (s.bell, s.t)))
        );
    }
    for h in heard {
        if truth.iter().any(|x| x.bell == h.0 && (h.1 - x.t).abs() < 0.1) {
            continue;
        }
        let other = truth
            .iter()
            .filter(|x| (h.1 - x.t).abs() < 0.1)
            .min_by(|p, q| (p.t - h.1).abs().total_cmp(&(q.t - h.1).abs()))
            .map_or("none".into(), |x| {
                format!("bell {} {:+.1} ms", x.bell, (h.1 - x.t) * 1e3)
            });
        // Signed as heard less true.
        let own = nearest(h.0, h.1, &mut truth.iter().map(|x| (x.bell, 2.0 * h.1 - x.t)));
        println!(
            "    extra bell {} at {:.3} s: its own bell's nearest {own}, nearest strike {other}",
            h.0, h.1
        );
    }
}
