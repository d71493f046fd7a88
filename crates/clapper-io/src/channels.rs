//! Whether a recording's channels agree in time (tester14 fault 12: a
//! stereo file whose right channel was 20 ms late was mixed to their mean
//! without a word, and each strike heard twice or between the two). Read
//! from each channel's onsets (the rises of its energy in 1 ms blocks)
//! over the recording's first two minutes; the same frames in the same
//! order give the same answer whether the file is read whole or streamed.

/// Length of a block of the channels' energies (s).
const BLOCK_S: f64 = 0.001;
/// The longest lag between channels looked for (s).
const MAX_LAG_S: f64 = 0.05;
/// A lag from which the channels are said to disagree (s): more than a
/// stereo pair's spacing gives (5 ms is 1.7 m of air).
const DISAGREE_S: f64 = 0.005;
/// The stretch of the recording read (s): bounded memory however long it is.
const READ_S: f64 = 120.0;
/// How much better the onsets must line up at the lag than at none.
const CLEARER: f64 = 1.5;

/// Each channel's energy in blocks, fed frame by frame.
pub(crate) struct ChannelTimes {
    block: usize,
    most: usize,
    at: usize,
    sums: Vec<f64>,
    energy: Vec<Vec<f64>>,
}

impl ChannelTimes {
    /// For `nch` channels at `rate` (Hz).
    pub(crate) fn new(nch: usize, rate: f64) -> Self {
        ChannelTimes {
            block: ((BLOCK_S * rate).round() as usize).max(1),
            most: (READ_S / BLOCK_S) as usize,
            at: 0,
            sums: vec![0.0; nch],
            energy: vec![vec![]; nch],
        }
    }

    /// The next frame (one sample per channel).
    pub(crate) fn push(&mut self, frame: &[f64]) {
        if self.energy.first().is_some_and(|e| e.len() >= self.most) {
            return;
        }
        for (s, v) in self.sums.iter_mut().zip(frame) {
            *s += v * v;
        }
        self.at += 1;
        if self.at == self.block {
            for (e, s) in self.energy.iter_mut().zip(self.sums.iter_mut()) {
                e.push(*s);
                *s = 0.0;
            }
            self.at = 0;
        }
    }

    /// A warning where a channel's onsets come over [`DISAGREE_S`] after
    /// or before the first channel's.
    pub(crate) fn warning(&self) -> Option<String> {
        let first = onsets(self.energy.first()?)?;
        let max_lag = (MAX_LAG_S / BLOCK_S) as isize;
        for (c, e) in self.energy.iter().enumerate().skip(1) {
            let Some(other) = onsets(e) else {
                continue;
            };
            let at = |lag: isize| -> f64 {
                (0..first.len())
                    .filter_map(|k| Some(first[k] * other.get(usize::try_from(k as isize + lag).ok()?)?))
                    .sum()
            };
            let none = at(0);
            let (lag, best) = (-max_lag..=max_lag)
                .map(|l| (l, at(l)))
                .fold((0, none), |b, x| if x.1 > b.1 { x } else { b });
            let ms = lag as f64 * BLOCK_S * 1e3;
            if ms.abs() > DISAGREE_S * 1e3 && best > CLEARER * none {
                let how = if ms > 0.0 { "later" } else { "earlier" };
                return Some(format!(
                    "the recording's channels disagree in time: channel {} is heard {:.0} ms {how} than channel 1, \
                     and their mix blurs every strike (strikes timed between the two, false doubles): record in \
                     mono, or keep one channel",
                    c + 1,
                    ms.abs()
                ));
            }
        }
        None
    }
}

/// Each block's rise of the log energy `e` (0 where it falls), over a
/// floor a millionth of its mean; none where the channel is silent.
fn onsets(e: &[f64]) -> Option<Vec<f64>> {
    let mean = e.iter().sum::<f64>() / e.len().max(1) as f64;
    if mean.is_nan() || mean <= 0.0 {
        return None;
    }
    let floor = 1e-6 * mean;
    let log: Vec<f64> = e.iter().map(|x| (x + floor).ln()).collect();
    Some(
        std::iter::once(0.0)
            .chain(log.windows(2).map(|w| (w[1] - w[0]).max(0.0)))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two channels of decaying 900 Hz strikes every 0.23 s, the second
    /// `late_s` later; its warning.
    fn told(late_s: f64) -> Option<String> {
        let rate = 8000.0;
        let strike = |t: f64| -> f64 {
            let k = (t / 0.23).floor();
            let dt = t - 0.23 * k;
            if k < 0.0 {
                0.0
            } else {
                (-dt / 0.3).exp() * (2.0 * std::f64::consts::PI * (900.0 + 37.0 * (k % 7.0)) * dt).sin()
            }
        };
        let mut c = ChannelTimes::new(2, rate);
        for i in 0..(20.0 * rate) as usize {
            let t = i as f64 / rate;
            c.push(&[strike(t), 0.7 * strike(t - late_s)]);
        }
        c.warning()
    }

    #[test]
    fn a_channel_20_ms_late_is_told_and_channels_together_are_not() {
        let w = told(0.02).unwrap();
        assert!(w.contains("channel 2 is heard 20 ms later than channel 1"), "{w}");
        assert_eq!(told(0.0), None);
        assert_eq!(told(0.001), None);
    }
}
