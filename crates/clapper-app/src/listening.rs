//! The double-strike listening test of Section 4.3: the stimuli, each
//! listener's order, and the analysis with its figure (Fig 13). Behind
//! `clapper listening-test` and the server's `/api/listening/*`.

use clapper_core::listening::{self, Analysis, Answer};
use clapper_plot::chart::{ChartFigure, Panel, Scale};
use clapper_plot::RGBColor;
use clapper_signal::synth::{lab_partials, synthesize, Strike, SynthSpec};
use clapper_signal::Signal;
use serde::Serialize;

use crate::AppError;

/// When the first strike sounds in a stimulus (s): a short lead-in so
/// that players do not clip the attack.
const FIRST_STRIKE_S: f64 = 0.05;
/// Length of a stimulus (s): long enough to hear the lab partials decay.
const STIMULUS_S: f64 = 1.5;
/// Contact pulse length of each strike (s): the paper measured 0.2 to 0.5 ms.
const PULSE_S: f64 = 3e-4;
/// Loudest sample of the loudest stimulus, as a fraction of full scale.
const HEADROOM: f64 = 0.9;
/// Default sample rate (Hz).
pub const DEFAULT_RATE_HZ: f64 = 44100.0;

/// One stimulus: a lab-bell strike and the same strike `ratio` as loud,
/// `delay_ms` later. `ratio = 0` is the single-strike reference.
pub fn stimulus(rate: f64, ratio: f64, delay_ms: f64) -> Result<Signal, AppError> {
    let first = Strike {
        t: FIRST_STRIKE_S,
        impulse: 1.0,
        pulse: PULSE_S,
    };
    let mut strikes = vec![first];
    if ratio > 0.0 {
        strikes.push(Strike {
            t: first.t + delay_ms * 1e-3,
            impulse: ratio,
            pulse: PULSE_S,
        });
    }
    synthesize(&SynthSpec {
        rate,
        duration: STIMULUS_S,
        modes: lab_partials(),
        strikes,
        rests: vec![],
        rest_damping: 1.0,
        acceleration: false,
    })
    .map_err(|e| AppError::Sound(e.to_string()))
}

/// One of the 100 stimuli of the grid.
#[derive(Clone, Debug)]
pub struct Stimulus {
    /// Index `ratio_index * 10 + delay_index`, 0..100.
    pub index: usize,
    /// File name, `s000.wav` .. `s099.wav`.
    pub name: String,
    /// Amplitude ratio of the second strike.
    pub ratio: f64,
    /// Delay of the second strike (ms).
    pub delay_ms: f64,
    /// The sound.
    pub signal: Signal,
}

/// All stimuli and the reference, sharing one loudness scale so that
/// their loudness compares.
#[derive(Clone, Debug)]
pub struct StimulusSet {
    /// The single strike.
    pub reference: Signal,
    /// The grid, by index.
    pub stimuli: Vec<Stimulus>,
    peak: f64,
}

