//! A bell's motion read from a 3-axis accelerometer on its headstock
//! (`clapper ringing-log`, docs/model.md §13): the bell's angle swing by
//! swing, bottom dead centre, the clapper's strikes, the swing's amplitude,
//! odd-struckness, and the phases of a session (down, raising, up,
//! ringing, lowering).
//!
//! The method, in order:
//! 1. **Strikes** are bursts: the clapper's impact shakes the headstock
//!    far harder and faster than the swing, often past the sensor's range.
//!    A sample is a burst when it departs from the straight line through
//!    the two samples before it (a causal prediction, so that the sample
//!    before an impact is never blamed for it) by more than 6 robust
//!    standard deviations of that departure over the log (at least 1.5
//!    m/s²), or is clipped. A strike is the first burst sample.
//! 2. **The angle**: θ = atan2(tangential, radial) on the samples that
//!    are not bursts (interpolated across those that are), then corrected
//!    for the swing's own accelerations at the sensor,
//!    g sin θ = f_t + h θ'' + d θ'² and g cos θ = f_r + h θ'² − d θ'' (h the sensor's distance
//!    above the pivot, d across the axis: read from the bell's free falls
//!    from the balance, else given or fitted so that the corrected force
//!    is g throughout), θ' and θ'' from local fits; twice.
//! 3. **Strokes**: each crossing of θ = 0 while the bell moves is a bottom
//!    dead centre, timed by the zero of the tangential reading corrected
//!    by h θ'' + d θ'² (a line over ±12 deg of the bottom); the stroke's
//!    amplitude is the turning point it fell from; its strike the first
//!    burst after it.
//! 4. **Phases**: rests (no motion for 1.5 s or more) are down (near
//!    θ = 0) or up (near the balance); what moves between two rests is
//!    raising (from down to up), ringing (from up; the full swings), and
//!    lowering (the swings after the last full one, down to rest).
//! 0. **Tilt**: a sensor not square on its nut reads the resting bell
//!    (which hangs plumb) a few degrees off; that angle, from the rests
//!    near the bottom, is turned out of the readings first.
//! 5. **Hand and back**: the bell is set at handstroke, so a stroke that
//!    starts from the side the bell was set on is a handstroke (with no
//!    set, the side with θ > 0 on the sensor's axes).

use crate::striking::mean_sd;
use crate::{median, SignalError};
use clapper_core::bell::G;
use clapper_core::linalg::solve;
use clapper_core::sensor::{specific_force, SensorPlace};

mod calibrate;
pub mod checks;
mod orient;
pub use calibrate::{Calibration, CalibrationSe};
pub use orient::{orientation, Orientation};

/// Fewer free stretches than this (free swings, falls from the balance)
/// do not calibrate the sensor: the rests alone are used.
const MIN_FREE: usize = 3;

/// An accelerometer log, its axes already named (m/s², s).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AccelLog {
    /// The bell's name, when the log gives one.
    pub name: Option<String>,
    /// Sample times (s), increasing.
    pub t: Vec<f64>,
    /// Along the bell's axis, toward the crown (m/s²): +g with the bell
    /// down and still.
    pub radial: Vec<f64>,
    /// Across the bell's axis in its plane of swing (m/s²): g sin θ with
    /// the bell still at θ.
    pub tangential: Vec<f64>,
    /// Along the pivot's axis (m/s²): no swing, only strikes and noise.
    pub axle: Vec<f64>,
}

/// How to read a log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogOptions {
    /// The sensor's distance above the pivot along the bell's axis (m), if
    /// known; otherwise read from the bell's falls from the balance, or
    /// without one fitted from the whole log.
    pub sensor_along: Option<f64>,
    /// The sensor's range (m/s²): readings at 99 % of it or more are taken
    /// as clipped. Default 2 g, an ADXL345 at its ±2 g setting.
    pub clip: f64,
    /// A stroke rings "full" (ringing, not raising or lowering) when its
    /// amplitude is at least this (rad). Default 150 deg.
    pub full_swing: f64,
    /// Read which way is down from the log (its small swings: [`orientation`])
    /// and turn the radial and tangential axes over if they read it upside
    /// down. Default true; false takes the axes as given.
    pub find_down: bool,
    /// Read the angle through a strike's ringing headstock: the samples of a
    /// burst lasting over [`RINGING_S`], after its strikes' first
    /// [`STRIKE_S`], that are not clipped go into the angle's fits, their
    /// vibration taken as noise (else the angle is bridged across the whole
    /// burst). Default true.
    pub through_ringing: bool,
}

impl Default for LogOptions {
    fn default() -> Self {
        Self {
            sensor_along: None,
            clip: 2.0 * G,
            full_swing: 150f64.to_radians(),
            find_down: true,
            through_ringing: true,
        }
    }
}

/// A part of a ringing session.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhaseKind {
    /// At rest, mouth down.
    Down,
    /// Being rung up.
    Raising,
    /// Set at the balance.
    Up,
    /// Rung full circle.
    Ringing,
    /// Being rung down.
    Lowering,
}

impl PhaseKind {
    /// The name in JSON and text.
    pub fn name(self) -> &'static str {
        match self {
            PhaseKind::Down => "down",
            PhaseKind::Raising => "raising",
            PhaseKind::Up => "up",
            PhaseKind::Ringing => "ringing",
            PhaseKind::Lowering => "lowering",
        }
    }
}

/// A phase and when it held (s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phase {
    /// What the bell was doing.
    pub kind: PhaseKind,
    /// Start (s).
    pub start: f64,
    /// End (s).
    pub end: f64,
}

/// One swing read from the log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogStroke {
    /// Bottom dead centre (s).
    pub bdc: f64,
    /// Handstroke (else backstroke).
    pub hand: bool,
    /// The clapper's first strike after bottom dead centre (s), if any.
    pub strike: Option<f64>,
    /// Whether a gap in the log (samples lost: an interval over [`GAP`]
    /// times the usual) lies between bottom dead centre and the first burst after
    /// it: the clapper may have struck in the gap, so `strike` is `None`
    /// (not known, rather than not struck).
    pub strike_hidden: bool,
    /// The bell's angle at the strike (rad).
    pub strike_theta: Option<f64>,
    /// The turning point it fell from: |θ| (rad).
    pub amplitude: f64,
    /// The side it fell from: +1 (θ > 0) or −1.
    pub from_side: f64,
    /// The phase it belongs to.
    pub phase: PhaseKind,
    /// The moment of greatest speed near the bottom (s): the peak of |θ'|
    /// ([`checks`]), which needs no zero of the angle; a check on `bdc`.
    pub speed_peak: Option<f64>,
    /// The standard error of `bdc` (s) that the sensor's calibration
    /// leaves (its tilt, offset and place across the axis).
    pub bdc_se: Option<f64>,
}

impl LogStroke {
    /// Bottom dead centre to strike (s).
    pub fn bdc_to_strike(&self) -> Option<f64> {
        self.strike.map(|s| s - self.bdc)
    }
}

/// Where clappering starts while the bell is raised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClapperingStart {
    /// When (s): the first strike of the raising (its bottom dead centre
    /// if a gap hides the strike).
    pub t: f64,
    /// The amplitude of the swing it is in (rad).
    pub amplitude: f64,
    /// Whether that swing is a handstroke.
    pub hand: bool,
}

/// What a log says.
#[derive(Clone, Debug, PartialEq)]
pub struct LogAnalysis {
    /// The phases, in time order.
    pub phases: Vec<Phase>,
    /// Every swing, in time order.
    pub strokes: Vec<LogStroke>,
    /// Odd-struckness in the ringing: mean handstroke minus mean backstroke
    /// BDC-to-strike (s), and its standard error (s).
    pub odd_struck: Option<(f64, f64)>,
    /// Clappering's start while raising.
    pub clappering_starts: Option<ClapperingStart>,
    /// The sensor's distance above the pivot used (m), given, read from the
    /// falls from the balance, or fitted.
    pub sensor_along: f64,
    /// The sensor's distance across the bell's axis, toward the back side
    /// (m; a nut or bracket off the axis line), read from the falls or
    /// fitted.
    pub sensor_across: f64,
    /// Whether `sensor_along` was read from the log (not given).
    pub sensor_fitted: bool,
    /// How well the angle was read: the corrected force's median departure
    /// from g while the bell moves, over g (about 0.01 on logs the model
    /// makes; above 0.1 the strokes are read without the angle).
    pub angle_misfit: f64,
    /// Median sample interval (s).
    pub interval: f64,
    /// The reconstructed angle at every sample (rad): continuous, the
    /// bottom at 0, within ±200 deg (past ±180 for a bell set beyond the
    /// balance).
    pub theta: Vec<f64>,
    /// Samples taken as bursts (strikes) or clipped.
    pub burst: Vec<bool>,
    /// The side the bell was set on (+1 or −1: θ's sign), which makes
    /// handstrokes; `None` if it was never set (θ > 0 taken).
    pub set_side: Option<f64>,
    /// Which way up the log was read ([`orientation`]); `None` when the
    /// axes were taken as given.
    pub orientation: Option<Orientation>,
    /// The sensor's calibration from the log's quiet stretches (`None`:
    /// too few free swings or falls; the rests' scale and tilt were used).
    pub calibration: Option<Calibration>,
    /// Things worth knowing (gaps, clipping, a fitted sensor place).
    pub warnings: Vec<String>,
}

/// Check a log: enough samples, finite, time increasing.
fn check(log: &AccelLog) -> Result<(), SignalError> {
    let n = log.t.len();
    if [log.radial.len(), log.tangential.len(), log.axle.len()] != [n; 3] {
        return Err(SignalError::Invalid(
            "the axes have different numbers of samples".into(),
        ));
    }
    if n < 20 {
        return Err(SignalError::TooShort(format!(
            "{n} samples: a log needs at least 20 (a second or so)"
        )));
    }
    for k in 0..n {
        let v = [log.t[k], log.radial[k], log.tangential[k], log.axle[k]];
        if v.iter().any(|x| !x.is_finite()) {
            return Err(SignalError::Invalid(format!("sample {} is not a finite number", k + 1)));
        }
        if k > 0 && log.t[k] <= log.t[k - 1] {
            return Err(SignalError::Invalid(format!(
                "time goes backwards or repeats at sample {} ({} s after {} s)",
                k + 1,
                log.t[k],
                log.t[k - 1]
            )));
        }
    }
    Ok(())
}

