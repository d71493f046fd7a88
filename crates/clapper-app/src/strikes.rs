//! Strikes from a recording of a ring (`clapper strikes`, docs/strikes.md):
//! every strike of every bell, its stroke and place, double strikes with
//! their D (33), and each bell's striking: place errors, odd-struckness,
//! double-strike rate.

use clapper_signal::lateness::Lateness;
use clapper_signal::self_calibrate::{calibrate, SelfCalibration};
use clapper_signal::strikes::{
    find_strikes_streamed_heard, rising_at, BellVoice, Heard, Hearing, InMemory, QuietStrokes, RecordingBlocks,
    RisePartial, StrikeOptions, Window, Windows, PLAUSIBLE_SHARE,
};
use clapper_signal::striking::{rhythm, Rhythm, Timed};
use clapper_signal::template_timing::median_of;
use clapper_signal::Signal;
use serde::Serialize;

use crate::AppError;

mod bells;
mod beside;
mod figure;
pub use beside::{beside, HeardBeside, RecordingBeside};
pub use figure::{StrikingFigure, STRIP_S};
mod choose;
pub use bells::{
    learn_nominals, learned_or_none, learned_voices, voices_from_nominals, Learned, LearnedNominal, LearnedSet,
    Learning,
};
pub use choose::{
    choose_timing, opening, Chosen, TimingAsked, TimingChoice, AUTO_LEAST_FOUND, AUTO_MARGIN, EVEN_SHARE,
};
mod doubt;
mod input;
mod kind;
mod method;
mod near;
mod odd;
mod one_stroke;
mod order;
mod per_bell;
#[cfg(test)]
use per_bell::stroke_stats;
use per_bell::{bell_striking, strike_reports};
#[cfg(test)]
mod report_tests;
mod ringer;
#[cfg(test)]
mod words_tests;
use input::signal_error;
pub use input::{NO_STRIKES, ONE_BELL};
pub use kind::{DOUBTED_DOUBLES, DOUBTED_DOUBLES_LEAST};
pub use method::MethodReport;
mod retime;
mod sure;
mod text;
mod warning;
pub use text::MEAN_D_WORDS;
pub use warning::{Warning, WarningKind, Warnings};

use retime::{in_core, lateness_of, lateness_used, timed_again};

/// The sample rates (Hz) of recordings listened to: a telephone's to a
/// studio's (the finder decimates each band, so a high rate costs reading
/// time, not accuracy).
pub const RECORDING_RATES_HZ: std::ops::RangeInclusive<f64> = 8_000.0..=192_000.0;

/// A double strike heard.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DoubleReport {
    /// Delay of the second strike after the first (ms).
    pub delay_ms: f64,
    /// The second strike's amplitude over the first's.
    pub amplitude_ratio: f64,
    /// The double strike index D of (33) at that delay and ratio.
    pub d_index: f64,
}

/// One strike heard.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StrikeReport {
    /// Bell, counting from 1 (the treble).
    pub bell: usize,
    /// Onset (s from the start of the recording).
    pub t_s: f64,
    /// "hand" or "back"; null when the rhythm does not say.
    pub stroke: Option<&'static str>,
    /// Row, counting from 0.
    pub row: Option<usize>,
    /// Place in its row (from 1), in rows holding every bell once.
    pub place: Option<usize>,
    /// Onset less its ideal time in the even rhythm of the rest of the row (ms).
    pub error_ms: Option<f64>,
    /// The clapper's second strike, if heard.
    pub double: Option<DoubleReport>,
    /// Far off its row's rhythm (a false strike, or one heard far from its
    /// time): left out of the line the row's ideal times are read from;
    /// placed, with an error, only where it lies between its place's
    /// neighbours in time (`clapper_signal::striking::Placed::far_off`).
    pub far_off: bool,
}

/// A stroke's column of fewer strikes than this (placed in full rows) is
/// printed with its count, not a spread: two or three strikes' standard
/// deviation reads as a measured figure and is not one (tester17: a
/// bell's backstroke "+8.3 ± 13.6" stood on two strikes). The JSON keeps
/// the numbers.
pub const FEW_IN_COLUMN: usize = 5;

/// One stroke's striking for a bell.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StrokeStats {
    /// Strikes placed whose errors are counted here: those far from the
    /// rest (`left_out`) are not.
    pub n: usize,
    /// Strikes placed whose errors lie far from the rest of the stroke's
    /// (`clapper_signal::striking::steady`): left out of the mean, the
    /// spread and the odd-struckness, which is the columns' difference.
    pub left_out: usize,
    /// Mean place error (ms): positive is late.
    pub mean_error_ms: Option<f64>,
    /// Standard deviation of the place error (ms); none under two strikes
    /// (a spread that cannot be measured).
    pub spread_ms: Option<f64>,
}

