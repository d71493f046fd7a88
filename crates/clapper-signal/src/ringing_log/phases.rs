//! Phases of a session (docs/model.md §13 step 5: down, raising, up,
//! ringing with its stands, lowering, down) and the ringing's
//! odd-struckness.

use super::types::{LogStroke, Phase, PhaseKind};
use crate::median;
use crate::striking::mean_sd;

/// Phases (method step 4), and each stroke's phase set.
pub(super) fn phases(
    t: &[f64],
    rests: &[(f64, f64, f64)],
    strokes: &mut [LogStroke],
    theta: &[f64],
    (full, length): (f64, Option<f64>),
) -> Vec<Phase> {
    let (t0, t1) = (t[0], t[t.len() - 1]);
    let rest_kind = |mean: f64| {
        if mean.abs() < std::f64::consts::FRAC_PI_2 {
            PhaseKind::Down
        } else {
            PhaseKind::Up
        }
    };
    // The full swings' height: their median over the log.
    let height = median(
        &strokes
            .iter()
            .map(|s| s.amplitude)
            .filter(|&x| x >= full)
            .collect::<Vec<_>>(),
    );
    let mut out: Vec<Phase> = vec![];
    let mut cursor = t0;
    let mut before: Option<PhaseKind> = None;
    // Each rest, with the moving segment before it; then the last segment.
    for k in 0..=rests.len() {
        let (seg_end, after) = match rests.get(k) {
            Some(r) => (r.0, Some(rest_kind(r.2))),
            None => (t1, None),
        };
        if seg_end > cursor {
            segment(
                t,
                theta,
                strokes,
                (full, height, length),
                (cursor, seg_end),
                (before, after),
                &mut out,
            );
        }
        if let Some(r) = rests.get(k) {
            push(&mut out, rest_kind(r.2), r.0, r.1);
            before = Some(rest_kind(r.2));
            cursor = r.1;
        }
    }
    // Stands: a short rest at the balance between two stretches of ringing
    // is part of the ringing.
    let mut merged: Vec<Phase> = vec![];
    for (i, p) in out.iter().enumerate() {
        let stand = p.kind == PhaseKind::Up
            && p.end - p.start <= STAND_MAX_S
            && i > 0
            && out[i - 1].kind == PhaseKind::Ringing
            && out.get(i + 1).is_some_and(|q| q.kind == PhaseKind::Ringing);
        let kind = if stand { PhaseKind::Ringing } else { p.kind };
        push(&mut merged, kind, p.start, p.end);
    }
    merged
}

/// Free swings after lowering (down) are smaller than this (rad): 45 deg.
pub(super) const FREE_SWING_MAX: f64 = std::f64::consts::FRAC_PI_4;

/// A rest at the balance between strokes of ringing no longer than this
/// (s) is a stand, part of the ringing; longer, the bell is set (up).
pub const STAND_MAX_S: f64 = 5.0;

/// Add a phase, merged with the one before if of the same kind.
pub(super) fn push(out: &mut Vec<Phase>, kind: PhaseKind, start: f64, end: f64) {
    if end <= start {
        return;
    }
    match out.last_mut() {
        Some(p) if p.kind == kind => p.end = end,
        _ => out.push(Phase { kind, start, end }),
    }
}

