//! Double strikes: each band's response to one strike learned from all
//! the bell's strikes, and a second copy of it fitted beside the first.

use super::band::{Band, SharedBand, C, SHARED_BAND_QUIET};
use super::fit::{conj, dot, dots, fit_alone, fit_gram3};
use super::heard::{HeardDouble, QuietStrokes, StrikeOptions};
use super::onsets::BellHearing;
use clapper_core::stroke::double_strike_index;

impl BellHearing {
    /// A second strike after each of `firsts` (onset s, strength), if
    /// any. The bell's own response to a strike in each band, in this
    /// room, is learned from all its strikes: a second strike is a second
    /// copy of it. A band it shares with other bells (`shared`, with
    /// those bells) is used where none of them strikes (`times`, every
    /// bell's onsets) within its window, and learned from those strikes;
    /// so is each of its own bands that other bells share (`with`, per
    /// band: those bells, from 0; none but where the bell has fewer than
    /// two bands of its own).
    pub(super) fn doubles(
        &self,
        firsts: &[(f64, f64)],
        shared: &[SharedBand],
        with: &[Vec<usize>],
        times: &[Vec<f64>],
        opts: &StrikeOptions,
    ) -> Vec<Option<HeardDouble>> {
        let own: Vec<f64> = firsts.iter().map(|f| f.0).collect();
        let responses: Vec<Option<Response>> = self.bands.iter().map(|b| learn_response(b, &own, opts)).collect();
        let fits = fitted(&self.bands, &responses, opts);
        // Whether no sharing bell strikes in the window of band `b` around `t`.
        let quiet = |b: &Band, with: &[usize], t: f64| {
            let (lead, tail) = response_window(b, opts);
            let (lo, hi) = (
                t - lead as f64 / b.rate - 2.0 * b.box_s,
                t + tail as f64 / b.rate + 2.0 * b.box_s,
            );
            with.iter()
                .all(|&o| times.get(o).is_none_or(|v| v.iter().all(|&u| u < lo || u > hi)))
        };
        let shared_resp: Vec<Option<Response>> = shared
            .iter()
            .map(|sb| {
                let clear: Vec<f64> = own.iter().copied().filter(|&t| quiet(&sb.band, &sb.with, t)).collect();
                learn_response(&sb.band, &clear, opts)
            })
            .collect();
        let shared_fits: Vec<(Fitted, &[usize])> = shared
            .iter()
            .zip(&shared_resp)
            .filter_map(|(sb, r)| Some((fit_band(&sb.band, r.as_ref()?, opts), sb.with.as_slice())))
            .collect();
        // ... and where what rings there before the strike (a sharing
        // bell's partial, beating against this one's) is small beside the
        // strike's own step.
        let faint = |b: &Band, t: f64| {
            let (lead, tail) = response_window(b, opts);
            let Some(seg) = segment(b, t, lead, tail) else {
                return false;
            };
            let before = ((0.01 * b.rate).round() as usize).max(1);
            let base = seg[..before].iter().fold((0.0, 0.0), |a, z| (a.0 + z.0, a.1 + z.1));
            let base = (base.0 / before as f64, base.1 / before as f64);
            let top = seg[(lead + (1.5 * b.box_s * b.rate).ceil() as usize).min(seg.len() - 1)];
            let step = (top.0 - base.0).hypot(top.1 - base.1);
            base.0.hypot(base.1) < SHARED_BAND_QUIET * step
        };
        // A bell heard in bands it shares (`with`, per band: the bells
        // whose partials lie there) is judged in each only where it is
        // judged as a shared band: no sharer strikes in its window and
        // what rings before the strike is small beside its step. In all
        // of them, the sharers' partials ringing on and beating were
        // fitted as second strikes (the 9th of bench/strikes' ten, seeds
        // 1-4: 16 of the ring's 34 false doubles).
        let fit_with = sharers_of(&self.bands, &fits, with);
        let copies: Vec<Option<Copy2>> = own
            .iter()
            .map(|&t| {
                let mut use_: Vec<&Fitted> = fits
                    .iter()
                    .zip(&fit_with)
                    .filter(|(f, w)| w.is_empty() || (quiet(f.band, w, t) && faint(f.band, t)))
                    .map(|(f, _)| f)
                    .collect();
                use_.extend(
                    shared_fits
                        .iter()
                        .filter(|(f, with)| quiet(f.band, with, t) && faint(f.band, t))
                        .map(|(f, _)| f),
                );
                best_copy(&use_, t, opts)
            })
            .collect();
        // Judged anew only in the hearing reported (`QuietStrokes::ByRhythm`, which
        // the app sets there alone with `--nominals` and `--bells N`): the
        // calibration learns each bell from its strikes not called double
        // (`self_calibrate::clean_strikes`), and with this judge there it
        // learned worse (held G6_wet `--bells` 0.787 -> 0.208 within 10 ms);
        // the template path's band doubles stay as they were.
        if opts.quiet_strokes == QuietStrokes::ByRhythm {
            judge_bell(&copies, opts)
        } else {
            copies.iter().map(|c| judge_plain(c.as_ref(), opts)).collect()
        }
    }
}

