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

mod bottoms;
mod calibrate;
pub mod checks;
mod falls;
mod orient;
mod phases;
mod reading;
pub use bottoms::GAP;
use bottoms::*;
pub use calibrate::{Calibration, CalibrationSe};
use falls::*;
pub use orient::{orientation, Orientation};
pub use phases::STAND_MAX_S;
use phases::*;
use reading::*;

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