/// The burst mask and the burst onsets (sample indices), method step 1.
fn bursts(log: &AccelLog, clip: f64) -> (Vec<bool>, Vec<usize>) {
    let n = log.t.len();
    let axes = [&log.radial, &log.tangential, &log.axle];
    let interval = median(&log.t.windows(2).map(|w| w[1] - w[0]).collect::<Vec<_>>());
    let mut d = vec![0.0; n];
    for k in 2..n {
        // Across a gap the swing has moved on: no prediction.
        if log.t[k] - log.t[k - 2] > 4.0 * interval {
            continue;
        }
        let f = (log.t[k] - log.t[k - 1]) / (log.t[k - 1] - log.t[k - 2]);
        d[k] = axes
            .iter()
            .map(|a| {
                let pred = a[k - 1] + (a[k - 1] - a[k - 2]) * f;
                (a[k] - pred).powi(2)
            })
            .sum::<f64>()
            .sqrt();
    }
    let typical = median(&d[2..]);
    let threshold = (6.0 * 1.4826 * typical).max(1.5);
    let clipped = |k: usize| axes.iter().any(|a| a[k].abs() >= 0.99 * clip);
    let mut mask = vec![false; n];
    let mut onsets = vec![];
    let mut last_hot: Option<f64> = None;
    for k in 0..n {
        let hot = d[k] > threshold || clipped(k);
        if hot {
            // A new burst unless one is still ringing (within 60 ms).
            if last_hot.is_none_or(|t| log.t[k] - t > 0.06) {
                // An impact just before a sample can read small there
                // (the ring near a node on every axis): the burst starts
                // one sample early when that sample already departs from
                // its prediction by half the threshold, far above noise.
                // (That sample stays out of the mask: under the threshold
                // it does the angle little harm, and masking it too moved
                // a real log's unwrapped angle while raising by a turn.)
                let early = k > 2 && d[k - 1] > 0.5 * threshold && !mask[k - 1];
                onsets.push(if early { k - 1 } else { k });
            }
            last_hot = Some(log.t[k]);
        }
        mask[k] = last_hot.is_some_and(|t| log.t[k] - t <= 0.04);
    }
    (mask, onsets)
}

/// The strike itself: the first this many seconds of a burst (s), left
/// out of the angle's fits.
pub const STRIKE_S: f64 = 0.06;

/// A burst lasting longer than this (s) is the headstock ringing.
pub const RINGING_S: f64 = 0.25;

/// The samples the angle's fits leave out: with `through`, of a burst
/// lasting over [`RINGING_S`] only the clipped samples and its strikes'
/// first [`STRIKE_S`]; else (and of shorter bursts) the whole burst.
fn ringing_masked(log: &AccelLog, burst: &[bool], onsets: &[usize], clip: f64, through: bool) -> Vec<bool> {
    if !through {
        return burst.to_vec();
    }
    let axes = [&log.radial, &log.tangential, &log.axle];
    let n = log.t.len();
    // Each burst run's length (s): only a long one (the headstock ringing,
    // not a strike's burst that dies in a few hundredths) is read through.
    let mut long = vec![false; n];
    let mut k = 0;
    while k < n {
        if !burst[k] {
            k += 1;
            continue;
        }
        let start = k;
        while k < n && burst[k] {
            k += 1;
        }
        let lasting = log.t[k - 1] - log.t[start] > RINGING_S;
        long[start..k].fill(lasting);
    }
    let mut o = 0;
    (0..n)
        .map(|k| {
            while o + 1 < onsets.len() && onsets[o + 1] <= k {
                o += 1;
            }
            let struck = onsets
                .get(o)
                .is_some_and(|&j| j <= k && log.t[k] - log.t[j] <= STRIKE_S);
            burst[k] && (!long[k] || struck || axes.iter().any(|a| a[k].abs() >= 0.99 * clip))
        })
        .collect()
}

/// Local quadratic fits of `y` (on samples not in `bad`) over ±`w` s:
/// the value, first and second derivative at every sample.
fn quadratic_fits(t: &[f64], y: &[f64], bad: &[bool], w: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = t.len();
    let (mut v, mut d1, mut d2) = (y.to_vec(), vec![0.0; n], vec![0.0; n]);
    let mut lo = 0;
    let mut hi = 0;
    for k in 0..n {
        while t[k] - t[lo] > w {
            lo += 1;
        }
        while hi + 1 < n && t[hi + 1] - t[k] <= w {
            hi += 1;
        }
        // Normal equations of a + b x + c x², x = t - t_k.
        let mut s = [0.0f64; 5];
        let mut r = [0.0f64; 3];
        for j in lo..=hi {
            if bad[j] {
                continue;
            }
            let x = t[j] - t[k];
            let mut p = 1.0;
            for m in s.iter_mut() {
                *m += p;
                p *= x;
            }
            r[0] += y[j];
            r[1] += y[j] * x;
            r[2] += y[j] * x * x;
        }
        if s[0] < 4.0 {
            continue;
        }
        let a = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
        if let Some(sol) = solve(a, r) {
            v[k] = sol[0];
            d1[k] = sol[1];
            d2[k] = 2.0 * sol[2];
        }
    }
    (v, d1, d2)
}