/// The phases of one moving segment `(a, b)` between rests of the kinds
/// `(from, to)` (`None`: the log's start or end), its strokes' phases set.
pub(super) fn segment(
    t: &[f64],
    theta: &[f64],
    strokes: &mut [LogStroke],
    (full, height, length): (f64, f64, Option<f64>),
    (a, b): (f64, f64),
    (from, to): (Option<PhaseKind>, Option<PhaseKind>),
    out: &mut Vec<Phase>,
) {
    let idx: Vec<usize> = (0..strokes.len())
        .filter(|&i| strokes[i].bdc >= a && strokes[i].bdc <= b)
        .collect();
    if idx.is_empty() {
        // Motion with no swing through the bottom (a tug, a check): it
        // belongs with the rest after it.
        push(out, to.or(from).unwrap_or(PhaseKind::Down), a, b);
        return;
    }
    // Free swings at the end (the bell let go after lowering) are down;
    // what comes before them ends down.
    if to != Some(PhaseKind::Up) {
        if let Some((first, cut)) = free_swings_at_end(t, theta, strokes, &idx) {
            for &i in &idx[first..] {
                strokes[i].phase = PhaseKind::Down;
            }
            if cut > a {
                segment(
                    t,
                    theta,
                    strokes,
                    (full, height, length),
                    (a, cut),
                    (from, Some(PhaseKind::Down)),
                    out,
                );
            }
            push(out, PhaseKind::Down, cut.max(a), b);
            return;
        }
    }
    if let Some(kind) = whole_kind(strokes, &idx, full, (from, to)) {
        for &i in &idx {
            strokes[i].phase = kind;
        }
        push(out, kind, a, b);
        return;
    }
    ringing_within(t, theta, strokes, &idx, (height, length), (a, b), from, out);
}

/// Free swings at the end of a segment's strokes `idx`: six or more small
/// swings, none struck, each within 3 deg of the one two before. The
/// position in `idx` of the first that is down, and the turning point
/// before it (s), where the down phase starts.
fn free_swings_at_end(t: &[f64], theta: &[f64], strokes: &[LogStroke], idx: &[usize]) -> Option<(usize, f64)> {
    let amp = |i: usize| strokes[i].amplitude;
    let free = |p: usize| {
        let s = &strokes[idx[p]];
        s.strike.is_none()
            && !s.strike_hidden
            && s.amplitude < FREE_SWING_MAX
            && (p < 2 || (s.amplitude - amp(idx[p - 2])).abs() <= 3f64.to_radians())
    };
    let mut p0 = idx.len();
    while p0 > 0 && free(p0 - 1) {
        p0 -= 1;
    }
    // (The first of the run may fall from a struck swing: from the next.)
    if idx.len() - p0 < 6 {
        return None;
    }
    let first = p0 + 1;
    let since = strokes[idx[first - 1]].bdc;
    Some((first, turning_before(t, theta, strokes[idx[first]].bdc, since)))
}

/// The one kind of all a segment's strokes `idx`, when the rests either
/// side or the want of a full swing (`full`, rad) settle it.
fn whole_kind(
    strokes: &[LogStroke],
    idx: &[usize],
    full: f64,
    (from, to): (Option<PhaseKind>, Option<PhaseKind>),
) -> Option<PhaseKind> {
    let amp = |i: usize| strokes[i].amplitude;
    let fulls = idx.iter().any(|&i| amp(i) >= full);
    match (from, to) {
        // Raised and set: every swing is raising, even the last full ones.
        (Some(PhaseKind::Down) | None, Some(PhaseKind::Up)) => Some(PhaseKind::Raising),
        (Some(PhaseKind::Up), Some(PhaseKind::Up)) => Some(PhaseKind::Ringing),
        _ if !fulls => {
            // No full swing: rising or falling amplitudes.
            let (f, l) = (amp(idx[0]), amp(idx[idx.len() - 1]));
            Some(
                if from == Some(PhaseKind::Up) || (to == Some(PhaseKind::Down) && l < f) {
                    PhaseKind::Lowering
                } else {
                    PhaseKind::Raising
                },
            )
        }
        _ => None,
    }
}

