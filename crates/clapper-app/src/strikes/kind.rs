//! Doubts about the bells given (issue 43, an independent tester's
//! findings): the kind of bell listened for against the kind heard
//! (`--handbells` on tower bells), nominals given tenor first, a nominal
//! given an octave off, and a bell heard far less often than the others.

use clapper_signal::strikes::{below_nominal, BellVoice, HeardStrike, Window, HANDBELL_BELOW, TOWER_BELOW};

use super::retime::in_core;
use super::warning::{Warning, WarningKind};

/// A bell's strikes under this share of the typical bell's are warned of.
const FEW: f64 = 0.5;
/// Consecutive bells of a ring lie within this ratio of each other (a
/// major third: two bells a whole tone apart each, one missing between).
const NEXT_MOST: f64 = 1.27;
/// ... and at least this far apart (a third of a semitone).
const NEXT_LEAST: f64 = 1.02;

/// The bell's strongest partial (Hz): its nominal, as given.
fn nominal(v: &BellVoice) -> Option<f64> {
    v.partials
        .iter()
        .max_by(|a, b| a.strength.total_cmp(&b.strength))
        .map(|p| p.freq_hz)
}

/// Whether the voice is a handbell's: no partial below its strongest.
fn is_handbell(v: &BellVoice) -> bool {
    nominal(v).is_some_and(|f| v.partials.iter().all(|p| p.freq_hz > 0.9 * f))
}

/// The median of `v`, if any.
fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    (!v.is_empty()).then(|| v[v.len() / 2])
}

/// Each of the `strikes` heard in window `w` (those in its core) adds
/// its rise below its bell's nominal ([`below_nominal`]) to `below`:
/// with nominals only (`nominals`: strikes timed as heard), as a
/// template's strongest partial may be its hum.
pub(super) fn below_in(
    nominals: bool,
    w: &Window,
    strikes: &[HeardStrike],
    voices: &[BellVoice],
    below: &mut Vec<f64>,
) {
    if nominals {
        for (s, b) in strikes.iter().zip(below_nominal(w.sig, strikes, voices)) {
            if let (Some(b), true) = (b, in_core(w, s.t)) {
                below.push(b);
            }
        }
    }
}

/// Add to `warnings`, with nominals given or learned (`nominals`:
/// strikes timed as heard), a nominal an octave off ([`octave_warnings`]) and bells that
/// do not sound of the kind listened for ([`kind_warning`], from
/// `below`; voices all of one kind).
/// Both ask the ringer to give other nominals or options
/// ([`WarningKind::Give`]).
pub(super) fn warn_of(warnings: &mut Vec<Warning>, nominals: bool, voices: &[BellVoice], below: &[f64]) {
    if !nominals {
        return;
    }
    let act = |t: String| Warning::new(WarningKind::Give, t);
    warnings.extend(octave_warnings(voices).into_iter().map(act));
    let handbells = voices.iter().all(is_handbell);
    if handbells || !voices.iter().any(is_handbell) {
        warnings.extend(kind_warning(below, handbells).map(act));
    }
}

/// A warning when the bells listened for (`handbells`: as handbells, else
/// tower bells) do not sound so: `below` holds each strike's rise an
/// octave and two below its bell's nominal against the nominal's
/// ([`clapper_signal::strikes::below_nominal`]); its median over the
/// recording tells a tower bell (hum and prime rising with the nominal)
/// from a handbell (nothing below its strike note). Needs 8 strikes.
pub(super) fn kind_warning(below: &[f64], handbells: bool) -> Option<String> {
    if below.len() < 8 {
        return None;
    }
    let m = median(below.to_vec())?;
    if handbells && m > TOWER_BELOW {
        Some(format!(
            "heard as handbells (--handbells), but these sound like tower bells: across the strikes heard the sound \
             an octave and two octaves below each bell's note (a tower bell's prime and hum; a handbell has nothing \
             there) rises with it, {:.0} % of its power (the median); heard as handbells, a tower bell's partials \
             are taken for strikes and double strikes: leave out --handbells",
            100.0 * m
        ))
    } else if !handbells && m < HANDBELL_BELOW {
        Some(format!(
            "heard as tower bells, but these sound like handbells: across the strikes heard nothing rises an octave \
             or two below each bell's nominal, where a tower bell's prime and hum are ({:.2} % of its power, the \
             median); if they are handbells, give --handbells",
            100.0 * m
        ))
    } else {
        None
    }
}

