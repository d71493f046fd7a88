//! `clapper synth-ring`'s options for what real bells do (issue 43):
//! doublets, the swing's level and Doppler, tunings, handbells, noise and
//! methods, each heard in the recording it writes, the truth file's format
//! unchanged, nonsense refused with a message.

mod common;

use std::f64::consts::PI;
use std::path::Path;

use common::clapper;

/// `clapper synth-ring ARGS --out DIR/NAME.wav --truth DIR/NAME.csv`:
/// the samples and the truth's text.
fn synth(dir: &Path, name: &str, args: &[&str]) -> (f64, Vec<f64>, String) {
    let (wav, csv) = (dir.join(format!("{name}.wav")), dir.join(format!("{name}.csv")));
    let out = clapper()
        .arg("synth-ring")
        .args(args)
        .arg("--out")
        .arg(&wav)
        .arg("--truth")
        .arg(&csv)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut r = hound::WavReader::open(&wav).unwrap();
    let rate = f64::from(r.spec().sample_rate);
    let x = r.samples::<i16>().map(|v| f64::from(v.unwrap()) / 32768.0).collect();
    (rate, x, std::fs::read_to_string(&csv).unwrap())
}

/// The truth's strike times (s), in file order.
fn times(truth: &str) -> Vec<f64> {
    truth
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect()
}

/// The band about `f` (Hz) over Hann windows of `win` s a quarter-window
/// apart: (time s, re, im).
fn band(rate: f64, x: &[f64], f: f64, win: f64) -> Vec<(f64, f64, f64)> {
    let n = (win * rate) as usize;
    let w = 2.0 * PI * f / rate;
    (0..(x.len() - n) / (n / 4))
        .map(|k| {
            let a = k * n / 4;
            let (mut re, mut im) = (0.0, 0.0);
            for (i, v) in x.iter().enumerate().skip(a).take(n) {
                let hann = 1.0 - (2.0 * PI * (i - a) as f64 / n as f64).cos();
                re += hann * v * (w * i as f64).cos();
                im -= hann * v * (w * i as f64).sin();
            }
            ((a as f64 + n as f64 / 2.0) / rate, re, im)
        })
        .collect()
}

/// One bell (nominal 1000 Hz), three strikes a second or two apart, its
/// partials single components: the effects asked come on top.
const ONE_BELL: [&str; 14] = [
    "--bells",
    "1",
    "--treble-hz",
    "1000",
    "--rows",
    "3",
    "--interval-ms",
    "1000",
    "--jitter-ms",
    "0",
    "--doublets",
    "0:0",
    "--doublet-shares",
    "1:1",
];

#[test]
fn the_swing_asked_is_heard_in_the_recording_and_the_truth_is_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let (rate, still, truth) = synth(dir.path(), "still", &ONE_BELL);
    let swung: Vec<&str> = ONE_BELL
        .iter()
        .copied()
        .chain(["--swing-db", "12", "--doppler-pct", "1"])
        .collect();
    let (_, swing, truth_swing) = synth(dir.path(), "swing", &swung);
    assert_eq!(truth, truth_swing, "the truth file is the same");
    let t = times(&truth);
    // The nominal's level swinging over still through the second stroke: a
    // 12 dB range (the whole file's scale drops out of the range).
    let (a, b) = (band(rate, &still, 1000.0, 0.04), band(rate, &swing, 1000.0, 0.04));
    let db: Vec<f64> = a
        .iter()
        .zip(&b)
        .filter(|(p, _)| p.0 > t[1] + 0.05 && p.0 < t[2] - 0.05)
        .map(|(p, q)| 20.0 * (q.1.hypot(q.2) / p.1.hypot(p.2)).log10())
        .collect();
    let range = db.iter().copied().fold(f64::MIN, f64::max) - db.iter().copied().fold(f64::MAX, f64::min);
    assert!((range - 12.0).abs() < 1.0, "level range {range:.2} dB");
    // Its frequency: up by about 1 % and down by about 1 % in the stroke.
    let hop = b[1].0 - b[0].0;
    let shift: Vec<f64> = b
        .windows(2)
        .filter(|w| w[0].0 > t[1] + 0.05 && w[1].0 < t[2] - 0.05)
        .map(|w| {
            (w[1].2 * w[0].1 - w[1].1 * w[0].2).atan2(w[1].1 * w[0].1 + w[1].2 * w[0].2) / (2.0 * PI * hop) / 1000.0
        })
        .collect();
    let (hi, lo) = (
        shift.iter().copied().fold(f64::MIN, f64::max),
        shift.iter().copied().fold(f64::MAX, f64::min),
    );
    assert!(
        (hi - 0.01).abs() < 0.001 && (lo + 0.01).abs() < 0.001,
        "shift {hi} to {lo}"
    );
}