/// One strike's best second copy judged as every strike was before session
/// 21: a double where it takes [`DOUBLE_MIN_GAIN`] of the one-copy error
/// away, half its bands or more hear it at the option's ratio, and it is no
/// louder than [`MAX_DOUBLE_RATIO`] (louder, the first was not the strike).
pub(super) fn judge_plain(c: Option<&Copy2>, opts: &StrikeOptions) -> Option<HeardDouble> {
    c.filter(|c| c.gain >= DOUBLE_MIN_GAIN && c.quorum >= opts.double_min_ratio && c.ratio <= MAX_DOUBLE_RATIO)
        .map(|c| HeardDouble {
            delay_s: c.delay_s,
            amplitude_ratio: c.ratio,
        })
}

/// The best second copy fitted after one strike, not yet judged a double.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Copy2 {
    /// Its delay after the strike as timed (s).
    pub(super) delay_s: f64,
    /// The share of the one-copy error it takes away (0-1).
    pub(super) gain: f64,
    /// Its size over the first copy's (the median over the bands).
    pub(super) ratio: f64,
    /// The lower median of that ratio over the bands.
    pub(super) quorum: f64,
}

/// Each strike of one bell judged double or not from its best second copy
/// (`copies`, every strike of the bell in order). A copy is a double where
/// it takes away at least [`HEARD_MIN_GAIN`] of the one-copy error and
/// [`OVER_TYPICAL_GAIN`] more than the bell's typical strike's best copy
/// does (the median over its strikes, from [`TYPICAL_FEWEST`] on: a bell
/// whose every strike differs from its learned response by a partial that
/// beats, a dip in its rise, or the room's tail, has some copy take much of
/// every strike's error away); where half its bands or more hear it at the
/// option's ratio; where it is no louder than [`HEARD_MAX_RATIO`] (louder,
/// the first was not the strike: no weaker copy is taken); where it lies in
/// the option's window after the strike as timed (a copy fitted from a
/// start slid earlier can fall before); and where a listener would hear it
/// ([`double_strike_index`] at least 1, docs/model.md eq. 33: none under
/// 24.8 ms). Doubles of one bell at one delay are kept: in steady ringing
/// a clapper that bounces does so alike at every blow (the model's strokes,
/// docs/model.md), and that bell is the one a bell-hanger asks about.
pub(super) fn judge_bell(copies: &[Option<Copy2>], opts: &StrikeOptions) -> Vec<Option<HeardDouble>> {
    let (lo, hi) = (opts.double_window_ms.0 * 1e-3, opts.double_window_ms.1 * 1e-3);
    let floor = typical_gain(copies).map_or(HEARD_MIN_GAIN, |g| (g + OVER_TYPICAL_GAIN).max(HEARD_MIN_GAIN));
    copies
        .iter()
        .map(|c| {
            c.filter(|c| {
                c.gain >= floor
                    && c.quorum >= opts.double_min_ratio
                    && c.ratio <= HEARD_MAX_RATIO
                    && (lo..=hi).contains(&c.delay_s)
                    && double_strike_index(c.ratio, c.delay_s * 1e3) >= 1.0
            })
            .map(|c| HeardDouble {
                delay_s: c.delay_s,
                amplitude_ratio: c.ratio,
            })
        })
        .collect()
}

/// The gain of a bell's typical strike's best second copy: the median over
/// `copies` (none counted as 0), or None from fewer than [`TYPICAL_FEWEST`].
fn typical_gain(copies: &[Option<Copy2>]) -> Option<f64> {
    if copies.len() < TYPICAL_FEWEST {
        return None;
    }
    super::stats::median(copies.iter().map(|c| c.map_or(0.0, |c| c.gain)).collect())
}

/// The bells sharing each band of `fits` (`with`, per band of `bands`;
/// none where not given).
fn sharers_of<'a>(bands: &[Band], fits: &[Fitted], with: &'a [Vec<usize>]) -> Vec<&'a [usize]> {
    fits.iter()
        .map(|f| {
            bands
                .iter()
                .position(|b| std::ptr::eq(b, f.band))
                .and_then(|i| with.get(i))
                .map_or(&[][..], |w| w.as_slice())
        })
        .collect()
}

/// A band's response to one strike of its bell, learned from all its
/// strikes: `z` at `t0 + (k − lead)/rate` less its level before, over its
/// size, the median over strikes (component by component, so a double
/// strike or another bell's strike in a few of them does not count).
pub(super) struct Response {
    /// Samples before the onset.
    pub(super) lead: usize,
    /// The response, one per band sample from `t0 − lead/rate`.
    pub(super) r: Vec<C>,
}

