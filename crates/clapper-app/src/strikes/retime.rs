//! Each window's strikes timed again (issue 43): against each bell's
//! template, or lined up on its average strike learned from the recording.

use clapper_signal::self_calibrate::SelfCalibration;
use clapper_signal::strikes::StrikeOptions;
use clapper_signal::strikes::{Heard, Hearing, Window};
use clapper_signal::template_timing::retime_each_deferred;
use clapper_signal::Signal;

/// Each strike of window `w` timed again against its bell's template
/// ([`retime_each_deferred`]: the doubles judged by the templates, else by
/// the band finder's `hearing`; with the user's options: the double's window
/// and ratio), how far each moved kept per bell in `moved` (those of
/// the window's core only, so a strike two windows hear counts once).
pub(super) fn retime_window(
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
pub(super) fn realign_window(w: &Window, heard: &mut Heard, c: &SelfCalibration, moved: &mut Vec<Vec<f64>>) {
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
