//! A bell whose strikes start with a sharp blow (docs/strikes.md, "A sharp
//! blow is the start (nom-5)"). The whitened average of a synthetic tuned
//! bell's clean strikes steps up 16-75 times within a block at the blow,
//! where the band finder already hears it; the recorded tower bells' step
//! 1.8-4.3 times (their partials build up after the blow). The strikes'
//! agreement and the walk back over a room's rise found the synthetic
//! bells' start 8-35 ms early (a tuned bell's partials, near a harmonic
//! series, agree before the blow and match themselves a period off), so a
//! step this sharp is taken as the start as it stands, and the bell's
//! strikes are lined up near their times heard.

use super::line_up::{heard_in, mad, reline};
use super::start::{block_energy, step_of, whiten, LATEST_STEP_S};
use super::{RELINE_SPREAD_S, SHIFT_S};
use crate::Signal;

/// The whitened average's step at a sharp blow: this many times or more
/// (synthetic tuned bells 16-75, the recorded tower bells 1.8-4.3 in
/// rings at 15-25 dB SNR). It was 8: on an independent tester's noiseless
/// mix of eight recorded bells two of them stepped over 8, were taken for
/// sharp and lined up wrong (recall within 10 ms 0.938 -> 0.887; at 15,
/// 0.925). Held out at 15 the synthetic rows keep nearly all 8 gave
/// (clean 0.904 against 0.929, minor, room and ten bells the same).
pub(super) const SHARP_STEP: f64 = 15.0;
/// A bell with a sharp blow has its strikes lined up within this of
/// where its times heard put them (s): the band finder hears such a bell
/// at its start, and lined up further a tuned bell's strikes jumped a
/// period of its partials (5-15 ms).
pub(super) const SHARP_REACH_S: f64 = 0.003;

/// A sharp blow's start (samples into the average), and the strikes'
/// average and lags where they were lined up again to find it.
pub(super) struct Sharp {
    pub(super) start: usize,
    pub(super) relined: Option<(Vec<f64>, Vec<usize>)>,
}

/// [`SHARP_REACH_S`] in samples at `rate` (Hz).
pub(super) fn reach(rate: f64) -> usize {
    (SHARP_REACH_S * rate) as usize
}

/// The sharp blow in the average `reference` of the strikes from `starts`
/// lined up by `lags` (as [`super::line_up`] gives them): the whitened
/// average's greatest step from [`LATEST_STEP_S`] before their time heard
/// to 5 ms after, where it is [`SHARP_STEP`] times or more. Strikes lined
/// up in scattered steps are lined up again near their times heard
/// ([`reline`]) and the blow looked for in that average. None where no
/// step is that sharp.
pub(super) fn sharp_start(
    sig: &Signal,
    starts: &[usize],
    reference: &[f64],
    lags: &[usize],
    before: usize,
    after: usize,
) -> Option<Sharp> {
    let rate = sig.rate;
    if mad(lags) <= RELINE_SPREAD_S * rate {
        let start = step_at(sig, starts, reference, lags, before, after)?;
        return Some(Sharp { start, relined: None });
    }
    let (r, l) = reline(sig, starts, before, after);
    let start = step_at(sig, starts, &r, &l, before, after)?;
    Some(Sharp {
        start,
        relined: Some((r, l)),
    })
}

/// Where the whitened average `reference` of the strikes lined up by
/// `lags` steps up [`SHARP_STEP`] times or more (samples), if it does.
fn step_at(
    sig: &Signal,
    starts: &[usize],
    reference: &[f64],
    lags: &[usize],
    before: usize,
    after: usize,
) -> Option<usize> {
    let rate = sig.rate;
    let shift = (SHIFT_S * rate).round() as usize;
    let len = before + after;
    let segs: Vec<&[f64]> = starts
        .iter()
        .zip(lags)
        .filter_map(|(&s, &lag)| sig.samples.get(s + lag..s + lag + len))
        .collect();
    if segs.len() != starts.len() {
        return None;
    }
    let heard = heard_in(lags, before, shift);
    let energy = block_energy(&whiten(reference, &segs, rate), rate);
    let from = heard.saturating_sub((LATEST_STEP_S * rate) as usize);
    let latest = heard + (0.005 * rate) as usize;
    step_of(&energy, rate, from, latest)
        .filter(|&(_, r)| r >= SHARP_STEP)
        .map(|(k, _)| k)
}