/// A bell's striking.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BellStriking {
    /// Bell, counting from 1.
    pub bell: usize,
    /// Strikes heard.
    pub strikes: usize,
    /// Handstrokes.
    pub hand: StrokeStats,
    /// Backstrokes.
    pub back: StrokeStats,
    /// Odd-struckness: steady handstroke error less steady backstroke error
    /// (ms), against the even rhythm of the rest of the ring: the hand
    /// column's mean less the back column's (each the mean of the stroke's
    /// errors less any far from the rest, `clapper_signal::striking::steady`);
    /// none where a stroke's errors disagree, or where its standard error
    /// is over 10 ms (`odd_struck_doubt` says why).
    pub odd_struck_ms: Option<f64>,
    /// Standard error of the odd-struckness (ms); none where a stroke holds
    /// too few errors to measure a spread (`odd_struck_doubt`).
    pub odd_struck_se_ms: Option<f64>,
    /// Why the odd-struckness is not to be trusted as it stands (too few
    /// errors at a stroke, or a stroke's errors disagree), in a ringer's
    /// words; none when it is.
    pub odd_struck_doubt: Option<String>,
    /// Double strikes heard.
    pub double_strikes: usize,
    /// Double strikes over strikes.
    pub double_rate: f64,
    /// Mean double strike index D (eq. 33, dimensionless) of its double
    /// strikes.
    pub mean_d: Option<f64>,
    /// Why the listener's own timing of this bell's strikes is in doubt, in
    /// a ringer's words (their scatter far over the other bells', a steady
    /// error at both strokes, where its sound starts learned from few
    /// strikes, few strikes heard); none when it is not. Its figures here
    /// may show the listener's mistiming rather than the ringer's striking.
    pub timing_doubt: Option<String>,
}

/// The recording as a whole.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StrikesSummary {
    /// Length of the recording (s).
    pub duration_s: f64,
    /// Strikes heard.
    pub strikes: usize,
    /// Rows found.
    pub rows: usize,
    /// Rows holding every bell of the ring once (a row lacking a bell,
    /// whatever the cause, is not full).
    pub full_rows: usize,
    /// Rows placed (each bell's striking judged in them): the full rows,
    /// and rows lacking one bell (never heard, or heard at one stroke
    /// only) whose empty place is left for it.
    pub placed_rows: usize,
    /// Mean interval between successive bells (ms).
    pub interval_ms: Option<f64>,
    /// The handstroke gap (intervals; 1 in good striking).
    pub handstroke_gap_intervals: Option<f64>,
    /// The handstroke gap's extra time (ms).
    pub handstroke_gap_ms: Option<f64>,
    /// Root-mean-square place error over every placed strike (ms).
    pub rms_error_ms: Option<f64>,
    /// The same over the strikes of the bells whose timing is not in doubt
    /// ([`BellStriking::timing_doubt`], ms); none when no bell's is, or
    /// fewer than two bells are left.
    pub rms_error_sure_ms: Option<f64>,
    /// Double strikes heard.
    pub double_strikes: usize,
    /// The bells (from 1) whose double strikes are not to be believed:
    /// heard double at more than a tenth of their strikes
    /// ([`DOUBTED_DOUBLES`]; a warning says so first). Left out of the JSON
    /// where none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub doubles_doubted: Vec<usize>,
    /// Strokes told from the rhythm (the handstroke gap stood out).
    pub strokes_known: bool,
    /// What the rows heard whole were: rounds or a method's plain course
    /// (`clapper_signal::methods::recognise`); none if not one of those.
    pub method: Option<MethodReport>,
    /// How much the recording sounds like bells struck: the share of the
    /// strikes heard (those not at its very ends) across whose onset their
    /// bell's strongest partial rises 6 dB or more (with templates, its
    /// highest partial at least 0.3 of its strongest: `RisePartial`). Under 0.5 it does not
    /// (noise, a steady tone: a warning says so); none without strikes.
    pub plausibility: Option<f64>,
    /// The strikes do not keep the rhythm of rows of the bells given (a
    /// warning says why): the rows, places and odd-struckness mean nothing,
    /// and each bell's odd-struckness is left out.
    pub rows_doubted: bool,
    /// Why a hand or back column is empty or of one strike, in one line
    /// (`ringer::columns_why`); none when every column is measured.
    pub columns_why: Option<String>,
    /// What could not be heard or placed, each with its kind, in the order
    /// a ringer reads them: in the JSON, `warnings` (words) and
    /// `warning_kinds` (one for each, [`WarningKind`]).
    #[serde(flatten)]
    pub warnings: Warnings,
}

