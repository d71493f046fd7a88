//! How strikes heard about given nominals are timed (issue 43): as heard
//! at the bells' assumed partials ("plain"), or each bell learned from the
//! recording's own clean strikes and timed at the start of its sound
//! ("recording", [`calibrate_from_recording`]). Neither suits every ring:
//! real bells do not follow a tuned bell's partial ratios and their sound
//! builds up after the blow (plain is tens of ms off, bell by bell), while
//! on a tuned ring plain is the sharper. So by default ("auto") both are
//! tried on the recording's opening window and the one whose strikes come
//! more evenly is kept. One function for the command line, the web server
//! and Python, so the three hear the same strikes.

use clapper_signal::self_calibrate::SelfCalibration;
use clapper_signal::strikes::{BellVoice, InMemory, StrikeOptions, Windows};
use clapper_signal::template_timing::median_of;
use clapper_signal::Signal;
use serde::Serialize;

use super::{
    calibrate_from_recording, signal_error, voices_from_nominals, Pass, StrikesReport, Timing, TimingReport, Voice,
};
use crate::AppError;
use clapper_signal::self_calibrate::calibrate_heard;
use clapper_signal::strikes::Hearing;

/// The timing asked for (`--timing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TimingAsked {
    /// Both tried on the opening window, the more even kept ([`choose_timing`]).
    #[default]
    Auto,
    /// As heard at the bells' assumed partials.
    Plain,
    /// Learned from the recording's own clean strikes (`--self-calibrate`).
    Recording,
}

impl std::str::FromStr for TimingAsked {
    type Err = AppError;
    fn from_str(s: &str) -> Result<Self, AppError> {
        match s {
            "auto" => Ok(Self::Auto),
            "plain" => Ok(Self::Plain),
            "recording" => Ok(Self::Recording),
            _ => Err(AppError::Request(format!("timing '{s}': auto, plain or recording"))),
        }
    }
}

impl TimingAsked {
    /// Its name, as `--timing` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Plain => "plain",
            Self::Recording => "recording",
        }
    }
}

/// The recording timing is kept only where its strikes' unevenness is under
/// this share of plain's: on the tuned synthetic rings (seeds 1-4) the two
/// come within 10-25 % of each other and plain is the sharper there, while
/// on rings of recorded bells plain's is 3 to 7 times the recording's.
pub const AUTO_MARGIN: f64 = 0.7;

/// The recording timing is kept only if it finds at least this share of the
/// strikes plain finds in the opening window: a timing that lost strikes
/// could look even on the rest.
pub const AUTO_LEAST_FOUND: f64 = 0.8;

/// Strikes are even where their unevenness is under this share of the
/// median interval between them. Plain timing is trusted only where its
/// own strikes are even: on every ring of recorded bells measured (76
/// rings, 6 and 8 bells, 0.16-0.22 s) plain's came 0.19-0.99 of the
/// interval, each bell late by its own build-up, while a tuned ring's come
/// near a tenth. And the timing used, if not even, is said to be doubtful:
/// where the recording's timing read over 0.2 of the interval, every ring
/// measured lost a bell or more to a lateness mislearned by 40-100 ms.
pub const EVEN_SHARE: f64 = 0.2;