impl StimulusSet {
    /// Synthesise the set at `rate` (Hz); about 0.3 s of work at 44.1 kHz.
    pub fn new(rate: f64) -> Result<Self, AppError> {
        if !(rate.is_finite() && (8000.0..=192_000.0).contains(&rate)) {
            return Err(AppError::Request(format!(
                "sample rate {rate} Hz must be 8000 to 192000"
            )));
        }
        let (rg, dg) = (listening::ratios(), listening::delays_ms());
        let reference = stimulus(rate, 0.0, 0.0)?;
        let mut stimuli = vec![];
        for (i, &ratio) in rg.iter().enumerate() {
            for (j, &delay_ms) in dg.iter().enumerate() {
                let index = i * 10 + j;
                stimuli.push(Stimulus {
                    index,
                    name: format!("s{index:03}.wav"),
                    ratio,
                    delay_ms,
                    signal: stimulus(rate, ratio, delay_ms)?,
                });
            }
        }
        let peak = stimuli
            .iter()
            .flat_map(|s| s.signal.samples.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        Ok(Self {
            reference,
            stimuli,
            peak,
        })
    }

    /// The peak (fraction of full scale) `sig` gets in its WAV file.
    pub fn scale(&self, sig: &Signal) -> f64 {
        let own = sig.samples.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        HEADROOM * own / self.peak.max(1e-300)
    }

    /// The WAV file's bytes of `sig` on the set's common scale.
    pub fn wav(&self, sig: &Signal) -> Result<Vec<u8>, AppError> {
        clapper_io::signal_file::wav_bytes(sig, self.scale(sig)).map_err(AppError::Sound)
    }

    /// Listener `listener`'s trials (from 0) in the order of `seed`.
    pub fn sheet(&self, seed: u64, listener: u64) -> Vec<&Stimulus> {
        listening::order(seed, listener)
            .into_iter()
            .map(|k| &self.stimuli[k])
            .collect()
    }
}

/// The analysis as `clapper listening-test analyse --json` prints it.
#[derive(Clone, Debug, Serialize)]
pub struct AnalysisReport {
    /// How many answers were read.
    pub answers: usize,
    /// Listeners whose answers were used.
    pub listeners_used: Vec<String>,
    /// Listeners left out, with their correlation with the others' mean.
    pub excluded: Vec<Excluded>,
    /// Mean answer per cell, rows by amplitude ratio (0.1 .. 1), columns by
    /// delay (10 .. 100 ms); `null` where nobody answered.
    pub scores: Vec<Vec<Option<f64>>>,
    /// The fitted hyperbola (A − a)(Δt − b) = c of (33), if there is a
    /// zero contour to fit.
    pub fit: Option<FitReport>,
}

/// A listener left out.
#[derive(Clone, Debug, Serialize)]
pub struct Excluded {
    /// Who.
    pub listener: String,
    /// Correlation with the others' mean.
    pub correlation: f64,
}

/// The fit of (33) with standard errors.
#[derive(Clone, Debug, Serialize)]
pub struct FitReport {
    /// a.
    pub a: f64,
    /// b (ms).
    pub b_ms: f64,
    /// c (ms).
    pub c_ms: f64,
    /// Standard error of a.
    pub sigma_a: f64,
    /// Standard error of b (ms).
    pub sigma_b_ms: f64,
    /// Standard error of c (ms).
    pub sigma_c_ms: f64,
    /// Width of the transition (ms).
    pub width_ms: f64,
}

/// Analyse answers: average, leave out listeners who stand apart, fit (33).
pub fn analyse(answers: &[Answer]) -> Result<(Analysis, AnalysisReport), AppError> {
    if answers.is_empty() {
        return Err(AppError::Request(
            "no answers: fill the 'answer' column with 1 (single) or -1 (double)".into(),
        ));
    }
    let an = listening::analyse(answers)?;
    let report = AnalysisReport {
        answers: answers.len(),
        listeners_used: an.used.clone(),
        excluded: an
            .excluded
            .iter()
            .map(|(n, r)| Excluded {
                listener: n.clone(),
                correlation: *r,
            })
            .collect(),
        scores: an
            .scores
            .iter()
            .map(|r| r.iter().map(|v| v.is_finite().then_some(*v)).collect())
            .collect(),
        fit: an.fit.map(|f| FitReport {
            a: f.a,
            b_ms: f.b,
            c_ms: f.c,
            sigma_a: f.sigma[0],
            sigma_b_ms: f.sigma[1],
            sigma_c_ms: f.sigma[2],
            width_ms: f.width,
        }),
    };
    Ok((an, report))
}

/// The score map with its zero contour and the fitted D = 1 and D = 10
/// curves: the paper's Fig 13.
pub fn figure(an: &Analysis) -> ChartFigure {
    let (rg, dg) = (listening::ratios(), listening::delays_ms());
    let mut values = vec![];
    let mut region = vec![];
    for row in &an.scores {
        for &s in row {
            values.push(s.is_finite().then_some(s));
            region.push(s > 0.0);
        }
    }
    let mut lines = vec![];
    if let Some(f) = &an.fit {
        for (d, label) in [(1.0, "D = 1 (fitted)"), (10.0, "D = 10")] {
            let pts: Vec<(f64, f64)> = (0..=400)
                .filter_map(|k| {
                    let r = 0.05 + 1.0 * k as f64 / 400.0;
                    f.delay_at(r, d).map(|t| (t, r))
                })
                .collect();
            lines.push((label.to_string(), pts, RGBColor(255, 255, 255)));
        }
    }
    ChartFigure {
        title: format!(
            "Fig 13: mean answer (+1 single, -1 double), {} listener(s); black: zero contour",
            an.used.len()
        ),
        // Panels are row-major by y (ratio) then x (delay): as the scores are.
        panels: vec![Panel {
            title: String::new(),
            xs: dg.to_vec(),
            ys: rg.to_vec(),
            values,
            region,
        }],
        scale: Scale::Continuous {
            min: -1.0,
            max: 1.0,
            label: "mean answer (+1 single, -1 double)".into(),
        },
        markers: vec![],
        axes: (
            "delay between strikes (ms)".into(),
            "amplitude ratio of the second strike".into(),
        ),
        lines,
    }
}

/// The analysis in words, as `clapper listening-test analyse` prints it.
pub fn text(rep: &AnalysisReport) -> String {
    let mut o = format!(
        "{} answer(s) from {} listener(s)\n",
        rep.answers,
        rep.listeners_used.len() + rep.excluded.len()
    );
    for e in &rep.excluded {
        o += &format!(
            "  left out {}: correlation {:.2} with the others' mean (below {})\n",
            e.listener,
            e.correlation,
            listening::EXCLUDE_BELOW
        );
    }
    match &rep.fit {
        Some(f) => {
            o += &format!(
                "zero contour fitted by (A - a)(dt - b) = c:\n  a = {:.3} +- {:.3}\n  b = {:.1} +- {:.1} ms\n  c = {:.2} +- {:.2} ms\n  (the paper: a = 0.2, b = 22 ms, c = 2.25 ms); D = (A - a)(dt - b)/c\n",
                f.a, f.sigma_a, f.b_ms, f.sigma_b_ms, f.c_ms, f.sigma_c_ms
            )
        }
        None => o += "the score map has no clear zero contour to fit\n",
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stimuli_share_one_scale_and_encode() {
        let set = StimulusSet::new(8000.0).unwrap();
        assert_eq!(set.stimuli.len(), 100);
        let loudest = set.stimuli.iter().map(|s| set.scale(&s.signal)).fold(0.0, f64::max);
        assert!((loudest - HEADROOM).abs() < 1e-12);
        // The reference (one strike) is quieter than the loudest double.
        assert!(set.scale(&set.reference) < loudest);
        let wav = set.wav(&set.stimuli[5].signal).unwrap();
        assert_eq!(&wav[..4], b"RIFF");
        assert_eq!(wav.len(), 44 + 2 * set.stimuli[5].signal.samples.len());
        let sheet = set.sheet(1, 0);
        let mut seen: Vec<usize> = sheet.iter().map(|s| s.index).collect();
        seen.sort_unstable();
        assert_eq!(seen, (0..100).collect::<Vec<_>>());
        assert!(StimulusSet::new(10.0).is_err());
    }

    #[test]
    fn no_answers_is_a_bad_request() {
        let e = analyse(&[]).unwrap_err();
        assert!(e.is_bad_input() && e.to_string().contains("no answers"));
    }
}