/// One bell's timing against its template (issue 43): how long after the
/// start of its sound the band finder heard it on a ring of the templates,
/// and how far its strikes moved when each was matched to its template.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BellTiming {
    /// Bell, counting from 1.
    pub bell: usize,
    /// How late the band finder heard it on a ring of the templates (ms):
    /// taken off its strikes only where its template is too short to match.
    pub lateness_ms: f64,
    /// Its spread over the strikes it was learned from (ms, median absolute deviation).
    pub spread_ms: f64,
    /// Strikes it was learned from (0: not learned, nothing taken off).
    pub learned_from: usize,
    /// How far its strikes then moved (the median, ms) when timed against
    /// its template; none without templates.
    pub matched_ms: Option<f64>,
    /// Timed from the recording: the start of its sound is not clear in
    /// its average strike, so its lateness may be off by tens of ms (the
    /// warnings say why). Left out of the JSON where false.
    #[serde(skip_serializing_if = "is_false")]
    pub start_unclear: bool,
}

/// For serde: a flag left out where false.
fn is_false(b: &bool) -> bool {
    !*b
}

/// The timing corrections used.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TimingReport {
    /// Where each bell's lateness was learned: "templates" (its recording
    /// struck alone) or "recording" (the recording's own clean strikes,
    /// with nominals: `learned_from` counts them); "plain" where none was
    /// (the strikes timed as heard, `per_bell` empty).
    pub source: &'static str,
    /// Treble first.
    pub per_bell: Vec<BellTiming>,
    /// With nominals: the timing asked, the one used and why
    /// ([`choose_timing`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub choice: Option<TimingChoice>,
}

/// How [`StrikesReport::listened`] hears a recording.
enum Pass {
    /// Every strike judged double (the recording heard for its report).
    Judged,
    /// No strike judged double (a trial of the opening window: it reads
    /// the strikes' times only), the window heard as the [`Hearing`] says
    /// if one is given (the calibration's of the same window and voices).
    Singles(Option<Box<Hearing>>),
}

/// How strike times are put on one footing for every bell.
#[derive(Clone, Copy, Debug)]
pub enum Timing<'a> {
    /// As the finder hears them (no correction).
    AsHeard,
    /// Each bell's lateness learned from its recording struck alone (one per
    /// bell, treble first, at one rate).
    Templates(&'a [Signal]),
    /// Each bell's template and lateness learned from the recording's own
    /// clean strikes ([`calibrate_from_recording`]; listen with its voices).
    Recording(&'a SelfCalibration),
}

/// Refuses a recording whose sample rate `rate` (Hz) is outside
/// [`RECORDING_RATES_HZ`].
fn check_rate(rate: f64) -> Result<(), AppError> {
    if RECORDING_RATES_HZ.contains(&rate) {
        return Ok(());
    }
    Err(AppError::Request(format!(
        "sample rate {rate} Hz: recordings from {} to {} kHz",
        RECORDING_RATES_HZ.start() / 1000.0,
        RECORDING_RATES_HZ.end() / 1000.0
    )))
}

/// Which partial a strike's rise is heard at, as the bells are `timing`
/// timed: with templates the voices' partials are the bells' own,
/// measured, and their highest strong partial starts afresh at each
/// strike; assumed partials keep the strongest.
fn rise_partial(timing: &Timing) -> RisePartial {
    match timing {
        Timing::Templates(_) => RisePartial::HighestStrong,
        _ => RisePartial::Strongest,
    }
}

/// The band finder's options `opts` for `timing`: a bell heard at one
/// stroke only has its quieter strokes looked for (issue 43): with
/// templates between its kept strikes ([`QuietStrokes::Between`]), else
/// where the ring's rhythm puts them ([`QuietStrokes::ByRhythm`]),
/// only in the hearing reported (`judged`): neither in the calibration,
/// which is handed `opts` as asked, nor in the choice's trials (with them
/// plain's strikes came a hair evener on tune ring A8_tilt `--bells 8`
/// and plain was chosen, 0.541 -> 0.322 within 10 ms).
fn heard_with(timing: &Timing, opts: &StrikeOptions, judged: bool) -> StrikeOptions {
    StrikeOptions {
        quiet_strokes: match timing {
            Timing::Templates(_) => QuietStrokes::Between,
            _ if judged => QuietStrokes::ByRhythm,
            _ => QuietStrokes::Off,
        },
        ..*opts
    }
}

/// Each bell's partials and template learned from the recording `sig`
/// itself, its nominals given (treble first): for [`Timing::Recording`],
/// heard through the calibration's voices.
pub fn calibrate_from_recording(
    sig: &Signal,
    nominals: &[f64],
    opts: &StrikeOptions,
) -> Result<SelfCalibration, AppError> {
    voices_from_nominals(nominals, Voice::Tower)?;
    calibrate(sig, nominals, opts).map_err(signal_error)
}

/// What `clapper strikes` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StrikesReport {
    /// Bells listened for.
    pub bells: usize,
    /// The nominals learned from the recording, treble first (with
    /// `--bells N` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub learned_nominals_hz: Option<Vec<LearnedNominal>>,
    /// How sure the set of nominals learned is (with `--bells N` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub learned_set: Option<LearnedSet>,
    /// Each bell's timing against its template or the recording, and with
    /// nominals how the timing was chosen.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timing: Option<TimingReport>,
    /// Every strike, in time order.
    pub strikes: Vec<StrikeReport>,
    /// Each bell's striking, treble first.
    pub per_bell: Vec<BellStriking>,
    /// The recording as a whole.
    pub summary: StrikesSummary,
}

