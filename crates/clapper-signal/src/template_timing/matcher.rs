//! Each bell's template at the recording's rate, and its match against
//! the recording (a normalised cross-correlation by FFT), and its whole
//! sound (for double strikes, [`super::doubles`], and to take a strike
//! heard out of the recording).

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use std::sync::Arc;

use crate::sampled_ring::sample_onset;
use crate::{Signal, SignalError};

/// The length of template matched (s).
pub(super) const MATCH_S: f64 = 0.15;
/// And the silence matched before it (s).
pub(super) const PRE_S: f64 = 0.04;
/// The widest stretch of lags one transform covers (s).
pub(super) const SPAN_S: f64 = 0.3;

/// How long a strike's blow lasts (s): its click, left out where the
/// template's partials are weighed ([`Matcher::order_for`]).
const BLOW_S: f64 = 0.02;
/// The frequency (Hz) above which a template's partials must carry
/// [`HIGH_SHARE`] of its sound to be matched by the third difference
/// (tmpl-11): the recorded tower bells d1-d12 carry 3-17 % of their sound
/// past the blow above it, the synthetic test bells of 700 and 1000 Hz
/// at 16 kHz (partials to three times the prime) none, and matched by the
/// third difference those rested on their blow's click and were matched
/// off (`a_bell_in_a_room_with_a_darker_tail_matches_at_its_direct_sound`
/// and `a_bell_heard_far_later_than_its_lateness_is_timed_at_its_sound`
/// fail with every template taken by the third).
const CORNER_HZ: f64 = 3000.0;
/// That share.
const HIGH_SHARE: f64 = 0.01;

/// Linear resampling of `s` to `rate` (Hz): templates recorded at another
/// rate than the recording.
fn resample(s: &Signal, rate: f64) -> Signal {
    if (s.rate - rate).abs() < 1e-9 {
        return s.clone();
    }
    let n = (s.samples.len() as f64 * rate / s.rate).floor() as usize;
    let samples = (0..n)
        .map(|k| {
            let x = k as f64 * s.rate / rate;
            let i = x.floor() as usize;
            let f = x - i as f64;
            let a = s.samples[i.min(s.samples.len() - 1)];
            let b = s.samples[(i + 1).min(s.samples.len() - 1)];
            a + f * (b - a)
        })
        .collect();
    Signal { rate, samples }
}

/// One bell's template, ready to match.
pub(super) struct Template {
    /// The conjugated spectrum of `pre` samples of silence and the first
    /// `len - pre` of the template's sound, as recorded (`[0]`) and
    /// weighted toward its upper partials (`[1]`: times the power of the
    /// difference of [`Self::order`], [`heard`]), against the recording as
    /// recorded.
    pub specs: [Vec<Complex<f64>>; 2],
    /// The energy of the part matched, as recorded and as weighted.
    pub energies: [f64; 2],
    /// Whether it is matched weighted ([`super::weight`]); as recorded
    /// until chosen.
    pub weighted: bool,
    /// The difference taken where it is matched weighted ([`heard`]: 2 or
    /// 3, by [`Matcher::order_for`]).
    pub order: u32,
    /// The template's whole sound, from its onset.
    pub sound: Vec<f64>,
    /// The sign its strikes match the recording with (+1 or -1), where
    /// known: a match of the other sign is then no match (0). 0 while not
    /// known: the match by magnitude ([`Matcher::normalised`]).
    pub polarity: f64,
}

impl Template {
    /// The spectrum matched ([`Self::specs`], as [`Self::weighted`] says).
    pub fn spec(&self) -> &[Complex<f64>] {
        &self.specs[usize::from(self.weighted)]
    }

    /// The energy matched.
    pub fn energy(&self) -> f64 {
        self.energies[usize::from(self.weighted)]
    }

    /// The difference the recording is matched by: [`Self::order`] where
    /// weighted, else 0 (as recorded).
    pub fn level_order(&self) -> u32 {
        if self.weighted {
            self.order
        } else {
            0
        }
    }
}