fn wrap(a: f64) -> f64 {
    let x = (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI;
    if x == -std::f64::consts::PI {
        std::f64::consts::PI
    } else {
        x
    }
}

/// The angle, method step 2: θ unwrapped (measured where good, fitted
/// across bursts), θ smoothed (the fits' values), θ', h, and whether h was
/// fitted.
struct Angle {
    theta: Vec<f64>,
    smooth: Vec<f64>,
    rate: Vec<f64>,
    /// θ' from the joint fits (rad/s): not smoothed over ±0.3 s, which
    /// reads a swing's fastest (at the bottom) slow.
    joint_rate: Vec<f64>,
    /// θ'' from the joint fits (rad/s²).
    acc: Vec<f64>,
    /// Whether the joint fit's cubic gave the sample's θ' and θ'' (not
    /// the fallback's, one-sided at a gap or the log's ends).
    cubic: Vec<bool>,
    h: f64,
    /// The sensor's distance across the axis (m), fitted.
    d: f64,
    fitted: bool,
    /// The median departure of the corrected force from g while the bell
    /// moves, over g: small when the angle is read right.
    misfit: f64,
}

fn angle(log: &AccelLog, bad: &[bool], given: Option<f64>, falls: Option<&Falls>, interval: f64) -> Angle {
    let n = log.t.len();
    // The place read from falls is kept (h given wins); else fitted.
    let known = match falls {
        Some(f) => Known {
            along: Some(given.unwrap_or(f.place().0)),
            across: Some(f.place().1),
        },
        None => Known {
            along: given,
            across: None,
        },
    };
    // From several starts (below), the one whose corrected force is
    // nearest g; the first (no correction) wins ties, so a log read well
    // without them reads the same. With falls read, their κ.
    let from_falls = falls.map(|f| [given.map_or(f.kappa, |h| h / f.length)]);
    let starts: &[f64] = match &from_falls {
        Some(k) => k,
        None => &STARTS,
    };
    let best = starts
        .iter()
        .map(|&kappa| first_pass(log, bad, known, interval, kappa))
        .reduce(|best, a| if a.misfit < best.misfit - 1e-3 { a } else { best })
        .expect("STARTS is not empty");
    let (mut theta, mut place) = (best.theta, best.place);
    // Then θ, θ', θ'' fitted to both readings at once over ±0.15 s (at
    // least 4 samples), and the sensor's place refitted from them; twice.
    let jw = (4.0 * interval).max(0.15);
    let mut derivatives = None;
    for _ in 0..2 {
        let (_, q1, q2) = quadratic_fits(&log.t, &theta, bad, best.window);
        let j = joint_fits(log, bad, &theta, place, jw, (&q1, &q2));
        place = fit_sensor(log, bad, &j.d1, &j.d2, known);
        theta = unwrap_fill(&log.t, &j.theta, bad);
        derivatives = Some((j.d1, j.d2, j.cubic));
    }
    let (d1, d2, cubic) = derivatives.expect("two passes");
    let misfit = misfit(log, bad, place, &d1, &d2);
    let (smooth, rate, _) = quadratic_fits(&log.t, &theta, bad, best.window);
    // Across a burst the fit bridges better than a straight line, unless
    // the burst is so long that the fit has little to stand on (then the
    // two disagree, and the line is kept).
    let theta: Vec<f64> = (0..n)
        .map(|k| {
            if bad[k] && (smooth[k] - theta[k]).abs() < 0.3 {
                smooth[k]
            } else {
                theta[k]
            }
        })
        .collect();
    Angle {
        theta,
        smooth,
        rate,
        joint_rate: d1,
        acc: d2,
        cubic,
        h: place.0,
        d: place.1,
        fitted: given.is_none(),
        misfit,
    }
}

/// Gravity's part of the reading at sample `k`, g (sin θ, cos θ) (m/s²;
/// tangential, radial): the reading less the swing's own acceleration at
/// the sensor's place (h along, d across; m) with θ' = `rate` (rad/s) and
/// θ'' = `acc` (rad/s²). The forward formula is clapper_core::sensor's
/// (docs/model.md §13).
fn gravity_part(log: &AccelLog, k: usize, (h, d): (f64, f64), rate: f64, acc: f64) -> [f64; 2] {
    let swing = specific_force(SensorPlace { along: h, across: d }, 0.0, rate, acc);
    [log.tangential[k] - swing[0], log.radial[k] - (swing[1] - G)]
}

/// The median departure of the corrected force from g while the bell
/// moves (|θ'| > 0.5 rad/s), over g.
fn misfit(log: &AccelLog, bad: &[bool], place: (f64, f64), d1: &[f64], d2: &[f64]) -> f64 {
    median(
        &(0..log.t.len())
            .filter(|&k| !bad[k] && d1[k].abs() > 0.5)
            .map(|k| {
                let [a, b] = gravity_part(log, k, place, d1[k], d2[k]);
                (a.hypot(b) - G).abs() / G
            })
            .collect::<Vec<_>>(),
    )
}

/// Starting guesses of κ = h/L (sensor height over the bell's equivalent
/// pendulum length) for the angle's first pass. With the sensor well above
/// the pivot (κ ≳ 0.25) the uncorrected angle is wrong in kind, not just
/// in size: at the bottom of a full swing the centripetal term outweighs
/// gravity, the radial reading goes negative, atan2 says "at the top", and
/// the derivatives that would correct it are taken from that wrong angle,
/// so the correction never gets started. A free pendulum has
/// g sin θ = f_t / (1 + κ) and, swinging from the balance,
/// g cos θ = (f_r + 2 g κ) / (1 − 2 κ); that first guess passes through
/// the bottom where it should (for smaller swings it reads them smaller,
/// but on the right side of the horizontal), and the correction refines it.
const STARTS: [f64; 5] = [0.0, 0.1, 0.2, 0.3, 0.4];

/// The angle of a free pendulum that fell from rest at cos θ = `c0` (a
/// sensor on its axis at κ = h/L) from its readings `ft`, `fr` in units of
/// `g` (m/s², or 1 for readings over g): ft = g (1 + κ) sin θ and
/// fr = g (cos θ − 2κ (cos θ − c₀)) solved for θ.
fn free_fall_angle(ft: f64, fr: f64, kappa: f64, c0: f64, g: f64) -> f64 {
    (ft / (1.0 + kappa)).atan2((fr - 2.0 * g * kappa * c0) / (1.0 - 2.0 * kappa))
}

/// The angle's first pass from start κ: θ unwrapped, the sensor's place,
/// the misfit, and the smoothing window used (s).
struct FirstPass {
    theta: Vec<f64>,
    place: (f64, f64),
    misfit: f64,
    window: f64,
}

fn first_pass(log: &AccelLog, bad: &[bool], known: Known, interval: f64, kappa: f64) -> FirstPass {
    let n = log.t.len();
    let (ft, fr) = (&log.tangential, &log.radial);
    let raw = |place: (f64, f64), d1: &[f64], d2: &[f64], k: usize| {
        let [s, c] = gravity_part(log, k, place, d1[k], d2[k]);
        s.atan2(c)
    };
    let first: Vec<f64> = (0..n).map(|k| free_fall_angle(ft[k], fr[k], kappa, -1.0, G)).collect();
    let mut theta = unwrap_fill(&log.t, &first, bad);
    // ±0.3 s: θ'' from a narrower fit is so noisy that the correction
    // (h θ'', fed back) amplifies the noise (at 100 Hz and ±0.12 s by 4.5 a
    // pass); over ±0.3 s the gain is 0.15, and a swing (seconds long) is
    // still a parabola there. (The joint fits that follow have no such
    // feedback.)
    let window = (5.0 * interval).max(0.3);
    let mut place = (known.along.unwrap_or(0.0), known.across.unwrap_or(0.0));
    for _ in 0..3 {
        let (_, d1, d2) = quadratic_fits(&log.t, &theta, bad, window);
        place = fit_sensor(log, bad, &d1, &d2, known);
        let corrected: Vec<f64> = (0..n).map(|k| raw(place, &d1, &d2, k)).collect();
        theta = unwrap_fill(&log.t, &corrected, bad);
    }
    let (_, d1, d2) = quadratic_fits(&log.t, &theta, bad, window);
    FirstPass {
        misfit: misfit(log, bad, place, &d1, &d2),
        theta,
        place,
        window,
    }
}

/// `a` made continuous sample to sample, but never more than 200 deg from
/// the bottom: each value the turn of it nearest the last one, else the
/// one in (−180, 180] deg.
fn bounded(a: &[f64]) -> Vec<f64> {
    let limit = 200f64.to_radians();
    let mut out = Vec::with_capacity(a.len());
    let mut prev = a.first().map_or(0.0, |&x| wrap(x));
    for &x in a {
        let near = prev + wrap(x - prev);
        let v = if near.abs() <= limit { near } else { wrap(x) };
        out.push(v);
        prev = v;
    }
    out
}

/// Unwrap `a` over the good samples and fill the bad ones by linear
/// interpolation in time.
fn unwrap_fill(t: &[f64], a: &[f64], bad: &[bool]) -> Vec<f64> {
    let n = t.len();
    let mut out = vec![f64::NAN; n];
    let mut bad = bad.to_vec();
    let mut prev: Option<(f64, f64)> = None;
    let mut refused_since: Option<f64> = None;
    for k in 0..n {
        if bad[k] {
            continue;
        }
        let mut v = a[k];
        if let Some((p, tp)) = prev {
            let step = wrap(v - p);
            // A bell turns at most some 6 rad/s: a sample further off is
            // a strike's shaking that the burst test let through; but a
            // quarter of a second of such samples means the last one
            // trusted was the odd one out.
            let since = *refused_since.get_or_insert(t[k]);
            if step.abs() > (8.0 * (t[k] - tp)).max(0.35) && t[k] - since < 0.25 {
                bad[k] = true;
                continue;
            }
            refused_since = None;
            v = p + step;
        }
        out[k] = v;
        prev = Some((v, t[k]));
    }
    let good: Vec<usize> = (0..n).filter(|&k| !bad[k]).collect();
    if good.is_empty() {
        return a.to_vec();
    }
    let mut g = 0;
    for k in 0..n {
        if !bad[k] {
            continue;
        }
        while g + 1 < good.len() && good[g + 1] < k {
            g += 1;
        }
        let (i, j) = (good[g], good.get(g + 1).copied().unwrap_or(good[g]));
        out[k] = if i >= k || j == i {
            out[i.min(j)]
        } else {
            out[i] + (out[j] - out[i]) * (t[k] - t[i]) / (t[j] - t[i])
        };
    }
    out
}

/// θ, θ' and θ'' at every sample from a local cubic θ(t) over ±`w` s
/// fitted to both readings at once (Gauss-Newton from `theta`), the
/// readings being g (sin θ, cos θ) less the swing's accelerations at the
/// sensor's `place` (h along, d across). Unlike differentiating a
/// smoothed θ, nothing is fed back, so the window can be short enough to
/// follow a light bell's fast swing through the bottom. Samples with too
/// few good neighbours keep `theta` and the derivatives `fallback`.
fn joint_fits(
    log: &AccelLog,
    bad: &[bool],
    theta: &[f64],
    (h, d): (f64, f64),
    w: f64,
    fallback: (&[f64], &[f64]),
) -> JointFits {
    let n = log.t.len();
    let (t, ft, fr) = (&log.t, &log.tangential, &log.radial);
    let (mut th, mut d1, mut d2) = (theta.to_vec(), fallback.0.to_vec(), fallback.1.to_vec());
    let mut cubic = vec![false; n];
    let (mut lo, mut hi) = (0, 0);
    for k in 0..n {
        while t[k] - t[lo] > w {
            lo += 1;
        }
        while hi + 1 < n && t[hi + 1] - t[k] <= w {
            hi += 1;
        }
        // At most some 40 samples a window: more adds time, not accuracy.
        let stride = (hi + 1 - lo).div_ceil(40).max(1);
        let good: Vec<usize> = (lo..=hi)
            .filter(|&j| !bad[j] && (j == k || j.abs_diff(k) % stride == 0))
            .collect();
        // A cubic with samples on one side only (at a gap's edge, or the
        // log's) extrapolates: there `theta` is kept (at a gap in a swing's
        // top it read 5 deg past the balance).
        let before = good.iter().filter(|&&j| j < k).count();
        if good.len() < 8 || before < 3 || good.len() - before < 4 {
            continue;
        }
        // Start: the cubic through `theta` (linear least squares).
        let mut ata = [[0.0f64; 4]; 4];
        let mut atb = [0.0f64; 4];
        for &j in &good {
            let x = t[j] - t[k];
            let p = [1.0, x, x * x, x * x * x];
            for i in 0..4 {
                atb[i] += p[i] * theta[j];
                for l in 0..4 {
                    ata[i][l] += p[i] * p[l];
                }
            }
        }
        let Some(mut a) = solve(ata, atb) else { continue };
        for _ in 0..4 {
            let mut jtj = [[0.0f64; 4]; 4];
            let mut jtr = [0.0f64; 4];
            for &j in &good {
                let x = t[j] - t[k];
                let q = a[0] + x * (a[1] + x * (a[2] + x * a[3]));
                let q1 = a[1] + x * (2.0 * a[2] + 3.0 * x * a[3]);
                let q2 = 2.0 * a[2] + 6.0 * x * a[3];
                let (sn, cs) = q.sin_cos();
                let model = specific_force(SensorPlace { along: h, across: d }, q, q1, q2);
                let (rt, rr) = (model[0] - ft[j], model[1] - fr[j]);
                let p = [1.0, x, x * x, x * x * x];
                let p1 = [0.0, 1.0, 2.0 * x, 3.0 * x * x];
                let p2 = [0.0, 0.0, 2.0, 6.0 * x];
                let mut jt = [0.0; 4];
                let mut jr = [0.0; 4];
                for i in 0..4 {
                    jt[i] = G * cs * p[i] - h * p2[i] - 2.0 * d * q1 * p1[i];
                    jr[i] = -G * sn * p[i] - 2.0 * h * q1 * p1[i] + d * p2[i];
                }
                for i in 0..4 {
                    jtr[i] -= jt[i] * rt + jr[i] * rr;
                    for l in 0..4 {
                        jtj[i][l] += jt[i] * jt[l] + jr[i] * jr[l];
                    }
                }
            }
            let Some(step) = solve(jtj, jtr) else { break };
            for i in 0..4 {
                a[i] += step[i];
            }
            if step[0].abs() < 1e-7 {
                break;
            }
        }
        if a.iter().all(|v| v.is_finite()) && (a[0] - theta[k]).abs() < 1.0 {
            th[k] = a[0];
            d1[k] = a[1];
            d2[k] = 2.0 * a[2];
            cubic[k] = true;
        }
    }
    JointFits {
        theta: th,
        d1,
        d2,
        cubic,
    }
}

/// The sensor's place read from the bell's falls from rest at the balance
/// (method step 2, first): from a set bell's release to its first strike
/// the bell swings free, θ'' = −(g/L) sin θ and θ'² = (2g/L)(cos θ − c₀),
/// so the readings over g are
/// f_t = (1 + κ) sin θ − 2δ (cos θ − c₀) and
/// f_r = cos θ − 2κ (cos θ − c₀) − δ sin θ, κ = h/L and δ = d/L, functions
/// of θ alone: κ, δ, c₀ and each sample's θ are fitted to both readings
/// (c₀ free: the ringer's pull off the balance adds a little energy), then
/// L from the time the fall took, ∫ dθ / √((2g/L)(cos θ − c₀)). Unlike the
/// fit over the whole log (which takes θ'' from the angle it corrects, and
/// reads h short where the strikes shake the headstock), nothing here is
/// differentiated. The median over the falls; `None` without one.
struct Falls {
    /// κ = h/L (h above the pivot, along the axis).
    kappa: f64,
    /// δ = d/L (d across the axis).
    delta: f64,
    /// The bell's equivalent pendulum length L (m).
    length: f64,
    /// How many falls were read.
    count: usize,
}

/// One fall's fit: (κ, δ, c₀), θ at each sample, and the rms misfit (in g).
fn fit_fall(ft: &[f64], fr: &[f64], rest: f64, kappa0: f64) -> Option<([f64; 3], Vec<f64>, f64)> {
    let n = ft.len();
    let mut p = [kappa0, 0.0, rest.cos()];
    // The first guess: the free pendulum's readings solved for θ, with δ = 0.
    let mut th: Vec<f64> = (0..n)
        .map(|k| free_fall_angle(ft[k], fr[k], kappa0, p[2], 1.0))
        .collect();
    let mut last = rest;
    for v in &mut th {
        *v = last + wrap(*v - last);
        last = *v;
    }
    let resid = |p: &[f64; 3], th: &[f64]| -> f64 {
        (0..n)
            .map(|k| {
                let (s, c) = th[k].sin_cos();
                let rt = (1.0 + p[0]) * s - 2.0 * p[1] * (c - p[2]) - ft[k];
                let rr = c - 2.0 * p[0] * (c - p[2]) - p[1] * s - fr[k];
                rt * rt + rr * rr
            })
            .sum()
    };
    let mut cost = resid(&p, &th);
    // Gauss-Newton, each θ_k eliminated (it touches only its own sample's
    // two residuals): a 3 × 3 system a step.
    for _ in 0..40 {
        let mut s = [[0.0f64; 3]; 3];
        let mut rhs = [0.0f64; 3];
        let mut local = Vec::with_capacity(n);
        for k in 0..n {
            let (sn, cs) = th[k].sin_cos();
            let ct = cs - p[2];
            let r = [
                (1.0 + p[0]) * sn - 2.0 * p[1] * ct - ft[k],
                cs - 2.0 * p[0] * ct - p[1] * sn - fr[k],
            ];
            let jt = [(1.0 + p[0]) * cs + 2.0 * p[1] * sn, -sn + 2.0 * p[0] * sn - p[1] * cs];
            let jp = [[sn, -2.0 * ct, 2.0 * p[1]], [-2.0 * ct, -sn, 2.0 * p[0]]];
            let a = jt[0] * jt[0] + jt[1] * jt[1];
            if a < 1e-12 {
                return None;
            }
            let b: [f64; 3] = std::array::from_fn(|i| jt[0] * jp[0][i] + jt[1] * jp[1][i]);
            let g = jt[0] * r[0] + jt[1] * r[1];
            for i in 0..3 {
                rhs[i] -= jp[0][i] * r[0] + jp[1][i] * r[1] - b[i] * g / a;
                for l in 0..3 {
                    s[i][l] += jp[0][i] * jp[0][l] + jp[1][i] * jp[1][l] - b[i] * b[l] / a;
                }
            }
            local.push((a, b, g));
        }
        let dp = solve(s, rhs)?;
        let dth: Vec<f64> = local
            .iter()
            .map(|(a, b, g)| -(g + b[0] * dp[0] + b[1] * dp[1] + b[2] * dp[2]) / a)
            .collect();
        // Halve the step until the misfit falls (a few times at most).
        let mut scale = 1.0;
        let mut accepted = false;
        for _ in 0..6 {
            let q: [f64; 3] = std::array::from_fn(|i| p[i] + scale * dp[i]);
            let t2: Vec<f64> = th.iter().zip(&dth).map(|(t, d)| t + scale * d).collect();
            let c2 = resid(&q, &t2);
            if c2 <= cost {
                p = q;
                th = t2;
                cost = c2;
                accepted = true;
                break;
            }
            scale *= 0.5;
        }
        if !accepted || dp.iter().all(|v| v.abs() < 1e-8) {
            break;
        }
    }
    (p.iter().all(|v| v.is_finite())).then(|| (p, th, (cost / (2 * n) as f64).sqrt()))
}

/// Falls longer than this (s) are cut: from the balance to the first strike
/// takes a second or two.
const FALL_MAX_S: f64 = 3.0;

/// A fall's misfit above this (m/s²) is not a free fall (a ringer checking
/// it, the clapper moving in the bell): left out.
const FALL_MAX_MISFIT: f64 = 0.5;

fn place_from_falls(log: &AccelLog, bad: &[bool], rests: &[(f64, f64, f64)], interval: f64) -> Option<Falls> {
    let (t, n) = (&log.t, log.t.len());
    // (κ, δ, L) of each fall read.
    let mut found: Vec<[f64; 3]> = vec![];
    // (The rests' angles may be unwrapped by turns.)
    for (_, r1, rest) in rests
        .iter()
        .map(|r| (r.0, r.1, wrap(r.2)))
        .filter(|r| r.2.abs() > 150f64.to_radians())
    {
        let j = t.partition_point(|&x| x <= r1);
        let mut e = j;
        // To the first strike, or a gap.
        while e < n && !bad[e] && t[e] - t[j] < FALL_MAX_S && (e == j || t[e] - t[e - 1] < 3.0 * interval) {
            e += 1;
        }
        if e - j < 20 {
            continue;
        }
        let ft: Vec<f64> = log.tangential[j..e].iter().map(|v| v / G).collect();
        let fr: Vec<f64> = log.radial[j..e].iter().map(|v| v / G).collect();
        let Some((p, th, rms)) = [0.0, 0.15, 0.3, 0.45]
            .iter()
            .filter_map(|&k0| fit_fall(&ft, &fr, rest, k0))
            .min_by(|a, b| a.2.total_cmp(&b.2))
        else {
            continue;
        };
        // A fall passes the bottom; and the energy is that of a bell near
        // the balance.
        let passes = th.iter().any(|v| wrap(*v).abs() < 0.2);
        if rms * G > FALL_MAX_MISFIT || !passes || !(-1.3..-0.8).contains(&p[2]) {
            continue;
        }
        let Some(length) = length_of_fall(&t[j..e], &th, p[2]) else {
            continue;
        };
        if (0.05..10.0).contains(&length) {
            found.push([p[0], p[1], length]);
        }
    }
    if found.is_empty() {
        return None;
    }
    let pick = |i: usize| median(&found.iter().map(|x| x[i]).collect::<Vec<_>>());
    let (kappa, delta, length) = (pick(0), pick(1), pick(2));
    Some(Falls {
        kappa,
        delta,
        length,
        count: found.len(),
    })
}

/// The equivalent pendulum length L (m) from a free swing's timing: `th`
/// (rad) at times `t` (s), swinging with cos θ − c₀ ∝ θ'².
fn length_of_fall(t: &[f64], th: &[f64], c0: f64) -> Option<f64> {
    // √(L/2g) from the time taken: t against ∫ dθ / √(cos θ − c₀), a
    // straight line's slope, where the bell moves well (cos θ − c₀ >
    // 0.2: away from the balance, where the fall's start is slow and
    // its timing uncertain; for a small swing, the half of it nearest
    // the bottom). Signed steps, so the angle's noise cancels rather than
    // adds.
    let fast_above = 0.2f64.min(0.5 * (1.0 - c0));
    let fast: Vec<usize> = (0..th.len()).filter(|&k| th[k].cos() - c0 > fast_above).collect();
    let (Some(&k0), Some(&k1)) = (fast.first(), fast.last()) else {
        return None;
    };
    if k1 < k0 + 10 {
        return None;
    }
    let sense = (0..th.len() - 1).map(|k| wrap(th[k + 1] - th[k])).sum::<f64>().signum();
    let mut integral = vec![0.0; k1 - k0 + 1];
    for k in k0..k1 {
        let cb = ((0.5 * (th[k] + th[k + 1])).cos() - c0).max(0.05f64.min(0.25 * (1.0 - c0)));
        integral[k + 1 - k0] = integral[k - k0] + sense * wrap(th[k + 1] - th[k]) / cb.sqrt();
    }
    let m = integral.len() as f64;
    let (mi, mt) = (
        integral.iter().sum::<f64>() / m,
        (k0..=k1).map(|k| t[k]).sum::<f64>() / m,
    );
    let (mut num, mut den) = (0.0, 0.0);
    for (i, k) in (k0..=k1).enumerate() {
        num += (integral[i] - mi) * (t[k] - mt);
        den += (integral[i] - mi).powi(2);
    }
    if den <= 0.0 || num <= 0.0 {
        return None;
    }
    // The slope is √(L/2g).
    Some(2.0 * G * (num / den).powi(2))
}

impl Falls {
    /// The sensor's place (h along, d across; m).
    fn place(&self) -> (f64, f64) {
        (self.kappa * self.length, self.delta * self.length)
    }
}

/// The sensor's place where known (m): given, or read from the falls.
#[derive(Clone, Copy)]
struct Known {
    along: Option<f64>,
    across: Option<f64>,
}

/// What [`joint_fits`] gives: θ, θ', θ'' at every sample (rad, rad/s,
/// rad/s²).
struct JointFits {
    theta: Vec<f64>,
    d1: Vec<f64>,
    d2: Vec<f64>,
    /// Whether the cubic was fitted at the sample (else the fallback).
    cubic: Vec<bool>,
}

/// The sensor's place (h along the axis above the pivot, d across it; m)
/// that makes the corrected force g throughout: least squares over the
/// moving, good samples by Gauss-Newton from the middle, each within
/// ±1 m; h (and d) held where known.
fn fit_sensor(log: &AccelLog, bad: &[bool], d1: &[f64], d2: &[f64], known: Known) -> (f64, f64) {
    if let Known {
        along: Some(h),
        across: Some(d),
    } = known
    {
        return (h, d);
    }
    let given = known.along;
    let moving: Vec<usize> = (0..log.t.len()).filter(|&k| !bad[k] && d1[k].abs() > 0.5).collect();
    let (mut h, mut d) = (given.unwrap_or(0.0), 0.0);
    // A handful of steps: the residual is nearly linear in (h, d).
    for _ in 0..20 {
        // Normal equations J'J δ = −J'r, r = |F| − g.
        let (mut a, mut b) = ([[0.0f64; 2]; 2], [0.0f64; 2]);
        for &k in &moving {
            let w2 = d1[k] * d1[k];
            let [x, y] = gravity_part(log, k, (h, d), d1[k], d2[k]);
            let m = x.hypot(y);
            if m < 1e-9 {
                continue;
            }
            let r = m - G;
            let j = [(x * d2[k] + y * w2) / m, (x * w2 - y * d2[k]) / m];
            for i in 0..2 {
                b[i] -= j[i] * r;
                for l in 0..2 {
                    a[i][l] += j[i] * j[l];
                }
            }
        }
        let step = if given.is_some() {
            if a[1][1] > 0.0 {
                (0.0, b[1] / a[1][1])
            } else {
                (0.0, 0.0)
            }
        } else {
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            if det.abs() < 1e-12 * (a[0][0] * a[1][1]).abs().max(1e-300) {
                break;
            }
            (
                (b[0] * a[1][1] - b[1] * a[0][1]) / det,
                (a[0][0] * b[1] - a[1][0] * b[0]) / det,
            )
        };
        h = (h + step.0).clamp(-1.0, 1.0);
        d = (d + step.1).clamp(-1.0, 1.0);
        if step.0.abs().max(step.1.abs()) < 1e-6 {
            break;
        }
    }
    (h, d)
}

/// Read `log` (module docs).
pub fn analyse_log(log: &AccelLog, opts: &LogOptions) -> Result<LogAnalysis, SignalError> {
    check(log)?;
    if !(opts.clip.is_finite() && opts.clip > 0.0) {
        return Err(SignalError::Option(format!(
            "clip level {} m/s² must be > 0",
            opts.clip
        )));
    }
    let n = log.t.len();
    let interval = median(&log.t.windows(2).map(|w| w[1] - w[0]).collect::<Vec<_>>());
    let mut warnings = vec![];
    let gaps = log.t.windows(2).filter(|w| w[1] - w[0] > 5.0 * interval).count();
    if gaps > 0 {
        warnings.push(format!("{gaps} gap(s) longer than 5 sample intervals"));
    }
    let (burst, onsets) = bursts(log, opts.clip);
    let bursty = burst.iter().filter(|b| **b).count();
    if bursty as f64 > 0.9 * n as f64 {
        return Err(SignalError::Invalid(format!(
            "{bursty} of {n} samples are clipped or bursts: nothing left to read the swing from (is the range right?)"
        )));
    }
    // Which way is down (the bursts are the same either way up).
    let turned;
    let orientation = opts.find_down.then(|| orientation(log, &burst));
    let log = match orientation {
        Some(o) if o.flipped => {
            warnings.push(format!(
                "the sensor reads the bell upside down on the axes given ({} small swings to and fro centred near 180 deg): its radial and tangential axes are turned over (give --axes to override)",
                o.swings
            ));
            turned = AccelLog {
                radial: log.radial.iter().map(|v| -v).collect(),
                tangential: log.tangential.iter().map(|v| -v).collect(),
                ..log.clone()
            };
            &turned
        }
        Some(o) if o.swings < orient::MIN_SWINGS => {
            warnings.push(format!(
                "which way is down cannot be told from this log ({} small swing(s) to and fro, {} needed): the axes are taken as given",
                o.swings,
                orient::MIN_SWINGS
            ));
            log
        }
        _ => log,
    };
    // The sensor calibrated from the log's quiet stretches (rests, free
    // swings, falls from the balance): per-axis gains and offsets, its
    // tilt, and its place.
    let plain: Vec<f64> = (0..n).map(|k| log.tangential[k].atan2(log.radial[k])).collect();
    let (level, slow, _) = quadratic_fits(&log.t, &unwrap_fill(&log.t, &plain, &burst), &burst, 0.5);
    let still0 = rests(&log.t, &level, &slow, interval);
    let calibration = {
        let (fine, _, _) = quadratic_fits(&log.t, &unwrap_fill(&log.t, &plain, &burst), &burst, 0.1);
        let turns = orient::turning_points(&fine, 5f64.to_radians());
        let stretches = calibrate::quiet_stretches(log, &burst, &still0, (&fine, &turns));
        calibrate::calibrate(log, &stretches).filter(|c| c.free >= MIN_FREE && c.length.is_some())
    };
    let calibrated;
    let (log, still) = if let Some(c) = &calibration {
        let gain = 0.5 * (c.gain[0] + c.gain[1]);
        let (tangential, radial): (Vec<f64>, Vec<f64>) =
            (0..n).map(|k| c.apply(log.tangential[k], log.radial[k])).unzip();
        warnings.push(format!(
            "sensor calibrated on {} rest(s) and {} free swing(s) or fall(s) ({} left out as not free): gains {:.3} ± {:.3} (tangential), {:.3} ± {:.3} (radial); offsets {:+.2} ± {:.2}, {:+.2} ± {:.2} m/s²; tilt {:+.2} ± {:.2} deg",
            c.rests, c.free, c.dropped, c.gain[0], c.se.gain[0], c.gain[1], c.se.gain[1],
            c.offset[0], c.se.offset[0], c.offset[1], c.se.offset[1],
            c.tilt.to_degrees(), c.se.tilt.to_degrees()
        ));
        if c.reach < 90f64.to_radians() {
            warnings.push(format!(
                "the log's free swings reach only {:.0} deg (no fall from the balance read): the gains and the sensor's place are poorly told",
                c.reach.to_degrees()
            ));
        }
        calibrated = AccelLog {
            tangential,
            radial,
            axle: log.axle.iter().map(|a| a / gain).collect(),
            ..log.clone()
        };
        // The rests again, on the calibrated readings.
        let plain: Vec<f64> = (0..n)
            .map(|k| calibrated.tangential[k].atan2(calibrated.radial[k]))
            .collect();
        let (level, slow, _) = quadratic_fits(&log.t, &unwrap_fill(&log.t, &plain, &burst), &burst, 0.5);
        let still = rests(&log.t, &level, &slow, interval);
        (&calibrated, still)
    } else {
        warnings.push(
            "the log has no free swing nor fall from the balance to calibrate the sensor on: its offsets are not told from a tilt (the bottoms may be off by tens of ms)".into(),
        );
        match calibrate_from_rests(log, &burst, &still0, &mut warnings) {
            Some(l) => {
                calibrated = l;
                (&calibrated, still0)
            }
            None => (log, still0),
        }
    };
    let falls = match &calibration {
        Some(c) => Some(Falls {
            kappa: c.kappa,
            delta: c.delta,
            length: c.length.unwrap_or(1.0),
            count: c.free,
        }),
        None => place_from_falls(log, &burst, &still, interval),
    };
    let Angle {
        theta: theta_u,
        smooth,
        rate: d1,
        joint_rate: j1,
        acc: d2,
        cubic,
        h,
        d: across,
        fitted,
        misfit,
    } = angle(
        log,
        &ringing_masked(log, &burst, &onsets, opts.clip, opts.through_ringing),
        opts.sensor_along,
        falls.as_ref(),
        interval,
    );
    match (fitted, &falls) {
        (true, Some(f)) => warnings.push(format!(
            "sensor place read from {} fall(s) from the balance: {h:.3} m above the pivot, {across:.3} m across the axis (the bell's equivalent pendulum {:.3} m; give --sensor-m when known)",
            f.count, f.length
        )),
        (true, None) => warnings.push(format!(
            "sensor place fitted: {h:.3} m above the pivot, {across:.3} m across the axis (give --sensor-m when known)"
        )),
        _ => {}
    }
    // The angle continuous but held within ±200 deg of the bottom: a bell
    // set past the balance (185 deg, say) reads more than 180 deg, not a
    // wrap to -175, and a strike's shaking cannot wind it round.
    let theta = bounded(&theta_u);
    let smooth = bounded(&smooth);
    // Rests by the slope over ±0.5 s: still to a few hundredths of a rad/s.
    let (level, slow, _) = quadratic_fits(&log.t, &theta, &burst, 0.5);
    let rests = rests(&log.t, &level, &slow, interval);
    let mut strokes = if misfit <= MAX_MISFIT {
        // Two bottoms come at least half a small swing apart (π √(L/g) for
        // a free pendulum, the shortest): within 60 % of that the second is
        // the strike's shaking read as a crossing. Without L, 0.3 s.
        let min_gap = falls
            .as_ref()
            .map_or(0.3, |f| (0.6 * std::f64::consts::PI * (f.length / G).sqrt()).max(0.3));
        strokes(
            log,
            &theta,
            &smooth,
            (&d1, &j1, &d2, h, across),
            (&burst, &onsets, &cubic),
            &rests,
            (min_gap, interval),
        )
    } else {
        warnings.push(format!(
            "the swing's own accelerations at the sensor are too large to read the angle (the corrected force is {:.0} % off g): bottoms from the tangential reading's zeros, amplitudes from the turning points",
            100.0 * misfit
        ));
        strokes_by_zeros(log, &theta, (&burst, &onsets), &rests)
    };
    hide_strikes_after_gaps(&log.t, interval, &mut strokes, &mut warnings);
    checks::speed_peaks(&log.t, &j1, &cubic, &burst, &mut strokes);
    if let Some(c) = &calibration {
        checks::bottom_errors(c, log, &j1, &mut strokes);
    }
    let phases = phases(&log.t, &rests, &mut strokes, &theta, opts.full_swing);
    // The side the bell was set on before it was rung.
    let set_side = phases
        .iter()
        .enumerate()
        .find(|(i, p)| p.kind == PhaseKind::Up && phases.get(i + 1).is_some_and(|q| q.kind == PhaseKind::Ringing))
        .or_else(|| phases.iter().enumerate().find(|(_, p)| p.kind == PhaseKind::Up))
        .map(|(_, p)| {
            // The side the first stroke after it fell from (the set's own
            // angle, a degree from the balance, may read either side).
            strokes.iter().find(|s| s.bdc > p.end).map_or_else(
                || {
                    let mid = log.t.partition_point(|&t| t < 0.5 * (p.start + p.end)).min(n - 1);
                    theta[mid].signum()
                },
                |s| s.from_side,
            )
        });
    let hand_side = set_side.unwrap_or(1.0);
    for s in &mut strokes {
        // A handstroke falls from the hand side.
        s.hand = s.from_side == hand_side;
    }
    // Its standard error: the strokes' spread, and the calibration's share
    // (an error in the bottoms' zero moves hand and back bottoms opposite
    // ways, so the difference by twice the mean bottom error).
    let odd_struck = odd_struck(&strokes).map(|(o, se)| {
        let ses: Vec<f64> = strokes
            .iter()
            .filter(|s| s.phase == PhaseKind::Ringing)
            .filter_map(|s| s.bdc_se)
            .collect();
        let cal = if ses.is_empty() {
            0.0
        } else {
            2.0 * ses.iter().sum::<f64>() / ses.len() as f64
        };
        (o, se.hypot(cal))
    });
    let clappering_starts = strokes
        .iter()
        .find(|s| s.phase == PhaseKind::Raising && (s.strike.is_some() || s.strike_hidden))
        .map(|s| ClapperingStart {
            t: s.strike.unwrap_or(s.bdc),
            amplitude: s.amplitude,
            hand: s.hand,
        });
    Ok(LogAnalysis {
        phases,
        strokes,
        odd_struck,
        clappering_starts,
        sensor_along: h,
        sensor_across: across,
        angle_misfit: misfit,
        sensor_fitted: fitted,
        interval,
        theta,
        burst,
        set_side,
        orientation,
        calibration,
        warnings,
    })
}

/// Without a free stretch to calibrate on (issue 24's reading): the rests'
/// magnitude sets one scale for all axes, and the rests down their tilt
/// (an offset across the axis is read as a tilt). The log turned, if it
/// needs to be.
fn calibrate_from_rests(
    log: &AccelLog,
    bad: &[bool],
    still: &[(f64, f64, f64)],
    warnings: &mut Vec<String>,
) -> Option<AccelLog> {
    // A sensor not square on its nut reads the bell at rest as tilted:
    // the bell hangs plumb when down, so its rest's angle is the tilt. And
    // a sensor's scale is often a few per cent out (an ADXL345 may read g
    // as 10.2 m/s²): every rest, down or up, reads g, which sets it.
    let n = log.t.len();
    {
        let mut downs: Vec<f64> = still.iter().map(|r| r.2).filter(|m| m.abs() < 0.5).collect();
        downs.sort_by(f64::total_cmp);
        let tilt = downs
            .get(downs.len() / 2)
            .copied()
            .filter(|t| t.abs() > 0.2f64.to_radians());
        let at_rest: Vec<f64> = (0..n)
            .filter(|&k| !bad[k] && still.iter().any(|r| log.t[k] >= r.0 && log.t[k] <= r.1))
            .map(|k| log.radial[k].hypot(log.tangential[k]).hypot(log.axle[k]))
            .collect();
        let gain = if at_rest.len() >= 20 { median(&at_rest) / G } else { 1.0 };
        let gain = if (gain - 1.0).abs() > 0.01 && (0.5..2.0).contains(&gain) {
            warnings.push(format!(
                "the sensor reads g at rest as {:.2} m/s²: its readings are scaled by {:.3}",
                gain * G,
                1.0 / gain
            ));
            gain
        } else {
            1.0
        };
        if let Some(tilt) = tilt {
            warnings.push(format!(
                "the sensor reads the bell at rest {:.1} deg off plumb: taken as its tilt and removed",
                tilt.to_degrees()
            ));
        }
        if tilt.is_some() || gain != 1.0 {
            let (s, c) = tilt.unwrap_or(0.0).sin_cos();
            let (s, c) = (s / gain, c / gain);
            Some(AccelLog {
                tangential: (0..n).map(|k| log.tangential[k] * c - log.radial[k] * s).collect(),
                radial: (0..n).map(|k| log.tangential[k] * s + log.radial[k] * c).collect(),
                axle: log.axle.iter().map(|a| a / gain).collect(),
                ..log.clone()
            })
        } else {
            None
        }
    }
}

/// Intervals of rest (s): no motion (|θ'| < 0.05 rad/s over ±0.5 s, and
/// θ within 3 deg) for at least 1.5 s (a swing's turning point at the
/// balance lasts less).
fn rests(t: &[f64], theta: &[f64], d1: &[f64], interval: f64) -> Vec<(f64, f64, f64)> {
    let n = t.len();
    let mut out = vec![];
    let mut start: Option<usize> = None;
    // `theta` here is smoothed (the same fit as `d1`).
    let still = |k: usize| d1[k].abs() < 0.05;
    for k in 0..=n {
        let s = k < n && still(k) && start.is_none_or(|i| (theta[k] - theta[i]).abs() < 3f64.to_radians());
        match (s, start) {
            (true, None) => start = Some(k),
            (false, Some(i)) => {
                let j = k - 1;
                if t[j] - t[i] >= 1.5 - 0.5 * interval {
                    let mean = theta[i..=j].iter().sum::<f64>() / (j - i + 1) as f64;
                    out.push((t[i], t[j], mean));
                }
                start = if k < n && still(k) { Some(k) } else { None };
            }
            _ => {}
        }
    }
    out
}

/// Bottom dead centres, amplitudes and strikes (method step 3).
fn strokes(
    log: &AccelLog,
    theta: &[f64],
    smooth: &[f64],
    (d1, j1, d2, h, across): (&[f64], &[f64], &[f64], f64, f64),
    (burst, onsets, cubic): (&[bool], &[usize], &[bool]),
    rests: &[(f64, f64, f64)],
    (min_gap, interval): (f64, f64),
) -> Vec<LogStroke> {
    let t = &log.t;
    let n = t.len();
    let resting = |time: f64| rests.iter().any(|r| time >= r.0 && time <= r.1);
    // The tangential reading is g sin θ less h θ'' less d θ'²; corrected
    // by both, its zero is the bottom. θ'' matters there: a rope's pull that
    // stops or starts at the bottom leaves h θ'' on one side only, which
    // moved a small swing's bottom 3 ms the way of the pull (θ'' from the
    // joint fits, smoothed across the step, takes off half of it on each
    // side, and what is left is odd about the bottom).
    let f: Vec<f64> = (0..n)
        .map(|j| gravity_part(log, j, (h, across), j1[j], d2[j])[0])
        .collect();
    let mut bdcs: Vec<(f64, usize)> = vec![];
    for k in 0..n - 1 {
        let (a, b) = (theta[k], theta[k + 1]);
        // A crossing of 0 while the bell moves.
        if a.signum() != b.signum() && a.abs() < 1.5 && b.abs() < 1.5 && (d1[k].abs() > 0.3 || d1[k + 1].abs() > 0.3) {
            let mut tc = t[k] + (t[k + 1] - t[k]) * a / (a - b);
            if resting(tc) || bdcs.last().is_some_and(|&(p, _)| tc - p < min_gap) {
                continue;
            }
            // The tangential reading's own zero, where clean (`f`).
            let near = (k.saturating_sub(4)..(k + 5).min(n - 1))
                .filter(|&j| !burst[j] && !burst[j + 1] && f[j].signum() != f[j + 1].signum() && f[j] != 0.0)
                .min_by_key(|&j| j.abs_diff(k));
            if let Some(j) = near {
                tc = t[j] + (t[j + 1] - t[j]) * f[j] / (f[j] - f[j + 1]);
                tc = bottom_time(t, &f, (burst, cubic), (tc, interval), G * 0.5 * (d1[k] + d1[k + 1]));
            }
            bdcs.push((tc, k));
        }
    }
    let mut out = Vec::with_capacity(bdcs.len());
    for (i, &(bdc, k)) in bdcs.iter().enumerate() {
        // The turning point it fell from: the largest |θ| since the last
        // bottom (or in the 3 s before the first), on its side.
        let mut from = if i == 0 {
            t.partition_point(|&x| x < bdc - 3.0)
        } else {
            bdcs[i - 1].1 + 1
        };
        // After a rest (set at the balance, or a stand), it fell from where
        // it rested: the rest's mean angle, read while still (the samples
        // after a strike, while the headstock rings, overshoot).
        let side = theta[k].signum();
        let stood = rests.iter().rev().find(|r| r.1 < bdc && t[from] <= r.1);
        if let Some(r) = stood {
            from = from.max(t.partition_point(|&x| x < r.1 - 0.5));
        }
        // From the smoothed angle: the largest of noisy samples overshoots.
        let amplitude = match stood {
            Some(r) if r.2.signum() == side => r.2.abs(),
            _ => (from..=k)
                .filter(|&j| smooth[j].signum() == side)
                .map(|j| smooth[j].abs())
                .fold(0.0, f64::max),
        };
        let until = bdcs.get(i + 1).map_or(f64::INFINITY, |b| b.0);
        out.push(stroke_between(t, theta, onsets, (bdc, until), amplitude, side));
    }
    out
}

/// The zero of the corrected tangential reading `f` near `tc` (s), where
/// it moves at about `slope` (m/s³, g θ'): a straight line through the
/// clean samples while |f| is within [`BOTTOM_SPAN`] (at least ±5 ms and
/// 1.5 samples, at most ±0.12 s). Through the bottom f is g sin θ, odd
/// about it, so a symmetric window adds no bias, and a long one averages
/// the noise down where a small swing moves slowly (at 400 Hz a 20 deg
/// swing's bottom moved 2 samples either way in a ±5 ms window). A gap in
/// the log ([`GAP`]) narrows the window on both sides, and so does a clean
/// sample whose θ'' is not the angle's cubic (`cubic` false: the fallback,
/// one-sided, near a gap or the log's ends): one-sided, the curve of f
/// beyond the line (sin θ, a rope's pull) put a slow swing's bottom, 60 ms
/// before a gap, 7.2 ms early (1.8 samples at 250 Hz); symmetric at the
/// gap, 4.9 ms, its last samples corrected by the fallback's θ'';
/// symmetric short of those, 0.04 ms.
fn bottom_time(
    t: &[f64],
    f: &[f64],
    (burst, cubic): (&[bool], &[bool]),
    (tc, interval): (f64, f64),
    slope: f64,
) -> f64 {
    let n = t.len();
    let k = t.partition_point(|&x| x < tc).clamp(1, n - 1);
    let dt = t[k] - t[k - 1];
    // (At a gap the interval is long: the window stays within ±0.12 s.)
    let shortest = 0.005f64.max(1.5 * dt).min(0.12);
    let mut half = (BOTTOM_SPAN / slope.abs().max(1e-9)).clamp(shortest, 0.12);
    let gap = |q: usize| t[q] - t[q - 1] > GAP * interval;
    // A clean sample whose θ'' is not the cubic's is one-sided: an edge.
    let edge = |q: usize| !burst[q] && !cubic[q];
    let (mut lo, mut hi) = (k - 1, k);
    while lo > 0 && tc - t[lo] < half && !gap(lo) && !edge(lo - 1) {
        lo -= 1;
    }
    while hi + 1 < n && t[hi] - tc < half && !gap(hi + 1) && !edge(hi + 1) {
        hi += 1;
    }
    half = half.min(tc - t[lo]).min(t[hi] - tc);
    let (a, b) = (
        t.partition_point(|&x| x < tc - half),
        t.partition_point(|&x| x <= tc + half),
    );
    let pts: Vec<usize> = (a..b).filter(|&q| !burst[q]).collect();
    if pts.len() < 3 {
        return tc;
    }
    let m = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, &q| (a.0 + t[q] - tc, a.1 + f[q]));
    let (mx, my) = (sx / m, sy / m);
    let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |a, &q| {
        (a.0 + (t[q] - tc - mx) * (f[q] - my), a.1 + (t[q] - tc - mx).powi(2))
    });
    if sxx <= 0.0 || sxy == 0.0 {
        return tc;
    }
    let zero = tc + mx - my * sxx / sxy;
    if (zero - tc).abs() <= half {
        zero
    } else {
        tc
    }
}

