//! Which bells a recording is heard for: their nominals given or learned
//! from the recording (`--bells N`), each bell's other partials assumed
//! from its nominal as a tower bell's or a handbell's (`--handbells`).
//! The CLI, the web server and Python share these.

use clapper_signal::strikes::BellVoice;
use clapper_signal::striking::Timed;
use clapper_signal::Signal;
use serde::Serialize;

use super::input::signal_error;
use crate::AppError;
use clapper_signal::tower::Voice;

/// A bell's nominal learned from the recording (`--bells N`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LearnedNominal {
    /// Bell, counting from 1 (the treble, the highest).
    pub bell: usize,
    /// Its nominal (Hz).
    pub nominal_hz: f64,
    /// How sure (0 to 1): its `support`, less where a step to a
    /// neighbouring nominal is no whole number of semitones, and no surer
    /// than the set where that is doubtful (below 0.5); 0 for a note of
    /// the ring guessed, no bell heard there.
    pub confidence: f64,
    /// The onsets (strikes heard rising) its nominal rose most at.
    pub onsets: usize,
    /// Its onsets against the typical learned bell's (0 to 1): every bell
    /// of a ring strikes as often as the others.
    pub support: f64,
    /// How well its strikes' partials fit a tuned bell's with this nominal,
    /// against the best octave of it (0 to 1; 1: it fits best here).
    /// Reported, not counted in `confidence` (docs/strikes.md).
    pub partials_fit: f64,
}

/// How sure the set of nominals learned is (`--bells N`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LearnedSet {
    /// How sure (0 to 1): its bells heard's mean confidence times their
    /// share, at most 0.4 with a note guessed or fewer bells learned than
    /// asked, less where the onsets' rhythm (of the bells heard well) says
    /// another number of bells ring or two neighbouring nominals step by
    /// no whole number of semitones; below 0.5 warned of.
    pub confidence: f64,
    /// Bells heard: learned from their strikes' rise, not guessed; once
    /// the strikes are heard about them, heard at half a typical bell's
    /// strikes or more.
    pub heard: usize,
    /// How many bells ring by the onsets' rhythm (`None` if it says nothing).
    pub ringing: Option<f64>,
    /// Bells asked for (`--bells N`): more than those learned where some
    /// could not be (the report's header says both, tester21 fault 7b).
    pub asked: usize,
}

/// Nominals (Hz) to voices, checked: each bell's other partials assumed
/// from its nominal as a bell of the kind `kind` (a tuned tower bell's,
/// or a handbell's: its strike note and twelfth).
pub fn voices_from_nominals(nominals: &[f64], kind: Voice) -> Result<Vec<BellVoice>, AppError> {
    if nominals.is_empty() {
        return Err(AppError::Request("no nominals: give one per bell, treble first".into()));
    }
    if nominals.len() > 64 {
        return Err(AppError::Request(format!("{} nominals: at most 64", nominals.len())));
    }
    if let Some((i, f)) = nominals
        .iter()
        .enumerate()
        .find(|(_, f)| !(f.is_finite() && (50.0..=10_000.0).contains(*f)))
    {
        return Err(AppError::Request(format!(
            "nominal of bell {}: {f} Hz; a nominal lies from 50 to 10000 Hz",
            i + 1
        )));
    }
    // Half a percent is a twelfth of a semitone: no two bells of a ring are
    // tuned so close, and their partials could not be told apart.
    for (i, a) in nominals.iter().enumerate() {
        if let Some(j) = nominals[i + 1..].iter().position(|b| (a - b).abs() < 0.005 * a.max(*b)) {
            return Err(AppError::Request(format!(
                "bells {} and {} have nominals {a} and {} Hz, within half a percent: one bell given twice?",
                i + 1,
                i + j + 2,
                nominals[i + j + 1]
            )));
        }
    }
    Ok(nominals.iter().map(|&f| BellVoice::assumed(f, kind)).collect())
}

/// The nominals of `bells` bells (3 to 16) learned from the recording
/// `sig` alone ([`clapper_signal::strikes::learn_nominals`]), treble first,
/// how sure the set is and what made it unsure, in words. Refused when no
/// bell is heard ([`AppError::NothingHeard`]: no onset, or none a bell's).
pub fn learn_nominals(sig: &Signal, bells: usize) -> Result<Learned, AppError> {
    if !(3..=16).contains(&bells) {
        return Err(AppError::Request(format!("--bells {bells}: from 3 to 16 bells")));
    }
    let l = clapper_signal::strikes::learn_nominals(sig, bells).map_err(|e| match e {
        // The learner's one Invalid: no onset at all (silent or steady);
        // too short to learn from is as little a ring (tester19: a 2 ms
        // file refused here, a report of none in the other modes).
        clapper_signal::SignalError::Invalid(m) | clapper_signal::SignalError::TooShort(m) => AppError::NothingHeard(m),
        e => signal_error(e),
    })?;
    if l.bells.is_empty() {
        return Err(AppError::NothingHeard(format!(
            "strikes: no bell's nominal heard again and again at {} onsets: is it a recording of bells ringing?",
            l.onsets
        )));
    }
    Ok(Learned::of(l))
}