/// The window a strike's response is learned and fitted over (band
/// samples before and after the onset): from before the rise to past the
/// latest second strike's rise.
pub(super) fn response_window(b: &Band, opts: &StrikeOptions) -> (usize, usize) {
    let lead = ((1.5 * b.box_s + 0.01) * b.rate).ceil() as usize;
    let tail = ((opts.double_window_ms.1 * 1e-3 + 1.5 * b.box_s + 0.02) * b.rate).ceil() as usize;
    (lead, tail)
}

/// `z` at fractional band sample `x` (linear between samples).
pub(super) fn z_at(z: &[C], x: f64) -> Option<C> {
    if x < 0.0 {
        return None;
    }
    let i = x.floor() as usize;
    let f = x - i as f64;
    let (a, b) = (*z.get(i)?, *z.get(i + 1)?);
    Some((a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1)))
}

/// Band `b` around onset `t0` (s): `lead + tail` samples, or None near
/// the recording's ends.
pub(super) fn segment(b: &Band, t0: f64, lead: usize, tail: usize) -> Option<Vec<C>> {
    let x0 = t0 * b.rate - lead as f64;
    (0..lead + tail).map(|k| z_at(&b.z, x0 + k as f64)).collect()
}

/// Band `b`'s [`Response`] from the strikes at `times` (s), or None from
/// fewer than five strikes clear of the recording's ends.
pub(super) fn learn_response(b: &Band, times: &[f64], opts: &StrikeOptions) -> Option<Response> {
    let (lead, tail) = response_window(b, opts);
    // The level before: the last few ms before the rise can start.
    let before = ((0.01 * b.rate).round() as usize).max(1);
    let rise_end = lead + (1.5 * b.box_s * b.rate).ceil() as usize;
    let mut norm: Vec<Vec<C>> = vec![];
    let mut sizes = vec![];
    for &t0 in times {
        let Some(seg) = segment(b, t0, lead, tail) else {
            continue;
        };
        let base = seg[..before].iter().fold((0.0, 0.0), |a, z| (a.0 + z.0, a.1 + z.1));
        let base = (base.0 / before as f64, base.1 / before as f64);
        let top = seg[rise_end.min(seg.len() - 1)];
        let a = (top.0 - base.0, top.1 - base.1);
        let d = a.0 * a.0 + a.1 * a.1;
        if d <= 0.0 {
            continue;
        }
        sizes.push(d.sqrt());
        norm.push(
            seg.iter()
                .map(|z| {
                    let (x, y) = (z.0 - base.0, z.1 - base.1);
                    ((x * a.0 + y * a.1) / d, (y * a.0 - x * a.1) / d)
                })
                .collect(),
        );
    }
    // Weak strikes are mostly noise: only those at least a third of the median.
    let mut s = sizes.clone();
    s.sort_by(f64::total_cmp);
    let cut = s.get(s.len() / 2).copied().unwrap_or(0.0) / 3.0;
    let used: Vec<&Vec<C>> = norm
        .iter()
        .zip(&sizes)
        .filter(|(_, &a)| a >= cut)
        .map(|(n, _)| n)
        .collect();
    if used.len() < 5 {
        return None;
    }
    let r = (0..lead + tail)
        .map(|k| {
            let mut re: Vec<f64> = used.iter().map(|n| n[k].0).collect();
            let mut im: Vec<f64> = used.iter().map(|n| n[k].1).collect();
            re.sort_by(f64::total_cmp);
            im.sort_by(f64::total_cmp);
            (re[re.len() / 2], im[im.len() / 2])
        })
        .collect();
    Some(Response { lead, r })
}

/// One strike's window in a band, with its Gram terms for the basis
/// [1, R]: (window, g, r, Σ|z|²).
pub(super) type Single = (Vec<C>, [[C; 2]; 2], [C; 2], f64);

/// The response a delay later, on the window's samples, with its Gram
/// terms against the constant, the response and itself: the same for
/// every strike, so found once per band.
pub(super) struct Shifted {
    /// Delay (s).
    pub(super) d: f64,
    pub(super) r2: Vec<C>,
    pub(super) sum: C,
    pub(super) r1_r2: C,
    pub(super) r2_r2: C,
}

/// A band with its learned response, as a strike is fitted in it.
pub(super) struct Fitted<'a> {
    pub(super) band: &'a Band,
    pub(super) resp: &'a Response,
    pub(super) tail: usize,
    /// The response at each delay of the double-strike window it can tell
    /// (from [`DOUBLE_MIN_BOXES`] boxes).
    pub(super) shifted: Vec<Shifted>,
}