/// An interval over this many times the median is a gap (samples lost):
/// past the 2 % jitter of a logger like belfry-sleuth's with room to
/// spare, short of one lost sample (2).
pub const GAP: f64 = 1.75;

/// The reading's span either side of a bottom that [`bottom_time`] fits a
/// line over (m/s²): 2 m/s² is g sin θ within ±12 deg of the bottom, where
/// sin θ departs from a line by 0.7 %, and that symmetrically.
const BOTTOM_SPAN: f64 = 2.0;

/// The stroke with bottom dead centre `bdc`, struck at the first burst
/// onset before `until` (the next bottom); its hand set later.
fn stroke_between(
    t: &[f64],
    theta: &[f64],
    onsets: &[usize],
    (bdc, until): (f64, f64),
    amplitude: f64,
    from_side: f64,
) -> LogStroke {
    let strike_at = onsets.iter().copied().find(|&j| t[j] > bdc && t[j] < until);
    LogStroke {
        bdc,
        hand: true,
        strike: strike_at.map(|j| t[j]),
        strike_hidden: false,
        strike_theta: strike_at.map(|j| theta[j]),
        amplitude,
        from_side,
        phase: PhaseKind::Ringing,
        speed_peak: None,
        bdc_se: None,
    }
}

/// Above this misfit (the corrected force's median departure from g, over
/// g) the angle is not trusted: 0.1 g. Logs the model makes read about
/// 0.01; a light bell with the sensor well off its pivot, whose
/// centripetal acceleration at the bottom passes g, reads far more.
const MAX_MISFIT: f64 = 0.1;