impl Learned {
    /// What the learner `l` learned, in the report's terms.
    fn of(l: clapper_signal::strikes::Learned) -> Learned {
        let nominals = l
            .bells
            .iter()
            .enumerate()
            .map(|(i, b)| LearnedNominal {
                bell: i + 1,
                nominal_hz: b.nominal_hz,
                confidence: b.confidence,
                onsets: b.onsets,
                support: b.support,
                partials_fit: b.partials_fit,
            })
            .collect();
        let set = LearnedSet {
            confidence: l.confidence,
            heard: l.bells.iter().filter(|b| b.onsets > 0).count(),
            ringing: l.ringing,
            asked: l.asked,
        };
        Learned {
            nominals,
            set,
            warnings: l.warnings.clone(),
            learner: l,
        }
    }

    /// The nominals judged again by the `strikes` heard about them (bell
    /// from 1, onset s): each bell as sure as its strikes bear it out, a
    /// typical bell's share and none with another bell's, and the
    /// learner's warnings said in the strikes' words (a note guessed and
    /// then heard at every row is said so, not "not heard").
    pub fn as_heard(&self, strikes: &[Timed]) -> Learned {
        let mut l = Learned::of(self.learner.as_heard(strikes));
        let count = |bell: usize| strikes.iter().filter(|s| s.bell == bell).count();
        let mut counts: Vec<usize> = (1..=l.nominals.len()).map(count).collect();
        counts.sort_unstable();
        let typical = counts.get(counts.len() / 2).copied().unwrap_or(0);
        l.set.heard = (1..=l.nominals.len())
            .filter(|&b| 2 * count(b) >= typical && count(b) > 0)
            .count();
        l
    }
}

/// The voices of `bells` bells of the kind `kind` whose nominals are
/// learned from `sig` ([`learn_nominals`]), with what was learned, for
/// [`StrikesReport::note_learned`](super::StrikesReport::note_learned): what `clapper strikes --bells N`, the
/// web server's `bells=N` and Python's `bells=N` share.
pub fn learned_voices(sig: &Signal, bells: usize, kind: Voice) -> Result<(Vec<BellVoice>, Learned), AppError> {
    let learned = learn_nominals(sig, bells)?;
    let hz: Vec<f64> = learned.nominals.iter().map(|b| b.nominal_hz).collect();
    Ok((voices_from_nominals(&hz, kind)?, learned))
}

/// What `bells` bells' nominals learned from a recording came to
/// ([`learned_or_none`]).
#[derive(Clone, Debug)]
pub enum Learning {
    /// The bells' voices, with what was learned.
    Learned(Vec<BellVoice>, Box<Learned>),
    /// No bell's strike is in the recording: its report, of no strikes
    /// ([`StrikesReport::unheard`](super::StrikesReport::unheard)).
    Unheard(Box<super::StrikesReport>),
}

/// The voices of `bells` bells of the kind `kind` learned from `sig`
/// ([`learned_voices`]), or, where no bell's strike is in it, the report
/// of none: a recording with no strikes is a result, not a failure, in
/// the CLI, the web server and Python alike (session 19: only the CLI).
pub fn learned_or_none(sig: &Signal, bells: usize, kind: Voice) -> Result<Learning, AppError> {
    match learned_voices(sig, bells, kind) {
        Ok((voices, l)) => Ok(Learning::Learned(voices, Box::new(l))),
        Err(AppError::NothingHeard(why)) => Ok(Learning::Unheard(Box::new(super::StrikesReport::unheard(
            sig, bells, &why,
        )))),
        Err(e) => Err(e),
    }
}

/// Nominals learned from a recording and what made them unsure.
#[derive(Clone, Debug)]
pub struct Learned {
    /// Each bell's nominal, treble first.
    pub nominals: Vec<LearnedNominal>,
    /// How sure the set is.
    pub set: LearnedSet,
    /// What made the learning unsure, in words.
    pub warnings: Vec<String>,
    /// What the learner learned, for [`Learned::as_heard`].
    pub learner: clapper_signal::strikes::Learned,
}