/// The templates and the transforms, at the recording's rate.
pub(super) struct Matcher {
    pub rate: f64,
    /// Silence matched before the template's sound (samples).
    pub pre: usize,
    /// Length matched (samples, `pre` included).
    pub len: usize,
    /// Transform length.
    pub n: usize,
    fwd: Arc<dyn RealToComplex<f64>>,
    inv: Arc<dyn ComplexToReal<f64>>,
    /// Each bell's template; none if it is too short.
    pub bells: Vec<Option<Template>>,
}

/// The buffers one match works in.
pub(super) struct Scratch {
    buf: Vec<f64>,
    /// A spectrum ([`Matcher::spectrum`]).
    pub spec: Vec<Complex<f64>>,
    /// The correlation at lags 0.. from the start asked.
    pub out: Vec<f64>,
    /// A whole recording's match, kept from one bell's to the next
    /// ([`super::fill`]): not allocated (and its pages not zeroed) anew
    /// for each.
    pub whole: (Vec<f64>, Vec<f64>),
    /// The last recording's spectrum, while [`Matcher::keeping`] asks for
    /// it: which recording (where its samples lie, and how many) and from
    /// which sample, and the spectrum.
    kept: Option<Kept>,
    /// The recording's level at a stretch of samples ([`levels`]).
    levels: Vec<f64>,
    /// The transforms' own working space, kept from one to the next
    /// (each `process` made and zeroed its own: speed-6; the same
    /// numbers, the space being only written before it is read).
    fft: Vec<Complex<f64>>,
}

impl Scratch {
    /// `f` run with each transform of the recording `x` kept
    /// ([`Matcher::spectrum`]): a match of another template, or of one
    /// weighted otherwise, from the same sample takes its spectrum again
    /// rather than transforming it anew (the same numbers). `x` is held
    /// borrowed throughout, so it cannot change under the spectrum kept;
    /// nothing is kept once `f` returns (nor where it fails).
    pub fn keeping<T>(
        &mut self,
        x: &[f64],
        f: impl FnOnce(&mut Scratch) -> Result<T, SignalError>,
    ) -> Result<T, SignalError> {
        self.kept = Some(Kept {
            x: (x.as_ptr() as usize, x.len()),
            start: i64::MIN,
            spec: vec![],
        });
        let r = f(self);
        self.kept = None;
        r
    }
}

/// A spectrum kept ([`Scratch::kept`]).
struct Kept {
    /// The recording's samples' address and count: the same recording,
    /// not changed, while kept ([`Matcher::keeping`] holds it borrowed).
    x: (usize, usize),
    start: i64,
    spec: Vec<Complex<f64>>,
}

impl Matcher {
    pub fn new(rate: f64, templates: &[Signal]) -> Result<Self, SignalError> {
        let pre = (PRE_S * rate).round() as usize;
        let len = (MATCH_S * rate).round() as usize + pre;
        let lags = (SPAN_S * rate).round() as usize;
        let n = (len + lags + 1).next_power_of_two();
        let mut planner = RealFftPlanner::<f64>::new();
        let fwd = planner.plan_fft_forward(n);
        let inv = planner.plan_fft_inverse(n);
        let mut m = Matcher {
            rate,
            pre,
            len,
            n,
            fwd,
            inv,
            bells: vec![],
        };
        for t in templates {
            let t = resample(t, rate);
            let o = (sample_onset(&t)? * rate).round() as usize;
            let b = (t.samples.len() >= o + len - pre)
                .then(|| m.template(&t.samples[o..]))
                .transpose()?;
            m.bells.push(b);
        }
        Ok(m)
    }

