//! `clapper strikes --bells N` and `--handbells`: the faults an
//! independent tester found (issue 43, docs/strikes.md "Handbells heard as
//! handbells" and "Nominals learned from the recording"), each heard
//! through the binary. The handbell rings are made here (a strike note, its
//! twelfth at 2.95 times 15 dB down, weak partials at 4.4 and 6.05 times,
//! decays of a few seconds, no hum), so that one bell can be made quiet;
//! the tower bells are `clapper synth-ring`'s.

mod common;
use common::{clapper, learned_nominals, recall_within, summary_warnings};

use std::f64::consts::PI;
use std::path::Path;

/// A handbell ring to write: its strike notes (Hz, treble first), the
/// time between bells (s), and each bell's level (amplitude) at each of
/// its strikes, by row.
struct HandbellRing {
    notes: Vec<f64>,
    interval_s: f64,
    rows: usize,
    level: fn(bell: usize, row: usize) -> f64,
    seed: u64,
}

/// A major scale's notes down from `treble` (Hz) for `bells` bells.
fn major_down(treble: f64, bells: usize) -> Vec<f64> {
    const STEPS: [f64; 7] = [1.0, 2.0, 2.0, 2.0, 1.0, 2.0, 2.0];
    let mut semis = 0.0;
    (0..bells)
        .map(|i| {
            if i > 0 {
                semis += STEPS[(i - 1) % 7];
            }
            treble * 2f64.powf(-semis / 12.0)
        })
        .collect()
}

/// A small generator (xorshift) so the rings are the same on every machine.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn gauss(&mut self) -> f64 {
        let (a, b) = (self.next().max(1e-12), self.next());
        (-2.0 * a.ln()).sqrt() * (2.0 * PI * b).cos()
    }
}