/// The response `r` shifted `shift` band samples later (0 before it
/// starts, its last value after it ends).
pub(super) fn shift_response(r: &[C], shift: f64) -> Vec<C> {
    (0..r.len())
        .map(|k| {
            let x = k as f64 - shift;
            if x < 0.0 {
                (0.0, 0.0)
            } else {
                z_at(r, x).unwrap_or(*r.last().unwrap_or(&(0.0, 0.0)))
            }
        })
        .collect()
}

impl Fitted<'_> {
    /// The Gram terms of window `z` (the band from `lead` before a
    /// strike) with a constant and the response: (g, r, Σ|z|²).
    pub(super) fn gram_of(&self, z: &[C]) -> ([[C; 2]; 2], [C; 2], f64) {
        let r1 = &self.resp.r;
        let sum_r1: C = r1.iter().fold((0.0, 0.0), |s, v| (s.0 + v.0, s.1 + v.1));
        let g = [[(z.len() as f64, 0.0), sum_r1], [conj(sum_r1), dot(r1, r1)]];
        let sum_z: C = z.iter().fold((0.0, 0.0), |s, v| (s.0 + v.0, s.1 + v.1));
        let r = [sum_z, dot(r1, z)];
        let zz = z.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum();
        (g, r, zz)
    }

    /// The strike fitted with a second copy later: (error with both,
    /// first's size, second's size); `r2_z` is Σ conj(r2)·z of the
    /// shifted response and the single's window.
    pub(super) fn pair(sh: &Shifted, single: &Single, r2_z: C) -> (f64, f64, f64) {
        let (_, g, r, zz) = single;
        let g3 = [
            [g[0][0], g[0][1], sh.sum],
            [g[1][0], g[1][1], sh.r1_r2],
            [conj(sh.sum), conj(sh.r1_r2), sh.r2_r2],
        ];
        let r3 = [r[0], r[1], r2_z];
        let (e2, c) = fit_gram3(&g3, &r3, *zz);
        (e2, c[1].0.hypot(c[1].1), c[2].0.hypot(c[2].1))
    }
}

/// The bands a strike is timed and fitted in: those whose response was
/// learned and that are mostly the bell's own (a shared band hears the
/// next bell).
pub(super) fn fitted<'a>(
    bands: &'a [Band],
    responses: &'a [Option<Response>],
    opts: &StrikeOptions,
) -> Vec<Fitted<'a>> {
    let wmax = bands.iter().map(|b| b.weight).fold(0.0, f64::max);
    bands
        .iter()
        .zip(responses)
        .filter(|(b, _)| b.weight >= 0.3 * wmax)
        .filter_map(|(b, r)| Some(fit_band(b, r.as_ref()?, opts)))
        .collect()
}

/// Band `b` with its learned response, ready to fit: the response at every
/// delay the band can tell (from [`DOUBLE_MIN_BOXES`] boxes).
pub(super) fn fit_band<'a>(b: &'a Band, resp: &'a Response, opts: &StrikeOptions) -> Fitted<'a> {
    let shifted = delays(opts, b.rate)
        .filter(|&d| d >= DOUBLE_MIN_BOXES * b.box_s)
        .map(|d| {
            let r2 = shift_response(&resp.r, d * b.rate);
            Shifted {
                d,
                sum: r2.iter().fold((0.0, 0.0), |s, v| (s.0 + v.0, s.1 + v.1)),
                r1_r2: dot(&resp.r, &r2),
                r2_r2: dot(&r2, &r2),
                r2,
            }
        })
        .collect();
    Fitted {
        band: b,
        resp,
        tail: response_window(b, opts).1,
        shifted,
    }
}

/// The delays of the double-strike window, one per band sample (s).
pub(super) fn delays(opts: &StrikeOptions, rate: f64) -> impl Iterator<Item = f64> {
    let (dmin, dmax) = (opts.double_window_ms.0 * 1e-3, opts.double_window_ms.1 * 1e-3);
    let steps = ((dmax - dmin) * rate).round() as usize + 1;
    (0..steps).map(move |j| dmin + j as f64 / rate)
}