/// Why the timing used was used: both timings' figures on the opening window
/// (`None` where not measured).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TimingChoice {
    /// What was asked: "auto", "plain" or "recording".
    pub asked: &'static str,
    /// What was used: "plain" or "recording".
    pub used: &'static str,
    /// The opening window both were tried on (s; with "auto" only).
    pub window_s: Option<f64>,
    /// Strikes plain timing found in the window.
    pub plain_strikes: Option<usize>,
    /// Strikes the recording timing found in the window.
    pub recording_strikes: Option<usize>,
    /// The unevenness of plain's strikes (ms): the median absolute
    /// difference of the intervals between successive strikes from their
    /// median. A bell timed off by a constant makes the intervals either
    /// side of each of its strikes uneven by that constant.
    pub plain_unevenness_ms: Option<f64>,
    /// The same for the recording timing's strikes (ms).
    pub recording_unevenness_ms: Option<f64>,
    /// Plain's RMS striking error in the window's rows (ms).
    pub plain_rms_ms: Option<f64>,
    /// The recording timing's RMS striking error in the window's rows (ms).
    pub recording_rms_ms: Option<f64>,
    /// Where neither timing's strikes were even, the nominals listened for
    /// instead, each moved to where the recording's bells are heard
    /// nearest it (Hz, treble first; `None`: those given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nominals_heard_hz: Option<Vec<f64>>,
    /// Strikes those nominals found in the window, timed from the recording.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub near_strikes: Option<usize>,
    /// Their unevenness (ms).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub near_unevenness_ms: Option<f64>,
    /// Their RMS striking error in the window's rows (ms).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub near_rms_ms: Option<f64>,
    /// Why, in words.
    pub reason: String,
    /// Doubts about the nominals the choice was made for (e.g. given
    /// tenor first): [`StrikesReport::note_choice`] adds them to the
    /// report's warnings.
    #[serde(skip)]
    pub warnings: Vec<super::Warning>,
}

/// The bells' voices and timing chosen: with a calibration, time the
/// strikes [`Timing::Recording`] with its voices, else as heard with these.
#[derive(Clone, Debug)]
pub struct Chosen {
    /// The voices to listen with.
    pub voices: Vec<BellVoice>,
    /// The calibration, when the recording timing is used.
    pub calibration: Option<SelfCalibration>,
    /// What was chosen and why (for the report's "timing").
    pub choice: TimingChoice,
}

impl Chosen {
    /// The timing to hear the whole recording with.
    pub fn timing(&self) -> Timing<'_> {
        self.calibration.as_ref().map_or(Timing::AsHeard, Timing::Recording)
    }
}

/// The opening of `sig` that the calibration and the choice read: its
/// first window ([`Windows::whole_s`], all of a shorter recording).
pub fn opening(sig: &Signal) -> Signal {
    let n = ((Windows::default().whole_s * sig.rate) as usize).min(sig.samples.len());
    Signal {
        rate: sig.rate,
        samples: sig.samples[..n].to_vec(),
    }
}

/// The unevenness of `report`'s strikes (ms): the median absolute
/// difference of successive intervals from their median. Robust: a lost
/// strike, a handstroke gap or a row the rhythm misplaces moves few
/// intervals and not the median, where the rows' RMS error was misled by
/// misplaced rows (177 ms on a ring whose strikes were within 10 ms).
fn unevenness_ms(report: &StrikesReport) -> Option<f64> {
    evenness(report).map(|e| e.0)
}

/// [`unevenness_ms`] and the median interval between successive strikes
/// (ms), which it is judged against ([`EVEN_SHARE`]).
pub(super) fn evenness(report: &StrikesReport) -> Option<(f64, f64)> {
    let gaps: Vec<f64> = report.strikes.windows(2).map(|w| w[1].t_s - w[0].t_s).collect();
    if gaps.len() < 4 {
        return None;
    }
    let m = median_of(gaps.clone())?;
    let d = median_of(gaps.iter().map(|g| (g - m).abs()).collect())?;
    Some((d * 1e3, m * 1e3))
}

/// The bells of `nominals` (treble first, of `kind`), timed as `asked`, on
/// the recording whose opening window is `head` ([`opening`]). Handbells
/// are timed plain: the calibration learns a tower bell's partials.
pub fn choose_timing(
    head: &Signal,
    nominals: &[f64],
    kind: Voice,
    asked: TimingAsked,
    opts: &StrikeOptions,
) -> Result<Chosen, AppError> {
    let mut chosen = choose(head, nominals, kind, asked, opts)?;
    let order = super::kind::order_warning(nominals);
    (chosen.choice.warnings).extend(order.map(|w| super::Warning::new(super::WarningKind::Give, w)));
    Ok(chosen)
}