/// Strokes without the angle (when it cannot be read): a bottom dead
/// centre is a zero of the tangential reading while it changes fast (at
/// least 5 m/s³; at the bottom θ'' is near zero and the reading moves as g
/// θ') and swings past 0.15 g on both sides within 0.25 s; the side it
/// fell from is the slope's sign, and sides alternate (of two in a row
/// from one side, the bottom is the one the reading swings further about); the amplitude is read
/// at the turning point, halfway between bottoms, where θ' = 0 and the
/// radial reading is exactly g cos A.
fn strokes_by_zeros(
    log: &AccelLog,
    theta: &[f64],
    (burst, onsets): (&[bool], &[usize]),
    rests: &[(f64, f64, f64)],
) -> Vec<LogStroke> {
    let (t, f) = (&log.t, &log.tangential);
    let n = t.len();
    let resting = |time: f64| rests.iter().any(|r| time >= r.0 && time <= r.1);
    let mut cands: Vec<(f64, f64, f64)> = vec![];
    for j in 0..n - 1 {
        if burst[j] || burst[j + 1] || f[j] == 0.0 || f[j].signum() == f[j + 1].signum() {
            continue;
        }
        let slope = (f[j + 1] - f[j]) / (t[j + 1] - t[j]);
        let tc = t[j] + (t[j + 1] - t[j]) * f[j] / (f[j] - f[j + 1]);
        if slope.abs() < 5.0 || resting(tc) {
            continue;
        }
        // Through the bottom the reading swings well away from zero on both
        // sides within a quarter of a second; a bell wobbling at the
        // balance (the ringer holding it) only flickers across.
        let reach =
            |range: std::ops::Range<usize>| range.filter(|&q| !burst[q]).map(|q| f[q].abs()).fold(0.0, f64::max);
        let (a, b) = (
            t.partition_point(|&x| x < tc - 0.25),
            t.partition_point(|&x| x <= tc + 0.25),
        );
        let swing = reach(a..j + 1).min(reach(j + 1..b));
        if swing < 0.15 * G {
            continue;
        }
        // Rising through zero: moving toward θ > 0, so it fell from θ < 0.
        cands.push((tc, -slope.signum(), swing));
    }
    // Swings alternate: a bottom falls from the side the last one rose to.
    // Two in a row from one side are a bottom and a wobble at the balance
    // (the ringer holding the bell jolts the reading, faster than through
    // the bottom): keep the one the reading swings further about.
    let mut kept: Vec<(f64, f64, f64)> = vec![];
    for &c in &cands {
        match kept.last_mut() {
            Some(last) if c.0 - last.0 < 0.3 => {}
            Some(last) if last.1 == c.1 && c.0 - last.0 < 4.0 => {
                if c.2 > last.2 {
                    *last = c;
                }
            }
            _ => kept.push(c),
        }
    }
    let bdcs: Vec<(f64, f64)> = kept.iter().map(|c| (c.0, c.1)).collect();
    let angle_at = |time: f64| {
        let k = t.partition_point(|&x| x < time).min(n - 1);
        let pts: Vec<usize> = (k.saturating_sub(2)..(k + 3).min(n)).filter(|&q| !burst[q]).collect();
        let m = pts.len().max(1) as f64;
        let (ft, fr) = pts.iter().fold((0.0, 0.0), |a, &q| (a.0 + f[q], a.1 + log.radial[q]));
        (ft / m).atan2(fr / m).abs()
    };
    let mut out = Vec::with_capacity(bdcs.len());
    for (i, &(bdc, side)) in bdcs.iter().enumerate() {
        let before = if i == 0 { bdc - 1.5 } else { bdcs[i - 1].0 };
        let amplitude = match rests.iter().rev().find(|r| r.1 < bdc && r.1 > before) {
            Some(r) => r.2.abs(),
            None => angle_at(0.5 * (before + bdc)),
        };
        let until = bdcs.get(i + 1).map_or(f64::INFINITY, |b| b.0);
        out.push(stroke_between(t, theta, onsets, (bdc, until), amplitude, side));
    }
    out
}

