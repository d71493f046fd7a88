//! Whether a recording's channels agree in time (tester14 fault 12: a
//! stereo file whose right channel was 20 ms late was mixed to their mean
//! without a word, and each strike heard twice or between the two). Read
//! from each channel's onsets (the rises of its energy in 1 ms blocks)
//! over the recording's first two minutes; the same frames in the same
//! order give the same answer whether the file is read whole or streamed.
//! Where they disagree one channel is heard alone (tester16 fault 7: the
//! mix of r8/stlate found 0.86 of the strikes within 10 ms, its first
//! channel alone 0.99).

/// Which of a recording's channels are heard.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ChannelChoice {
    /// Mixed to one, unless they disagree in time, when one is heard alone
    /// (the one whose strikes stand clearest over its quiet, or the first).
    #[default]
    Auto,
    /// Mixed to one whatever their timing (their mean, or the loudest
    /// where the mean cancels).
    Mix,
    /// This channel alone (counted from 0).
    One(usize),
}

impl std::str::FromStr for ChannelChoice {
    type Err = String;

    /// `auto`, `mix`, or a channel's number counted from 1 (as the
    /// report's words count them); the error is one line.
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "auto" => Ok(ChannelChoice::Auto),
            "mix" => Ok(ChannelChoice::Mix),
            n => match n.parse::<usize>() {
                Ok(0) => Err("channel 0: channels count from 1 (1 the first, the left), or mix or auto".into()),
                Ok(k) => Ok(ChannelChoice::One(k - 1)),
                _ => Err(format!("channel '{n}': a channel's number (1 the first), mix or auto")),
            },
        }
    }
}

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
/// Blocks summed to judge a channel's clarity (10 ms: a strike's rise,
/// not each cycle's).
const CLARITY_BLOCKS: usize = 10;
/// How much wider (as a ratio) another channel's range of levels must be
/// than the first's to be heard instead of it: noise over the quiet between
/// strikes narrows it (white noise at 0 dB on r8/stlate's first channel:
/// 1.85 times narrower than the second's; at 10 dB 1.09).
const CLEANER: f64 = 1.25;

/// Channels found to disagree in time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Disagreement {
    /// The channel heard at a lag from the first (from 0).
    pub(crate) other: usize,
    /// Its lag behind the first (ms; below 0 ahead of it).
    pub(crate) lag_ms: f64,
    /// The channel to hear alone (from 0).
    pub(crate) keep: usize,
}

impl Disagreement {
    /// The report's words: the lag, and whether the channels were mixed as
    /// asked (`mixed`) or one heard alone.
    pub(crate) fn words(&self, mixed: bool) -> String {
        let how = if self.lag_ms > 0.0 { "later" } else { "earlier" };
        let head = format!(
            "the recording's channels disagree in time: channel {} is heard {:.0} ms {how} than channel 1",
            self.other + 1,
            self.lag_ms.abs()
        );
        if mixed {
            format!(
                "{head}, and their mix blurs every strike (strikes timed between the two, false doubles): \
                 record in mono, or keep one channel"
            )
        } else {
            format!(
                "{head}: channel {} used alone (their mix would blur every strike)",
                self.keep + 1
            )
        }
    }
}

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

    /// Whether the frames pushed are all those wanted (the rest of the
    /// file need not be read for this).
    pub(crate) fn full(&self) -> bool {
        self.energy.first().is_some_and(|e| e.len() >= self.most)
    }

    /// The first channel whose onsets come over [`DISAGREE_S`] after or
    /// before the first channel's, and the channel to hear alone.
    pub(crate) fn disagreement(&self) -> Option<Disagreement> {
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
                return Some(Disagreement {
                    other: c,
                    lag_ms: ms,
                    keep: self.cleanest(),
                });
            }
        }
        None
    }

    /// The channel whose levels range widest (strikes clearest over the
    /// quiet between them), if [`CLEANER`] times the first's; else the first.
    fn cleanest(&self) -> usize {
        let ranges: Vec<f64> = self.energy.iter().map(|e| level_range(e)).collect();
        let best = (1..ranges.len()).fold(0, |b, k| if ranges[k] > ranges[b] { k } else { b });
        if ranges[best] > CLEANER * ranges[0] {
            best
        } else {
            0
        }
    }
}