/// [`choose_timing`] but for the doubts about the nominals.
fn choose(
    head: &Signal,
    nominals: &[f64],
    kind: Voice,
    asked: TimingAsked,
    opts: &StrikeOptions,
) -> Result<Chosen, AppError> {
    let plain = voices_from_nominals(nominals, kind)?;
    let simple = |used: &'static str, reason: String| TimingChoice {
        asked: asked.name(),
        used,
        reason,
        ..TimingChoice::default()
    };
    match (asked, kind) {
        (TimingAsked::Recording, Voice::Handbell) => Err(AppError::Request(
            "the recording timing learns each bell's partials as a tower bell's: not with handbells".into(),
        )),
        (TimingAsked::Plain, _) => Ok(Chosen {
            voices: plain,
            calibration: None,
            choice: simple("plain", "asked".into()),
        }),
        (TimingAsked::Recording, _) => {
            let c = calibrate_from_recording(head, nominals, opts)?;
            Ok(Chosen {
                voices: c.voices.clone(),
                calibration: Some(c),
                choice: simple("recording", "asked".into()),
            })
        }
        (TimingAsked::Auto, Voice::Handbell) => Ok(Chosen {
            voices: plain,
            calibration: None,
            choice: simple(
                "plain",
                "handbells: the recording timing learns tower bells' partials".into(),
            ),
        }),
        (TimingAsked::Auto, _) => auto(head, nominals, plain, opts),
    }
}

/// Both timings tried on `head`, the more even kept, and the recording's
/// where plain's own strikes are not even ([`decide`]); plain where the
/// calibration fails.
fn auto(head: &Signal, nominals: &[f64], plain: Vec<BellVoice>, opts: &StrikeOptions) -> Result<Chosen, AppError> {
    // The trials read the strikes' times only: no strike judged double.
    let p = StrikesReport::timed_singles(head, &plain, opts, Timing::AsHeard, None)?;
    let mut choice = TimingChoice {
        asked: "auto",
        used: "plain",
        window_s: Some(head.duration()),
        plain_strikes: Some(p.strikes.len()),
        plain_unevenness_ms: unevenness_ms(&p),
        plain_rms_ms: p.summary.rms_error_ms,
        ..TimingChoice::default()
    };
    // The calibration's hearing of the window is the recording trial's.
    let learned = voices_from_nominals(nominals, Voice::Tower)
        .and_then(|_| calibrate_heard(head, nominals, opts).map_err(signal_error));
    let (c, hearing) = match learned {
        Ok(c) => c,
        Err(e) => {
            choice.reason = format!("plain: nothing learned from the recording ({e})");
            return Ok(Chosen {
                voices: plain,
                calibration: None,
                choice,
            });
        }
    };
    let r = StrikesReport::timed_singles(head, &c.voices, opts, Timing::Recording(&c), Some(hearing))?;
    choice.recording_strikes = Some(r.strikes.len());
    choice.recording_unevenness_ms = unevenness_ms(&r);
    choice.recording_rms_ms = r.summary.rms_error_ms;
    let (np, nr) = (p.strikes.len(), r.strikes.len());
    let (recording, reason, doubt) = decide((np, evenness(&p)), (nr, evenness(&r)));
    choice.reason = reason;
    // Neither even: the nominals moved to where the bells are heard tried.
    let kept_ms = if recording {
        choice.recording_unevenness_ms
    } else {
        choice.plain_unevenness_ms
    };
    if let (Some(_), Some(u)) = (&doubt, kept_ms) {
        if let Some(t) = super::near::near_trial(head, nominals, opts, np, u)? {
            return Ok(near_chosen(t, nominals, u, choice));
        }
    }
    choice
        .warnings
        .extend(doubt.map(|w| super::Warning::new(super::WarningKind::Note, w)));
    Ok(if recording {
        choice.used = "recording";
        Chosen {
            voices: c.voices.clone(),
            calibration: Some(c),
            choice,
        }
    } else {
        Chosen {
            voices: plain,
            calibration: None,
            choice,
        }
    })
}