/// The best second copy of the response after a strike at `t` (s)
/// within the double-strike window, over the bands that can tell it at
/// each delay: the one that takes most of the one-copy error away (summed
/// over the bands, each over its first copy's size squared), with its size
/// over the first's (the median over the bands); [`judge_bell`] or
/// [`judge_plain`] judges it. The one-copy error is the least within
/// [`SLIDE_S`] of `t`, and the two copies are fitted from `t` and from
/// there: a strike timed a few ms off is not a double.
///
/// The error taken away is summed over the bands each over its first
/// copy's size squared, so a band the one-copy fit leaves far from its
/// response (bell 8's hum in README's tower.wav, 50 ms boxes beating with
/// bell 7's hum 9 Hz off: an error 5 times its step against 0.6 in its
/// 1772 Hz band) decides the gain; with the median of two ratios (the
/// upper) it decided the ratio too (0.45 there against 0.05 in the band
/// that could tell 80 ms as well), a false double. The ratio reported
/// is still the median: the lower one reads a double's low where a band
/// hears it weakly (0.34 for a planted 0.7 on bell 6 of the test
/// `a_double_strike_is_told_in_a_band_shared_with_another_bell`).
pub(super) fn best_copy(fits: &[&Fitted], t: f64, opts: &StrikeOptions) -> Option<Copy2> {
    let rate = fits.first()?.band.rate;
    // One strike at its best time: the least error alone within SLIDE_S of
    // t, each band's over its strike's size squared. Each band's window is
    // read once, long enough for every slide (so a band is not fitted for
    // a strike within 20 ms of where its window would leave the recording).
    let slide = (SLIDE_S * rate).round() as usize;
    let long: Vec<Option<Vec<C>>> = fits
        .iter()
        .map(|f| segment(f.band, t - slide as f64 / rate, f.resp.lead, f.tail + 2 * slide))
        .collect();
    // The response's own terms, the same at every slide: (Σ r, Σ|r|²).
    let own: Vec<(C, f64)> = fits
        .iter()
        .map(|f| {
            let r = &f.resp.r;
            (
                r.iter().fold((0.0, 0.0), |s, v| (s.0 + v.0, s.1 + v.1)),
                r.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum(),
            )
        })
        .collect();
    let (k_best, e1_best) = best_slide(fits, &long, &own, slide)?;
    let singles_at = |k: usize| -> Vec<Option<Single>> {
        fits.iter()
            .zip(&long)
            .map(|(f, z)| {
                let z = &z.as_ref()?[k..k + f.resp.lead + f.tail];
                let (g, r, zz) = f.gram_of(z);
                Some((z.to_vec(), g, r, zz))
            })
            .collect()
    };
    let mut starts = vec![(t, singles_at(slide))];
    if k_best != slide {
        starts.push((t + (k_best as f64 - slide as f64) / rate, singles_at(k_best)));
    }
    best_second(fits, &starts, &e1_best, t, opts).map(|(delay_s, gain, ratio, quorum)| Copy2 {
        delay_s,
        gain,
        ratio,
        quorum,
    })
}

/// The slide where one strike alone fits best and, per band, its error
/// there (see [`best_copy`]).
fn best_slide(
    fits: &[&Fitted],
    long: &[Option<Vec<C>>],
    own: &[(C, f64)],
    slide: usize,
) -> Option<(usize, Vec<Option<f64>>)> {
    // Per slide k (from −slide), per band: its error alone and the score's share.
    let alone_at = |k: usize| -> Vec<Option<(f64, f64)>> {
        fits.iter()
            .zip(long)
            .zip(own)
            .map(|((f, z), &(s, rr))| {
                let z = &z.as_ref()?[k..k + f.resp.lead + f.tail];
                let (e1, c1) = fit_alone(z, &f.resp.r, s, rr)?;
                Some((e1, e1 / (c1.0 * c1.0 + c1.1 * c1.1).max(1e-300)))
            })
            .collect()
    };
    // (slide, per band (error, score share), score).
    type Alone = (usize, Vec<Option<(f64, f64)>>, f64);
    let mut alone: Option<Alone> = None;
    for k in 0..=2 * slide {
        let e = alone_at(k);
        let score: f64 = e.iter().flatten().map(|x| x.1).sum();
        if alone.as_ref().is_none_or(|a| score < a.2) {
            alone = Some((k, e, score));
        }
    }
    let (k_best, e1_best, _) = alone?;
    Some((k_best, e1_best.iter().map(|e| e.map(|x| x.0)).collect()))
}

