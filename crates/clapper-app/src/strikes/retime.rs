//! Each window's strikes timed again (issue 43): against each bell's
//! template, or lined up on its average strike learned from the recording.

use clapper_signal::lateness::{from_templates, Lateness};
use clapper_signal::sampled_ring::sample_onset_checked;
use clapper_signal::self_calibrate::SelfCalibration;
use clapper_signal::strikes::BellVoice;
use clapper_signal::strikes::StrikeOptions;
use clapper_signal::strikes::{Heard, Hearing, Window};
use clapper_signal::template_timing::{matchable, retime_each_deferred};
use clapper_signal::Signal;

use super::Timing;

/// Each strike of window `w` timed again as `timing` says, how far each
/// moved kept per bell in `moved`. With templates, each strike is timed
/// against its bell's template; the lateness learned on a ring of the
/// templates (`late`) then serves only a bell whose template is too short
/// to match. Only with templates do the strikes come not yet judged
/// double: the templates judge them, else the band finder (`hearing`).
pub(super) fn timed_again(
    timing: Timing,
    w: &Window,
    heard: &mut Heard,
    hearing: Hearing,
    late: &[Option<f64>],
    opts: &StrikeOptions,
    moved: &mut Vec<Vec<f64>>,
) -> Result<(), clapper_signal::SignalError> {
    if let Timing::Templates(t) = timing {
        return retime_window(w, heard, hearing, t, late, opts, moved);
    }
    drop(hearing);
    match timing {
        Timing::Recording(c) => realign_window(w, heard, c, moved),
        Timing::AsHeard | Timing::Templates(_) => {}
    }
    Ok(())
}

/// The lateness learned on a ring of the `templates` with `timing` by
/// templates, else none; warnings in words where it could not be learned,
/// and where a template has no quiet before its sound ([`cut_templates`]).
/// The ring of the templates needs them at one rate; matching each strike
/// does not (it resamples them).
pub(super) fn lateness_of(
    timing: &Timing,
    voices: &[BellVoice],
    opts: &StrikeOptions,
) -> (Option<Lateness>, Vec<String>) {
    match timing {
        Timing::AsHeard | Timing::Recording(_) => (None, vec![]),
        Timing::Templates(t) => {
            let cut = cut_templates(t);
            match from_templates(t, voices, opts) {
                Ok(l) => (Some(l), cut.into_iter().collect()),
                Err(e) => (
                    None,
                    std::iter::once(format!("no lateness learned from the templates: {e}"))
                        .chain(cut)
                        .collect(),
                ),
            }
        }
    }
}

/// A warning naming the templates (treble first) with no whole
/// millisecond quieter than their sound before it
/// ([`sample_onset_checked`]): each is taken to start at its first
/// sample, and if it was cut into its sound, its strikes are timed late by
/// as much as was cut.
fn cut_templates(templates: &[Signal]) -> Option<String> {
    let cut: Vec<String> = templates
        .iter()
        .enumerate()
        .filter(|(_, t)| sample_onset_checked(t).is_ok_and(|o| !o.quiet_before))
        .map(|(i, _)| format!("{}.wav", i + 1))
        .collect();
    (!cut.is_empty()).then(|| {
        format!(
            "template {} starts at its sound, with no quiet before it: timed from its first sample \
             (if it was cut into the sound, that bell's strikes are timed late by as much); \
             keep a few ms of the recording before each strike",
            cut.join(", ")
        )
    })
}

/// Each strike of window `w` timed again against its bell's template
/// ([`retime_each_deferred`]: the doubles judged by the templates, else by
/// the band finder's `hearing`; with the user's options: the double's window
/// and ratio), how far each moved kept per bell in `moved` (those of
/// the window's core only, so a strike two windows hear counts once).
fn retime_window(
    w: &Window,
    heard: &mut Heard,
    hearing: Hearing,
    templates: &[Signal],
    late: &[Option<f64>],
    opts: &StrikeOptions,
    moved: &mut Vec<Vec<f64>>,
) -> Result<(), clapper_signal::SignalError> {
    moved.resize(templates.len(), vec![]);
    let moves = retime_each_deferred(w.sig, heard, hearing, templates, late, opts)?;
    for (s, m) in heard.strikes.iter().zip(moves) {
        if let (Some(m), true) = (m, in_core(w, s.t)) {
            moved[s.bell - 1].push(m);
        }
    }
    heard
        .strikes
        .sort_by(|a, b| a.t.total_cmp(&b.t).then(a.bell.cmp(&b.bell)));
    Ok(())
}