/// The nominals moved near where their bells are heard (`t`, tried on
/// the window as [`super::near::near_trial`] says), timed from the
/// recording; the nominals `given` and their timing's unevenness
/// (`given_ms`) said why. Their strikes are even: no doubt said.
fn near_chosen(t: super::near::NearTrial, given: &[f64], given_ms: f64, mut choice: TimingChoice) -> Chosen {
    choice.used = "recording";
    choice.reason = t.reason(given, given_ms);
    choice.near_strikes = Some(t.strikes);
    choice.near_unevenness_ms = Some(t.unevenness_ms);
    choice.near_rms_ms = t.rms_ms;
    choice
        .warnings
        .push(super::Warning::new(super::WarningKind::Give, t.warning(given)));
    choice.nominals_heard_hz = Some(t.nominals);
    Chosen {
        voices: t.calibration.voices.clone(),
        calibration: Some(t.calibration),
        choice,
    }
}

/// One trial's strikes found and their [`evenness`] (unevenness, median
/// interval; ms), if measured.
type Trial = (usize, Option<(f64, f64)>);

/// Which timing the trials `plain` and `rec` decide ([`AUTO_MARGIN`],
/// [`AUTO_LEAST_FOUND`], [`EVEN_SHARE`]): the recording's (true) or
/// plain; why, in words; and a doubt where the timing used is not even.
fn decide(plain: Trial, rec: Trial) -> (bool, String, Option<String>) {
    let ((np, pe), (nr, re)) = (plain, rec);
    let found_enough = nr as f64 >= AUTO_LEAST_FOUND * np as f64;
    let (Some((pu, pg)), Some((ru, rg))) = (pe, re) else {
        let why = if found_enough {
            "plain: too few strikes to compare the two timings' evenness".to_string()
        } else {
            format!("plain: the recording timing found {nr} strikes where plain found {np}")
        };
        return (false, why, None);
    };
    let more_even = ru < AUTO_MARGIN * pu;
    // Plain uneven: the bells do not sound as tuned bells, each heard late
    // by its own build-up (tens of ms), which the rhythm cannot tell.
    let plain_even = pu < EVEN_SHARE * pg;
    let recording = found_enough && (more_even || !plain_even);
    let reason = if !found_enough {
        format!("plain: the recording timing found {nr} strikes where plain found {np}")
    } else if more_even {
        format!("recording: its strikes came evener ({ru:.1} ms against plain's {pu:.1} ms)")
    } else if recording {
        format!(
            "recording: plain's own strikes were far from even ({pu:.1} ms in {pg:.0} ms intervals, over {EVEN_SHARE} of them), as where the bells do not sound as tuned bells and each is heard late by its own time; the recording's {ru:.1} ms"
        )
    } else {
        format!(
            "plain: the recording timing's strikes were not even enough ({ru:.1} ms against plain's {pu:.1} ms; it must be under {AUTO_MARGIN} of plain's)"
        )
    };
    let (u, g) = if recording { (ru, rg) } else { (pu, pg) };
    let doubt = (u >= EVEN_SHARE * g).then(|| {
        format!(
            "the strikes came unevenly timed either way ({ru:.1} ms timed from the recording, {pu:.1} ms as heard, in intervals of {g:.0} ms; a band's are nearer a tenth): some bells' lateness after the blow could not be told from this recording, so all of such a bell's strikes may be timed tens of ms early or late, bell by bell (or more bells ring than were given: give every bell that rings; or the ringing is itself far from even); a template of each bell (a strike of it alone) times each from its own sound"
        )
    });
    (recording, reason, doubt)
}

impl StrikesReport {
    /// [`Self::timed`] with no strike judged double (not for templates):
    /// for what reads the strikes' times only (the choice's trials), the
    /// finder's double-strike fits (a quarter of its time) are not made.
    /// `ready`, if given, is the finder's hearing of `sig` through `voices`
    /// (the calibration's, made on the same window): not heard again.
    pub(super) fn timed_singles(
        sig: &Signal,
        voices: &[BellVoice],
        opts: &StrikeOptions,
        timing: Timing,
        ready: Option<Hearing>,
    ) -> Result<Self, AppError> {
        let (whole, src) = (Windows::default(), &mut InMemory::new(sig));
        Self::listened(
            src,
            voices,
            opts,
            timing,
            &whole,
            None,
            Pass::Singles(ready.map(Box::new)),
        )
    }