/// The best second copy over the start times `starts` (each with its
/// bands' windows) and every delay of the window: (delay after `t`,
/// gain, ratio, quorum ratio).
fn best_second(
    fits: &[&Fitted],
    starts: &[(f64, Vec<Option<Single>>)],
    e1_best: &[Option<f64>],
    t: f64,
    opts: &StrikeOptions,
) -> Option<(f64, f64, f64, f64)> {
    let rate = fits.first()?.band.rate;
    let all = delays(opts, rate).count();
    // (delay, gain, ratio, quorum ratio).
    let mut best: Option<(f64, f64, f64, f64)> = None;
    let mut ratios = vec![];
    for (t0, singles) in starts {
        // Per band, each delay's Σ conj(r2)·z, four delays side by side.
        let r2_z: Vec<Vec<C>> = fits
            .iter()
            .zip(singles)
            .zip(e1_best)
            .map(|((f, single), e1b)| match (single, e1b) {
                (Some((z, ..)), Some(_)) => {
                    let r2: Vec<&[C]> = f.shifted.iter().map(|sh| sh.r2.as_slice()).collect();
                    dots(&r2, z)
                }
                _ => vec![],
            })
            .collect();
        for (j, d) in delays(opts, rate).enumerate() {
            let (mut e1, mut e2) = (0.0, 0.0);
            ratios.clear();
            for (((f, single), e1b), r2_z) in fits.iter().zip(singles).zip(e1_best).zip(&r2_z) {
                let (Some(single), Some(e1b)) = (single, e1b) else {
                    continue;
                };
                // The band's delays are the window's from its first it can tell.
                let skipped = all - f.shifted.len();
                let Some(k) = j.checked_sub(skipped).filter(|&k| k < f.shifted.len()) else {
                    continue;
                };
                let sh = &f.shifted[k];
                debug_assert!((sh.d - d).abs() < 1e-9);
                let (b, s1, s2) = Fitted::pair(sh, single, r2_z[k]);
                if s1 <= 0.0 {
                    continue;
                }
                e1 += e1b / (s1 * s1);
                e2 += b / (s1 * s1);
                ratios.push(s2 / s1);
            }
            if ratios.is_empty() || e1 <= 0.0 {
                continue;
            }
            ratios.sort_by(f64::total_cmp);
            let gain = 1.0 - e2 / e1;
            let ratio = ratios[ratios.len() / 2];
            // The lower median: at least half the bands that can tell
            // the delay must hear the second copy (of two, both).
            let quorum = ratios[(ratios.len() - 1) / 2];
            if best.is_none_or(|b| gain > b.1) {
                // The second strike's delay after the strike as timed.
                best = Some((t0 + d - t, gain, ratio, quorum));
            }
        }
    }
    best
}

/// How far a strike may slide (s) when fitted alone, before a second copy
/// is weighed against it: timed a few ms off (onsets in a room: 95 % within
/// 6 ms, some 20 ms), one copy leaves an error that a second copy a little
/// later takes away. Over 40 benchmark recordings per condition, false
/// doubles in % of strikes at ±6 / ±12 / ±20 ms: at RT60 1.2 s 25 dB
/// 0.89 / 0.74 / 0.59, without a room 0.72 / 0.48 / 0.41, the doubles
/// flagged within three of 240 of each other.
pub(super) const SLIDE_S: f64 = 0.02;

/// The share of the one-copy error a second copy must take away to be a
/// double strike. Fitted about the start times, over 40 benchmark
/// recordings per condition: at 0.5 / 0.6 / 0.7, doubles flagged at RT60
/// 1.2 s 25 dB 97.1 / 97.1 / 96.7 %, false doubles 1.07 / 0.74 / 0.38 %
/// of strikes (at ±12 ms sliding); at 15 dB doubles 93.8 / 92.5 / 89.2 %.
pub(super) const DOUBLE_MIN_GAIN: f64 = 0.6;

/// The least share of the one-copy error a second copy must take away to
/// be a double in the hearing reported with `--nominals` or `--bells N`
/// ([`judge_bell`], which asks more of a bell whose typical strike has a
/// copy take much away). In the recorded bells' rings planted doubles at
/// 0.45-0.7 of the first, 45-90 ms on, took 0.4-0.6 away where the bell's
/// ring differs from strike to strike (dbl-2, session 21, tuning rings and
/// tester20's): at 0.6 a third of those timed right were missed.
pub(super) const HEARD_MIN_GAIN: f64 = 0.4;

/// How much more of the one-copy error (a share, 0-1) a double's second
/// copy must take away than the best copy of the bell's typical strike
/// (the median over its strikes). On the tuning rings (`--nominals`, the
/// recorded bells) the typical strike's best copy took 0.13-0.37 away on
/// most bells, 0.45-0.64 on a bell whose partials beat or whose rise dips
/// (A8's bell 7, d7) or in a dark room's tail; set from those rings.
pub(super) const OVER_TYPICAL_GAIN: f64 = 0.1;

/// The fewest strikes of a bell its typical copy is learned from.
pub(super) const TYPICAL_FEWEST: usize = 5;

/// The shortest delay a band is fitted for a second copy, in its boxes
/// (its rise is 3): a second strike within the rise still changes its
/// shape. At 3 (the second strike after the first's rise), bell 6 of the
/// benchmark, heard in its own bands only through 33-44 ms boxes, could be
/// told no double under 100-130 ms there; at 1.5, over the benchmark's
/// first 20 recordings at RT60 1.2 s, 115 of 120 doubles were flagged
/// against 112 (fitted about the half-way times, ±8 ms sliding, a gain
/// of 0.5), false doubles 0.91 % of strikes against 0.88 %.
pub(super) const DOUBLE_MIN_BOXES: f64 = 1.5;