/// The ringing within a segment `(a, b)` (strokes `idx`): swings that
/// fall from near the ringing's `height` (rad) and rise back to it (3 deg
/// below the full swings' median); raising before, lowering from the
/// first swing that does not rise back. (The full swings' height over the
/// whole log: a segment lowered from its first swing after a set has none
/// that reach it.)
#[allow(clippy::too_many_arguments)]
fn ringing_within(
    t: &[f64],
    theta: &[f64],
    strokes: &mut [LogStroke],
    idx: &[usize],
    (height, length): (f64, Option<f64>),
    (a, b): (f64, f64),
    from: Option<PhaseKind>,
    out: &mut Vec<Phase>,
) {
    let amp = |i: usize| strokes[i].amplitude;
    let threshold = height - 3f64.to_radians();
    let core = |p: usize| amp(idx[p]) >= threshold && idx.get(p + 1).is_none_or(|&q| amp(q) >= threshold);
    if from == Some(PhaseKind::Up) && !(0..idx.len()).any(core) {
        for &i in idx {
            strokes[i].phase = PhaseKind::Lowering;
        }
        push(out, PhaseKind::Lowering, a, b);
        return;
    }
    let first = (0..idx.len()).find(|&p| core(p)).unwrap_or(0);
    let mut last = (0..idx.len()).rev().find(|&p| core(p)).unwrap_or(idx.len() - 1);
    // After a set, fewer core strokes than a lowering's dying swings, and
    // swings after them that are not: the lowering's first swings, near
    // the ringing's height within the amplitude's reading error (Data141's
    // second swing after its last set read 165.5 or 166.8 deg, as the
    // headstock's ring was taken out one way or the other, about the
    // threshold, and the lowering's first two strokes became "ringing").
    let cores = (0..idx.len()).filter(|&p| core(p)).count();
    if from == Some(PhaseKind::Up) && cores < DECLINE_SWINGS && last + 1 < idx.len() {
        for &i in idx {
            strokes[i].phase = PhaseKind::Lowering;
        }
        push(out, PhaseKind::Lowering, a, b);
        return;
    }
    // Lowering from its first swing: the ringing ends before the first
    // stroke after which the swings die away steadily.
    let amps: Vec<f64> = idx.iter().map(|&i| amp(i)).collect();
    let bdcs: Vec<f64> = idx.iter().map(|&i| strokes[i].bdc).collect();
    let by_amplitude = (first..=last).find(|&p| declines_after(&amps, p, height));
    let core_at: Vec<bool> = (0..idx.len()).map(core).collect();
    let by_time = shortens_after(&bdcs, &core_at, (first, last), length);
    if let Some(p) = by_amplitude.into_iter().chain(by_time).min() {
        if p == 0 && from == Some(PhaseKind::Up) {
            for &i in idx {
                strokes[i].phase = PhaseKind::Lowering;
            }
            push(out, PhaseKind::Lowering, a, b);
            return;
        }
        last = p.saturating_sub(1).max(first);
    }
    // The turning point just before the stroke at position p.
    let before = |p: usize| {
        let since = if p == 0 { a } else { strokes[idx[p - 1]].bdc };
        turning_before(t, theta, strokes[idx[p]].bdc, since)
    };
    let start_ring = if from == Some(PhaseKind::Up) { a } else { before(first) };
    let end_ring = if last + 1 < idx.len() { before(last + 1) } else { b };
    for (p, &i) in idx.iter().enumerate() {
        strokes[i].phase = if p < first {
            PhaseKind::Raising
        } else if p <= last {
            PhaseKind::Ringing
        } else {
            PhaseKind::Lowering
        };
    }
    push(out, PhaseKind::Raising, a, start_ring);
    push(out, PhaseKind::Ringing, start_ring, end_ring);
    push(out, PhaseKind::Lowering, end_ring, b);
}

/// Swings in a row that must die away for a lowering to start.
const DECLINE_SWINGS: usize = 4;

/// How much (rad) they must lose in all: 10 deg (a ringing's swings, with
/// or without stands, keep their height within a few degrees).
const DECLINE_DROP: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// A swing may read this much (rad) above the one before and still count
/// as dying away (the amplitude's reading error): 2 deg.
const DECLINE_SLACK: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// The first of them rises at least this far (rad) below the full swings'
/// median: 1 deg (a ringing stroke rises to the median itself, give or
/// take its reading; the generator's lowering follows on from a ringing
/// stroke that rose to it).
const DECLINE_BELOW: f64 = std::f64::consts::PI / 180.0;