/// Each strike of window `w` lined up on its bell's average strike learned
/// from the recording ([`SelfCalibration::retime_each`]: on the synthetic
/// rings of the tests this timed better than matching its template), how
/// far each moved kept per bell in `moved` (those of the window's core).
fn realign_window(w: &Window, heard: &mut Heard, c: &SelfCalibration, moved: &mut Vec<Vec<f64>>) {
    moved.resize(c.bells.len(), vec![]);
    let moves = c.retime_each(w.sig, heard);
    for (s, m) in heard.strikes.iter().zip(moves) {
        if let (Some(m), true) = (m, in_core(w, s.t)) {
            moved[s.bell - 1].push(m);
        }
    }
    heard
        .strikes
        .sort_by(|a, b| a.t.total_cmp(&b.t).then(a.bell.cmp(&b.bell)));
}

/// Whether a strike at `t` (s from the start of window `w`) is one the
/// window reports: any, where the window is the whole recording.
pub(super) fn in_core(w: &Window, t: f64) -> bool {
    let at = w.start as f64 + t * w.sig.rate;
    (w.start == 0 && w.core == (0, w.sig.samples.len())) || (at >= w.core.0 as f64 && at < w.core.1 as f64)
}

/// The lateness of `l` to take off each bell's strikes: none where its
/// template (`templates`, treble first, in a recording at `rate` Hz) can
/// match, its strikes then each timed at the start of their sound.
pub(super) fn lateness_used(
    l: &Lateness,
    matched: &[Option<f64>],
    templates: &[Signal],
    rate: f64,
) -> Result<Lateness, clapper_signal::SignalError> {
    Ok(kept(l, matched, &matchable(rate, templates)?))
}

/// [`lateness_used`], whether each bell's template can match given
/// (`can`): a bell none of whose strikes the band finder heard has them
/// all found by its template, none moved (`matched` none), and taking its
/// lateness off them too put them early by it (the recorded tenor d8 by
/// 35.2 ms in dry rounds; d2 by 87.6 ms at RT60 1.2 s).
fn kept(l: &Lateness, matched: &[Option<f64>], can: &[bool]) -> Lateness {
    let mut used = l.clone();
    for (k, b) in used.bells.iter_mut().enumerate() {
        if matched.get(k).is_some_and(Option::is_some) || can.get(k).copied().unwrap_or(false) {
            b.lateness_s = 0.0;
        }
    }
    used
}

#[cfg(test)]
mod tests {
    use super::kept;
    use clapper_signal::lateness::{BellLateness, Lateness};
    use clapper_signal::strikes::{Heard, HeardStrike};

    /// A bell none of whose strikes the band finder heard has them all
    /// found by its template, each at the start of its sound and none
    /// "moved": they keep their times (on the recorded eight in dry rounds
    /// its lateness, 35.2 ms, was taken off every one of them); a bell
    /// whose template cannot match has its lateness taken off.
    #[test]
    fn strikes_found_only_by_their_template_are_not_moved_by_the_lateness() {
        let bell = |bell: usize| BellLateness {
            bell,
            lateness_s: 0.0352,
            spread_s: 0.001,
            strikes: 15,
            of: 16,
        };
        let lateness = Lateness {
            source: "templates",
            bells: vec![bell(1), bell(2)],
            warnings: vec![],
        };
        let strike = |bell: usize, t: f64| HeardStrike {
            bell,
            t,
            strength: 1.0,
            double: None,
        };
        let mut heard = Heard {
            strikes: vec![strike(1, 1.0), strike(2, 1.2)],
            warnings: vec![],
        };
        // Bell 1's template matches (its strikes all from the fill, so
        // none moved); bell 2's is too short to match.
        kept(&lateness, &[None, None], &[true, false]).correct(&mut heard);
        assert_eq!(heard.strikes[0].t, 1.0, "bell 1 moved: {:?}", heard.strikes);
        assert!(
            (heard.strikes[1].t - (1.2 - 0.0352)).abs() < 1e-12,
            "bell 2: {:?}",
            heard.strikes
        );
    }
}
