//! How sure the learner is of the bells it learned (`clapper strikes
//! --bells N`, [`super::learn`]; issue 43: "say how sure it is"), and a
//! recording of fewer bells than asked for told apart from a ring whose
//! quiet bells keep their places; the learner's warnings.
//!
//! A bell learned is as sure as the share of a typical bell's strikes it
//! was heard at (every bell of a ring strikes as often as the others); a
//! note of the ring no bell was heard at is guessed: sure 0. The set is
//! as sure as its bells heard, doubtful with a note guessed, and less
//! where the onsets' rhythm says another number of bells rings.

use super::learn::LearnedBell;
use super::learn_gaps::Heard;
use super::learn_pick::{mean_rise, nominal_of};

/// Two bells heard whose strikes' mean rises are alike past this (the
/// cosine of their spectra) are one sound: one bell's nominal, octave and
/// superquint each noted at some of its strikes.
const ONE_SOUND: f64 = 0.75;
/// A set of learned bells less sure than this is warned of.
pub(super) const DOUBTFUL: f64 = 0.5;
/// A set with a note guessed is at most this sure: on the tuning rings
/// (docs/strikes.md, "How sure `--bells N` is") half such sets were
/// right, half slid a note or two, and no set without one was wrong.
const GUESSED: f64 = 0.4;
/// The rhythm's number of bells within this (bells) of the number learned
/// agrees with it (every right set of the tuning rings was within 0.25).
const RHYTHM_SLACK: f64 = 0.5;
/// Past [`RHYTHM_SLACK`], the set is less sure in proportion, to nothing
/// this much (bells) further off.
const RHYTHM_WIDTH: f64 = 1.0;

/// Each heard bell's mean rise, scaled to unit length.
fn unit_means(heard: &[Heard], rises: &[Vec<f64>]) -> Vec<Vec<f64>> {
    heard
        .iter()
        .map(|b| {
            let m = mean_rise(rises, &b.onsets);
            let norm = m.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-300);
            m.into_iter().map(|v| v / norm).collect()
        })
        .collect()
}

/// The bells `heard` (most onsets first) gathered into the sounds they
/// are: each joins the first sound heard before it whose mean rise is
/// like its own past [`ONE_SOUND`] (its nominal then picked again from
/// them all, bins from `k_lo`, `df` Hz apart). Used only to tell how many
/// bells ring: a ring's bells rise at different partials and are not
/// alike so (the tuning rings' closest pair: see docs/strikes.md,
/// "How sure `--bells N` is").
pub(super) fn sounds(heard: &[Heard], rises: &[Vec<f64>], k_lo: usize, df: f64) -> Vec<Heard> {
    let means = unit_means(heard, rises);
    let cos = |i: usize, j: usize| -> f64 { means[i].iter().zip(&means[j]).map(|(a, b)| a * b).sum() };
    let mut lead: Vec<usize> = vec![];
    let mut members: Vec<Vec<usize>> = vec![];
    for i in 0..heard.len() {
        match lead.iter().position(|&l| cos(i, l) > ONE_SOUND) {
            Some(s) => members[s].push(i),
            None => {
                lead.push(i);
                members.push(vec![i]);
            }
        }
    }
    members
        .iter()
        .map(|m| {
            let mut onsets: Vec<usize> = m.iter().flat_map(|&i| heard[i].onsets.iter().copied()).collect();
            onsets.sort_unstable();
            let first = heard[m[0]].nominal_hz;
            let nominal_hz = if m.len() > 1 {
                nominal_of(&mean_rise(rises, &onsets), k_lo, df, &[], 0.0).map_or(first, |p| p.hz)
            } else {
                first
            };
            Heard { nominal_hz, onsets }
        })
        .collect()
}

/// How sure one learned bell is (0 to 1): its `support` (its onsets
/// against a typical bell's, at most 1). Its partials' fit is reported
/// beside it but not counted: on the tuning rings every bell learned
/// wrong fitted best where it was put, and a right treble whose nominal
/// rises at a fifth of its superquint fitted nowhere.
pub(super) fn bell_sure(support: f64) -> f64 {
    support.clamp(0.0, 1.0)
}

