//! The contact detector (the paper's Figs 2 and 5): a two-level signal,
//! one level in contact and the other out of it. Transitions are found
//! with hysteresis, and out-of-contact gaps shorter than a minimum are
//! merged, against the "fuzzy" lift-off the paper describes.

use crate::{Signal, SignalError};

/// Options of [`detect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOptions {
    /// The lower level means "in contact" (the paper's circuit). Default true.
    pub contact_is_low: bool,
    /// Gaps out of contact shorter than this (s) are noise, not flights.
    /// Default 1 ms: the paper's contacts last 0.2 to 0.5 ms, and the flights
    /// of a bouncing clapper are longer than that until it comes to rest.
    pub min_gap_s: f64,
    /// A contact longer than this (s) is the clapper at rest. Default 50 ms.
    pub rest_s: f64,
}

impl Default for ContactOptions {
    fn default() -> Self {
        Self {
            contact_is_low: true,
            min_gap_s: 1e-3,
            rest_s: 0.05,
        }
    }
}

/// What the contact detector says.
#[derive(Clone, Debug, PartialEq)]
pub struct Contacts {
    /// Sample rate (Hz).
    pub rate: f64,
    /// Contacts as sample ranges: first sample in contact, first sample out
    /// again (or the signal's length if still in contact).
    pub intervals: Vec<(usize, usize)>,
    /// Index in `intervals` of the contact where the clapper came to rest
    /// after striking.
    pub rest: Option<usize>,
    /// Whether the recording starts with the clapper resting (a whole
    /// stroke: rest, lift-off, strike, bounces, rest): that first contact
    /// is where it lifts off from, not where it comes to rest.
    pub starts_at_rest: bool,
}

impl Contacts {
    /// Time (s) of sample `i`.
    pub fn time(&self, i: usize) -> f64 {
        i as f64 / self.rate
    }

    /// Index of the first contact of the strike (after a starting rest).
    fn first_strike(&self) -> usize {
        usize::from(self.starts_at_rest)
    }

    /// Time from the strike (the first contact after any starting rest)
    /// until the clapper came to rest (s).
    pub fn time_to_rest(&self) -> Option<f64> {
        let first = self.intervals.get(self.first_strike())?;
        Some(self.time(self.intervals[self.rest?].0 - first.0))
    }

    /// When the resting clapper lifted off (s), if it did: from the rest
    /// the recording starts with, else from the rest after the strike.
    pub fn liftoff(&self, len: usize) -> Option<f64> {
        let k = if self.starts_at_rest { 0 } else { self.rest? };
        let (_, end) = self.intervals[k];
        (end < len).then(|| self.time(end))
    }

    /// The bounces: contacts from the strike until rest (or all).
    pub fn bounces(&self) -> &[(usize, usize)] {
        let from = self.first_strike().min(self.intervals.len());
        match self.rest {
            Some(r) => &self.intervals[from..r],
            None => &self.intervals[from..],
        }
    }
}

fn percentile(v: &[f64], p: f64) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[((s.len() - 1) as f64 * p).round() as usize]
}