/// Whether the swings the stroke at `p` and the next rise to (the
/// amplitudes `amps[p + 1..]`) die away: [`DECLINE_SWINGS`] of them, the
/// first [`DECLINE_BELOW`] under the full swings' median `height` (rad), each no higher than
/// the one before (give or take [`DECLINE_SLACK`]), losing
/// [`DECLINE_DROP`] in all. The stroke at `p` is then the lowering's first
/// (an independent tester's log, lowered from a stand at 184 deg: 171,
/// 168, 157, 157 deg read, where its ringing's rose to 172-177 and the
/// first lowering stroke was counted as ringing; its ringing with stands
/// rose to 186, 182, 183, 175 deg, which is no lowering).
fn declines_after(amps: &[f64], p: usize, height: f64) -> bool {
    let Some(run) = amps.get(p + 1..p + 1 + DECLINE_SWINGS) else {
        return false;
    };
    run[0] < height - DECLINE_BELOW
        && run.windows(2).all(|w| w[1] <= w[0] + DECLINE_SLACK)
        && run[0] - run[DECLINE_SWINGS - 1] >= DECLINE_DROP
}

/// Swings whose times say the bell no longer rises to the balance: the
/// half swing after the stroke at `p` (bottom to bottom) and the median of
/// the [`SHORT_SWINGS`] from it both under [`SHORT_FRACTION`] of the
/// ringing's shorter half swings (the lower quartile of its core strokes'
/// `core`, between `first` and `last`: a stand lengthens the others). The
/// first such stroke is the lowering's first. A swing to the balance
/// lingers at its top (a free pendulum's time there grows without
/// bound), so one that turns back short of it is much the quicker,
/// however its turning point is read: under a headstock that clips for a
/// second after each strike the lowering's turning points read up to 199
/// deg, which broke [`declines_after`], and the first lowering stroke,
/// struck sooner after its bottom, was counted as ringing (the
/// odd-struckness 4 ms off on one of the clipping test's 30 logs). A
/// bottom sooner after the one before than [`QUICKEST`] of a free small
/// swing's half (π √(L/g), `length` L m, when known) is the ringing's
/// shaking read as a crossing, and is passed over here. Only the last two
/// core strokes are judged so.
fn shortens_after(bdcs: &[f64], core: &[bool], (first, last): (usize, usize), length: Option<f64>) -> Option<usize> {
    let quickest = length.map_or(0.0, |l| {
        QUICKEST * std::f64::consts::PI * (l / clapper_core::bell::G).sqrt()
    });
    // The bottoms kept (their positions), and each one's next kept.
    let mut kept: Vec<usize> = vec![];
    for p in 0..bdcs.len() {
        if kept.last().is_none_or(|&q| bdcs[p] - bdcs[q] >= quickest) {
            kept.push(p);
        }
    }
    let halves: Vec<f64> = kept.windows(2).map(|w| bdcs[w[1]] - bdcs[w[0]]).collect();
    let mut ringing: Vec<f64> = (0..halves.len())
        .filter(|&j| (first..=last).contains(&kept[j]) && core[kept[j]])
        .map(|j| halves[j])
        .collect();
    if ringing.len() < 3 {
        return None;
    }
    ringing.sort_by(f64::total_cmp);
    let limit = SHORT_FRACTION * ringing[ringing.len() / 4];
    // Only the last two core strokes: the lowering's first falls from the
    // balance and may read as core; the ringing's own shaking read as
    // bottoms, two close together, would else cut the ringing short.
    (0..halves.len())
        .filter(|&j| (first.max(last.saturating_sub(1))..=last).contains(&kept[j]))
        .find(|&j| {
            j + SHORT_SWINGS <= halves.len() && halves[j] < limit && median(&halves[j..j + SHORT_SWINGS]) < limit
        })
        .map(|j| kept[j])
}

