//! What the strike finder is asked (its options) and what it hears.

use crate::SignalError;

/// Options for finding strikes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrikeOptions {
    /// No bell strikes twice in less than this (s), double strikes apart.
    /// Default 0.5 s: a bell's handstroke and backstroke are a row apart,
    /// at least 0.9 s in any ring.
    pub min_separation_s: f64,
    /// The double-strike window (ms): a second strike this long after the
    /// first. Default 10 to 150 ms (issue 19; the paper's double strikes
    /// fall from 20 to 120 ms).
    pub double_window_ms: (f64, f64),
    /// A second strike this loud or louder, against the first (amplitude
    /// ratio), is a double strike. Default 0.3: below it the paper's
    /// listeners heard no double strike at any delay (eq. 33's A − 0.2 is
    /// small).
    pub double_min_ratio: f64,
    /// Whether and how a bell heard at one stroke only has its quieter
    /// strokes looked for (issue 43: a tower bell's level is not the same
    /// at hand and back). Default [`QuietStrokes::Off`].
    pub quiet_strokes: QuietStrokes,
}

/// How a bell heard at one stroke only (its kept strikes two rows apart)
/// has its quieter strokes looked for ([`StrikeOptions::quiet_strokes`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum QuietStrokes {
    /// Not looked for (the default): with the nominals' assumed partials a
    /// recorded ring in rounds (RT60 1.2 s) has a bump a row after every
    /// strike at half the strike's height, and a search among the
    /// candidates took it (precision within 10 ms 0.902 -> 0.758); and the
    /// calibration from the recording's own strikes hears without them, so
    /// that strokes found so never move the lateness it learns nor the
    /// other bells' fitted strikes (quiet-2, session 18: tune ring A8_tilt
    /// 0.725 -> 0.572 within 10 ms).
    #[default]
    Off,
    /// Among the bell's candidates, one in the middle of each interval
    /// between its kept strikes: with templates (`clapper_app`'s
    /// `--templates`), where the bump a row after each strike was not taken.
    Between,
    /// Where the ring's rhythm puts them, at the highest peak of the bell's
    /// onset function there (issue 43, `--nominals` and `--bells N`: a bell
    /// 9 dB quieter at one stroke lost every strike at it): in the hearing
    /// timed with the calibration from the recording's own strikes, not in
    /// the calibration itself.
    ByRhythm,
}

/// The default [`StrikeOptions::double_min_ratio`] (see there why), for
/// front ends' option defaults.
pub const DEFAULT_DOUBLE_MIN_RATIO: f64 = 0.3;

impl Default for StrikeOptions {
    fn default() -> Self {
        StrikeOptions {
            min_separation_s: 0.5,
            double_window_ms: (10.0, 150.0),
            double_min_ratio: DEFAULT_DOUBLE_MIN_RATIO,
            quiet_strokes: QuietStrokes::Off,
        }
    }
}

/// A second strike heard after a first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeardDouble {
    /// Delay after the first strike (s).
    pub delay_s: f64,
    /// Its amplitude over the first's.
    pub amplitude_ratio: f64,
}

/// A strike heard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeardStrike {
    /// Bell, counting from 1 (the treble).
    pub bell: usize,
    /// Onset (s from the start of the recording): the start of its sound.
    pub t: f64,
    /// Its onset function's peak over the bell's typical strike (1 is typical).
    pub strength: f64,
    /// The clapper's second strike, if it struck twice.
    pub double: Option<HeardDouble>,
}

/// What was heard.
#[derive(Clone, Debug, PartialEq)]
pub struct Heard {
    /// Every strike, in time order.
    pub strikes: Vec<HeardStrike>,
    /// What the listener could not do (a bell never heard, say), in words.
    pub warnings: Vec<String>,
}

impl Heard {
    /// The strikes as (bell, onset s, double (delay s, ratio)), to score
    /// against a synthetic recording's truth ([`crate::tower::score`]).
    pub fn times(&self) -> Vec<crate::tower::HeardTimes> {
        self.strikes
            .iter()
            .map(|s| (s.bell, s.t, s.double.map(|d| (d.delay_s, d.amplitude_ratio))))
            .collect()
    }
}

pub(super) fn check_options(o: &StrikeOptions) -> Result<(), SignalError> {
    let (a, b) = o.double_window_ms;
    let ok = o.min_separation_s.is_finite()
        && o.min_separation_s >= 0.2
        && o.min_separation_s <= 5.0
        && a.is_finite()
        && b.is_finite()
        && a >= 5.0
        && a < b
        && b * 1e-3 < o.min_separation_s
        && o.double_min_ratio.is_finite()
        && o.double_min_ratio > 0.0
        && o.double_min_ratio <= 2.0;
    if ok {
        Ok(())
    } else {
        Err(SignalError::Option(format!(
            "strike options (separation {} s, double-strike window {} to {} ms, ratio {}): separation 0.2 to 5 s, a double-strike window from 5 ms up and shorter than the separation, a ratio in (0, 2]",
            o.min_separation_s, o.double_window_ms.0, o.double_window_ms.1, o.double_min_ratio
        )))
    }
}