/// A bell's fit at the octave it was put at (`fits`: each octave's, from
/// the lowest; `at`: its index) against its best octave's: 1 where it
/// fits best, 0 where it fits nowhere.
pub(super) fn octave_share(fits: &[f64], at: usize) -> f64 {
    let best = fits.iter().copied().fold(0.0, f64::max);
    match fits.get(at) {
        Some(&f) if best > 0.0 => f / best,
        _ => 0.0,
    }
}

/// How sure the set of learned bells is (0 to 1): the share of them heard
/// (not guessed) times their mean confidence (`sure`, one per bell; 0 for
/// a guess), at most [`GUESSED`] with a guess, less where the onsets'
/// rhythm says `ringing` bells ring and not the `learned` (past
/// [`RHYTHM_SLACK`] bells, to nothing [`RHYTHM_WIDTH`] further). No
/// bells: 0.
pub(super) fn set_sure(sure: &[f64], learned: usize, ringing: Option<f64>) -> f64 {
    if sure.is_empty() {
        return 0.0;
    }
    let heard: Vec<f64> = sure.iter().copied().filter(|&s| s > 0.0).collect();
    let mean = heard.iter().sum::<f64>() / heard.len().max(1) as f64;
    let mut set = mean * heard.len() as f64 / sure.len() as f64;
    if heard.len() < sure.len() {
        set = set.min(GUESSED);
    }
    let rhythm = ringing.map_or(1.0, |r| {
        let off = (r - learned as f64).abs();
        1.0 - ((off - RHYTHM_SLACK) / RHYTHM_WIDTH).clamp(0.0, 1.0)
    });
    (set * rhythm).clamp(0.0, 1.0)
}

/// Learned nominals closer than this (fraction, about two-thirds of a
/// semitone) are warned of: no ring is tuned so close.
pub(super) const CLOSE: f64 = 0.04;

/// A set with two nominals closer than [`CLOSE`] is at most this sure: one
/// of them is another bell's partial. Of the 122 learned sets of session
/// 16's check (docs/strikes.md) the four with such a pair were all wrong,
/// one of them said 94 % sure; an eight whose four back bells were learned
/// at their upper partials (1711.8 and 1645.7 Hz among them) 92 %.
pub(super) const CLOSE_SURE: f64 = GUESSED;

/// The first two of the `learned` nominals (Hz, highest first) closer
/// than [`CLOSE`], if any.
pub(super) fn close_pair(learned: &[LearnedBell]) -> Option<(f64, f64)> {
    learned
        .windows(2)
        .find(|p| p[0].nominal_hz - p[1].nominal_hz < CLOSE * p[0].nominal_hz)
        .map(|p| (p[0].nominal_hz, p[1].nominal_hz))
}

/// Warnings on the bells `learned` (highest first) of `bells` asked for:
/// fewer heard (`few`: far fewer, so no note was guessed for the rest), a
/// bell guessed, heard seldom, or two close.
pub(super) fn warnings_of(learned: &[LearnedBell], bells: usize, few: bool) -> Vec<String> {
    let mut w = vec![];
    let heard = learned.iter().filter(|b| b.onsets > 0).count();
    if few {
        w.push(format!(
            "heard {heard} bell(s), not {bells}: the recording's strikes rise alike, as {} sound(s) struck again \
             and again; only the bell(s) heard are listened for",
            heard
        ));
    } else if heard < bells {
        w.push(format!(
            "{bells} bells asked for, but only {heard} nominal(s) heard again and again: fewer bells ring, or some are too faint",
        ));
    }
    for (i, b) in learned.iter().enumerate() {
        if b.onsets == 0 {
            w.push(format!(
                "bell {} (about {:.1} Hz): not heard often enough to learn its nominal; it keeps its place, its \
                 nominal guessed as its note of the ring's scale, so that the other bells keep their numbers",
                i + 1,
                b.nominal_hz
            ));
        } else if b.support < 0.5 {
            w.push(format!(
                "bell {} ({:.1} Hz): its nominal rose most at only {} onsets, {:.0} % of a typical bell's: unsure",
                i + 1,
                b.nominal_hz,
                b.onsets,
                100.0 * b.support
            ));
        }
    }
    for p in learned.windows(2) {
        if p[0].nominal_hz - p[1].nominal_hz < CLOSE * p[0].nominal_hz {
            w.push(format!(
                "two nominals learned close together ({:.1} and {:.1} Hz): one may be another bell's partial",
                p[0].nominal_hz, p[1].nominal_hz
            ));
        }
    }
    w
}