    /// A template from its sound (from its onset).
    fn template(&self, sound: &[f64]) -> Result<Template, SignalError> {
        let (pre, len) = (self.pre, self.len);
        // The template from `pre` before its sound starts (silence: a lag
        // where the bell already sounds there matches worse).
        let mut buf = self.fwd.make_input_vec();
        buf[pre..len].copy_from_slice(&sound[..len - pre]);
        let energy = buf.iter().map(|v| v * v).sum();
        let mut spec = self.fwd.make_output_vec();
        let order = self.order_for(sound, &mut spec)?;
        // Weighted: the difference's energy, and its power on the
        // spectrum (the recording's own spectrum is taken as recorded).
        let weighted_energy = (0..buf.len() as i64).map(|j| heard(&buf, j, order).powi(2)).sum();
        self.fwd
            .process(&mut buf, &mut spec)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let plain: Vec<Complex<f64>> = spec.into_iter().map(|c| c.conj()).collect();
        let step = std::f64::consts::TAU / self.n as f64;
        let weighted = plain
            .iter()
            .enumerate()
            .map(|(k, c)| c * (2.0 - 2.0 * (step * k as f64).cos()).powi(order as i32))
            .collect();
        Ok(Template {
            specs: [plain, weighted],
            energies: [energy, weighted_energy],
            weighted: false,
            order,
            sound: sound.to_vec(),
            polarity: 0.0,
        })
    }

    /// The difference a template of `sound` (from its onset) is matched
    /// weighted by (`spec` a spectrum's buffer): the third where its sound
    /// past the blow carries [`HIGH_SHARE`] of its energy above
    /// [`CORNER_HZ`], else the second.
    fn order_for(&self, sound: &[f64], spec: &mut [Complex<f64>]) -> Result<u32, SignalError> {
        let mut buf = self.fwd.make_input_vec();
        let from = ((BLOW_S * self.rate).round() as usize).min(sound.len());
        let to = (self.len - self.pre).min(sound.len()).max(from);
        buf[..to - from].copy_from_slice(&sound[from..to]);
        self.fwd
            .process(&mut buf, spec)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let bin = self.rate / self.n as f64;
        let (mut high, mut all) = (0.0, 0.0);
        for (k, c) in spec.iter().enumerate() {
            let e = c.norm_sqr();
            all += e;
            if k as f64 * bin > CORNER_HZ {
                high += e;
            }
        }
        Ok(if all > 0.0 && high >= HIGH_SHARE * all { 3 } else { 2 })
    }

    pub fn scratch(&self) -> Scratch {
        Scratch {
            buf: self.fwd.make_input_vec(),
            spec: self.fwd.make_output_vec(),
            out: self.inv.make_output_vec(),
            whole: (vec![], vec![]),
            kept: None,
            levels: vec![],
            fft: vec![Complex::new(0.0, 0.0); self.fwd.get_scratch_len().max(self.inv.get_scratch_len())],
        }
    }

    /// The most lags one call covers.
    pub fn span(&self) -> usize {
        self.n - self.len - 1
    }

    /// `sc.out[k]`: the recording `x` from sample `start + k` against
    /// template `t` (its sound from `start + k + pre`), for k up to
    /// [`Self::span`]; raw (not normalised). (The match is normalised
    /// by [`Self::normalised`]; this is its test's.)
    #[cfg(test)]
    pub fn correlate(&self, x: &[f64], t: &Template, start: i64, sc: &mut Scratch) -> Result<(), SignalError> {
        self.spectrum(x, start, sc)?;
        self.times_template(t, sc)
    }

    /// `sc.spec`: the spectrum of the recording `x` from sample `start`,
    /// as [`Self::correlate`] takes it.
    pub fn spectrum(&self, x: &[f64], start: i64, sc: &mut Scratch) -> Result<(), SignalError> {
        self.spectrum_times(x, start, None, sc)
    }

