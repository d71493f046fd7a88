//! The sample recordings that ship in `examples/data/`, made by clapper's
//! own synthesis with known truth (so README's measurement commands run on
//! copy-paste, and tests have inputs whose answers are known). Every file
//! is synthetic and says so in `examples/data/README.md`, which is written
//! here too. `clapper sample-data --out DIR` writes them; the same bytes
//! on every run (fixed seeds).

use std::fmt::Write as _;

use clapper_core::prelude::*;
use clapper_io::signal_file::wav_bytes;
use clapper_signal::tower::{major_scale, tower_recording, DoubleStrikeSpec, Method, Room, TowerSpec};
use clapper_signal::Signal;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

use crate::simulate::{Preset, SimulateRequest};
use crate::sound::{synth, SynthOptions};
use crate::AppError;

/// One file of the sample set: its name in the folder and its bytes.
pub struct SampleFile {
    /// File name (no directories).
    pub name: &'static str,
    /// Contents.
    pub bytes: Vec<u8>,
}

/// Restitution of the clapper drop in `drop.wav`: R of the first impact
/// and R2 of the later ones (the paper's lab clapper is near R = 0.1).
pub const DROP_R: (f64, f64) = (0.1, 0.3);

/// Nominals (Hz) of the ring in `tower.wav`: a major scale of eight from
/// 1400 Hz, as `clapper synth-ring` rings by default.
pub fn tower_nominals() -> Vec<f64> {
    tower_spec().bells.iter().map(|b| b.nominal_hz).collect()
}

/// The ring of `tower.wav`: eight bells ringing six rows of plain hunt in
/// a 0.6 s room at 25 dB SNR, bell 4 planted 15 ms odd-struck and one
/// double strike of bell 6, at 16 kHz.
fn tower_spec() -> TowerSpec {
    let mut bells = major_scale(8, 1400.0).unwrap_or_default();
    bells[3].odd_struck_ms = 15.0;
    TowerSpec {
        rate: 16_000.0,
        rows: 6,
        method: Method::PlainHunt,
        doubles: vec![DoubleStrikeSpec {
            bell: 6,
            row: 3,
            delay_ms: 60.0,
            amplitude_ratio: 0.7,
        }],
        room: Some(Room::chamber(0.6)),
        snr_db: Some(25.0),
        seed: 7,
        ..TowerSpec::new(bells)
    }
}

/// Every sample file, in the order README lists them.
pub fn sample_files() -> Result<Vec<SampleFile>, AppError> {
    let (tower, truth) = tower()?;
    Ok(vec![
        SampleFile {
            name: "strike.wav",
            bytes: strike()?,
        },
        SampleFile {
            name: "modes.csv",
            bytes: modes_csv(),
        },
        SampleFile {
            name: "contact.csv",
            bytes: contact_csv()?,
        },
        SampleFile {
            name: "drop.wav",
            bytes: drop_wav()?,
        },
        SampleFile {
            name: "tower.wav",
            bytes: tower,
        },
        SampleFile {
            name: "tower-truth.csv",
            bytes: truth,
        },
        SampleFile {
            name: "tower-nominals.json",
            bytes: format!("{:?}\n", tower_nominals()).into_bytes(),
        },
        SampleFile {
            name: "listening-answers.csv",
            bytes: listening_answers(),
        },
        SampleFile {
            name: "README.md",
            bytes: readme().into_bytes(),
        },
    ])
}

fn wav(sig: &Signal) -> Result<Vec<u8>, AppError> {
    wav_bytes(sig, 0.9).map_err(AppError::Sound)
}

/// The lab bell chimed once (its three measured partials), 22.05 kHz, 3 s.
fn strike() -> Result<Vec<u8>, AppError> {
    let req = SimulateRequest {
        preset: Some(Preset::Lab),
        ..SimulateRequest::default()
    };
    let opts = SynthOptions {
        rate: 22050.0,
        chime: true,
        tail: 3.0,
        ..SynthOptions::default()
    };
    wav(&synth(&req, None, &opts)?.signal)
}

/// The lab bell's three partials with the paper's effective-mass estimate
/// (a third of its 45.8 kg), as `impulse --modes` reads them.
fn modes_csv() -> Vec<u8> {
    let mut o = String::from("freq_hz,effective_mass_kg\n");
    for m in clapper_signal::synth::lab_partials() {
        let _ = writeln!(o, "{},{:.4}", m.freq_hz, m.effective_mass);
    }
    o.into_bytes()
}