/// How sure the set of bells `learned` (highest first) is: [`set_sure`]
/// of their confidences, at most [`CLOSE_SURE`] with two too close
/// ([`close_pair`]).
pub(super) fn learned_set_sure(learned: &[LearnedBell], ringing: Option<f64>) -> f64 {
    let sure: Vec<f64> = learned.iter().map(|b| b.confidence).collect();
    let set = set_sure(&sure, learned.len(), ringing);
    if close_pair(learned).is_some() {
        set.min(CLOSE_SURE)
    } else {
        set
    }
}

/// The warning for a set of bells `learned` only `sure` sure (below
/// [`DOUBTFUL`]): two of its nominals too close, else its least sure bell
/// and why; and the rhythm's count (`ringing`).
pub(super) fn doubt_of_set(learned: &[LearnedBell], sure: f64, ringing: Option<f64>) -> String {
    let (i, b) = learned
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.confidence.total_cmp(&b.1.confidence))
        .map_or((0, None), |(i, b)| (i, Some(b)));
    let close = close_pair(learned);
    let why = match b {
        _ if close.is_some() && sure <= CLOSE_SURE => {
            let (hi, lo) = close.unwrap_or_default();
            format!("two nominals learned ({hi:.1} and {lo:.1} Hz) lie closer than any ring is tuned")
        }
        Some(b) if b.onsets == 0 => format!("bell {} was guessed, not heard", i + 1),
        Some(b) => format!(
            "bell {} was heard at {:.0} % of a typical bell's strikes",
            i + 1,
            100.0 * b.support
        ),
        None => "no bell was heard".into(),
    };
    let rhythm = ringing.map_or(String::new(), |r| {
        format!(
            "; the onsets' rhythm says about {r:.1} bells ring, {} were learned",
            learned.len()
        )
    });
    format!(
        "the nominals learned are doubtful ({:.0} % sure): {why}{rhythm}; if the bells' nominals are known, \
         give them (--nominals), else check the learned ones against the bells' notes",
        100.0 * sure
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strikes::learn_pick::tests::spectrum;

    /// One bell's strikes noted at its nominal, its superquint and its
    /// octave (tester 12's one bell struck 20 times, `--bells 8` heard
    /// three bells): one sound, at its nominal. Two bells of a ring a
    /// tone apart stay two.
    #[test]
    fn one_bells_partials_are_one_sound() {
        let bell = spectrum(&[
            (327.0, 0.2),
            (655.0, 0.5),
            (775.0, 0.4),
            (1310.0, 0.8),
            (1940.0, 1.0),
            (2620.0, 0.6),
        ]);
        let other = spectrum(&[
            (292.0, 0.2),
            (584.0, 0.5),
            (692.0, 0.4),
            (1167.0, 0.8),
            (1728.0, 1.0),
            (2334.0, 0.6),
        ]);
        let rises: Vec<Vec<f64>> = (0..40)
            .map(|i| if i < 30 { bell.clone() } else { other.clone() })
            .collect();
        let heard = vec![
            Heard {
                nominal_hz: 2620.0,
                onsets: (0..12).collect(),
            },
            Heard {
                nominal_hz: 1940.0,
                onsets: (12..22).collect(),
            },
            Heard {
                nominal_hz: 1310.0,
                onsets: (22..30).collect(),
            },
            Heard {
                nominal_hz: 1167.0,
                onsets: (30..40).collect(),
            },
        ];
        let s = sounds(&heard, &rises, 30, 5.0);
        assert_eq!(s.len(), 2, "{:?}", s.iter().map(|h| h.nominal_hz).collect::<Vec<_>>());
        assert!((s[0].nominal_hz - 1310.0).abs() < 6.0, "{}", s[0].nominal_hz);
        assert_eq!(s[0].onsets.len(), 30);
        assert!((s[1].nominal_hz - 1167.0).abs() < 6.0, "{}", s[1].nominal_hz);
    }

    /// A set is as sure as its bells heard, on average; a guessed note
    /// makes it doubtful, and so does a rhythm of another number of bells.
    /// An eight whose back bells were learned at their upper partials
    /// (tester15's A8_quietback, `--bells 8`): each heard at most onsets,
    /// the rhythm right, but 1711.8 and 1645.7 Hz are 3.9 % apart.
    #[test]
    fn a_set_with_two_nominals_closer_than_any_ring_is_doubtful() {
        let bell = |nominal_hz: f64| LearnedBell {
            nominal_hz,
            confidence: 0.95,
            onsets: 100,
            support: 0.95,
            partials_fit: 1.0,
        };
        let hz = [1951.1, 1711.8, 1645.7, 1498.6, 1309.1, 1193.8, 1101.7, 977.7];
        let set: Vec<LearnedBell> = hz.iter().map(|&f| bell(f)).collect();
        let sure = learned_set_sure(&set, Some(7.8));
        assert!(sure <= CLOSE_SURE, "{sure}");
        assert!(doubt_of_set(&set, sure, Some(7.8)).contains("1711.8 and 1645.7 Hz) lie closer"));
        let apart: Vec<LearnedBell> = hz.iter().map(|&f| bell(if f == 1645.7 { 1600.0 } else { f })).collect();
        assert!(learned_set_sure(&apart, Some(7.8)) > DOUBTFUL);
    }

    #[test]
    fn a_set_is_as_sure_as_its_bells_heard_and_its_rhythm() {
        assert_eq!(set_sure(&[], 0, None), 0.0);
        assert!((set_sure(&[1.0, 0.8, 0.9], 3, Some(3.2)) - 0.9).abs() < 1e-12);
        assert!((set_sure(&[1.0, 1.0, 1.0, 0.0], 4, None) - GUESSED).abs() < 1e-12);
        assert_eq!(set_sure(&[1.0, 1.0], 2, Some(4.5)), 0.0);
        assert!((set_sure(&[1.0; 8], 8, Some(9.0)) - 0.5).abs() < 1e-12);
        assert_eq!(octave_share(&[0.0, 0.3, 0.6, 0.0, 0.0], 2), 1.0);
        assert!((octave_share(&[0.0, 0.3, 0.6, 0.0, 0.0], 1) - 0.5).abs() < 1e-12);
        assert_eq!(octave_share(&[0.0; 5], 2), 0.0);
        assert_eq!(bell_sure(2.0), 1.0);
    }

    /// One bell struck 20 times, 1.5 s apart, in a room, heard with
    /// `--bells 8`: one bell, at its nominal, said so; no note guessed
    /// for the seven others (main learned eight, seven of them guessed,
    /// and gave the one bell's strikes to six of them).
    #[test]
    fn one_bell_struck_again_and_again_is_one_bell_not_eight() {
        use crate::strikes::learn_nominals;
        use crate::tower::{major_scale, tower_recording, Room, TowerSpec};
        let spec = TowerSpec {
            rows: 20,
            interval: 1.5,
            seed: 3,
            room: Some(Room::chamber(0.8)),
            snr_db: Some(25.0),
            ..TowerSpec::new(major_scale(1, 1310.0).unwrap())
        };
        let (sig, _) = tower_recording(&spec).unwrap();
        let l = learn_nominals(&sig, 8).unwrap();
        let hz: Vec<f64> = l.bells.iter().map(|b| b.nominal_hz).collect();
        assert_eq!(hz.len(), 1, "{hz:.1?} {:?}", l.warnings);
        assert!((hz[0] / 1310.0 - 1.0).abs() < 0.01, "{hz:.1?}");
        assert!(
            l.warnings.iter().any(|w| w.starts_with("heard 1 bell(s), not 8")),
            "{:?}",
            l.warnings
        );
    }
}