/// The range of a channel's log energy in 10 ms (its 99th percentile less
/// its 10th; 0 where it is silent).
fn level_range(e: &[f64]) -> f64 {
    let sums: Vec<f64> = e.chunks_exact(CLARITY_BLOCKS).map(|c| c.iter().sum()).collect();
    let mean = sums.iter().sum::<f64>() / sums.len().max(1) as f64;
    if mean.is_nan() || mean <= 0.0 {
        return 0.0;
    }
    let mut log: Vec<f64> = sums.iter().map(|x| (x + 1e-6 * mean).ln()).collect();
    log.sort_by(f64::total_cmp);
    let at = |q: f64| log[((q * (log.len() - 1) as f64).round() as usize).min(log.len() - 1)];
    at(0.99) - at(0.10)
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

/// How `nch` channels become one as `choice` asks, given their times:
/// `None` mixed, `Some(k)` channel `k` alone; and what the report should
/// be told in words. The error (one line) where the channel asked is not
/// in the file.
pub(crate) fn decide(
    choice: ChannelChoice,
    nch: usize,
    times: &ChannelTimes,
) -> Result<(Option<usize>, Vec<String>), String> {
    match choice {
        ChannelChoice::One(k) if k >= nch => {
            Err(format!("channel {} asked, the recording has {nch} (1 to {nch})", k + 1))
        }
        ChannelChoice::One(k) => Ok((Some(k), vec![])),
        _ if nch < 2 => Ok((None, vec![])),
        ChannelChoice::Mix => Ok((None, times.disagreement().map(|d| d.words(true)).into_iter().collect())),
        ChannelChoice::Auto => Ok(match times.disagreement() {
            Some(d) => (Some(d.keep), vec![d.words(false)]),
            None => (None, vec![]),
        }),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A decaying 900 Hz strike every 0.23 s (its pitch stepping so no two
    /// neighbours are alike), `t` s into the ring.
    pub(crate) fn strike(t: f64) -> f64 {
        let k = (t / 0.23).floor();
        let dt = t - 0.23 * k;
        if k < 0.0 {
            0.0
        } else {
            (-dt / 0.3).exp() * (2.0 * std::f64::consts::PI * (900.0 + 37.0 * (k % 7.0)) * dt).sin()
        }
    }

    /// Two channels of strikes, the second `late_s` later (0.7 times as
    /// loud) and the first with noise `noise` times its strikes' peak over
    /// it (a cheap deterministic hash for the noise): their times.
    fn times(late_s: f64, noise: f64) -> ChannelTimes {
        let rate = 8000.0;
        let mut c = ChannelTimes::new(2, rate);
        for i in 0..(20.0 * rate) as usize {
            let t = i as f64 / rate;
            let h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
            let n = noise * (h as f64 / (1u64 << 53) as f64 - 0.5);
            c.push(&[strike(t) + n, 0.7 * strike(t - late_s)]);
        }
        c
    }

    fn told(late_s: f64) -> Option<String> {
        times(late_s, 0.0).disagreement().map(|d| d.words(false))
    }

    #[test]
    fn a_channel_20_ms_late_is_told_and_channels_together_are_not() {
        let w = told(0.02).unwrap();
        assert!(w.contains("channel 2 is heard 20 ms later than channel 1"), "{w}");
        assert!(w.contains("channel 1 used alone"), "{w}");
        assert_eq!(told(0.0), None);
        assert_eq!(told(0.001), None);
    }

    /// Tester16 fault 7: channels that disagree are not mixed; the first
    /// is heard alone, or the other where the first is noisy; channels
    /// that agree, a mono file and a channel asked for are as before.
    #[test]
    fn one_channel_is_kept_where_they_disagree() {
        let late = times(0.02, 0.0);
        let (keep, words) = decide(ChannelChoice::Auto, 2, &late).unwrap();
        assert_eq!(keep, Some(0));
        assert!(words[0].ends_with("channel 1 used alone (their mix would blur every strike)"));
        let noisy = times(0.02, 2.0);
        assert_eq!(decide(ChannelChoice::Auto, 2, &noisy).unwrap().0, Some(1));
        let (keep, words) = decide(ChannelChoice::Mix, 2, &late).unwrap();
        assert_eq!(keep, None);
        assert!(words[0].ends_with("record in mono, or keep one channel"), "{words:?}");
        assert_eq!(
            decide(ChannelChoice::Auto, 2, &times(0.0, 0.0)).unwrap(),
            (None, vec![])
        );
        assert_eq!(decide(ChannelChoice::One(1), 2, &late).unwrap(), (Some(1), vec![]));
        let e = decide(ChannelChoice::One(2), 2, &late).unwrap_err();
        assert_eq!(e, "channel 3 asked, the recording has 2 (1 to 2)");
        assert_eq!("2".parse(), Ok(ChannelChoice::One(1)));
        assert_eq!(" mix".parse(), Ok(ChannelChoice::Mix));
        assert_eq!("auto".parse(), Ok(ChannelChoice::Auto));
        assert!("0".parse::<ChannelChoice>().unwrap_err().contains("count from 1"));
        assert!("left".parse::<ChannelChoice>().is_err());
        let mono = ChannelTimes::new(1, 8000.0);
        assert_eq!(decide(ChannelChoice::Auto, 1, &mono).unwrap(), (None, vec![]));
    }
}
