//! What is not a ring, said (issue 43): a nominal a recording cannot hold
//! is refused; a recording with no strike of the bells given, and one bell
//! alone, are warned of. The CLI, the web server and Python share these.

use clapper_signal::strikes::{BellVoice, Heard};

use super::warning::{Warning, WarningKind};
use crate::AppError;

/// A signal-processing error as a refused request, said as the strike finder's.
pub(super) fn signal_error(e: clapper_signal::SignalError) -> AppError {
    AppError::Request(format!("strikes: {e}"))
}

/// The warning, first, when a recording that is not silent holds no strike
/// of the bells given (speech, music, another ring).
pub const NO_STRIKES: &str = "no strikes heard: nothing here starts the given bells' partials as a bell's strike \
                              does; is this a recording of these bells ringing, and are the nominals or recorded strikes given \
                              theirs?";

/// The warning for one bell: its strikes are real, but striking is judged
/// between bells.
pub const ONE_BELL: &str = "one bell: its strikes are listed, but rows, places, striking errors, the handstroke \
                            gap and odd-struckness are judged between bells ringing together: give every \
                            ringing bell (its nominal with --nominals; with --templates its strike alone, 1.wav, \
                            2.wav, .. treble first, in the folder), or --bells N";

/// Refused: a bell whose strongest partial lies at or above half the
/// recording's rate `rate_hz` (Hz), where the recording holds nothing (it
/// was heard as a bell that never struck).
pub(super) fn heard_at(rate_hz: f64, voices: &[BellVoice]) -> Result<(), AppError> {
    for (i, v) in voices.iter().enumerate() {
        let strongest = v.partials.iter().max_by(|a, b| a.strength.total_cmp(&b.strength));
        if let Some(p) = strongest.filter(|p| p.freq_hz >= 0.5 * rate_hz) {
            return Err(AppError::Request(format!(
                "bell {}'s strongest partial, {} Hz (its nominal), is above {} Hz, the highest sound a recording \
                 at {} Hz holds: is the nominal right, and the recording's rate?",
                i + 1,
                p.freq_hz,
                0.5 * rate_hz,
                rate_hz
            )));
        }
    }
    Ok(())
}

/// How [`not_bells`]'s warning starts.
const NOT_BELLS_START: &str = "this does not sound like a recording of bells";

/// The warning, first, when only the share `p` (under
/// [`PLAUSIBLE_SHARE`](clapper_signal::strikes::PLAUSIBLE_SHARE)) of the
/// strikes heard rise and ring on as a bell's strike does.
pub(super) fn not_bells(p: f64) -> String {
    format!(
        "{NOT_BELLS_START}: across only {:.0} % of the strikes heard does their \
         bell's partial listened to rise and ring on (its strongest, or with templates its highest strong one: a \
         bell's strike starts it and it rings for seconds; noise or a steady tone does not rise, a syllable of \
         speech stops within a fifth of a second); the strikes, rows and double strikes below are not to be \
         trusted",
        100.0 * p
    )
}

/// Under this length (s) a recording holds no ring to judge: the learner
/// of `--bells N` asks a second of ringing, and a row of even six bells
/// takes over a second (six places of 0.2 s).
pub const SHORTEST_RING_S: f64 = 1.0;

/// How [`too_short`]'s warning starts.
const TOO_SHORT_START: &str = "the recording is only";

/// The warning, first, for a recording `duration_s` (s) long, shorter
/// than [`SHORTEST_RING_S`] (tester19: a 2 ms file was said to be silent).
pub(super) fn too_short(duration_s: f64) -> String {
    format!(
        "{TOO_SHORT_START} {:.0} ms long: a ring's strikes need seconds of recording (is this the whole file?)",
        1000.0 * duration_s
    )
}

/// How many of `warnings` at their head are about the recording as a
/// whole (silent, too short, no strikes heard, not bells: their kind
/// [`WarningKind::Recording`]): they stand before every other.
pub(super) fn leading(warnings: &[Warning]) -> usize {
    warnings.iter().take_while(|w| w.kind == WarningKind::Recording).count()
}

/// Under this sample rate (Hz) the recording's double strikes judged
/// against recorded strikes (templates) at a higher rate are not to be
/// trusted: tester21's six (I6, 6 doubles struck), made 8 kHz, gave 40
/// doubles with its 44.1 kHz templates, and the same with them made
/// 8 kHz first; at 11.025 kHz 7, at 16 kHz 6; with `--nominals` at 8 kHz, 5.
pub const TEMPLATE_DOUBLES_LEAST_RATE_HZ: f64 = 11_000.0;

/// A warning when the recording's rate `rate` (Hz) is under
/// [`TEMPLATE_DOUBLES_LEAST_RATE_HZ`] and the templates' `template_rate`
/// (Hz) is higher: its double strikes may be false.
pub(super) fn low_rate_doubles(rate: f64, template_rate: f64) -> Option<String> {
    (rate < TEMPLATE_DOUBLES_LEAST_RATE_HZ && template_rate > rate).then(|| {
        format!(
            "the recording is at {:.1} kHz, the recorded strikes given at {:.1} kHz: heard against them at so low a \
             rate, many single strikes are taken for double strikes; record at 16 kHz or more, or judge the doubles with --nominals",
            rate / 1e3,
            template_rate / 1e3
        )
    })
}

/// Under this length (s) a recording holds a row or two at most: its
/// strikes are listed, but a bell's striking is not judged on so few
/// (tester21: a 2 s clip read "10 strikes in 4 rows" without a word, where
/// 0.5 s was warned of). Six bells at 0.2 s ring two whole pulls in 5.2 s.
pub const SHORT_RING_S: f64 = 5.0;

