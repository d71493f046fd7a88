//! A recording's strikes set beside the model's diagnosis of the same
//! ring (`clapper diagnose --recording`): each bell's odd-struckness and
//! double strikes heard against what the model gives.

use std::fmt::Write as _;

use serde::Serialize;

use super::{StrikesReport, StrikesSummary};

/// A bell's striking heard in a recording beside what the model gives for
/// it (`clapper diagnose --recording`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HeardBeside {
    /// Bell, counting from 1: the recording's bell n is the ring file's n-th.
    pub bell: usize,
    /// The bell's name in the ring file.
    pub name: String,
    /// Strikes heard.
    pub strikes: usize,
    /// Odd-struckness heard (ms, hand minus back against the rest of the ring).
    pub heard_odd_struck_ms: Option<f64>,
    /// Its standard error (ms).
    pub heard_odd_struck_se_ms: Option<f64>,
    /// Odd-struckness the model gives with the tower's readings (ms; 0 for
    /// a symmetric hanging; null when the bell sustains neither style).
    pub simulated_odd_struck_ms: Option<f64>,
    /// Double strikes heard over strikes.
    pub heard_double_rate: f64,
    /// Mean D of the double strikes heard.
    pub heard_mean_d: Option<f64>,
    /// D the model gives at R = 0.1 (None: no second impact).
    pub simulated_d: Option<f64>,
    /// The two set side by side, in words.
    pub words: Vec<String>,
}

/// A recording heard beside a ring's diagnosis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RecordingBeside {
    /// The recording.
    pub file: String,
    /// The recording as a whole.
    pub summary: StrikesSummary,
    /// Each bell heard and diagnosed, treble first.
    pub bells: Vec<HeardBeside>,
}

/// Set what was heard (`heard`, from the recording `file`) beside the
/// diagnosis `diag` of the same ring, bell by bell in order.
pub fn beside(diag: &crate::diagnosis::DiagnosisReport, heard: &StrikesReport, file: &str) -> RecordingBeside {
    let mut summary = heard.summary.clone();
    if diag.bells.len() != heard.bells {
        summary.warnings.push(super::Warning::new(
            super::WarningKind::Give,
            format!(
                "the ring file has {} bell(s), the recording was listened to for {}: the first {} are set side by \
                 side",
                diag.bells.len(),
                heard.bells,
                diag.bells.len().min(heard.bells)
            ),
        ));
    }
    let bells = diag
        .bells
        .iter()
        .zip(&heard.per_bell)
        .map(|(d, h)| {
            let sim = d.odd_struck.as_ref().map_or(Some(0.0), |o| o.odd_struck_ms);
            let sim_d = d.double_strike_index.r01;
            let mut words = vec![];
            match (h.odd_struck_ms, h.odd_struck_se_ms, sim) {
                (Some(_), _, None) => words.push("the model gives no odd-struckness: it sustains neither style".into()),
                (Some(o), se, Some(sim_odd)) => {
                    let se = se.unwrap_or(f64::NAN);
                    // Agreement within twice the standard error, and never
                    // closer than 5 ms: a ringer's own habit, and what an
                    // odd-struck bell lends its neighbours in rounds, are
                    // that size; an odd-struck hanging shows as 10 ms and more.
                    let tol = if se.is_finite() { (2.0 * se).max(5.0) } else { 5.0 };
                    words.push(if (o - sim_odd).abs() <= tol {
                        format!("odd-struckness heard {o:+.1} ± {se:.1} ms agrees with the model's {sim_odd:+.1} ms")
                    } else {
                        format!(
                            "odd-struckness heard {o:+.1} ± {se:.1} ms where the model gives {sim_odd:+.1} ms: measure the clapper pivot's offset and the two contact angles (--pivot-offset, --phi-max-hand and --phi-max-back, or the tape's --gap-hand, --gap-back and --ball-below-pivot), or the ringer is holding it up at one stroke"
                        )
                    });
                }
                _ => words.push("odd-struckness not heard (too few placed strikes)".into()),
            }
            let heard_d = h.mean_d;
            words.push(match (h.double_strikes, sim_d) {
                (0, Some(s)) if s > 10.0 => format!(
                    "no double strikes heard, though the model gives D = {s:.1} at R = 0.1: the clapper's restitution may be lower than 0.1"
                ),
                (0, _) => "no double strikes heard".into(),
                (n, s) => format!(
                    "double strikes heard on {n} of {} strikes (mean D {}), the model gives D = {} at R = 0.1",
                    h.strikes,
                    heard_d.map_or("-".into(), |v| format!("{v:.1}")),
                    s.map_or("- (no second impact)".into(), |v| format!("{v:.1}"))
                ),
            });
            HeardBeside {
                bell: h.bell,
                name: d.name.clone(),
                strikes: h.strikes,
                heard_odd_struck_ms: h.odd_struck_ms,
                heard_odd_struck_se_ms: h.odd_struck_se_ms,
                simulated_odd_struck_ms: sim,
                heard_double_rate: h.double_rate,
                heard_mean_d: heard_d,
                simulated_d: sim_d,
                words,
            }
        })
        .collect();
    RecordingBeside {
        file: file.to_string(),
        summary,
        bells,
    }
}

impl RecordingBeside {
    /// The readable comparison.
    pub fn text(&self) -> String {
        let s = &self.summary;
        let mut o = format!(
            "\nHeard in {}: {} strike(s) in {} row(s), RMS striking error {} ms\n",
            self.file,
            s.strikes,
            s.rows,
            s.rms_error_ms.map_or("-".into(), |v| format!("{v:.1}"))
        );
        let _ = writeln!(
            o,
            "  {:>4} {:<14} {:>16} {:>14} {:>12} {:>10}",
            "bell", "name", "odd heard (ms)", "odd model ms", "doubles", "D model"
        );
        for b in &self.bells {
            let odd = match (b.heard_odd_struck_ms, b.heard_odd_struck_se_ms) {
                (Some(x), Some(se)) => format!("{x:+.1} ± {se:.1}"),
                (Some(x), None) => format!("{x:+.1}"),
                _ => "-".into(),
            };
            let _ = writeln!(
                o,
                "  {:>4} {:<14} {:>16} {:>14} {:>12} {:>10}",
                b.bell,
                b.name.chars().take(14).collect::<String>(),
                odd,
                b.simulated_odd_struck_ms.map_or("-".into(), |v| format!("{v:+.1}")),
                format!("{:.0} %", 100.0 * b.heard_double_rate),
                b.simulated_d.map_or("-".into(), |v| format!("{v:.1}"))
            );
            for w in &b.words {
                let _ = writeln!(o, "       {w}");
            }
        }
        for w in s.warnings.iter() {
            let _ = writeln!(o, "warning: {w}");
        }
        o
    }
}