/// A warning when the nominals given rise more often than they fall
/// from one bell to the next: given tenor first. Bells are numbered in
/// the order given, so the ring's lowest bell would be reported as bell 1
/// and rounds as backrounds (an independent tester's finding: taken
/// silently). `f`: the nominals given (Hz), in the order given.
pub(super) fn order_warning(f: &[f64]) -> Option<String> {
    if f.len() < 2 {
        return None;
    }
    let rising = f.windows(2).filter(|p| p[1] > p[0]).count();
    let falling = f.windows(2).filter(|p| p[1] < p[0]).count();
    (rising > falling).then(|| {
        format!(
            "the nominals given rise from the first ({:.1} Hz) to the last ({:.1} Hz): bells are numbered in the \
             order given, treble (the highest) first, so here bell 1 is the lowest and rounds read as backrounds; \
             give the nominals treble first",
            f[0],
            f[f.len() - 1]
        )
    })
}

/// Warnings for nominals given (treble first) of which one lies an
/// octave from where its neighbours put it: out of order or too far from
/// them, while an octave up or down it sits between them as the next
/// bell does. Such a bell is heard (a handbell's octave, a tower bell's
/// prime or octave nominal rises at its strikes) but at the wrong note.
pub(super) fn octave_warnings(voices: &[BellVoice]) -> Vec<String> {
    let f: Vec<f64> = voices.iter().filter_map(nominal).collect();
    if f.len() < 3 || f.len() != voices.len() {
        return vec![];
    }
    let next = |hi: f64, lo: f64| (NEXT_LEAST..=NEXT_MOST).contains(&(hi / lo));
    let fits = |i: usize, g: f64| (i == 0 || next(f[i - 1], g)) && (i + 1 == f.len() || next(g, f[i + 1]));
    let mut out = vec![];
    for i in 0..f.len() {
        if fits(i, f[i]) {
            continue;
        }
        let Some(g) = [2.0, 0.5].iter().map(|m| f[i] * m).find(|&g| fits(i, g)) else {
            continue;
        };
        // An end bell has one neighbour: that one must sit among its own.
        let sure = if i == 0 {
            next(f[1], f[2])
        } else if i + 1 == f.len() {
            next(f[i - 2], f[i - 1])
        } else {
            true
        };
        if sure {
            out.push(format!(
                "bell {}'s nominal, {:.1} Hz, lies an octave from where its neighbours put it ({:.1} Hz would sit \
                 between them as a ring's next bell does): is it the octave of its nominal? It is heard at the \
                 nominal given, an octave off",
                i + 1,
                f[i],
                g
            ));
        }
    }
    out
}

/// Warnings for bells heard far less often than the typical bell (under
/// [`FEW`] of the median strikes over the bells), heard at all: the
/// others' strikes are heard, its are missed (`strikes`: each bell's,
/// treble first). (A bell not heard at all is warned of by the strike
/// finder.)
pub(super) fn few_strikes_warnings(strikes: &[usize]) -> Vec<String> {
    let typical = median(strikes.iter().map(|&n| n as f64).collect()).unwrap_or(0.0);
    few_bells(strikes)
        .into_iter()
        .map(|b| {
            format!(
                "bell {b}: heard at only {} strikes, where a typical bell is heard at {typical:.0}: it is quiet, or \
                 its nominal is not right; its strikes missed are not in the report, and its striking is judged on \
                 few",
                strikes[b - 1]
            )
        })
        .collect()
}

/// The bells (from 1) [`few_strikes_warnings`] warns of, `strikes` each
/// bell's, treble first.
pub(super) fn few_bells(strikes: &[usize]) -> Vec<usize> {
    let Some(typical) = median(strikes.iter().map(|&n| n as f64).collect()) else {
        return vec![];
    };
    if strikes.len() < 2 || typical < 6.0 {
        return vec![];
    }
    (1..=strikes.len())
        .filter(|&b| strikes[b - 1] > 0 && (strikes[b - 1] as f64) < FEW * typical)
        .collect()
}

/// Whether `w` names bell `b` ("bell 4: ...", "bell 4 (1458.2 Hz)",
/// "bell 4's nominal").
fn names(w: &str, b: usize) -> bool {
    [":", " (", "'s"]
        .iter()
        .any(|end| w.contains(&format!("bell {b}{end}")))
}