pub use clapper_signal::strikes::DEFAULT_DOUBLE_MIN_RATIO;
/// A bell's kind, for the partials assumed from its nominal: a tuned tower
/// bell's (`Voice::Tower`) or a handbell's (`Voice::Handbell`).
pub use clapper_signal::tower::Voice;

/// The strike finder's options with the double strike's least amplitude
/// ratio `double_min_ratio` ([`DEFAULT_DOUBLE_MIN_RATIO`] unless asked:
/// below it the paper's listeners heard no double strike), checked.
pub fn strike_options(double_min_ratio: f64) -> Result<StrikeOptions, AppError> {
    if !(double_min_ratio.is_finite() && double_min_ratio > 0.0 && double_min_ratio <= 2.0) {
        return Err(AppError::Request(format!(
            "double-strike ratio {double_min_ratio}: an amplitude ratio above 0 and at most 2"
        )));
    }
    Ok(StrikeOptions {
        double_min_ratio,
        ..StrikeOptions::default()
    })
}

impl StrikesReport {
    /// Listen to `sig` for the bells `voices` (treble first), the strikes
    /// timed as heard ([`Timing::AsHeard`]).
    pub fn new(sig: &Signal, voices: &[BellVoice], opts: &StrikeOptions) -> Result<Self, AppError> {
        Self::timed(sig, voices, opts, Timing::AsHeard)
    }

    /// Listen to `sig` for the bells `voices` (treble first), timing each
    /// bell's strikes as `timing` says.
    pub fn timed(sig: &Signal, voices: &[BellVoice], opts: &StrikeOptions, timing: Timing) -> Result<Self, AppError> {
        Self::streamed(&mut InMemory::new(sig), voices, opts, timing, &Windows::default(), None)
    }

    /// Listen to the recording `src`, read in blocks and heard in windows
    /// ([`find_strikes_streamed`](clapper_signal::strikes::find_strikes_streamed): one window up to 80 s, as [`Self::timed`]
    /// hears it), for the bells `voices` (treble first), timing each bell's
    /// strikes as `timing` says. Each strike is timed against its template
    /// in its window's audio. `strip`, if given, receives the first
    /// [`STRIP_S`] of the recording (for [`StrikingFigure`]).
    pub fn streamed(
        src: &mut dyn RecordingBlocks,
        voices: &[BellVoice],
        opts: &StrikeOptions,
        timing: Timing,
        windows: &Windows,
        strip: Option<&mut Signal>,
    ) -> Result<Self, AppError> {
        Self::listened(src, voices, opts, timing, windows, strip, Pass::Judged)
    }