/// A contact detector on the lab bell's clapper through one handstroke
/// (penalty contact, k = 1e6 N m/rad, so each contact lasts a few ms):
/// 3.3 V apart, 0.1 V touching, 0.05 V of noise, at 5 kHz for 1.6 s.
fn contact_csv() -> Result<Vec<u8>, AppError> {
    let bell = Bell::lab();
    let cfg = SimConfig {
        contact: ContactModel::Penalty,
        stiffness: 1e6,
        ..SimConfig::default()
    };
    let rate = 5000.0;
    // Recorded four times finer than the file's grid, and every event.
    let mut rec = TraceRecorder::new(0.25 / rate);
    ring(&bell, &cfg, Style::Right, Protocol::Restart, 1, &mut rec)?;
    let samples = &rec.samples;
    let mut rng = Pcg64::seed_from_u64(3);
    let mut o = String::from("t_s,contact_v\n");
    let mut j = 0;
    for k in 0..(1.6 * rate) as usize {
        let t = k as f64 / rate;
        // The last recorded state at or before t.
        while j + 1 < samples.len() && samples[j + 1].t <= t {
            j += 1;
        }
        let touching = samples.get(j).is_some_and(|s| s.contact_force != 0.0);
        let v = if touching { 0.1 } else { 3.3 } + 0.05 * rng.random_range(-1.0..1.0);
        let _ = writeln!(o, "{t:.4},{v:.3}");
    }
    Ok(o.into_bytes())
}

/// An accelerometer on the lab bell while its clapper is dropped onto it
/// from 0.5 m/s and bounces: each impact a 0.4 ms half-sine of the
/// velocity jump, R = 0.1 for the first and 0.3 for the later bounces
/// ([`DROP_R`]), with drift and noise, 50 kHz.
fn drop_wav() -> Result<Vec<u8>, AppError> {
    let (rate, g, pulse) = (50_000.0, 5.0, 4e-4);
    let (r1, r2) = (DROP_R.0.sqrt(), DROP_R.1.sqrt());
    let mut impacts = vec![];
    let (mut t, mut v) = (0.05, 0.5);
    for k in 0..6 {
        let e = if k == 0 { r1 } else { r2 };
        impacts.push((t, v * (1.0 + e)));
        t += 2.0 * e * v / g;
        v *= e;
    }
    t += 0.05;
    let mut rng = Pcg64::seed_from_u64(9);
    let n = (t * rate) as usize;
    let samples = (0..n)
        .map(|i| {
            let tt = i as f64 / rate;
            let mut a = 0.3 + 0.2 * tt + 20.0 * rng.random_range(-1.0..1.0);
            for &(ti, dv) in &impacts {
                if tt >= ti && tt < ti + pulse {
                    a += dv * std::f64::consts::PI / (2.0 * pulse) * (std::f64::consts::PI * (tt - ti) / pulse).sin();
                }
            }
            a
        })
        .collect();
    wav(&Signal { rate, samples })
}

/// The recording of [`tower_spec`], with the true strike times.
fn tower() -> Result<(Vec<u8>, Vec<u8>), AppError> {
    let spec = tower_spec();
    let (sig, truth) = tower_recording(&spec).map_err(|e| AppError::Sound(e.to_string()))?;
    let mut o = String::from("bell,t_s,row,place,stroke,double_delay_ms,double_ratio\n");
    for s in &truth {
        let (d, r) = s.double.map_or((String::new(), String::new()), |(d, r)| {
            (format!("{:.1}", d * 1e3), format!("{r:.2}"))
        });
        let _ = writeln!(
            o,
            "{},{:.5},{},{},{},{d},{r}",
            s.bell,
            s.t,
            s.row,
            s.place,
            if s.hand { "hand" } else { "back" }
        );
    }
    Ok((wav(&sig)?, o.into_bytes()))
}

/// The hyperbola (A − a)(Δt − b) = c that the listeners of
/// `listening-answers.csv` hear by: a, b (ms), c (ms), and the width of
/// their uncertain band (ms).
pub const LISTENING_TRUTH: (f64, f64, f64, f64) = (0.25, 18.0, 3.0, 1.2);

/// Twenty listeners' answers to the 100 stimuli of the listening test
/// (+1 single, −1 double), each heard double with a logistic probability
/// across [`LISTENING_TRUTH`]'s hyperbola.
fn listening_answers() -> Vec<u8> {
    let (a, b, c, w) = LISTENING_TRUTH;
    let mut rng = Pcg64::seed_from_u64(13);
    let mut o = String::from("listener,trial,stimulus,amplitude_ratio,delay_ms,answer\n");
    for l in 1..=20 {
        for (k, (i, j)) in (1..=10).flat_map(|i| (1..=10).map(move |j| (i, j))).enumerate() {
            let (r, d) = (0.1 * i as f64, 10.0 * j as f64);
            let p_double = 1.0 / (1.0 + (-((r - a) * (d - b) - c) / w).exp());
            let answer = if rng.random_range(0.0..1.0) < p_double { -1 } else { 1 };
            let _ = writeln!(o, "listener{l:02},{},A{r:.1}-D{d:.0},{r:.1},{d:.0},{answer}", k + 1);
        }
    }
    o.into_bytes()
}