/// Every bell heard at no strike (`strikes`: each bell's count, treble
/// first) named in `warnings` with why where it is known (tester17: on a
/// 2.1 s clip a bell with no strike found was named nowhere): the finder's
/// bare "bell N: no strikes heard" said again with why, and a bell no
/// warning names added. `duration_s`: the recording's length (s);
/// `templates`: the bells were given by their recorded strikes.
/// Each is of the kind [`WarningKind::Unheard`].
pub(super) fn unheard_warnings(strikes: &[usize], duration_s: f64, templates: bool, warnings: &mut Vec<Warning>) {
    let heard: Vec<f64> = strikes.iter().filter(|&&n| n > 0).map(|&n| n as f64).collect();
    let Some(typical) = median(heard) else {
        return;
    };
    for b in (1..=strikes.len()).filter(|&b| strikes[b - 1] == 0) {
        let why = if typical < 6.0 {
            format!(
                "in {duration_s:.1} s the other bells are heard only {typical:.0} time(s) each, and a bell's strike \
                 lost under another bell's or cut at the recording's ends leaves it unheard: a longer recording \
                 hears it"
            )
        } else {
            let own = if templates {
                "its recorded strike given is not its own"
            } else {
                "the nominal given is not its own"
            };
            format!("it did not ring, or it is far quieter than the others, or {own}")
        };
        let said = Warning::new(
            WarningKind::Unheard,
            format!("bell {b}: not heard at all (no strike found): {why}"),
        );
        let bare = format!("bell {b}: no strikes heard");
        if let Some(w) = warnings.iter_mut().find(|w| w.text == bare) {
            *w = said;
        } else if !warnings.iter().any(|w| names(&w.text, b)) {
            warnings.push(said);
        }
    }
}

/// A bell heard double at more than this share of its strikes has its
/// double strikes doubted, with [`DOUBTED_DOUBLES_LEAST`] at least: a bell
/// in good order doubles at a few strikes in a hundred. In every one of
/// tester22's 21 rings, 6 doubles were planted, at most 3 % of any bell's
/// strikes, and every bell read over 10 % was false: its dark rooms read
/// "48 (100 %)" (r6a `--templates`), 77 % (r8d), 29 % (s_d0); the rings
/// heard right read 1-9 %.
pub const DOUBTED_DOUBLES: f64 = 0.10;

/// The fewest double strikes of a bell that are doubted: one or two on a
/// short ring may be its own (2 of 16 strikes is 12 %).
pub const DOUBTED_DOUBLES_LEAST: usize = 4;