    /// Say in the report's "timing" how its strikes were timed and why
    /// (`choice`, from [`choose_timing`]).
    pub fn note_choice(&mut self, mut choice: TimingChoice) {
        self.summary.warnings.append(&mut choice.warnings);
        super::doubt::once_each(&mut self.summary.warnings);
        match &mut self.timing {
            Some(t) => t.choice = Some(choice),
            None => {
                self.timing = Some(TimingReport {
                    source: "plain",
                    per_bell: vec![],
                    choice: Some(choice),
                })
            }
        }
    }
}

impl TimingChoice {
    /// The choice in one line of the text report.
    pub fn line(&self) -> String {
        let fmt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.1}"));
        match self.window_s {
            Some(w) => format!(
                "timing {} (asked {}), tried on the first {w:.0} s (unevenness: the median departure of the gaps between successive strikes from their median gap): plain {} strikes, unevenness {} ms, rows' RMS {} ms; recording {} strikes, unevenness {} ms, rows' RMS {} ms; {}",
                self.used,
                self.asked,
                self.plain_strikes.map_or("-".into(), |n| n.to_string()),
                fmt(self.plain_unevenness_ms),
                fmt(self.plain_rms_ms),
                self.recording_strikes.map_or("-".into(), |n| n.to_string()),
                fmt(self.recording_unevenness_ms),
                fmt(self.recording_rms_ms),
                self.reason
            ),
            None => format!("timing {} (asked {}): {}", self.used, self.asked, self.reason),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unevenness measured on a ring of eight recorded bells (d4-d11,
    /// rounds; the interval about its own) where plain timing lost nine
    /// strikes in ten, every bell late by its own build-up: plain's
    /// strikes far from even, the recording's not under 0.7 of them.
    #[test]
    fn plain_far_from_even_is_not_kept_though_the_recording_is_not_evener_by_the_margin() {
        let (recording, reason, doubt) = decide((329, Some((99.5, 184.0))), (354, Some((73.4, 184.0))));
        assert!(recording, "{reason}");
        assert!(reason.contains("plain's own strikes were far from even"), "{reason}");
        // Neither is even: said, with both figures.
        let doubt = doubt.expect("a doubt");
        assert!(
            doubt.contains("73.4 ms timed from the recording, 99.5 ms as heard"),
            "{doubt}"
        );
        // Even the recording's less even than plain's: plain is not trusted.
        let (recording, _, doubt) = decide((190, Some((87.2, 216.0))), (193, Some((111.6, 216.0))));
        assert!(recording && doubt.is_some());
    }

    #[test]
    fn a_tuned_rings_even_strikes_keep_plain_and_raise_no_doubt() {
        let (recording, reason, doubt) = decide((240, Some((12.0, 220.0))), (240, Some((11.0, 220.0))));
        assert!(!recording, "{reason}");
        assert!(doubt.is_none(), "{doubt:?}");
        // The recording's far evener is kept, as before, and not doubted.
        let (recording, reason, doubt) = decide((240, Some((90.0, 220.0))), (238, Some((10.0, 220.0))));
        assert!(recording && reason.contains("came evener"), "{reason}");
        assert!(doubt.is_none(), "{doubt:?}");
    }

    #[test]
    fn a_recording_that_lost_strikes_is_not_kept_and_an_uneven_plain_is_doubted() {
        let (recording, reason, doubt) = decide((300, Some((90.0, 220.0))), (200, Some((10.0, 220.0))));
        assert!(
            !recording && reason.contains("found 200 strikes where plain found 300"),
            "{reason}"
        );
        assert!(doubt.is_some());
        // Too few strikes to measure: plain, nothing said of evenness.
        let (recording, _, doubt) = decide((3, None), (3, None));
        assert!(!recording && doubt.is_none());
    }
}