#[test]
fn a_doublet_asked_beats_in_the_recording() {
    let dir = tempfile::tempdir().unwrap();
    let mut args: Vec<&str> = ONE_BELL.to_vec();
    args[5] = "1";
    // Split 2 Hz, shares 0.3 and 0.7: the nominal beats every 0.5 s, 7.4 dB deep.
    args[11] = "2:2";
    args[13] = "0.3:0.3";
    let (rate, x, truth) = synth(dir.path(), "beat", &args);
    let t0 = times(&truth)[0];
    let env: Vec<(f64, f64)> = band(rate, &x, 1000.0, 0.05)
        .into_iter()
        .filter(|p| p.0 > t0 + 0.05 && p.0 < t0 + 2.0)
        .map(|(t, re, im)| (t, 20.0 * re.hypot(im).log10()))
        .collect();
    // Take out the decay (a straight line in dB); the beat is what is left.
    let n = env.len() as f64;
    let (mt, my) = (
        env.iter().map(|p| p.0).sum::<f64>() / n,
        env.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope =
        env.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum::<f64>() / env.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    let rest: Vec<(f64, f64)> = env.iter().map(|p| (p.0, p.1 - my - slope * (p.0 - mt))).collect();
    let power = |f: f64| {
        let (c, s) = rest.iter().fold((0.0, 0.0), |(c, s), p| {
            (
                c + p.1 * (2.0 * PI * f * p.0).cos(),
                s + p.1 * (2.0 * PI * f * p.0).sin(),
            )
        });
        c * c + s * s
    };
    let beat = (30..=600)
        .map(|k| k as f64 / 100.0)
        .max_by(|a, b| power(*a).total_cmp(&power(*b)))
        .unwrap();
    assert!((beat - 2.0).abs() < 0.1, "beats at {beat} Hz");
}

#[test]
fn no_new_option_leaves_the_recording_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let base = ["--bells", "5", "--rows", "4", "--snr", "30"];
    let (_, plain, truth) = synth(dir.path(), "plain", &base);
    let zeros: Vec<&str> = base
        .iter()
        .copied()
        .chain(["--swing-db", "0", "--doppler-pct", "0"])
        .collect();
    let (_, zero, truth_zero) = synth(dir.path(), "zero", &zeros);
    assert_eq!(
        (&plain, &truth),
        (&zero, &truth_zero),
        "a swing of nothing changes nothing"
    );
    let with: Vec<&str> = base
        .iter()
        .copied()
        .chain(["--doublets", "0.1:3", "--swing-db", "10", "--attack", "-24:30"])
        .collect();
    let (_, other, truth_other) = synth(dir.path(), "other", &with);
    assert_eq!(truth, truth_other, "the effects leave the strikes where they were");
    assert_ne!(plain, other, "and change the sound");
}