    /// [`Self::spectrum`], times template `t`'s spectrum where one is
    /// given (the product [`Self::normalised`] transforms back). A
    /// spectrum kept ([`Scratch::keeping`]) is transformed into its keep
    /// and read there, not copied there and back (speed-9: two copies of
    /// the spectrum at each match of the weighting's vote); each bin the
    /// same product, `a * b` and `a *= b` being the same operations.
    fn spectrum_times(&self, x: &[f64], start: i64, t: Option<&Template>, sc: &mut Scratch) -> Result<(), SignalError> {
        let key = (x.as_ptr() as usize, x.len());
        let keep = sc.kept.as_ref().is_some_and(|k| k.x == key);
        if !keep || sc.kept.as_ref().is_some_and(|k| k.start != start) {
            // Copied straight from the recording where the transform lies
            // inside it (speed-8: through `sc.levels` it was copied twice).
            match inside(x, start, sc.buf.len()) {
                Some(s) => sc.buf.copy_from_slice(s),
                None => {
                    levels(x, start, sc.buf.len(), 0, &mut sc.levels);
                    sc.buf.copy_from_slice(&sc.levels);
                }
            }
            let into = match sc.kept.as_mut().filter(|_| keep) {
                Some(k) => {
                    k.start = start;
                    k.spec.resize(sc.spec.len(), Complex::new(0.0, 0.0));
                    &mut k.spec
                }
                None => &mut sc.spec,
            };
            self.fwd
                .process_with_scratch(&mut sc.buf, into, &mut sc.fft)
                .map_err(|e| SignalError::Invalid(e.to_string()))?;
        }
        match (sc.kept.as_ref().filter(|_| keep), t) {
            (Some(k), Some(t)) => {
                for ((d, a), b) in sc.spec.iter_mut().zip(&k.spec).zip(t.spec()) {
                    *d = a * b;
                }
            }
            (Some(k), None) => sc.spec.copy_from_slice(&k.spec),
            (None, Some(t)) => {
                for (a, b) in sc.spec.iter_mut().zip(t.spec()) {
                    *a *= b;
                }
            }
            (None, None) => {}
        }
        Ok(())
    }

    /// [`Self::correlate`] from the recording's spectrum `spec` there
    /// ([`Self::spectrum`]), found once for every bell.
    pub fn correlate_spectrum(&self, spec: &[Complex<f64>], t: &Template, sc: &mut Scratch) -> Result<(), SignalError> {
        for ((d, a), b) in sc.spec.iter_mut().zip(spec).zip(t.spec()) {
            *d = a * b;
        }
        self.back(sc)
    }

    /// `sc.out` from the recording's spectrum in `sc.spec`: times the
    /// template's, back to lags.
    #[cfg(test)]
    fn times_template(&self, t: &Template, sc: &mut Scratch) -> Result<(), SignalError> {
        for (a, b) in sc.spec.iter_mut().zip(t.spec()) {
            *a *= b;
        }
        self.back(sc)
    }

    /// `sc.out` from the product of spectra in `sc.spec`, back to lags.
    fn back(&self, sc: &mut Scratch) -> Result<(), SignalError> {
        let scale = self.back_unscaled(sc)?;
        for o in &mut sc.out {
            *o *= scale;
        }
        Ok(())
    }

    /// [`Self::back`] without its last step, each lag times the scale
    /// returned (1/n): [`Self::normalised`] takes that step only at the
    /// lags it keeps.
    fn back_unscaled(&self, sc: &mut Scratch) -> Result<f64, SignalError> {
        sc.spec[0].im = 0.0;
        if let Some(l) = sc.spec.last_mut() {
            l.im = 0.0;
        }
        self.inv
            .process_with_scratch(&mut sc.spec, &mut sc.out, &mut sc.fft)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        Ok(1.0 / self.n as f64)
    }

    /// [`Self::correlate`] over the recording's level in each lag's
    /// window, for `lags + 1` lags (a normalised match: unnormalised, a
    /// lag where the bell has grown louder matches better than the lag
    /// where its sound starts). Silence matches 0; with its template's
    /// [`Template::polarity`] known, so does a match of the other sign: a bell whose sound is
    /// nearly one or two partials matches half a period off, the sign
    /// turned, nearly as well as at its strike (the recorded d4, 730 and
    /// 858 Hz, 15.9 ms late at 13 of 24 strikes in a room). `sc.out`
    /// past `lags` is left as the inverse transform leaves it (unscaled).
    pub fn normalised(
        &self,
        x: &[f64],
        t: &Template,
        start: i64,
        lags: usize,
        sc: &mut Scratch,
    ) -> Result<(), SignalError> {
        self.spectrum_times(x, start, Some(t), sc)?;
        let scale = self.back_unscaled(sc)?;
        let len = self.len;
        let lags = lags.min(self.span());
        // The recording's level at each sample the lags reach: as
        // recorded, read where it lies (inside the recording; `at` gives
        // the same numbers), else found once.
        let count = lags + len + 1;
        let lv = match inside(x, start, count) {
            Some(s) if !t.weighted => s,
            _ => {
                levels(x, start, count, t.level_order(), &mut sc.levels);
                &sc.levels[..]
            }
        };
        let e: f64 = lv[..len].iter().map(|v| v.powi(2)).sum();
        let shape = Shape {
            scale,
            norm: t.energy().sqrt(),
            polarity: t.polarity,
        };
        normalise(&mut sc.out[..=lags], lv, len, e, &shape);
        Ok(())
    }