fn readme() -> String {
    let partials = clapper_signal::synth::lab_partials();
    let list =
        |f: &dyn Fn(&clapper_signal::synth::SynthMode) -> String| partials.iter().map(f).collect::<Vec<_>>().join(", ");
    let t = tower_spec();
    let odd: Vec<String> = (t.bells.iter().enumerate())
        .filter(|(_, b)| b.odd_struck_ms != 0.0)
        .map(|(k, b)| format!("bell {} {} ms odd-struck", k + 1, b.odd_struck_ms))
        .collect();
    let doubles: Vec<String> = t
        .doubles
        .iter()
        .map(|d| format!("bell {} double-strikes in row {}", d.bell, d.row))
        .collect();
    let nominals: Vec<String> = tower_nominals().iter().map(|f| format!("{f:.1}")).collect();
    format!(
        "# Sample data (synthetic)\n\
         \n\
         Every file here is **synthetic**: made by clapper's own synthesis with\n\
         known truth, not recorded. They let README's measurement commands run on\n\
         copy-paste and give the tests inputs whose answers are known. Made by\n\
         \n\
         \x20   cargo run --release -- sample-data --out examples/data\n\
         \n\
         which writes the same bytes every time (fixed seeds); a test checks that.\n\
         \n\
         | file | what | truth |\n\
         |---|---|---|\n\
         | `strike.wav` | the lab bell chimed once: its partials {freqs} Hz (22.05 kHz) | Q {qs} |\n\
         | `modes.csv` | those partials with effective masses, for `impulse --modes` | {masses} kg |\n\
         | `contact.csv` | a contact detector on the lab clapper through one handstroke (penalty contact, k = 1e6 N m/rad; 5 kHz) | the simulated stroke: lift-off, strike, bounces, rest |\n\
         | `drop.wav` | an accelerometer while the clapper is dropped onto the bell and bounces (50 kHz) | R = {r1}, R2 = {r2} |\n\
         | `tower.wav` | {nb} bells, {rows} rows of {method}, {rt60} s room, {snr} dB SNR ({rate} Hz) | `tower-truth.csv`: every strike; {odd}; {doubles} |\n\
         | `tower-nominals.json` | the nominals (Hz), treble first: {n} | |\n\
         | `listening-answers.csv` | twenty listeners' answers to the double-strike listening test | heard double across (A - {la})(dt - {lb} ms) = {lc} ms |\n",
        freqs = list(&|m| format!("{}", m.freq_hz)),
        qs = list(&|m| format!("{}", m.q)),
        masses = list(&|m| format!("{:.2}", m.effective_mass)),
        r1 = DROP_R.0,
        r2 = DROP_R.1,
        nb = t.bells.len(),
        rows = t.rows,
        method = t.method.name(),
        rt60 = t.room.map_or(0.0, |r| r.rt60_s),
        snr = t.snr_db.unwrap_or(f64::INFINITY),
        rate = t.rate,
        odd = odd.join(", "),
        doubles = doubles.join(", "),
        n = nominals.join(", "),
        la = LISTENING_TRUTH.0,
        lb = LISTENING_TRUTH.1,
        lc = LISTENING_TRUTH.2,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_contact_file_holds_the_strokes_contacts() {
        let text = String::from_utf8(contact_csv().unwrap()).unwrap();
        let low: Vec<f64> = text
            .lines()
            .skip(1)
            .filter_map(|l| l.split_once(','))
            .filter(|(_, v)| v.parse::<f64>().unwrap() < 1.0)
            .map(|(t, _)| t.parse().unwrap())
            .collect();
        // Resting before lift-off (0.54 s), then contacts from the strike
        // (0.97 s) on.
        assert!(low.iter().any(|&t| t < 0.5));
        assert!(
            low.iter().any(|&t| (0.96..1.0).contains(&t)),
            "no contact at the strike"
        );
        assert!(!low.iter().any(|&t| (0.6..0.95).contains(&t)), "touching in flight");
    }

    #[test]
    fn the_tower_truth_has_every_strike() {
        let (_, truth) = tower().unwrap();
        let rows = String::from_utf8(truth).unwrap().lines().count() - 1;
        assert_eq!(rows, 8 * 6);
    }
}