#[test]
fn nonsense_is_refused_with_a_reason() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.wav");
    for (args, says) in [
        (&["--swing-db", "-3"][..], "swing level -3 dB"),
        (&["--doppler-pct", "9"][..], "Doppler shift 9 %"),
        (&["--doublets", "3:1"][..], "doublet splits 3 to 1 Hz"),
        (&["--doublets", "fast"][..], "--doublets is LOW_HZ:HIGH_HZ"),
        (
            &["--doublets", "-1:2"][..],
            "doublet splits -1 to 2 Hz: from 0 to 20 Hz",
        ),
        (
            &["--doublets", "0.1:3", "--doublet-shares", "0.2:1.5"][..],
            "doublet shares 0.2 to 1.5",
        ),
        (&["--method", "grandsire"][..], "Grandsire on 3 bells: 5 to 12 bells"),
        (
            &["--method", "cambridge"][..],
            "invalid value 'cambridge' for '--method",
        ),
        (&["--noise", "wind"][..], "--noise: say how loud with --snr DB"),
        (
            &["--tuning", "minor", "--tenor-hz", "5"][..],
            "--tenor-hz 5: from 20 Hz",
        ),
        (&["--tenor-hz", "300"][..], "--tuning"),
        (&["--tuning", "major", "--treble-hz", "900"][..], "cannot be used with"),
        (&["--plain-hunt", "--method", "stedman"][..], "cannot be used with"),
        (&["--attack", "-24"][..], "--attack is DB:MS"),
        (&["--attack", "6:30"][..], "attack 6 dB, 30 ms: from -80 to 0 dB"),
    ] {
        let o = clapper()
            .args(["synth-ring", "--bells", "3", "--rows", "2"])
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn methods_tunings_handbells_and_noise_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    // Plain Bob Minor, minor tuning from a 250 Hz tenor, handbells, traffic.
    let args = [
        "--bells",
        "6",
        "--rows",
        "16",
        "--method",
        "plain-bob",
        "--tuning",
        "minor",
        "--tenor-hz",
        "250",
        "--handbells",
        "--noise",
        "traffic",
        "--snr",
        "20",
        "--interval-ms",
        "150",
    ];
    let (rate, x, truth) = synth(dir.path(), "bob", &args);
    // Row 2, the first change (x): 214365; row 3 (16): 241635.
    let row = |r: usize| -> Vec<usize> {
        let mut v: Vec<(usize, usize)> = truth
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect::<Vec<_>>())
            .filter(|f| f[1] == r.to_string())
            .map(|f| (f[2].parse().unwrap(), f[0].parse().unwrap()))
            .collect();
        v.sort();
        v.into_iter().map(|p| p.1).collect()
    };
    assert_eq!(
        (row(1), row(2), row(3)),
        (vec![1, 2, 3, 4, 5, 6], vec![2, 1, 4, 3, 6, 5], vec![2, 4, 1, 6, 3, 5])
    );
    assert_eq!(
        truth.lines().next().unwrap(),
        "bell,row,place,stroke,t_s,ideal_t_s,double_delay_ms,double_amplitude_ratio"
    );
    // The tenor's strike note is 250 Hz and there is no hum at 62.5 Hz:
    // at the tenor's first strike, 250 Hz stands 25 dB over 62.5 Hz.
    let t = times(&truth);
    let tenor = truth.lines().skip(1).position(|l| l.starts_with("6,")).unwrap();
    let level = |f: f64| {
        band(rate, &x, f, 0.1)
            .iter()
            .filter(|p| (p.0 - t[tenor] - 0.1).abs() < 0.03)
            .map(|p| 20.0 * p.1.hypot(p.2).log10())
            .fold(f64::MIN, f64::max)
    };
    assert!(level(250.0) > level(62.5) + 25.0, "{} {}", level(250.0), level(62.5));
    let out = clapper()
        .args([
            "synth-ring",
            "--bells",
            "6",
            "--tuning",
            "minor",
            "--tenor-hz",
            "250",
            "--rows",
            "2",
            "--out",
        ])
        .arg(dir.path().join("n.wav"))
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("--nominals 396.9,374.6,333.7,297.3,280.6,250.0"),
        "{said}"
    );
}