/// The warning for a recording `duration_s` (s) long, at least
/// [`SHORTEST_RING_S`] but under [`SHORT_RING_S`].
pub(super) fn short(duration_s: f64) -> String {
    format!(
        "{TOO_SHORT_START} {duration_s:.1} s long: a row or two at most, too few strikes to judge a bell's striking \
         by (is this the whole file?)"
    )
}

/// Under this many rows at the ring's pace a recording is short too,
/// however many seconds: a bell's hand and back columns each need
/// [`super::FEW_IN_COLUMN`] strikes, so no bell's striking at either
/// stroke is measured in fewer (tester22 fault 11: a 6 s clip of a six
/// with templates found 10 of some 27 strikes, three bells "not heard at
/// all", with no word that the clip was short).
pub const SHORT_RING_ROWS: usize = 2 * super::FEW_IN_COLUMN;

/// The interval between bells (s) taken where none is heard: a fast
/// ring's, so that the rows a recording holds are not undercounted.
const FAST_INTERVAL_S: f64 = 0.2;

/// The warning for a recording `duration_s` (s) long, [`SHORT_RING_S`] or
/// longer, that holds fewer than [`SHORT_RING_ROWS`] rows of `bells`
/// bells at the interval heard (`interval_s`, s; a fast ring's where
/// none is): rows of `bells` places and a handstroke gap's half.
pub(super) fn short_for_pace(duration_s: f64, bells: usize, interval_s: Option<f64>) -> Option<String> {
    let row_s = (bells as f64 + 0.5) * interval_s.unwrap_or(FAST_INTERVAL_S);
    let rows = duration_s / row_s;
    (duration_s >= SHORT_RING_S && bells > 1 && rows < SHORT_RING_ROWS as f64).then(|| {
        format!(
            "{TOO_SHORT_START} {duration_s:.1} s long: about {rows:.0} rows of {bells} bells at this pace, too few \
             for any bell's hand and back columns ({} strikes each) to be measured, or a bell missed at some strikes \
             to be told from one not ringing (is this the whole file?)",
            super::FEW_IN_COLUMN
        )
    })
}

/// Add to `warnings` what makes the report no ring's: silence (the
/// recording's `peak` 0), a recording `duration_s` (s) too short to hold a
/// ring, no strike heard (first, in words, so that an empty table is not
/// read as a quiet ring), one bell of `bells`.
pub(super) fn warn_of(warnings: &mut Vec<Warning>, peak: f64, duration_s: f64, strikes: usize, bells: usize) {
    let recording = |t: String| Warning::new(WarningKind::Recording, t);
    if peak == 0.0 {
        warnings.insert(0, recording("the recording is silent".into()));
    } else if strikes == 0 {
        warnings.insert(0, recording(NO_STRIKES.into()));
    }
    if duration_s < SHORTEST_RING_S {
        warnings.insert(0, recording(too_short(duration_s)));
    } else if duration_s < SHORT_RING_S && strikes > 0 {
        warnings.insert(0, recording(short(duration_s)));
    }
    if bells == 1 && strikes > 0 {
        warnings.push(Warning::new(WarningKind::Give, ONE_BELL));
    }
}

/// Strikes timed before the recording starts (a bell's lateness taken off
/// a sound heard in its first moments: a tester's chatter before the ring
/// gave a strike at -0.124 s) dropped from `heard`, with a warning in
/// `warnings`: no strike's sound starts before the recording does.
pub(super) fn drop_before_start(heard: &mut Heard, warnings: &mut Vec<Warning>) {
    let first = heard.strikes.iter().map(|s| s.t).fold(0.0, f64::min);
    let before = heard.strikes.iter().filter(|s| s.t < 0.0).count();
    if before > 0 {
        heard.strikes.retain(|s| s.t >= 0.0);
        warnings.push(Warning::new(
            WarningKind::Note,
            format!(
                "{before} strike(s) timed before the recording starts (the first at {first:.3} s): left out; a \
                 sound heard as the recording starts is a strike cut short, or not a bell's"
            ),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_signal::strikes::HeardStrike;

    /// Tester21: an 8 kHz recording with 44.1 kHz templates gave 12.6 %
    /// false doubles without a word.
    #[test]
    fn doubles_at_a_telephones_rate_against_finer_templates_are_doubted() {
        assert!(low_rate_doubles(8_000.0, 44_100.0).is_some_and(|w| w.contains("8.0 kHz")));
        assert_eq!(low_rate_doubles(16_000.0, 44_100.0), None);
        assert_eq!(low_rate_doubles(8_000.0, 8_000.0), None);
    }

    #[test]
    fn a_strike_timed_before_the_recording_starts_is_left_out_and_said() {
        let strike = |t: f64| HeardStrike {
            bell: 1,
            t,
            strength: 1.0,
            double: None,
        };
        let mut heard = Heard {
            strikes: vec![strike(-0.124), strike(0.5), strike(0.9)],
            warnings: vec![],
        };
        let mut w = vec![];
        drop_before_start(&mut heard, &mut w);
        assert_eq!(heard.strikes.len(), 2);
        assert!(heard.strikes.iter().all(|s| s.t >= 0.0));
        assert!(w.len() == 1 && w[0].text.contains("-0.124 s"), "{w:?}");
        let mut again = vec![];
        drop_before_start(&mut heard, &mut again);
        assert!(again.is_empty());
    }
}