impl HandbellRing {
    /// Write `dir/r.wav` (44.1 kHz, rounds, a handstroke gap of one
    /// interval, striking errors within ±5 ms, noise 25 dB below a bell)
    /// and `dir/t.csv` (each strike's bell and time).
    fn write(&self, dir: &Path) {
        let rate = 44_100.0;
        let n = self.notes.len();
        let mut rng = Rng(self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
        let mut strikes = vec![];
        let mut t = 0.5;
        for row in 0..self.rows {
            if row % 2 == 0 && row > 0 {
                t += self.interval_s;
            }
            for bell in 0..n {
                strikes.push((bell, t + 0.005 * (2.0 * rng.next() - 1.0), (self.level)(bell + 1, row)));
                t += self.interval_s;
            }
        }
        let len = ((t + 3.0) * rate) as usize;
        let mut x = vec![0.0f64; len];
        for &(bell, at, level) in &strikes {
            let f = self.notes[bell];
            let decay = 2.5 * if f < 1000.0 { 1.0 } else { 0.7 };
            for (ratio, db, d) in [
                (1.0, 0.0, 1.0),
                (2.95, -15.0, 0.5),
                (4.4, -26.0, 0.3),
                (6.05, -30.0, 0.25),
            ] {
                let (pf, pa, t60) = (f * ratio, level * 10f64.powf(db / 20.0), decay * d);
                if pf > 0.45 * rate {
                    continue;
                }
                let phase = 2.0 * PI * rng.next();
                let start = (at * rate) as usize;
                for (i, v) in x[start..(start + (3.0 * t60 * rate) as usize).min(len)]
                    .iter_mut()
                    .enumerate()
                {
                    let s = i as f64 / rate;
                    let attack = (s / 0.001).min(1.0);
                    *v += attack * pa * (-6.9 * s / t60).exp() * (2.0 * PI * pf * s + phase).sin();
                }
            }
        }
        let noise = 0.3 * 10f64.powf(-25.0 / 20.0);
        x.iter_mut().for_each(|v| *v += noise * rng.gauss());
        let peak = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let spec = hound::WavSpec {
            channels: 1,
            sample_rate: rate as u32,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut w = hound::WavWriter::create(dir.join("r.wav"), spec).unwrap();
        for v in &x {
            w.write_sample((v / peak * 0.9 * 32767.0) as i16).unwrap();
        }
        w.finalize().unwrap();
        let mut csv = String::from("bell,t_s\n");
        for &(bell, at, _) in &strikes {
            csv += &format!("{},{at}\n", bell + 1);
        }
        std::fs::write(dir.join("t.csv"), csv).unwrap();
    }
}

fn heard(dir: &Path, wav: &str, options: &[&str]) -> serde_json::Value {
    let out = clapper()
        .current_dir(dir)
        .args(["strikes", wav, "--json"])
        .args(options)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Each bell's share of its true strikes heard as its own within 10 ms.
fn recall_per_bell(j: &serde_json::Value, truth: &Path, bells: usize) -> Vec<f64> {
    let text = std::fs::read_to_string(truth).unwrap();
    let truth: Vec<(u64, f64)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let (b, t) = l.split_once(',').unwrap();
            (b.parse().unwrap(), t.parse().unwrap())
        })
        .collect();
    (1..=bells as u64)
        .map(|b| {
            let mine: Vec<f64> = truth.iter().filter(|s| s.0 == b).map(|s| s.1).collect();
            let found = mine
                .iter()
                .filter(|&&t| {
                    j["strikes"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .any(|s| s["bell"] == b && (s["t_s"].as_f64().unwrap() - t).abs() < 0.010)
                })
                .count();
            found as f64 / mine.len() as f64
        })
        .collect()
}

fn loud(_: usize, _: usize) -> f64 {
    1.0
}

/// Ten handbells 150 ms apart: every nominal is learned (the tester's
/// `--bells 10` learned 4 and heard no strike within 10 ms), each within
/// 2 % of its note, and every bell's strikes are heard.
#[test]
fn ten_handbells_at_150_ms_are_all_learned() {
    let dir = tempfile::tempdir().unwrap();
    let ring = HandbellRing {
        notes: major_down(1512.0, 10),
        interval_s: 0.15,
        rows: 24,
        level: loud,
        seed: 3,
    };
    ring.write(dir.path());
    let j = heard(dir.path(), "r.wav", &["--bells", "10", "--handbells"]);
    let learned = learned_nominals(&j);
    assert_eq!(learned.len(), 10, "{learned:?} {:?}", summary_warnings(&j));
    for (l, t) in learned.iter().zip(&ring.notes) {
        assert!((l / t - 1.0).abs() < 0.02, "learned {learned:?} for {:?}", ring.notes);
    }
    let per = recall_per_bell(&j, &dir.path().join("t.csv"), 10);
    assert!(per.iter().all(|r| *r >= 0.95), "{per:?}");
}

/// A bell heard too little to learn keeps its number: bell 3 of eight
/// handbells 12 dB down, `--bells 8` learned seven and numbered them 1 to
/// 7, so every strike from bell 3 down was given to the bell above. Now
/// bell 3's note is guessed from the ring's scale, said in a warning, and
/// every bell's strikes carry its own number.
#[test]
fn a_quiet_handbell_keeps_its_number() {
    fn quiet_third(bell: usize, _: usize) -> f64 {
        if bell == 3 {
            0.25
        } else {
            1.0
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let ring = HandbellRing {
        notes: major_down(1040.0, 8),
        interval_s: 0.2,
        rows: 24,
        level: quiet_third,
        seed: 5,
    };
    ring.write(dir.path());
    let j = heard(dir.path(), "r.wav", &["--bells", "8", "--handbells"]);
    let learned = learned_nominals(&j);
    assert_eq!(learned.len(), 8, "{learned:?} {:?}", summary_warnings(&j));
    let per = recall_per_bell(&j, &dir.path().join("t.csv"), 8);
    for (b, r) in per.iter().enumerate() {
        if b != 2 {
            assert!(*r >= 0.95, "bell {}: {per:?}", b + 1);
        }
    }
    let w = summary_warnings(&j);
    assert!(
        w.iter()
            .any(|w| w.starts_with("bell 3 (about") && w.contains("keeps its place")),
        "{w:?}"
    );
}

/// A bell heard at far fewer strikes than the others is warned of (the
/// tester's quiet bell heard 5 of 24 times was not): here bell 4 is loud
/// at 5 of its 24 strikes and 40 dB down at the rest.
#[test]
fn a_bell_heard_far_less_than_the_others_is_warned_of() {
    fn mostly_silent_fourth(bell: usize, row: usize) -> f64 {
        if bell == 4 && row % 5 != 0 {
            0.01
        } else {
            1.0
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let ring = HandbellRing {
        notes: major_down(1040.0, 8),
        interval_s: 0.2,
        rows: 24,
        level: mostly_silent_fourth,
        seed: 7,
    };
    ring.write(dir.path());
    let nominals: Vec<String> = ring.notes.iter().map(|f| format!("{f:.1}")).collect();
    let nominals = nominals.join(",");
    let j = heard(dir.path(), "r.wav", &["--nominals", &nominals, "--handbells"]);
    let w = summary_warnings(&j);
    let bell4 = j["per_bell"][3]["strikes"].as_u64().unwrap();
    assert!((1..12).contains(&bell4), "{bell4}");
    assert!(
        w.iter()
            .any(|w| w.starts_with(&format!("bell 4: heard at only {bell4} strikes"))),
        "{w:?}"
    );
    // The same in the text report.
    let out = clapper()
        .current_dir(dir.path())
        .args(["strikes", "r.wav", "--nominals", &nominals, "--handbells"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    // Said after the table, one line for the bell (report-2): its first
    // warning or its timing doubt, both of how seldom it was heard.
    assert!(
        text.lines()
            .any(|l| l.trim_start().starts_with("bell 4:") && l.contains("heard at only")),
        "{text}"
    );
}

/// `synth-ring` (tower bells, or `--handbells`) on eight: its listening
/// command's options after `clapper strikes r.wav`, and its nominals.
fn synth(dir: &Path, handbells: bool) -> (Vec<String>, Vec<f64>) {
    let mut c = clapper();
    c.current_dir(dir)
        .args(["synth-ring", "--out", "r.wav", "--truth", "t.csv", "--plain-hunt"])
        .args(["--rows", "24", "--snr", "25", "--seed", "21"]);
    if handbells {
        c.arg("--handbells");
    }
    let out = c.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let said = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    let listen: Vec<String> = said
        .rsplit("r.wav ")
        .next()
        .unwrap()
        .split_whitespace()
        .map(String::from)
        .collect();
    let at = listen.iter().position(|o| o == "--nominals").expect("nominals given");
    let nominals = listen[at + 1].split(',').map(|f| f.parse().unwrap()).collect();
    (listen, nominals)
}

fn nominals_arg(f: &[f64]) -> String {
    f.iter().map(|f| format!("{f:.2}")).collect::<Vec<_>>().join(",")
}

/// `--handbells` on tower bells is warned of (the tester's 26 false
/// doubles came unwarned): a tower bell's hum and prime rise with its
/// nominal, a handbell has nothing below its note. And the reverse:
/// handbells heard as tower bells.
#[test]
fn the_wrong_kind_of_bell_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let (_, tower) = synth(dir.path(), false);
    let n = nominals_arg(&tower);
    let as_tower = heard(dir.path(), "r.wav", &["--nominals", &n]);
    let as_hand = heard(dir.path(), "r.wav", &["--nominals", &n, "--handbells"]);
    let kind = |j: &serde_json::Value, says: &str| summary_warnings(j).iter().any(|w| w.contains(says));
    assert!(
        kind(&as_hand, "but these sound like tower bells"),
        "{:?}",
        summary_warnings(&as_hand)
    );
    assert!(
        !kind(&as_tower, "but these sound like"),
        "{:?}",
        summary_warnings(&as_tower)
    );

    let dir = tempfile::tempdir().unwrap();
    let (_, hand) = synth(dir.path(), true);
    let n = nominals_arg(&hand);
    let as_tower = heard(dir.path(), "r.wav", &["--nominals", &n]);
    let as_hand = heard(dir.path(), "r.wav", &["--nominals", &n, "--handbells"]);
    assert!(
        kind(&as_tower, "but these sound like handbells"),
        "{:?}",
        summary_warnings(&as_tower)
    );
    assert!(
        !kind(&as_hand, "but these sound like"),
        "{:?}",
        summary_warnings(&as_hand)
    );
}

/// Handbells' strike notes given 1.5 % sharp or flat (what a ringer's
/// figures may be off by) are heard as well as the true ones: given 1 %
/// sharp, the tester lost 3 bells of eight.
#[test]
fn handbell_nominals_off_by_one_and_a_half_percent_are_heard() {
    let dir = tempfile::tempdir().unwrap();
    let (_, hand) = synth(dir.path(), true);
    for off in [1.015, 0.985] {
        let given: Vec<f64> = hand.iter().map(|f| f * off).collect();
        let j = heard(
            dir.path(),
            "r.wav",
            &["--nominals", &nominals_arg(&given), "--handbells"],
        );
        let r = recall_within(&j, &dir.path().join("t.csv"), 0.010);
        assert!(r >= 0.98, "nominals times {off}: recall within 10 ms {r}");
    }
}

/// A nominal given an octave off (bell 3's doubled, the tenor's halved)
/// is warned of; the true nominals are not.
#[test]
fn a_nominal_given_an_octave_off_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let (_, hand) = synth(dir.path(), true);
    let j = heard(
        dir.path(),
        "r.wav",
        &["--nominals", &nominals_arg(&hand), "--handbells"],
    );
    assert!(
        !summary_warnings(&j).iter().any(|w| w.contains("an octave from")),
        "{:?}",
        summary_warnings(&j)
    );
    for (bell, by) in [(3, 2.0), (8, 0.5)] {
        let mut given = hand.clone();
        given[bell - 1] *= by;
        let j = heard(
            dir.path(),
            "r.wav",
            &["--nominals", &nominals_arg(&given), "--handbells"],
        );
        let w = summary_warnings(&j);
        assert!(
            w.iter()
                .any(|w| w.starts_with(&format!("bell {bell}'s nominal")) && w.contains("an octave from")),
            "bell {bell}: {w:?}"
        );
    }
}
