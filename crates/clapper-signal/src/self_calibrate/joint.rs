//! Each bell's strike fitted jointly with the others' (docs/strikes.md,
//! "`--nominals` timed from the recording's own strikes").

use super::line_up::line_up;
use super::{AFTER_S, BEFORE_S, FEWEST, SHIFT_S};
use crate::strikes::Heard;
use crate::Signal;

/// Each bell's strike estimated jointly: the recording taken as the sum of
/// every bell's strike (a kernel from [`BEFORE_S`] before its time heard
/// to [`JOINT_AFTER_S`] after) placed at each of its strikes, fitted by
/// least squares (block coordinate descent over the bells). In rounds a
/// bell always follows the same bell at nearly the same interval, so in
/// its plain average that bell's ringing does not average away: it lies
/// under the bell's own start as a fixed feature. Fitted jointly, each
/// bell's kernel holds its own sound only, and the recording with the
/// other bells' fitted strikes taken out is what its start is sought in.
pub(super) struct Joint {
    /// Each bell's kernel (none where it has too few clean strikes).
    pub(super) kernels: Vec<Option<Vec<f64>>>,
    /// Where each bell's kernels are placed (samples, the kernel's first).
    at: Vec<Vec<usize>>,
    /// The sum of every placed kernel.
    model: Vec<f64>,
    /// How far before a strike's time heard its bell's kernel starts, a
    /// strike not clean placed so (samples, by the median lag).
    pub(super) offset: Vec<usize>,
}

/// The joint fit's kernels run this long after a strike's time heard (s):
/// in rounds of eight the bell two places before rings on under a bell's
/// start from some 450 ms after its own.
const JOINT_AFTER_S: f64 = 1.0;
/// Sweeps over the bells in the joint fit.
const SWEEPS: usize = 4;

impl Joint {
    /// The joint fit of the strikes `heard` in `sig`, each bell's kernel
    /// learned from its clean strikes `cleans[bell - 1]` (times heard, s)
    /// lined up as [`line_up`] lines them; a strike not clean is placed at
    /// its time heard moved by its bell's median lag. None if no bell has
    /// [`FEWEST`] clean strikes.
    pub(super) fn estimate(sig: &Signal, heard: &Heard, cleans: &[Vec<f64>]) -> Option<Joint> {
        let rate = sig.rate;
        let (before, after) = ((BEFORE_S * rate).round() as usize, (AFTER_S * rate).round() as usize);
        let shift = (SHIFT_S * rate).round() as usize;
        let len = before + (JOINT_AFTER_S * rate).round() as usize;
        let n = sig.samples.len();
        let mut at = vec![vec![]; cleans.len()];
        let mut offset = vec![0; cleans.len()];
        let mut clean_at = vec![vec![]; cleans.len()];
        for (k, times) in cleans.iter().enumerate() {
            if times.len() < FEWEST {
                continue;
            }
            let starts: Vec<usize> = times
                .iter()
                .map(|t| (t * rate).round() as usize - before - shift)
                .collect();
            let (_, lags) = line_up(sig, &starts, before, after)?;
            let mut sorted = lags.clone();
            sorted.sort_unstable();
            let median = sorted[sorted.len() / 2];
            offset[k] = (before + shift).saturating_sub(median);
            clean_at[k] = starts
                .iter()
                .zip(&lags)
                .map(|(&s, &l)| s + l)
                .filter(|&o| o + len <= n)
                .collect();
            at[k] = heard
                .strikes
                .iter()
                .filter(|s| s.bell == k + 1)
                .filter_map(|s| {
                    // A clean strike where it was lined up, another by the median lag.
                    let o = match times.iter().position(|&t| t == s.t) {
                        Some(i) => starts[i] + lags[i],
                        None => ((s.t * rate).round() as usize).checked_sub(before + shift)? + median,
                    };
                    (o + len <= n).then_some(o)
                })
                .collect();
        }
        if clean_at.iter().all(|c| c.len() < FEWEST) {
            return None;
        }
        let mut model = vec![0.0; n];
        let mut kernels: Vec<Option<Vec<f64>>> = vec![None; cleans.len()];
        for _ in 0..SWEEPS {
            for k in 0..cleans.len() {
                if clean_at[k].len() < FEWEST {
                    continue;
                }
                if let Some(h) = &kernels[k] {
                    for &o in &at[k] {
                        model[o..o + len].iter_mut().zip(h).for_each(|(m, v)| *m -= v);
                    }
                }
                let mut h = vec![0.0; len];
                for &o in &clean_at[k] {
                    for ((hv, x), m) in h.iter_mut().zip(&sig.samples[o..o + len]).zip(&model[o..o + len]) {
                        *hv += x - m;
                    }
                }
                let c = clean_at[k].len() as f64;
                h.iter_mut().for_each(|v| *v /= c);
                for &o in &at[k] {
                    model[o..o + len].iter_mut().zip(&h).for_each(|(m, v)| *m += v);
                }
                kernels[k] = Some(h);
            }
        }
        Some(Joint {
            kernels,
            at,
            model,
            offset,
        })
    }

    /// The recording `sig` with every bell's fitted strikes but `bell`'s
    /// taken out; none if that bell has no kernel.
    pub(super) fn others_out(&self, sig: &Signal, bell: usize) -> Option<Signal> {
        let h = self.kernels.get(bell - 1)?.as_ref()?;
        let mut samples: Vec<f64> = sig.samples.iter().zip(&self.model).map(|(x, m)| x - m).collect();
        for &o in &self.at[bell - 1] {
            samples[o..o + h.len()].iter_mut().zip(h).for_each(|(s, v)| *s += v);
        }
        Some(Signal {
            rate: sig.rate,
            samples,
        })
    }
}