    /// [`Self::streamed`], heard as `pass` says.
    fn listened(
        src: &mut dyn RecordingBlocks,
        voices: &[BellVoice],
        opts: &StrikeOptions,
        timing: Timing,
        windows: &Windows,
        mut strip: Option<&mut Signal>,
        pass: Pass,
    ) -> Result<Self, AppError> {
        let (doubles, ready) = match pass {
            Pass::Judged => (true, None),
            Pass::Singles(ready) => (false, ready.map(|h| *h)),
        };
        let rate = src.rate();
        check_rate(rate).and_then(|()| input::heard_at(rate, voices))?;
        let opts = &heard_with(&timing, opts, doubles);
        let duration_s = src.total() as f64 / rate;
        let (lateness, no_lateness) = lateness_of(&timing, voices, opts);
        let late: Vec<Option<f64>> = lateness
            .as_ref()
            .map(|l| l.bells.iter().map(|b| b.sure().then_some(b.lateness_s)).collect())
            .unwrap_or_default();
        let (mut peak, mut moved) = (0.0f64, Vec::<Vec<f64>>::new());
        // Strikes judged, and of them those that rise ([`rising_at`]).
        let (mut rises, listen_rise) = ((0usize, 0usize), rise_partial(&timing));
        // Each strike's rise below its bell's nominal ([`kind::below_in`]).
        let mut below: Vec<f64> = vec![];
        let mut each = |w: &Window, heard: &mut Heard, hearing: Hearing| -> Result<(), clapper_signal::SignalError> {
            peak = w.sig.samples.iter().fold(peak, |p, v| p.max(v.abs()));
            for (s, r) in heard
                .strikes
                .iter()
                .zip(rising_at(w.sig, &heard.strikes, voices, listen_rise))
            {
                if let (Some(r), true) = (r, in_core(w, s.t)) {
                    rises = (rises.0 + 1, rises.1 + usize::from(r));
                }
            }
            kind::below_in(matches!(timing, Timing::AsHeard), w, &heard.strikes, voices, &mut below);
            if let Some(strip) = strip.as_deref_mut().filter(|_| w.start == 0) {
                let end = ((STRIP_S * rate) as usize).min(w.sig.samples.len());
                *strip = Signal {
                    rate,
                    samples: w.sig.samples[..end].to_vec(),
                };
            }
            if doubles && !matches!(timing, Timing::Templates(_)) {
                (heard.strikes.iter_mut().enumerate()).for_each(|(i, s)| s.double = hearing.double(i));
            }
            timed_again(timing, w, heard, hearing, &late, opts, &mut moved)
        };
        let mut heard =
            find_strikes_streamed_heard(src, voices, opts, windows, ready, &mut each).map_err(signal_error)?;
        let matched: Vec<Option<f64>> = moved.into_iter().map(median_of).collect();
        // The finder's and the lateness's warnings, given a kind here.
        let received = |w: String| Warning::received(WarningKind::Note, w);
        let mut warnings: Vec<Warning> = std::mem::take(&mut heard.warnings).into_iter().map(received).collect();
        warnings.extend(no_lateness.into_iter().map(received));
        let timing_report = match timing {
            Timing::Recording(c) => Some(recording_timing(c, &matched, &mut warnings)),
            Timing::Templates(t) => lateness
                .map(|l| correct_lateness(l, t, rate, &matched, &mut heard, &mut warnings))
                .transpose()
                .map_err(signal_error)?,
            Timing::AsHeard => None,
        };
        let plausibility = (rises.0 > 0).then(|| rises.1 as f64 / rises.0 as f64);
        if let Some(p) = plausibility.filter(|p| *p < PLAUSIBLE_SHARE) {
            warnings.insert(0, Warning::new(WarningKind::Recording, input::not_bells(p)));
        }
        input::drop_before_start(&mut heard, &mut warnings);
        if let (Timing::Templates(t), true) = (timing, doubles) {
            let low = input::low_rate_doubles(rate, t.first().map_or(rate, |s| s.rate));
            warnings.extend(low.map(|w| Warning::new(WarningKind::Give, w)));
        }
        input::warn_of(&mut warnings, peak, duration_s, heard.strikes.len(), voices.len());
        kind::warn_of(&mut warnings, matches!(timing, Timing::AsHeard), voices, &below);
        let tpl = matches!(timing, Timing::Templates(_));
        let mut report = Self::of(&heard, voices.len(), duration_s, warnings, timing_report, tpl);
        doubt::once_each(&mut report.summary.warnings);
        report.summary.plausibility = plausibility;
        Ok(report)
    }

    /// Say in the report what reading the recording found (`warnings`, in
    /// words: clapper-io's, e.g. its channels disagreeing in time), first.
    pub fn note_recording(&mut self, warnings: &[String]) {
        let read = warnings.iter().map(|w| Warning::received(WarningKind::Note, w.clone()));
        self.summary.warnings.splice(0..0, read);
        doubt::once_each(&mut self.summary.warnings);
    }

    /// The report of `sig`, listened to for `bells` bells whose nominals
    /// could not be learned from it because no bell's strike is in it
    /// (`why`, [`AppError::NothingHeard`]'s words): no strikes, said as
    /// with nominals given (a recording with no strikes is a result, not
    /// a failure: `clapper strikes` exits 0 in every mode).
    pub fn unheard(sig: &Signal, bells: usize, why: &str) -> Self {
        let peak = sig.samples.iter().fold(0.0f64, |p, v| p.max(v.abs()));
        let duration_s = sig.samples.len() as f64 / sig.rate;
        let mut warnings = vec![Warning::new(
            WarningKind::Recording,
            match peak > 0.0 {
                true => format!("nothing to learn the bells from: {why}"),
                false => "the recording is silent".to_string(),
            },
        )];
        if duration_s < input::SHORTEST_RING_S {
            warnings.insert(0, Warning::new(WarningKind::Recording, input::too_short(duration_s)));
        }
        let heard = Heard {
            strikes: vec![],
            warnings: vec![],
        };
        let mut report = Self::of(&heard, bells, duration_s, warnings, None, false);
        doubt::once_each(&mut report.summary.warnings);
        report
    }