/// The loudest second strike against its first (amplitude ratio) that
/// is a double strike: a double is the clapper bouncing back, its second
/// blow weaker than the first. A best second copy louder than this means
/// the strike was timed before its sound (on noise, a precursor, or
/// another bell's partial beating in a weak band): not a double, and no
/// weaker copy is taken instead (the template path's bound, tmpl-4). A
/// strike is taken as the first of a double only when the first stands
/// at least half as high as the second in the onset function
/// (`first_of_double`). At 2.0 and the best copy within it (over the
/// benchmark's first 20 recordings at 15 dB and RT60 1.2 s, 26 of 72
/// false doubles had ratios over 2, and the best copy within the limit
/// took them to 57 of 6331 strikes) the heavy ring's tenor, timed early,
/// was called double at 1.3-2.0 (bench/strikes seeds 1-4).
pub(super) const MAX_DOUBLE_RATIO: f64 = 1.5;

/// The loudest second blow against its first (amplitude ratio) that is a
/// double in the hearing reported ([`judge_bell`]): a bounce is weaker than
/// its blow (the paper's listening test played them up to 1); planted
/// doubles of 0.9-1.0 read at up to 1.03 with `--nominals`, the band
/// finder's false doubles at 1.05-1.49 (dbl-3, session 19).
pub(super) const HEARD_MAX_RATIO: f64 = 1.2;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strikes::timing::box3_step;

    /// One strike judged alone: its best copy, judged as [`judge_plain`]
    /// and as [`judge_bell`] judge it (asserted alike here).
    fn second_strike(fits: &[&Fitted], t: f64, opts: &StrikeOptions) -> Option<HeardDouble> {
        let c = best_copy(fits, t, opts);
        let plain = judge_plain(c.as_ref(), opts);
        assert_eq!(plain, judge_bell(&[c], opts)[0], "{c:?}");
        plain
    }

    /// A band built for `second_strike`: its response a step through three
    /// boxes of `box_s` (decaying slowly), and its signal one strike at
    /// `t0` (size `s1`) with a second copy `ratio` as large `d` later, on a
    /// constant, with a little deterministic noise.
    fn double_band(box_s: f64, t0: f64, s1: C, second: Option<(f64, f64)>, opts: &StrikeOptions) -> (Band, Response) {
        let rate = 1000.0;
        let step = |u: f64| box3_step(u / box_s + 1.5) * (-u.max(0.0) / 2.0).exp();
        let z: Vec<C> = (0..3000)
            .map(|k| {
                let t = k as f64 / rate;
                let mut v = (0.01 + s1.0 * step(t - t0), -0.02 + s1.1 * step(t - t0));
                if let Some((d, ratio)) = second {
                    v.0 += ratio * s1.0 * step(t - t0 - d);
                    v.1 += ratio * s1.1 * step(t - t0 - d);
                }
                let noise = ((k * 7919 % 101) as f64 / 101.0 - 0.5) * 2e-3;
                (v.0 + noise, v.1 - noise)
            })
            .collect();
        let len = (box_s * rate).round() as usize;
        let b = Band {
            rate,
            weight: 1.0,
            box_s,
            z,
            rise: (3 * len).max(2),
            scale: 1.0,
        };
        let (lead, tail) = response_window(&b, opts);
        let r = (0..lead + tail)
            .map(|k| (step((k as f64 - lead as f64) / rate), 0.0))
            .collect();
        (b, Response { lead, r })
    }

    /// A second copy heard in one band of two that can tell its delay is
    /// not a double strike (the band beating with another bell's partial
    /// fits one; the other, hearing none, outweighs it); heard in both, it
    /// is.
    #[test]
    fn a_double_strike_is_heard_in_half_the_bands_that_can_tell_it() {
        let opts = StrikeOptions::default();
        let t0 = 1.5;
        let heard = |second_in_short: Option<(f64, f64)>| {
            let (long, rl) = double_band(0.05, t0, (0.3, 0.1), Some((0.08, 0.45)), &opts);
            let (short, rs) = double_band(0.012, t0, (0.02, -0.01), second_in_short, &opts);
            let fits = [fit_band(&long, &rl, &opts), fit_band(&short, &rs, &opts)];
            second_strike(&fits.iter().collect::<Vec<_>>(), t0, &opts)
        };
        assert_eq!(heard(None), None);
        let d = heard(Some((0.08, 0.45))).expect("a double heard in both bands");
        assert!(
            (d.delay_s - 0.08).abs() < 0.003 && (d.amplitude_ratio - 0.45).abs() < 0.05,
            "{d:?}"
        );
    }

    /// A second copy 1.8 times as loud as the first, 80 ms after it: the
    /// first was not the strike (a precursor, another bell's partial, a
    /// beat's swell), and the strike is not a double. Before, the best
    /// copy up to twice the first was taken: a double at ratio 1.8. A
    /// copy 0.7 as loud is still one.
    #[test]
    fn a_second_copy_far_louder_than_the_first_is_not_a_double() {
        let opts = StrikeOptions::default();
        let t0 = 1.5;
        let heard = |ratio: f64| {
            let (long, rl) = double_band(0.05, t0, (0.3, 0.1), Some((0.08, ratio)), &opts);
            let (short, rs) = double_band(0.012, t0, (0.02, -0.01), Some((0.08, ratio)), &opts);
            let fits = [fit_band(&long, &rl, &opts), fit_band(&short, &rs, &opts)];
            second_strike(&fits.iter().collect::<Vec<_>>(), t0, &opts)
        };
        assert_eq!(heard(1.8), None);
        let d = heard(0.7).expect("a double");
        assert!((d.amplitude_ratio - 0.7).abs() < 0.1, "{d:?}");
    }

    /// `n` strikes' best copies: each at `gain`, a 40-140 ms delay varying
    /// from strike to strike, 0.35 of the first (a bell's ring, its room).
    fn typical_copies(n: usize, gain: f64) -> Vec<Option<Copy2>> {
        (0..n)
            .map(|k| {
                Some(Copy2 {
                    delay_s: 0.04 + 0.1 * ((k * 37 % 23) as f64 / 23.0),
                    gain,
                    ratio: 0.35,
                    quorum: 0.35,
                })
            })
            .collect()
    }

    fn copy(delay_s: f64, gain: f64, ratio: f64) -> Option<Copy2> {
        Some(Copy2 {
            delay_s,
            gain,
            ratio,
            quorum: ratio,
        })
    }

    /// A second blow at 0.55 of the first, 60 ms on, whose copy takes half
    /// the one-copy error away on a bell whose strikes are otherwise well
    /// fitted (their best copies take 0.15 away) is a double; before, 0.6
    /// was asked of every bell, and it was missed.
    #[test]
    fn a_double_that_takes_half_the_error_away_on_a_well_fitted_bell_is_one() {
        let opts = StrikeOptions::default();
        let mut copies = typical_copies(30, 0.15);
        copies[7] = copy(0.06, 0.5, 0.55);
        let calls = judge_bell(&copies, &opts);
        assert!(
            calls[7].is_some_and(|d| (d.delay_s - 0.06).abs() < 1e-9),
            "{:?}",
            calls[7]
        );
        assert_eq!(calls.iter().flatten().count(), 1, "{calls:?}");
    }

    /// On a bell whose every strike has a copy take 0.55 of its error away
    /// (a dark room's tail, a partial that beats), a copy taking 0.6 is
    /// that bell's sound, not a double; one taking 0.8 is a double.
    #[test]
    fn a_bell_whose_every_strike_has_a_copy_asks_more_of_a_double() {
        let opts = StrikeOptions::default();
        let mut copies = typical_copies(30, 0.55);
        for c in copies.iter_mut() {
            // Below the option's ratio in half the bands: none a double.
            *c = c.map(|c| Copy2 { quorum: 0.2, ..c });
        }
        copies[4] = copy(0.07, 0.6, 0.6);
        copies[20] = copy(0.09, 0.8, 0.6);
        let calls = judge_bell(&copies, &opts);
        assert_eq!(calls[4], None);
        assert!(calls[20].is_some(), "{calls:?}");
        assert_eq!(calls.iter().flatten().count(), 1, "{calls:?}");
    }

    /// Three strikes of a bell with a second copy at 60-63 ms are doubles
    /// (a clapper bouncing alike at every blow; session 21's first judge
    /// dropped doubles that recurred at one delay, and tester21's planted
    /// 67-71 ms doubles went from 6 to 2 found), as is a fourth at 85 ms.
    /// A copy 5 ms after the strike as timed (fitted from a start slid
    /// earlier) or 20 ms on at 0.9 (no listener hears it, eq. 33) is none.
    #[test]
    fn doubles_of_a_bell_at_one_delay_are_doubles_all() {
        let opts = StrikeOptions::default();
        let mut copies = typical_copies(40, 0.15);
        copies[3] = copy(0.060, 0.8, 0.6);
        copies[11] = copy(0.062, 0.8, 0.6);
        copies[25] = copy(0.063, 0.8, 0.6);
        copies[30] = copy(0.085, 0.8, 0.6);
        copies[33] = copy(0.005, 0.8, 0.6);
        copies[36] = copy(0.020, 0.8, 0.9);
        let calls = judge_bell(&copies, &opts);
        let called: Vec<usize> = (0..calls.len()).filter(|&k| calls[k].is_some()).collect();
        assert_eq!(called, vec![3, 11, 25, 30], "{calls:?}");
    }
}