/// Half swings judged by [`shortens_after`].
const SHORT_SWINGS: usize = 5;

/// A half swing under this fraction of the ringing's shorter ones is
/// short.
const SHORT_FRACTION: f64 = 0.8;

/// Bottoms sooner than this fraction of a free small swing's half after the
/// one before are not counted by [`shortens_after`].
const QUICKEST: f64 = 1.1;

/// The turning point (largest |θ|) before bottom dead centre `bdc`, after `from`.
pub(super) fn turning_before(t: &[f64], theta: &[f64], bdc: f64, from: f64) -> f64 {
    let (i, j) = (t.partition_point(|&x| x < from), t.partition_point(|&x| x < bdc));
    (i..j)
        .max_by(|&a, &b| theta[a].abs().total_cmp(&theta[b].abs()))
        .map_or(from, |k| t[k])
}

/// Odd-struckness of the ringing: mean hand minus mean back BDC-to-strike
/// (s) and its standard error.
pub(super) fn odd_struck(strokes: &[LogStroke]) -> Option<(f64, f64)> {
    let times = |hand: bool| -> Vec<f64> {
        strokes
            .iter()
            .filter(|s| s.phase == PhaseKind::Ringing && s.hand == hand)
            .filter_map(LogStroke::bdc_to_strike)
            .collect()
    };
    let (h, b) = (times(true), times(false));
    if h.len() < 2 || b.len() < 2 {
        return None;
    }
    // The mean and its variance, sd²/n.
    let stats = |v: &[f64]| mean_sd(v).map(|(m, sd)| (m, sd * sd / v.len() as f64));
    let ((mh, vh), (mb, vb)) = (stats(&h)?, stats(&b)?);
    Some((mh - mb, (vh + vb).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A struck stroke falling from `deg` at `bdc` s.
    fn stroke(bdc: f64, deg: f64, hand: bool) -> LogStroke {
        LogStroke {
            bdc,
            hand,
            strike: Some(bdc + 0.35),
            strike_hidden: false,
            strike_theta: None,
            amplitude: deg.to_radians(),
            from_side: if hand { 1.0 } else { -1.0 },
            phase: PhaseKind::Down,
            speed_peak: None,
            bdc_se: None,
            stand: None,
            amplitude_timed: false,
        }
    }

    /// After a set, a lowering whose first two swings read within the
    /// amplitude's error of the ringing's height (Data141's read 166.8 and
    /// 165.5 deg against a threshold of about 165.4) is lowering from its
    /// first swing: its first stroke was called ringing, one stroke of it,
    /// and counted in the ringing's odd-struckness.
    #[test]
    fn a_lowering_whose_first_swings_read_near_the_ringings_height_is_lowering() {
        let amps = [168.0, 166.5, 160.0, 154.0, 148.0, 142.0, 136.0, 130.0, 120.0, 110.0];
        let mut strokes: Vec<LogStroke> = amps
            .iter()
            .enumerate()
            .map(|(k, &a)| stroke(101.0 + 2.0 * k as f64, a, k % 2 == 0))
            .collect();
        let t: Vec<f64> = (0..12_500).map(|i| 100.0 + 0.01 * f64::from(i)).collect();
        let theta = vec![0.0; t.len()];
        let mut out = vec![];
        segment(
            &t,
            &theta,
            &mut strokes,
            (165f64.to_radians(), 167f64.to_radians(), None),
            (100.0, 225.0),
            (Some(PhaseKind::Up), Some(PhaseKind::Down)),
            &mut out,
        );
        assert!(strokes.iter().all(|s| s.phase == PhaseKind::Lowering), "{:?}", out);
        assert!(out.iter().all(|p| p.kind == PhaseKind::Lowering), "{out:?}");
    }
}