    /// Say in the report that its bells' nominals were `learned` from the
    /// recording: the nominals (`learned_nominals_hz`), and what made them
    /// unsure first among the warnings.
    pub fn note_learned(&mut self, learned: Learned) {
        // No nominals were given: the ring-size warning says so.
        let timed: Vec<Timed> = self.strikes.iter().map(|s| Timed { bell: s.bell, t: s.t_s }).collect();
        let noun = doubt::given_as(false);
        let asked = Some(learned.learner.asked);
        if let Some(given) = doubt::ring_size_warning(&timed, self.bells, noun) {
            let worded = doubt::ring_size_warning_as(&timed, self.bells, asked, noun);
            self.summary.warnings.retain(|w| w.text != given);
            (self.summary.warnings).extend(worded.map(|w| Warning::new(WarningKind::Give, w)));
        }
        if let Some(given) = doubt::gap_warning(&self.strikes, self.bells, None, noun) {
            let worded = doubt::gap_warning(&self.strikes, self.bells, asked, noun);
            for w in self.summary.warnings.iter_mut().filter(|w| w.text == given) {
                w.text = worded.clone().unwrap_or_default();
            }
        }
        // The strikes heard about the nominals say more than the onsets
        // they were learned at (bells-9). The learner's warnings ask for
        // other bells (more, fewer, or their nominals given), unless about
        // one bell.
        let learned = learned.as_heard(&timed);
        let words = learned.warnings.into_iter();
        (self.summary.warnings).splice(0..0, words.map(|w| Warning::received(WarningKind::Give, w)));
        doubt::once_each(&mut self.summary.warnings);
        self.learned_nominals_hz = Some(learned.nominals);
        self.learned_set = Some(learned.set);
    }

    /// The report of the strikes `heard` of `bells` bells in a recording
    /// `duration_s` long: rows, places and each bell's striking. The
    /// warnings that say the table's rows mean little stand first, after
    /// those about the recording itself.
    fn of(
        heard: &Heard,
        bells: usize,
        duration_s: f64,
        mut warnings: Vec<Warning>,
        timing: Option<TimingReport>,
        templates: bool,
    ) -> Self {
        let timed: Vec<Timed> = heard.strikes.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
        let r = rhythm(&timed, bells);
        let (mut wide, one_stroke) = rhythm_warnings(&timed, &r, bells, duration_s, templates, &mut warnings);
        let strikes = strike_reports(heard, &r);
        if !wide.iter().any(|w| w.kind == WarningKind::Give) {
            let gap = doubt::gap_warning(&strikes, bells, None, doubt::given_as(templates));
            wide.extend(gap.map(|w| Warning::new(WarningKind::Give, w)));
        }
        let mut per_bell: Vec<BellStriking> = (1..=bells)
            .map(|bell| bell_striking(bell, &strikes, &r, &timed))
            .collect();
        let counts: Vec<usize> = per_bell.iter().map(|b| b.strikes).collect();
        kind::unheard_warnings(&counts, duration_s, templates, &mut warnings);
        let bell_note = |w: String| Warning::received(WarningKind::Note, w);
        warnings.extend(kind::few_strikes_warnings(&counts).into_iter().map(bell_note));
        let doubles: Vec<usize> = per_bell.iter().map(|b| b.double_strikes).collect();
        let (doubles_doubted, doubled) = kind::doubted_doubles(&doubles, &counts);
        wide.extend(doubled.map(|w| Warning::new(WarningKind::Doubles, w)));
        // Bells already warned of (heard far less often, or at one stroke
        // only) are not warned of again as short.
        let mut few = kind::few_bells(&counts);
        let doubts = sure::timing_doubts(&strikes, &per_bell, timing.as_ref(), &few);
        few.extend(one_stroke.iter().map(|(b, _)| *b));
        let missing = ringer::missing_warnings(&strikes, bells, r.rows, r.strokes_known, &few);
        warnings.extend(missing.into_iter().map(bell_note));
        let by = doubt::timed_by(templates, timing.as_ref());
        let (rms, rows_doubted) = rows_fit(&strikes, &timed, &r, bells, by, &mut wide, &mut warnings);
        let interval_ms = r.interval.map(|i| i * 1e3);
        let lead = input::leading(&warnings);
        warnings.splice(lead..lead, wide);
        for (b, d) in per_bell.iter_mut().zip(doubts) {
            b.timing_doubt = d;
            if rows_doubted {
                // Each bell's odd-struckness is read against those rows: not
                // printed as if it meant something (tester16 fault 1).
                (b.odd_struck_ms, b.odd_struck_se_ms, b.odd_struck_doubt) = (None, None, None);
            }
            odd::doubt_mistimed(b, doubles_doubted.contains(&b.bell));
        }
        let doubted: Vec<usize> = per_bell
            .iter()
            .filter(|b| b.timing_doubt.is_some())
            .map(|b| b.bell)
            .collect();
        let columns_why = ringer::columns_why(&strikes, &per_bell, &r.one_stroke);
        let summary = StrikesSummary {
            duration_s,
            strikes: strikes.len(),
            rows: r.rows,
            full_rows: r.full_rows,
            placed_rows: r.placed_rows,
            interval_ms,
            handstroke_gap_intervals: r.handstroke_gap,
            handstroke_gap_ms: r.handstroke_gap_s.map(|g| g * 1e3),
            rms_error_ms: rms,
            rms_error_sure_ms: sure::rms_without(&strikes, &doubted, bells),
            double_strikes: strikes.iter().filter(|s| s.double.is_some()).count(),
            doubles_doubted,
            strokes_known: r.strokes_known,
            method: method::method_of(&strikes, r.rows, bells),
            plausibility: None,
            rows_doubted,
            columns_why,
            warnings: Warnings(warnings),
        };
        StrikesReport {
            bells,
            learned_nominals_hz: None,
            learned_set: None,
            timing,
            strikes,
            per_bell,
            summary,
        }
    }

