//! `clapper strikes --plot`: the striking diagram of a report and the
//! spectrogram strip of the recording's opening, as data to draw.

use clapper_signal::strikes::BellVoice;
use clapper_signal::Signal;

use super::{signal_error, StrikesReport};
use crate::AppError;

/// The opening stretch of the recording drawn in the striking plot's
/// spectrogram strip (s): a few rows, enough to see each bell's onsets.
pub const STRIP_S: f64 = 8.0;

/// `clapper strikes --plot`: the striking diagram and the spectrogram strip
/// of the recording's opening [`STRIP_S`] seconds, as data to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct StrikingFigure {
    title: String,
    strip_title: String,
    bells: usize,
    interval_ms: f64,
    strikes: Vec<clapper_plot::PlotStrike>,
    spectrogram: clapper_signal::spectrogram::Spectrogram,
    fmax_hz: f64,
}

impl StrikingFigure {
    /// The figure of `report` heard in `sig` (the recording `name`) for the
    /// bells `voices`; the strip is drawn up to 1.6 times the highest bell's
    /// strongest partial (a tuned bell's nominal), and over every partial
    /// at least 0.3 of its bell's strongest: a recorded bell's strongest
    /// partial is often its prime, an octave under its nominal, and a strip
    /// up to 1.6 times that left the trebles' nominals out.
    pub fn new(report: &StrikesReport, sig: &Signal, name: &str, voices: &[BellVoice]) -> Result<Self, AppError> {
        let fmax_hz = voices
            .iter()
            .filter_map(|v| {
                let top = v.partials.iter().max_by(|a, b| a.strength.total_cmp(&b.strength))?;
                let strong = v.partials.iter().filter(|p| p.strength >= 0.3 * top.strength);
                Some(strong.map(|p| 1.1 * p.freq_hz).fold(1.6 * top.freq_hz, f64::max))
            })
            .fold(0.0, f64::max);
        let end = ((STRIP_S * sig.rate) as usize).min(sig.samples.len());
        let opening = Signal {
            rate: sig.rate,
            samples: sig.samples[..end].to_vec(),
        };
        // 46 ms windows (1024 samples at 22.05 kHz), 90 % overlap: a strike's
        // onset is sharp to a few ms in the picture.
        let window = ((0.046 * sig.rate) as usize).next_power_of_two().min(end.max(16));
        let spectrogram =
            clapper_signal::spectrogram::spectrogram(&opening, window, 0.9, 70.0).map_err(signal_error)?;
        let s = &report.summary;
        let interval_ms = s.interval_ms.unwrap_or(200.0);
        Ok(StrikingFigure {
            title: format!(
                "{name}: {} strikes of {} bells, RMS error {} ms, {} double strike(s) (ringed)",
                s.strikes,
                report.bells,
                s.rms_error_ms.map_or("-".into(), |v| format!("{v:.1}")),
                s.double_strikes
            ),
            strip_title: format!(
                "the first {:.0} s: strikes heard, by bell",
                (end as f64 / sig.rate).min(STRIP_S)
            ),
            bells: report.bells,
            interval_ms,
            strikes: report
                .strikes
                .iter()
                .map(|st| clapper_plot::PlotStrike {
                    bell: st.bell,
                    t_s: st.t_s,
                    row_place: st.row.zip(st.place),
                    error_ms: st.error_ms,
                    hand: st.stroke.map(|k| k == "hand"),
                    double: st.double.is_some(),
                })
                .collect(),
            spectrogram,
            fmax_hz: fmax_hz.min(0.5 * sig.rate),
        })
    }

    /// What to draw.
    pub fn plot(&self) -> clapper_plot::StrikingPlot<'_> {
        clapper_plot::StrikingPlot {
            title: &self.title,
            bells: self.bells,
            interval_ms: self.interval_ms,
            strikes: &self.strikes,
            spectrogram: clapper_plot::SpectrogramPlot {
                title: &self.strip_title,
                times: &self.spectrogram.times,
                freqs: &self.spectrogram.freqs,
                db: &self.spectrogram.db,
                fmax: self.fmax_hz,
                range_db: 70.0,
            },
        }
    }
}