    /// Take `gain` times bell `t`'s whole sound out of `x`, its onset at
    /// `onset` (s).
    pub fn subtract(&self, x: &mut [f64], t: &Template, onset: f64, gain: f64) {
        let start = onset * self.rate;
        let i0 = start.floor();
        let frac = start - i0;
        let n = x.len() as i64;
        let (s, len) = (&t.sound, t.sound.len() as i64);
        if i0 as i64 >= 0 && (i0 as i64).saturating_add(len) < n && len > 0 {
            // Inside `x`: each sample takes its two shares in the same
            // order as below (the earlier sample's first), side by side.
            let (a, b, base) = (1.0 - frac, frac, i0 as usize);
            x[base] -= gain * a * s[0];
            for (k, xi) in x[base + 1..base + s.len()].iter_mut().enumerate() {
                *xi = *xi - gain * b * s[k] - gain * a * s[k + 1];
            }
            x[base + s.len()] -= gain * b * s[s.len() - 1];
            return;
        }
        for (k, v) in t.sound.iter().enumerate() {
            let j = i0 as i64 + k as i64;
            for (jj, w) in [(j, 1.0 - frac), (j + 1, frac)] {
                if jj >= 0 && jj < n {
                    x[jj as usize] -= gain * w * v;
                }
            }
        }
    }
}

/// How [`normalise`] turns a lag's raw correlation into its match.
struct Shape {
    /// The inverse transform's scale (1/n).
    scale: f64,
    /// The root of the template's energy.
    norm: f64,
    /// [`Template::polarity`].
    polarity: f64,
}

/// Lags [`normalise`] takes at a time.
const GROUP: usize = 8;

/// `out[k]` (raw correlations, at lags 0..) normalised in place: times
/// the scale, over the root of the recording's energy in the window of
/// `len` levels `lv` from lag `k` (`e` at lag 0, then each lag's gone
/// level's square taken off and the come one's put on, never below 0)
/// times the template's, 0 where that energy is at most 1e-300; with a
/// polarity, a match of the other sign 0.
///
/// The running energy is one chain of dependent additions, and its floor
/// at 0 (a `max`, with its care for NaN) lengthened each link by half
/// again (about 12 cycles a lag: speed-7). Here [`GROUP`] lags' energies
/// are run first without the floor, which changes nothing where every
/// one of them is at least +0 (the floor is then the identity), and their
/// divisions and roots are then taken side by side (the compiler puts
/// them in vectors: the same correctly rounded operations, lane by lane);
/// a group where one falls below +0 (rounding, where a loud stretch
/// leaves the window over silence), is NaN or -0, is run again lag by lag
/// with the floor, as [`normalise_each`].
fn normalise(out: &mut [f64], lv: &[f64], len: usize, mut e: f64, s: &Shape) {
    let mut k = 0;
    while k + GROUP <= out.len() {
        let mut es = [0.0; GROUP];
        let mut next = e;
        let mut plain = true;
        for (l, ek) in es.iter_mut().enumerate() {
            *ek = next;
            let (gone, come) = (lv[k + l], lv[k + l + len]);
            next = next - gone * gone + come * come;
            plain &= next >= 0.0 && next.is_sign_positive();
        }
        if !plain {
            e = normalise_each(&mut out[k..k + GROUP], &lv[k..], len, e, s);
            k += GROUP;
            continue;
        }
        let group: &mut [f64; GROUP] = (&mut out[k..k + GROUP]).try_into().expect("GROUP long");
        // Every lane's quotient made and the one wanted kept (no branch:
        // so the compiler puts the lanes in vectors).
        for (o, &ek) in group.iter_mut().zip(&es) {
            let q = *o * s.scale / (ek.sqrt() * s.norm);
            let v = if ek > 1e-300 { q } else { 0.0 };
            let turned = (s.polarity * v).max(0.0);
            *o = if s.polarity == 0.0 { v } else { turned };
        }
        e = next;
        k += GROUP;
    }
    normalise_each(&mut out[k..], &lv[k..], len, e, s);
}