    /// The strikes as CSV rows (bell, t_s, stroke, row, place, error_ms,
    /// double delay_ms, amplitude ratio, D), header first.
    pub fn csv_rows(&self) -> Vec<[String; 9]> {
        let f = |v: Option<f64>, d: usize| v.map_or(String::new(), |x| format!("{x:.d$}"));
        let u = |v: Option<usize>| v.map_or(String::new(), |x| x.to_string());
        let mut rows = vec![[
            "bell",
            "t_s",
            "stroke",
            "row",
            "place",
            "error_ms",
            "double_delay_ms",
            "double_amplitude_ratio",
            "d_index",
        ]
        .map(String::from)];
        for s in &self.strikes {
            rows.push([
                s.bell.to_string(),
                format!("{:.4}", s.t_s),
                s.stroke.unwrap_or("").to_string(),
                u(s.row),
                u(s.place),
                f(s.error_ms, 2),
                f(s.double.map(|d| d.delay_ms), 1),
                f(s.double.map(|d| d.amplitude_ratio), 3),
                f(s.double.map(|d| d.d_index), 2),
            ]);
        }
        rows
    }

    /// The strikes as the Lowndes format's (bell, handstroke, time ms).
    pub fn lowndes_blows(&self) -> Vec<(usize, bool, f64)> {
        let mut count = vec![0usize; self.bells + 1];
        self.strikes
            .iter()
            .map(|s| {
                // Without a stroke from the rhythm, a bell's strikes alternate from hand.
                let hand = s.stroke.map_or(count[s.bell] % 2 == 0, |x| x == "hand");
                count[s.bell] += 1;
                (s.bell, hand, s.t_s * 1e3)
            })
            .collect()
    }
}

/// The lateness `l` learned on a ring of the `templates` (at `rate`, Hz)
/// taken off the strikes of `heard` whose bell's template cannot match
/// ([`lateness_used`]; `matched`: per bell, how far its strikes moved when
/// matched), its warnings added to `warnings`; the timing report.
fn correct_lateness(
    l: Lateness,
    templates: &[Signal],
    rate: f64,
    matched: &[Option<f64>],
    heard: &mut Heard,
    warnings: &mut Vec<Warning>,
) -> Result<TimingReport, clapper_signal::SignalError> {
    let used = lateness_used(&l, matched, templates, rate)?;
    used.correct(heard);
    // The ring of the templates' warnings, kept only for bells whose
    // template cannot match. A bell's count of strikes is judged against
    // the rows instead (`ringer::missing_warnings`): against the bells'
    // median it blamed a bell heard in full when the others were short
    // (tester15 A8_level), so every bell is given the same count here.
    let can = clapper_signal::template_timing::matchable(rate, templates)?;
    let said = l.warnings_after_matching(&can, &vec![heard.strikes.len(); l.bells.len()]);
    warnings.extend(said.into_iter().map(|w| Warning::received(WarningKind::Note, w)));
    Ok(TimingReport {
        source: l.source,
        per_bell: l
            .bells
            .iter()
            .map(|b| BellTiming {
                bell: b.bell,
                lateness_ms: b.lateness_s * 1e3,
                spread_ms: b.spread_s * 1e3,
                learned_from: b.strikes,
                matched_ms: matched.get(b.bell - 1).copied().flatten().map(|m| m * 1e3),
                start_unclear: false,
            })
            .collect(),
        choice: None,
    })
}