/// Phases (method step 4), and each stroke's phase set.
fn phases(t: &[f64], rests: &[(f64, f64, f64)], strokes: &mut [LogStroke], theta: &[f64], full: f64) -> Vec<Phase> {
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
                (full, height),
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
const FREE_SWING_MAX: f64 = std::f64::consts::FRAC_PI_4;

/// A rest at the balance between strokes of ringing no longer than this
/// (s) is a stand, part of the ringing; longer, the bell is set (up).
pub const STAND_MAX_S: f64 = 5.0;

/// Add a phase, merged with the one before if of the same kind.
fn push(out: &mut Vec<Phase>, kind: PhaseKind, start: f64, end: f64) {
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
fn segment(
    t: &[f64],
    theta: &[f64],
    strokes: &mut [LogStroke],
    (full, height): (f64, f64),
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
    let amp = |i: usize| strokes[i].amplitude;
    // Free swings at the end (the bell let go after lowering): six or more
    // small swings, none struck, each within 3 deg of the one two before.
    // They are down; what comes before them ends down.
    if to != Some(PhaseKind::Up) {
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
        if idx.len() - p0 >= 6 {
            let first = p0 + 1;
            let since = strokes[idx[first - 1]].bdc;
            let cut = turning_before(t, theta, strokes[idx[first]].bdc, since);
            for &i in &idx[first..] {
                strokes[i].phase = PhaseKind::Down;
            }
            if cut > a {
                segment(
                    t,
                    theta,
                    strokes,
                    (full, height),
                    (a, cut),
                    (from, Some(PhaseKind::Down)),
                    out,
                );
            }
            push(out, PhaseKind::Down, cut.max(a), b);
            return;
        }
    }
    let fulls: Vec<f64> = idx.iter().map(|&i| amp(i)).filter(|&x| x >= full).collect();
    let kind_all = match (from, to) {
        // Raised and set: every swing is raising, even the last full ones.
        (Some(PhaseKind::Down) | None, Some(PhaseKind::Up)) => Some(PhaseKind::Raising),
        (Some(PhaseKind::Up), Some(PhaseKind::Up)) => Some(PhaseKind::Ringing),
        _ if fulls.is_empty() => {
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
    };
    if let Some(kind) = kind_all {
        for &i in &idx {
            strokes[i].phase = kind;
        }
        push(out, kind, a, b);
        return;
    }
    // The ringing: swings that fall from near the ringing's height and rise
    // back to it (3 deg below the full swings' median); raising before,
    // lowering from the first swing that does not rise back.
    // (The full swings' height over the whole log: a segment lowered from
    // its first swing after a set has none that reach it.)
    let threshold = height - 3f64.to_radians();
    let core = |p: usize| amp(idx[p]) >= threshold && idx.get(p + 1).is_none_or(|&q| amp(q) >= threshold);
    if from == Some(PhaseKind::Up) && !(0..idx.len()).any(core) {
        for &i in &idx {
            strokes[i].phase = PhaseKind::Lowering;
        }
        push(out, PhaseKind::Lowering, a, b);
        return;
    }
    let first = (0..idx.len()).find(|&p| core(p)).unwrap_or(0);
    let last = (0..idx.len()).rev().find(|&p| core(p)).unwrap_or(idx.len() - 1);
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

/// The turning point (largest |θ|) before bottom dead centre `bdc`, after `from`.
fn turning_before(t: &[f64], theta: &[f64], bdc: f64, from: f64) -> f64 {
    let (i, j) = (t.partition_point(|&x| x < from), t.partition_point(|&x| x < bdc));
    (i..j)
        .max_by(|&a, &b| theta[a].abs().total_cmp(&theta[b].abs()))
        .map_or(from, |k| t[k])
}

/// After a gap between bottom dead centre and the first burst read, the
/// clapper may have struck in the gap (and its burst died away there, so
/// the burst read is a bounce): the strike's time is not known, and a
/// stroke timed from it moves the odd-struckness (one such stroke in 20
/// moved a synthetic log's by 30 ms).
fn hide_strikes_after_gaps(t: &[f64], interval: f64, strokes: &mut [LogStroke], warnings: &mut Vec<String>) {
    let mut hidden = 0;
    for s in strokes.iter_mut() {
        let Some(ts) = s.strike else { continue };
        let (a, b) = (
            t.partition_point(|&x| x <= s.bdc).max(1),
            t.partition_point(|&x| x <= ts),
        );
        if (a..b).any(|k| t[k] - t[k - 1] > GAP * interval) {
            s.strike = None;
            s.strike_theta = None;
            s.strike_hidden = true;
            hidden += 1;
        }
    }
    if hidden > 0 {
        warnings.push(format!(
            "{hidden} strike(s) not timed: a gap in the log lies between the bottom and the first burst after it"
        ));
    }
}

/// Odd-struckness of the ringing: mean hand minus mean back BDC-to-strike
/// (s) and its standard error.
fn odd_struck(strokes: &[LogStroke]) -> Option<(f64, f64)> {
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

    /// A reading odd about its zero (a x + b x|x|: the part of a rope's
    /// pull the θ'' fits leave) is read at its zero exactly when a gap cuts
    /// the window on one side: the window is cut on the other side too
    /// (one-sided, the line through it misses the zero by 0.7 ms here).
    #[test]
    fn a_gap_beside_a_bottom_keeps_its_window_symmetric() {
        let t0 = 1.005;
        let t: Vec<f64> = (0..300)
            .map(|k| k as f64 * 0.01)
            .filter(|&x| !(t0 + 0.04..t0 + 0.5).contains(&x))
            .collect();
        let f: Vec<f64> = t
            .iter()
            .map(|&x| 2.0 * (x - t0) + 60.0 * (x - t0) * (x - t0).abs())
            .collect();
        let burst = vec![false; t.len()];
        let cubic = vec![true; t.len()];
        let got = bottom_time(&t, &f, (&burst, &cubic), (t0, 0.01), 2.0);
        assert!((got - t0).abs() < 1e-9, "{got}");
    }

    /// Two bottoms come at least `min_gap` apart: the angle shaken back
    /// across zero 0.1 s after a bottom (as a strike's burst can read) is
    /// not taken for two more bottoms.
    #[test]
    fn a_crossing_soon_after_a_bottom_is_not_a_bottom() {
        // A 1 rad swing of period 2 s (bottoms at 1, 2, 3, 4 s), 100 Hz,
        // the sensor at the pivot.
        let t: Vec<f64> = (0..500).map(|k| k as f64 * 0.01).collect();
        let w = std::f64::consts::PI;
        let mut theta: Vec<f64> = t.iter().map(|&x| (w * x).sin()).collect();
        let d1: Vec<f64> = t.iter().map(|&x| w * (w * x).cos()).collect();
        let d2: Vec<f64> = theta.iter().map(|&q| -w * w * q).collect();
        let log = AccelLog {
            name: None,
            radial: theta.iter().map(|q| G * q.cos()).collect(),
            tangential: theta.iter().map(|q| G * q.sin()).collect(),
            axle: vec![0.0; t.len()],
            t: t.clone(),
        };
        // Shaken back below zero for two samples 0.1 s after the bottom at 2 s.
        theta[210] = -0.02;
        theta[211] = -0.01;
        let (burst, cubic) = (vec![false; t.len()], vec![true; t.len()]);
        let bottoms = |min_gap: f64| -> Vec<f64> {
            strokes(
                &log,
                &theta,
                &theta,
                (&d1, &d1, &d2, 0.0, 0.0),
                (&burst, &[], &cubic),
                &[],
                (min_gap, 0.01),
            )
            .iter()
            .map(|s| s.bdc)
            .collect()
        };
        let got = bottoms(0.3);
        assert_eq!(got.len(), 4, "{got:?}");
        for (b, want) in got.iter().zip([1.0, 2.0, 3.0, 4.0]) {
            assert!((b - want).abs() < 1e-3, "{got:?}");
        }
        // Without the rule the shaking reads as two more bottoms.
        assert_eq!(bottoms(0.0).len(), 6);
    }

    /// Where the angle's cubic could not be fitted (near the log's end, a
    /// gap's edge) θ'' is one-sided and the reading there is not trusted:
    /// the bottom's window stops short of it on both sides, as at a gap.
    #[test]
    fn samples_without_the_cubic_cut_a_bottoms_window_on_both_sides() {
        let t0 = 1.005;
        let t: Vec<f64> = (0..300).map(|k| k as f64 * 0.01).collect();
        // The reading odd about t0 up to t0 + 0.04 s, then skewed.
        let f: Vec<f64> = t
            .iter()
            .map(|&x| {
                2.0 * (x - t0)
                    + if x > t0 + 0.04 {
                        3.0
                    } else {
                        60.0 * (x - t0) * (x - t0).abs()
                    }
            })
            .collect();
        let burst = vec![false; t.len()];
        let mut cubic: Vec<bool> = t.iter().map(|&x| x < t0 + 0.04).collect();
        let got = bottom_time(&t, &f, (&burst, &cubic), (t0, 0.01), 2.0);
        assert!((got - t0).abs() < 1e-9, "{got}");
        // Trusted everywhere, the skewed samples pull the line off.
        cubic.fill(true);
        let all = bottom_time(&t, &f, (&burst, &cubic), (t0, 0.01), 2.0);
        assert!((all - t0).abs() > 1e-3, "{all}");
    }

    /// A gap between a bottom and the burst read after it leaves the
    /// strike untimed (it may have come in the gap); a gap before the
    /// bottom, or after the burst, does not.
    #[test]
    fn a_strike_after_a_gap_is_not_timed() {
        // 100 Hz, with 0.3 s lost after 1.05 s and after 3.05 s.
        let t: Vec<f64> = (0..500)
            .map(|k| k as f64 * 0.01)
            .filter(|&x| !(1.05..1.35).contains(&x) && !(3.05..3.35).contains(&x))
            .collect();
        let stroke = |bdc: f64, strike: f64| LogStroke {
            bdc,
            hand: true,
            strike: Some(strike),
            strike_hidden: false,
            strike_theta: Some(0.5),
            amplitude: 3.0,
            from_side: 1.0,
            phase: PhaseKind::Ringing,
            speed_peak: None,
            bdc_se: None,
        };
        let mut strokes = [stroke(1.0, 1.4), stroke(2.0, 2.4), stroke(3.4, 3.8)];
        let mut warnings = vec![];
        hide_strikes_after_gaps(&t, 0.01, &mut strokes, &mut warnings);
        assert!(strokes[0].strike_hidden && strokes[0].strike.is_none() && strokes[0].strike_theta.is_none());
        assert!(!strokes[1].strike_hidden && strokes[1].strike == Some(2.4));
        assert!(!strokes[2].strike_hidden && strokes[2].strike == Some(3.8));
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].starts_with("1 strike(s) not timed"), "{warnings:?}");
        // Without strikes timed, odd-struckness leaves the stroke out.
        assert_eq!(strokes[0].bdc_to_strike(), None);
    }

    /// A free pendulum (L = 0.66 m) released at 179 deg, integrated here by
    /// RK4 and read through clapper_core::sensor's forward formula at a
    /// place off the axis: the falls give the place and L back, though
    /// their fit never differentiates and the formula is not theirs.
    #[test]
    fn a_free_fall_from_the_balance_gives_the_sensor_place_and_the_length() {
        let (length, place) = (
            0.66,
            SensorPlace {
                along: 0.2,
                across: 0.07,
            },
        );
        let acc = |th: f64| -G / length * th.sin();
        let (mut th, mut w, mut now) = (179f64.to_radians(), 0.0, 0.0);
        let (dt, every) = (1e-4, 50); // 200 Hz samples
        let mut log = AccelLog::default();
        for k in 0..(4.2 / dt) as usize {
            if k % every == 0 {
                // At rest for the first 2 s, then released.
                let (a, b, c) = if now < 2.0 {
                    (179f64.to_radians(), 0.0, 0.0)
                } else {
                    (th, w, acc(th))
                };
                let f = specific_force(place, a, b, c);
                log.t.push(now);
                log.tangential.push(f[0]);
                log.radial.push(f[1]);
                log.axle.push(0.0);
            }
            if now >= 2.0 {
                let k1 = (w, acc(th));
                let k2 = (w + 0.5 * dt * k1.1, acc(th + 0.5 * dt * k1.0));
                let k3 = (w + 0.5 * dt * k2.1, acc(th + 0.5 * dt * k2.0));
                let k4 = (w + dt * k3.1, acc(th + dt * k3.0));
                th += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                w += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
            now += dt;
        }
        // A strike ends the fall 2 s after the release.
        let bad: Vec<bool> = log.t.iter().map(|&x| x > 4.0).collect();
        let falls = place_from_falls(&log, &bad, &[(0.0, 2.0, 179f64.to_radians())], 1.0 / 200.0).expect("a fall read");
        assert_eq!(falls.count, 1);
        let (along, across) = falls.place();
        assert!((along - 0.2).abs() < 1e-3, "along {along}");
        assert!((across - 0.07).abs() < 1e-3, "across {across}");
        assert!((falls.length - length).abs() < 0.01 * length, "L {}", falls.length);
        assert!((falls.kappa - 0.2 / length).abs() < 1e-3, "κ {}", falls.kappa);
        // No rest at the balance, no fall.
        assert!(place_from_falls(&log, &bad, &[(0.0, 2.0, 0.1)], 1.0 / 200.0).is_none());
    }
}