/// [`normalise`] lag by lag, the energy floored at 0 at every lag; the
/// energy after the last lag.
fn normalise_each(out: &mut [f64], lv: &[f64], len: usize, mut e: f64, s: &Shape) -> f64 {
    for (k, o) in out.iter_mut().enumerate() {
        let v = if e > 1e-300 {
            *o * s.scale / (e.sqrt() * s.norm)
        } else {
            0.0
        };
        *o = if s.polarity == 0.0 {
            v
        } else {
            (s.polarity * v).max(0.0)
        };
        let (gone, come) = (lv[k], lv[k + len]);
        e = (e - gone * gone + come * come).max(0.0);
    }
    e
}

/// `x[start..start + count]`, where that lies inside `x`.
fn inside(x: &[f64], start: i64, count: usize) -> Option<&[f64]> {
    let s = usize::try_from(start).ok()?;
    x.get(s..s.checked_add(count)?)
}

/// The recording `x` at sample `j` as it is matched by the difference of
/// `order` (0: as recorded; 2: `x[j] - 2 x[j-1] + x[j-2]`; 3: `x[j] -
/// 3 x[j-1] + 3 x[j-2] - x[j-3]`; 0 outside `x`), which weights the match
/// by the frequency to the power 2 `order` (the cross-spectrum is
/// weighted twice). A room's tail is darker than the direct sound (high
/// frequencies die first), so at a bell's low partials the reverberation
/// can be louder than the direct sound, and matched as recorded the tail's
/// partials came into step with the dry template 16-52 ms after the
/// strike (the tester's rings r2 and r4, a tail darkened by
/// y[n] = x[n] + 0.6 y[n-1] at 0 dB direct-to-reverberant: searched 150 ms
/// either side of the true time, 165 of 464 strikes matched over 10 ms
/// off; by the second difference 1; on r4 by the first difference 53 of
/// 272, against 97 as recorded and 0 by the second). The third (tmpl-10):
/// with the tail low-passed at 3 kHz and 2 dB louder than the direct
/// sound, the treble d1 (1967 Hz) matched 50-70 ms late at 13 of its
/// first 14 strikes by the second difference, at none by the third.
pub(super) fn heard(x: &[f64], j: i64, order: u32) -> f64 {
    match order {
        0 => at(x, j),
        2 => at(x, j) - 2.0 * at(x, j - 1) + at(x, j - 2),
        _ => at(x, j) - 3.0 * at(x, j - 1) + 3.0 * at(x, j - 2) - at(x, j - 3),
    }
}

/// The recording `x` at sample `j` as a double strike of a bell matched
/// weighted is judged ([`super::weight`]): its first
/// difference (0 outside `x`). The match's second difference there read a
/// second copy of the template out of the templates' own rooms (the
/// tester's templates re-recorded in another room: 4 -> 18 false doubles
/// on a six in rounds); as recorded, the dark tail's low partials made
/// second copies (own rings of a dark tail, seeds 1-4: 1-30 false
/// doubles); the first difference 0-1 on those, 3 on the six.
pub(super) fn sloped(x: &[f64], j: i64) -> f64 {
    at(x, j) - at(x, j - 1)
}