/// The warnings the rhythm `r` of the strikes `timed` (of `bells` bells,
/// in a recording `duration_s` (s) long; timed by templates where
/// `templates`) gives before the strikes are placed: the strokes guessed,
/// a short recording and each bell heard at one stroke only added to
/// `warnings`; returned, the warnings that say the rows mean little or
/// ask for other bells (said before the rest), and the bells heard at
/// one stroke only with their warnings.
fn rhythm_warnings(
    timed: &[Timed],
    r: &Rhythm,
    bells: usize,
    duration_s: f64,
    templates: bool,
    warnings: &mut Vec<Warning>,
) -> (Vec<Warning>, Vec<(usize, String)>) {
    if !timed.is_empty() && !r.strokes_known {
        warnings.push(Warning::new(
            WarningKind::Note,
            "no handstroke gap stands out: hand and back are a guess",
        ));
    }
    if !timed.is_empty() {
        let short = input::short_for_pace(duration_s, bells, r.interval);
        // After what says the recording is no ring's at all (not like bells).
        let at = warnings.iter().take_while(|w| w.kind == WarningKind::Recording).count();
        warnings.splice(at..at, short.map(|w| Warning::new(WarningKind::Recording, w)));
    }
    let mut wide = vec![];
    let together = doubt::struck_together(timed);
    if together.is_none() {
        let heard = (1..=bells).filter(|b| timed.iter().any(|s| s.bell == *b)).count();
        let none = doubt::no_full_row(timed.len(), r.rows, r.placed_rows, heard, bells);
        wide.extend(none.map(|w| Warning::new(WarningKind::Rows, w)));
    }
    wide.extend(together.map(|w| Warning::new(WarningKind::Recording, w)));
    let size = doubt::ring_size_warning(timed, bells, doubt::given_as(templates));
    wide.extend(size.map(|w| Warning::new(WarningKind::Give, w)));
    let one_stroke = one_stroke::one_stroke_warnings(timed, bells, templates);
    warnings.extend(
        one_stroke
            .iter()
            .map(|(_, w)| Warning::new(WarningKind::OneStroke, w.clone())),
    );
    (wide, one_stroke)
}

/// How the `strikes` (placed by the rhythm `r` of `timed`, `bells` bells,
/// timed `by`) fit their rows: the RMS of their place errors (ms) and
/// whether the rows are in doubt (too loose to be rows, or more rows read
/// than the ringing holds); those warnings and a looser-than-a-band's
/// added to `wide`, a pace read where the rows are not in doubt to
/// `warnings`.
fn rows_fit(
    strikes: &[StrikeReport],
    timed: &[Timed],
    r: &Rhythm,
    bells: usize,
    by: doubt::TimedBy,
    wide: &mut Vec<Warning>,
    warnings: &mut Vec<Warning>,
) -> (Option<f64>, bool) {
    let errs: Vec<f64> = strikes.iter().filter_map(|s| s.error_ms).collect();
    let rms = (!errs.is_empty()).then(|| (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt());
    let interval_ms = r.interval.map(|i| i * 1e3);
    let misfit = doubt::misfit_warning(rms, interval_ms, bells);
    let slipped = doubt::rows_slipped(timed, bells, r.rows);
    let rows_doubted = misfit.is_some() || slipped.is_some();
    let rows_void = |w: String| Warning::new(WarningKind::Rows, w);
    wide.extend(misfit.map(rows_void));
    wide.extend(slipped.map(rows_void));
    let bell_note = |w: String| Warning::received(WarningKind::Note, w);
    wide.extend(doubt::loose_warning(rms, interval_ms, by).map(bell_note));
    // Strikes that do not keep rows read no pace either (tester21's E8
    // `--nominals`: 123 and 109 ms a minute apart beside an interval of
    // 171 ms, on a steady 190 ms ring).
    warnings.extend(ringer::pace_warning(timed).filter(|_| !rows_doubted).map(bell_note));
    (rms, rows_doubted)
}

/// The timing report of a calibration from the recording itself: each
/// bell's lateness found on its clean strikes, and how far its strikes
/// moved when lined up on its average strike (`matched`, per bell); the
/// calibration's warnings added to `warnings`.
fn recording_timing(c: &SelfCalibration, matched: &[Option<f64>], warnings: &mut Vec<Warning>) -> TimingReport {
    warnings.extend(
        c.warnings
            .iter()
            .map(|w| Warning::received(WarningKind::Note, w.clone())),
    );
    TimingReport {
        source: "recording",
        per_bell: c
            .bells
            .iter()
            .map(|b| BellTiming {
                bell: b.bell,
                lateness_ms: b.lateness_s.unwrap_or(0.0) * 1e3,
                spread_ms: b.spread_s * 1e3,
                learned_from: b.strikes,
                matched_ms: matched.get(b.bell - 1).copied().flatten().map(|m| m * 1e3),
                start_unclear: b.start_unclear,
            })
            .collect(),
        choice: None,
    }
}