/// Detect contacts in a two-level signal.
pub fn detect(sig: &Signal, opts: &ContactOptions) -> Result<Contacts, SignalError> {
    sig.validate()?;
    let lo = percentile(&sig.samples, 0.02);
    let hi = percentile(&sig.samples, 0.98);
    let span = hi - lo;
    if span.is_nan() || span <= 1e-9 * (lo.abs() + hi.abs()).max(1e-12) {
        return Err(SignalError::Invalid(
            "the signal has one level only: not a contact signal".into(),
        ));
    }
    // Hysteresis: enter contact past 30 % of the span from the contact level, leave past 70 %.
    let x = |v: f64| {
        if opts.contact_is_low {
            (v - lo) / span
        } else {
            (hi - v) / span
        }
    };
    let mut in_contact = x(sig.samples[0]) < 0.5;
    let mut raw: Vec<(usize, usize)> = vec![];
    let mut start = 0;
    for (i, &v) in sig.samples.iter().enumerate() {
        let u = x(v);
        if in_contact && u > 0.7 {
            raw.push((start, i));
            in_contact = false;
        } else if !in_contact && u < 0.3 {
            start = i;
            in_contact = true;
        }
    }
    if in_contact {
        raw.push((start, sig.samples.len()));
    }
    // A contact that starts the signal is not a detected transition unless it ends.
    let min_gap = (opts.min_gap_s * sig.rate).round() as usize;
    let mut merged: Vec<(usize, usize)> = vec![];
    for c in raw {
        match merged.last_mut() {
            Some(last) if c.0 - last.1 < min_gap => last.1 = c.1,
            _ => merged.push(c),
        }
    }
    let rest_len = (opts.rest_s * sig.rate).round() as usize;
    let long = |&(a, b): &(usize, usize)| b - a >= rest_len;
    // A long contact from the first sample, with more after it, is the
    // rest the stroke started from.
    let starts_at_rest = merged.len() > 1 && merged[0].0 == 0 && long(&merged[0]);
    let rest = merged
        .iter()
        .enumerate()
        .skip(usize::from(starts_at_rest))
        .find(|(_, c)| long(c))
        .map(|(k, _)| k);
    Ok(Contacts {
        rate: sig.rate,
        intervals: merged,
        rest,
        starts_at_rest,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_whole_stroke_lifts_off_from_its_starting_rest_and_comes_to_rest_after_bouncing() {
        let rate = 1000.0;
        // Resting to 200, lift-off; strike at 500, two bounces, rest from 620.
        let contacts = [(0, 200), (500, 502), (560, 563), (600, 602), (620, 1000)];
        let samples = (0..1000)
            .map(|i| {
                if contacts.iter().any(|&(a, b)| i >= a && i < b) {
                    0.0
                } else {
                    1.0
                }
            })
            .collect();
        let c = detect(&Signal { rate, samples }, &ContactOptions::default()).unwrap();
        assert!(c.starts_at_rest);
        assert_eq!(c.rest, Some(4));
        assert_eq!(c.bounces().len(), 3);
        assert!((c.liftoff(1000).unwrap() - 0.2).abs() < 1e-12);
        assert!((c.time_to_rest().unwrap() - 0.12).abs() < 1e-12);
    }

    use super::*;

    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

    fn uniform(rng: &mut Pcg64) -> f64 {
        rng.random_range(-1.0..1.0)
    }

    /// A bounce sequence with known transitions, noise, and a fuzzy lift-off.
    #[test]
    fn contact_times_within_one_sample() {
        let rate = 20000.0;
        let n = 30000;
        let truth: Vec<(usize, usize)> = vec![(2000, 2008), (4000, 4006), (5200, 5205), (5800, 5804), (6100, 24000)];
        let mut seed = Pcg64::seed_from_u64(3);
        let samples: Vec<f64> = (0..n)
            .map(|i| {
                let inside = truth.iter().any(|&(a, b)| i >= a && i < b);
                // Fuzzy lift-off: brief spikes out of contact just before 24000.
                let fuzz = (23900..24000).contains(&i) && i % 17 == 0;
                let level = if inside && !fuzz { 0.0 } else { 5.0 };
                level + 0.3 * uniform(&mut seed)
            })
            .collect();
        let c = detect(&Signal { rate, samples }, &ContactOptions::default()).unwrap();
        assert_eq!(c.intervals.len(), truth.len(), "{:?}", c.intervals);
        for (got, want) in c.intervals.iter().zip(&truth) {
            assert!(
                got.0.abs_diff(want.0) <= 1 && got.1.abs_diff(want.1) <= 1,
                "{got:?} vs {want:?}"
            );
        }
        assert_eq!(c.rest, Some(4));
        assert_eq!(c.bounces().len(), 4);
        assert!((c.time_to_rest().unwrap() - (6100.0 - 2000.0) / rate).abs() <= 1.0 / rate);
        assert!((c.liftoff(n).unwrap() - 24000.0 / rate).abs() <= 1.0 / rate);
    }

    #[test]
    fn a_flat_signal_is_refused() {
        let s = Signal {
            rate: 100.0,
            samples: vec![1.0; 500],
        };
        assert!(detect(&s, &ContactOptions::default()).is_err());
    }
}