/// Into `out`, the recording `x` at `count` samples from `start` as
/// [`heard`] gives it by the difference of `order` (0: as recorded; the
/// same numbers, indexed directly where the stretch lies inside `x`).
pub(super) fn levels(x: &[f64], start: i64, count: usize, order: u32, out: &mut Vec<f64>) {
    out.clear();
    let inside = start >= 3 && start.saturating_add(count as i64) <= x.len() as i64;
    let s = start as usize;
    match (inside, order) {
        (true, 0) => out.extend_from_slice(&x[s..s + count]),
        (true, 2) => out.extend((s..s + count).map(|i| x[i] - 2.0 * x[i - 1] + x[i - 2])),
        (true, _) => out.extend((s..s + count).map(|i| x[i] - 3.0 * x[i - 1] + 3.0 * x[i - 2] - x[i - 3])),
        (false, o) => out.extend((0..count).map(|j| heard(x, start + j as i64, o))),
    }
}

/// `x[j]`, 0 outside it.
pub(super) fn at(x: &[f64], j: i64) -> f64 {
    if j >= 0 && (j as usize) < x.len() {
        x[j as usize]
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::{heard, levels, Matcher};
    use crate::template_timing::tests::slow_bell;

    /// A template whose partials lie below 3 kHz (the synthetic 700 and
    /// 1000 Hz bells, partials to three times the prime) is matched
    /// weighted by the second difference, one whose partials reach above
    /// it (1400 Hz: 3.8 and 4.2 kHz) by the third, at 16 and 44.1 kHz.
    #[test]
    fn a_template_is_weighted_by_the_third_difference_only_where_it_sounds_above_the_corner() {
        for rate in [16_000.0, 44_100.0] {
            let orders: Vec<u32> = [700.0, 1000.0, 1400.0]
                .iter()
                .map(|&f| {
                    Matcher::new(rate, &[slow_bell(rate, f, 0.03)]).unwrap().bells[0]
                        .as_ref()
                        .unwrap()
                        .order
                })
                .collect();
            assert_eq!(orders, [2, 2, 3], "at {rate} Hz");
        }
    }

    /// A strike's sound taken out side by side is taken out as sample by
    /// sample (the old loop), to the bit, inside the recording and over
    /// its edges.
    #[test]
    fn a_sound_taken_out_side_by_side_is_taken_out_sample_by_sample() {
        let rate = 8000.0;
        let m = Matcher::new(rate, &[slow_bell(rate, 900.0, 0.03)]).unwrap();
        let t = m.bells[0].as_ref().unwrap();
        let x0: Vec<f64> = (0..30_000).map(|k| ((k * 7919) % 263) as f64 / 263.0 - 0.5).collect();
        for onset in [-0.3, 0.0, 0.41237, 1.0, 2.2345, 3.6] {
            let mut x = x0.clone();
            m.subtract(&mut x, t, onset, 0.731);
            let mut y = x0.clone();
            let start = onset * rate;
            let (i0, n) = (start.floor(), y.len() as i64);
            let frac = start - i0;
            for (k, v) in t.sound.iter().enumerate() {
                let j = i0 as i64 + k as i64;
                for (jj, w) in [(j, 1.0 - frac), (j + 1, frac)] {
                    if jj >= 0 && jj < n {
                        y[jj as usize] -= 0.731 * w * v;
                    }
                }
            }
            assert!(
                x.iter().zip(&y).all(|(a, b)| a.to_bits() == b.to_bits()),
                "onset {onset}"
            );
            assert_ne!(x, x0);
        }
    }

    /// The normalised match reads the levels its transform read where it
    /// can (as recorded, the spectrum not kept): the same match, to the
    /// bit, as with the levels found again, with the spectrum transformed
    /// or kept, as recorded and weighted, over the recording's edges too.
    #[test]
    fn a_match_normalised_on_the_levels_its_transform_read_is_the_same() {
        let rate = 8000.0;
        let mut m = Matcher::new(rate, &[slow_bell(rate, 900.0, 0.03)]).unwrap();
        let x: Vec<f64> = (0..30_000).map(|k| ((k * 7919) % 263) as f64 / 263.0 - 0.5).collect();
        for weighted in [false, true] {
            m.bells[0].as_mut().unwrap().weighted = weighted;
            let t = m.bells[0].as_ref().unwrap();
            let mut sc = m.scratch();
            for (start, lags) in [(-500i64, 900usize), (0, m.span()), (4_000, 300), (29_000, 2_000)] {
                // As it was: correlated, then the levels found anew.
                m.correlate(&x, t, start, &mut sc).unwrap();
                let raw = sc.out.clone();
                let mut lv = vec![];
                levels(&x, start, lags + m.len + 1, t.level_order(), &mut lv);
                let mut e: f64 = lv[..m.len].iter().map(|v| v.powi(2)).sum();
                let norm = t.energy().sqrt();
                let mut want = vec![];
                for k in 0..=lags {
                    want.push(if e > 1e-300 { raw[k] / (e.sqrt() * norm) } else { 0.0 });
                    e = (e - lv[k] * lv[k] + lv[k + m.len] * lv[k + m.len]).max(0.0);
                }
                m.normalised(&x, t, start, lags, &mut sc).unwrap();
                let fresh = sc.out[..=lags].to_vec();
                let kept = sc
                    .keeping(&x, |sc| {
                        m.normalised(&x, t, start, lags, sc)?;
                        m.normalised(&x, t, start, lags, sc)?;
                        Ok(sc.out[..=lags].to_vec())
                    })
                    .unwrap();
                for got in [&fresh, &kept] {
                    assert!(
                        got.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()),
                        "weighted {weighted}, from {start}"
                    );
                }
                assert!(want.iter().any(|v| *v != 0.0));
            }
        }
    }

    /// Matches made while the recording's spectrum is kept, of two
    /// templates (one weighted) at starts that come back after another
    /// (the kept spectrum read in place, transformed into its keep anew
    /// where the start moves), are each the match made afresh, to the bit.
    #[test]
    fn matches_read_from_a_kept_spectrum_are_the_matches_made_afresh() {
        let rate = 8000.0;
        let mut m = Matcher::new(rate, &[slow_bell(rate, 900.0, 0.03), slow_bell(rate, 1300.0, 0.03)]).unwrap();
        m.bells[1].as_mut().unwrap().weighted = true;
        let x: Vec<f64> = (0..30_000).map(|k| ((k * 7919) % 263) as f64 / 263.0 - 0.5).collect();
        let asks = [
            (0, 4_000i64),
            (1, 4_000),
            (0, 9_000),
            (1, 4_000),
            (1, -200),
            (0, -200),
            (0, 4_000),
        ];
        let mut sc = m.scratch();
        let fresh: Vec<Vec<f64>> = asks
            .iter()
            .map(|&(b, start)| {
                m.normalised(&x, m.bells[b].as_ref().unwrap(), start, 700, &mut sc)
                    .unwrap();
                sc.out[..=700].to_vec()
            })
            .collect();
        let kept = sc
            .keeping(&x, |sc| {
                let mut got = vec![];
                for &(b, start) in &asks {
                    m.normalised(&x, m.bells[b].as_ref().unwrap(), start, 700, sc)?;
                    got.push(sc.out[..=700].to_vec());
                }
                Ok(got)
            })
            .unwrap();
        for (i, (a, b)) in fresh.iter().zip(&kept).enumerate() {
            assert!(a.iter().any(|v| *v != 0.0), "ask {i}");
            assert!(a.iter().zip(b).all(|(p, q)| p.to_bits() == q.to_bits()), "ask {i}");
        }
    }

    /// The levels found a stretch at a time are those found sample by
    /// sample, to the bit, inside the recording and across its edges.
    #[test]
    fn levels_a_stretch_at_a_time_are_levels_sample_by_sample() {
        let x: Vec<f64> = (0..300).map(|k| ((k * 7919) % 263) as f64 / 263.0 - 0.5).collect();
        let mut out = vec![];
        for order in [0, 2, 3] {
            for (start, count) in [
                (-5i64, 40usize),
                (0, 10),
                (1, 10),
                (2, 100),
                (150, 150),
                (250, 80),
                (299, 3),
            ] {
                levels(&x, start, count, order, &mut out);
                let direct: Vec<f64> = (0..count).map(|j| heard(&x, start + j as i64, order)).collect();
                assert_eq!(out.len(), count);
                for (a, b) in out.iter().zip(&direct) {
                    assert_eq!(a.to_bits(), b.to_bits(), "order {order}, from {start}");
                }
            }
        }
    }
}