/// The bells (from 1) whose double strikes are not to be believed (over
/// [`DOUBTED_DOUBLES`] of their strikes, [`DOUBTED_DOUBLES_LEAST`] at
/// least), and the warning naming them, first in the report (tester22
/// fault 2: "2? 48 (100 %)", 85 doubles, no warning line); `doubles` and
/// `strikes` each bell's counts, treble first.
pub(super) fn doubted_doubles(doubles: &[usize], strikes: &[usize]) -> (Vec<usize>, Option<String>) {
    let bells: Vec<usize> = (1..=strikes.len().min(doubles.len()))
        .filter(|&b| {
            let (d, n) = (doubles[b - 1], strikes[b - 1]);
            d >= DOUBTED_DOUBLES_LEAST && d as f64 > DOUBTED_DOUBLES * n as f64
        })
        .collect();
    let Some(&first) = bells.first() else {
        return (bells, None);
    };
    let mut each = vec![format!(
        "bell {first} heard double at {} of its {} strikes",
        doubles[first - 1],
        strikes[first - 1]
    )];
    each.extend(
        bells[1..]
            .iter()
            .map(|&b| format!("bell {b} at {} of {}", doubles[b - 1], strikes[b - 1])),
    );
    let heard = strikes.iter().filter(|&&n| n > 0).count();
    if bells.len() == heard && heard > 2 {
        // Every bell: the range says it, eight bells' counts bury it.
        let share = |b: usize| 100.0 * doubles[b - 1] as f64 / strikes[b - 1] as f64;
        let (lo, hi) = (bells.iter().map(|&b| share(b))).fold((100.0_f64, 0.0_f64), |(l, h), x| (x.min(l), x.max(h)));
        each = vec![format!(
            "every bell heard double, at {lo:.0} to {hi:.0} % of its strikes"
        )];
    }
    let w = format!(
        "double strikes not to be believed: {} (marked {} in the doubles column); a bell in good order doubles at a \
         few strikes in a hundred, so the room's echo (a dark, reverberant tower) is likely heard as a second blow, \
         or a clapper bounces (a fault to see to in the tower): listen to {} before trusting {} double strikes",
        each.join(", "),
        super::text::DOUBT_MARK,
        if bells.len() == 1 { "that bell" } else { "those bells" },
        if bells.len() == 1 { "its" } else { "their" },
    );
    (bells, Some(w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_signal::tower::Voice;

    #[test]
    fn a_nominal_an_octave_off_is_told() {
        let ring = [1040.0, 981.6, 874.5, 779.1, 694.1, 655.2, 583.7, 520.0];
        let voices =
            |f: &[f64]| -> Vec<BellVoice> { f.iter().map(|&x| BellVoice::assumed(x, Voice::Handbell)).collect() };
        assert!(octave_warnings(&voices(&ring)).is_empty());
        for (bell, m) in [(3, 2.0), (1, 0.5), (8, 0.5), (5, 2.0)] {
            let mut g = ring;
            g[bell - 1] *= m;
            let w = octave_warnings(&voices(&g));
            assert_eq!(w.len(), 1, "{bell}: {w:?}");
            assert!(w[0].starts_with(&format!("bell {bell}'s nominal")), "{w:?}");
        }
    }

    #[test]
    fn nominals_given_tenor_first_are_told() {
        let ring = [1966.8, 1749.8, 1645.9, 1458.2, 1308.9, 1237.2];
        assert_eq!(order_warning(&ring), None);
        let mut up = ring;
        up.reverse();
        let w = order_warning(&up).expect("tenor first is told");
        assert!(w.contains("first (1237.2 Hz)") && w.contains("treble first"), "{w}");
        // One bell out of place among falling nominals is the octave
        // warning's business, not this one's.
        let mut one = ring;
        one.swap(2, 3);
        assert_eq!(order_warning(&one), None);
    }

    /// Tester17: a bell with no strike found on a 2.1 s clip was named
    /// nowhere. Every such bell is named, with why; one named already is
    /// not named twice.
    #[test]
    fn a_bell_heard_at_no_strike_is_named_with_why() {
        let mut w = vec![];
        unheard_warnings(&[2, 2, 0, 2, 2, 2], 2.1, false, &mut w);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].text.starts_with("bell 3: not heard at all") && w[0].text.contains("2.1 s"),
            "{w:?}"
        );
        assert_eq!(w[0].kind, WarningKind::Unheard);
        let mut w = vec![
            Warning::received(WarningKind::Note, "bell 6: no strikes heard"),
            Warning::received(WarningKind::Note, "bell 2: not listened for: .."),
        ];
        unheard_warnings(&[40, 0, 40, 40, 40, 0], 60.0, true, &mut w);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].text.starts_with("bell 6: not heard at all") && w[0].text.contains("recorded strike"),
            "{w:?}"
        );
        let mut w = vec![];
        unheard_warnings(&[40, 39, 40], 60.0, false, &mut w);
        assert!(w.is_empty());
    }

    #[test]
    fn a_bell_heard_far_less_than_the_others_is_told() {
        let w = few_strikes_warnings(&[24, 24, 5, 24, 23, 24]);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("bell 3: heard at only 5 strikes"), "{w:?}");
        assert!(few_strikes_warnings(&[24, 24, 20, 24, 0, 24]).is_empty());
    }

    /// Tester22's dark rooms: a bell heard double at every strike was
    /// printed "48 (100 %)" without a word. Every bell over a tenth is
    /// named in one warning; a tenth or fewer, or three doubles, is not.
    #[test]
    fn double_strikes_beyond_a_bells_own_are_doubted() {
        let (bells, w) = doubted_doubles(&[48, 14, 4, 4, 3, 12], &[48, 48, 48, 48, 20, 41]);
        assert_eq!(bells, vec![1, 2, 6]);
        let w = w.unwrap_or_default();
        assert!(
            w.starts_with(
                "double strikes not to be believed: bell 1 heard double at 48 of its 48 strikes, bell 2 at 14 of 48, \
                 bell 6 at 12 of 41"
            ),
            "{w}"
        );
        assert!(w.contains("listen to those bells"), "{w}");
        assert_eq!(doubted_doubles(&[2, 1, 3], &[72, 72, 16]), (vec![], None));
        let (_, w) = doubted_doubles(&[45, 96, 26], &[123, 125, 94]);
        let w = w.unwrap_or_default();
        assert!(
            w.starts_with("double strikes not to be believed: every bell heard double, at 28 to 77 % of its strikes"),
            "{w}"
        );
    }
}
