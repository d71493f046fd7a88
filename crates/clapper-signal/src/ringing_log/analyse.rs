//! The reading of a log, step by step (the method: [`super`]).

use super::bottoms::{hide_strikes_after_gaps, strokes, strokes_by_zeros, MAX_MISFIT};
use super::bursts::{bursts, radial_clipped, ringing_masked, STRIKE_S};
use super::calibrate::{self, Calibration, Stretch};
use super::checks;
use super::falls::{place_from_falls, Falls};
use super::fits::{bounded, quadratic_fits, unwrap_fill};
use super::orient::{self, orientation, Orientation};
use super::phases::{odd_struck, phases};
use super::plausible::{half_swing, plausibility, Plausibility};
use super::reading::{angle, misfit, Angle};
use super::rests::{calibrate_from_rests, rests};
use super::tops;
use super::types::{AccelLog, ClapperingStart, LogOptions, LogStroke, Phase, PhaseKind};
use super::unring::unrung;
use crate::{median, SignalError};
use clapper_core::bell::G;
use std::borrow::Cow;

/// Fewer free stretches than this (free swings, falls from the balance)
/// do not calibrate the sensor: the rests alone are used.
const MIN_FREE: usize = 3;

/// An odd-struckness whose standard error is over this (s) says nothing
/// (a bell's is a few tens of ms at most): it is withheld, with why.
pub const MAX_ODD_SE: f64 = 0.05;

/// What a log says.
#[derive(Clone, Debug, PartialEq)]
pub struct LogAnalysis {
    /// The phases, in time order.
    pub phases: Vec<Phase>,
    /// Every swing, in time order.
    pub strokes: Vec<LogStroke>,
    /// Odd-struckness in the ringing: mean handstroke minus mean backstroke
    /// BDC-to-strike (s), and its standard error (s); `None` when not read
    /// or withheld ([`LogAnalysis::odd_struck_withheld`]).
    pub odd_struck: Option<(f64, f64)>,
    /// The calibration's share of the odd-struckness's standard error (s):
    /// the larger of its covariance's and its jackknife's (the calibration
    /// refitted without each part of the log's free stretches, the bottoms
    /// re-read with each).
    pub odd_struck_calibration_se: Option<f64>,
    /// Why an odd-struckness that was computed is not given: its standard
    /// error over [`MAX_ODD_SE`], or hand and back not told apart for sure.
    pub odd_struck_withheld: Option<String>,
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
    /// Whether the log looks like a bell's at all (else nothing is read
    /// from it: no phases, no swings).
    pub plausibility: Plausibility,
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

/// The falls from the balance the angle is read with: the calibration's,
/// or, without one, those fitted on the log's own falls (`out`: samples
/// left out; `still`: its rests, start, end and angle in s, s, rad).
fn falls_of(
    calibration: Option<&Calibration>,
    log: &AccelLog,
    (out, still): (&[bool], &[(f64, f64, f64)]),
    interval: f64,
) -> Option<Falls> {
    match calibration {
        Some(c) => Some(Falls {
            kappa: c.kappa,
            delta: c.delta,
            length: c.length.unwrap_or(1.0),
            count: c.free,
        }),
        None => place_from_falls(log, out, still, interval),
    }
}

/// Each stroke labelled hand or back: a handstroke falls from the side the
/// bell is set on (+1 where it is never seen set).
fn label_hand(strokes: &mut [LogStroke], set_side: Option<f64>) {
    let hand_side = set_side.unwrap_or(1.0);
    for s in strokes {
        s.hand = s.from_side == hand_side;
    }
}

/// Read `log` (module docs).
pub fn analyse_log(log: &AccelLog, opts: &LogOptions) -> Result<LogAnalysis, SignalError> {
    let (interval, (burst, onsets), mut warnings) = prepare(log, opts)?;
    let mut plausibility = plausibility(log, &burst, interval);
    if let Some(why) = plausibility.why_not() {
        warnings.push(why);
        return Ok(not_a_ringing_log(log, opts, (interval, burst), plausibility, warnings));
    }
    let raw = log;
    // The radial axis clipped alone (a far sensor's bottoms): out of the
    // calibration's, the place's and the angle's fits, not a burst.
    let rclip = radial_clipped(log, opts.clip);
    let out: Vec<bool> = burst.iter().zip(&rclip).map(|(b, r)| *b || *r).collect();
    // Which way is down (the bursts are the same either way up).
    let (orientation, oriented) = orient_log(log, &out, opts.find_down, &mut warnings);
    let Calibrated {
        calibration,
        log,
        still,
        stretches,
    } = calibrate_log(&oriented, &out, interval, &mut warnings);
    let falls = falls_of(calibration.as_ref(), &log, (&out, &still), interval);
    let bad = ringing_masked(&log, &burst, &onsets, opts.clip, opts.through_ringing);
    // The headstock's ring taken out where it rings in one mode: the
    // angle and the bottoms read through it.
    let (log, shaken, bad, lone) = ring_taken_out(raw, log, (&burst, &bad, &rclip), &onsets, opts);
    let a = judged_angle(&log, (&bad, &lone, &out), opts.sensor_along, falls.as_ref(), interval);
    place_warning(&a, falls.as_ref(), &mut warnings);
    let (theta, smooth, rests) = bounded_and_rests(&log.t, (&a.theta, &a.smooth), &burst, interval);
    let mut strokes = read_strokes(
        &log,
        (&theta, &smooth),
        &a,
        (&burst, &shaken, &onsets),
        &rests,
        (falls.as_ref(), interval),
        &mut warnings,
    );
    if let Some(why) = pendulum_check(&mut plausibility, &strokes) {
        warnings.push(why);
        return Ok(not_a_ringing_log(raw, opts, (interval, burst), plausibility, warnings));
    }
    hide_strikes_after_gaps(&log.t, interval, &mut strokes, &mut warnings);
    checks_and_tops(calibration.as_ref(), &log, &a, (&burst, &rests), &mut strokes);
    let length = falls.as_ref().map(|f| f.length);
    let phases = phases(&log.t, &rests, &mut strokes, &theta, (opts.full_swing, length));
    radial_clip_warning(&log.t, &rclip, &strokes, &mut warnings);
    let set_side = set_side(&log.t, &theta, &phases, &strokes);
    label_hand(&mut strokes, set_side);
    let clappering_starts = clappering_start(&strong_onsets(&log, &onsets), &phases, &strokes);
    let jack = calibration_spread(
        calibration.as_ref(),
        (&oriented, &stretches),
        &a,
        (&burst, interval),
        &mut strokes,
    );
    let (odd_struck, odd_struck_calibration_se, odd_struck_withheld) =
        odd_struck_judged(&strokes, jack, set_side, a.misfit <= MAX_MISFIT);
    warnings.extend(odd_struck_withheld.clone());
    Ok(LogAnalysis {
        phases,
        odd_struck,
        odd_struck_calibration_se,
        odd_struck_withheld,
        strokes,
        clappering_starts,
        sensor_along: a.h,
        sensor_across: a.d,
        angle_misfit: a.misfit,
        sensor_fitted: a.fitted,
        interval,
        theta,
        burst,
        set_side,
        orientation,
        calibration,
        plausibility,
        warnings,
    })
}

/// The readings with the headstock's ring taken out (`unring`, when
/// reading through the ringing): the log, which burst samples' tangential
/// readings are still shaken, the samples the angle's fits leave out, and
/// those read on the tangential axis alone. Each axis's clipping is read
/// on the readings as logged (`raw`: the calibration's gains move the
/// calibrated ones off the range).
#[allow(clippy::type_complexity)]
fn ring_taken_out<'a>(
    raw: &AccelLog,
    log: Cow<'a, AccelLog>,
    (burst, bad, rclip): (&[bool], &[bool], &[bool]),
    onsets: &[usize],
    opts: &LogOptions,
) -> (Cow<'a, AccelLog>, Vec<bool>, Vec<bool>, Vec<bool>) {
    if !opts.through_ringing {
        return (log, burst.to_vec(), bad.to_vec(), rclip.to_vec());
    }
    let clipped = [&raw.radial, &raw.tangential, &raw.axle]
        .map(|a| a.iter().map(|v| v.abs() >= 0.99 * opts.clip).collect::<Vec<bool>>());
    let u = unrung(&log, (burst, bad), &clipped, onsets);
    // A cleaned sample is read on what it has: both axes, or the
    // tangential alone where the radial clips.
    let fit_bad = (0..bad.len()).map(|k| bad[k] && u.usable[k] == 0).collect();
    let lone = (0..bad.len()).map(|k| rclip[k] || u.usable[k] == 1).collect();
    (Cow::Owned(u.log), u.shaken, fit_bad, lone)
}

/// The angle and its smoothed form held within ±200 deg of the bottom (a
/// bell set past the balance, 185 deg say, reads more than 180 deg, not a
/// wrap to -175, and a strike's shaking cannot wind it round), and the
/// rests found on it by the slope over ±0.5 s (still to a few hundredths
/// of a rad/s).
#[allow(clippy::type_complexity)]
fn bounded_and_rests(
    t: &[f64],
    (raw, raw_smooth): (&[f64], &[f64]),
    burst: &[bool],
    interval: f64,
) -> (Vec<f64>, Vec<f64>, Vec<(f64, f64, f64)>) {
    let theta = bounded(raw);
    let smooth = bounded(raw_smooth);
    let (level, slow, _) = quadratic_fits(t, &theta, burst, 0.5);
    let rests = rests(t, &level, &slow, interval);
    (theta, smooth, rests)
}

/// The ringing's odd-struckness with its standard error, the
/// calibration's share of it (ms), and why it is withheld where it is.
#[allow(clippy::type_complexity)]
fn odd_struck_judged(
    strokes: &[LogStroke],
    jack: Option<f64>,
    set_side: Option<f64>,
    fits: bool,
) -> (Option<(f64, f64)>, Option<f64>, Option<String>) {
    let with_se = odd_struck_with_se(strokes, jack);
    let (odd_struck, withheld) = odd_struck_checked(with_se.map(|o| (o.0, o.1)), set_side, fits);
    (odd_struck, odd_struck.and(with_se.map(|o| o.2)), withheld)
}

/// Each stroke's moment of greatest speed and its bottom's standard error
/// from the calibration's covariance (`checks`); its turning point read
/// from the swing's time where the headstock's ringing hid it, and its
/// stand on the stay (`tops`).
fn checks_and_tops(
    calibration: Option<&Calibration>,
    log: &AccelLog,
    a: &Angle,
    (burst, rests): (&[bool], &[(f64, f64, f64)]),
    strokes: &mut [LogStroke],
) {
    checks::speed_peaks(&log.t, &a.joint_rate, &a.cubic, burst, strokes);
    if let Some(c) = calibration {
        checks::bottom_errors(c, log, &a.joint_rate, strokes);
        if let Some(length) = c.length {
            tops::timed_tops(&log.t, burst, rests, length, strokes);
        }
    }
    tops::stands(log, burst, rests, strokes);
}

/// The calibration's own uncertainty (when the log was calibrated):
/// refitted without each part of the log's free `stretches` (of the
/// oriented, uncalibrated log `raw`), the bottoms re-read with each; each
/// stroke's `bdc_se` widened, and the odd-struckness's jackknife standard
/// error (s).
fn calibration_spread(
    calibration: Option<&Calibration>,
    (raw, stretches): (&AccelLog, &[Stretch]),
    a: &Angle,
    (burst, interval): (&[bool], f64),
    strokes: &mut [LogStroke],
) -> Option<f64> {
    calibration?;
    let refits = checks::jackknife(raw, stretches);
    checks::jackknife_errors(
        &refits,
        raw,
        (&a.joint_rate, &a.acc),
        (burst, &a.cubic),
        interval,
        strokes,
    )
}

/// The angle (method step 2) read with the samples `bad` left out, and how
/// well it is read (its misfit) judged off the bursts `burst`: read
/// through the headstock's ringing, the shaken samples are in the angle's
/// fits as noise, but judged with them a log whose headstock clips for a
/// second after each strike (as Data141's) read 10 % off g and fell back
/// to the tangential zeros, its bottoms 9 ms off.
fn judged_angle(
    log: &AccelLog,
    (bad, rclip, out): (&[bool], &[bool], &[bool]),
    given: Option<f64>,
    falls: Option<&Falls>,
    interval: f64,
) -> Angle {
    let mut a = angle(log, (bad, rclip), given, falls, interval);
    a.misfit = misfit(log, out, (a.h, a.d), &a.joint_rate, &a.acc);
    a
}

/// Swings that are no pendulum's (a vibration, noise about gravity): their
/// timing put into `plausibility`, and why the log is not read, if so.
fn pendulum_check(plausibility: &mut Plausibility, strokes: &[LogStroke]) -> Option<String> {
    (plausibility.half_swing, plausibility.irregularity) =
        half_swing(&strokes.iter().map(|s| (s.bdc, s.amplitude)).collect::<Vec<_>>());
    plausibility.why_not()
}

/// What is said of a log that does not look like a bell's: nothing read
/// (no phases, no swings, no odd-struckness), the plain angle for a plot.
fn not_a_ringing_log(
    log: &AccelLog,
    opts: &LogOptions,
    (interval, burst): (f64, Vec<bool>),
    plausibility: Plausibility,
    warnings: Vec<String>,
) -> LogAnalysis {
    let n = log.t.len();
    let plain: Vec<f64> = (0..n).map(|k| log.tangential[k].atan2(log.radial[k])).collect();
    LogAnalysis {
        phases: vec![],
        strokes: vec![],
        odd_struck: None,
        odd_struck_calibration_se: None,
        odd_struck_withheld: None,
        clappering_starts: None,
        sensor_along: opts.sensor_along.unwrap_or(0.0),
        sensor_across: 0.0,
        sensor_fitted: false,
        angle_misfit: f64::NAN,
        interval,
        theta: plain,
        burst,
        set_side: None,
        orientation: None,
        calibration: None,
        plausibility,
        warnings,
    }
}

/// The log checked, its median sample interval (s), its bursts (mask and
/// onsets: method step 1), and a warning of its gaps.
#[allow(clippy::type_complexity)]
fn prepare(log: &AccelLog, opts: &LogOptions) -> Result<(f64, (Vec<bool>, Vec<usize>), Vec<String>), SignalError> {
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
    let rclip = radial_clipped(log, opts.clip);
    let bursty = (0..n).filter(|&k| burst[k] || rclip[k]).count();
    if bursty as f64 > 0.9 * n as f64 {
        return Err(SignalError::Invalid(format!(
            "{bursty} of {n} samples are clipped or bursts: nothing left to read the swing from (is the range right?)"
        )));
    }
    Ok((interval, (burst, onsets), warnings))
}

/// The log the right way up ([`orientation`], when `find_down`), and
/// which way it was read.
fn orient_log<'a>(
    log: &'a AccelLog,
    burst: &[bool],
    find_down: bool,
    warnings: &mut Vec<String>,
) -> (Option<Orientation>, Cow<'a, AccelLog>) {
    let orientation = find_down.then(|| orientation(log, burst));
    match orientation {
        Some(o) if o.flipped => {
            warnings.push(format!(
                "the sensor reads the bell upside down on the axes given ({} small swings to and fro centred near 180 deg): its radial and tangential axes are turned over (give --axes to override)",
                o.swings
            ));
            let turned = AccelLog {
                radial: log.radial.iter().map(|v| -v).collect(),
                tangential: log.tangential.iter().map(|v| -v).collect(),
                ..log.clone()
            };
            (orientation, Cow::Owned(turned))
        }
        Some(o) if o.swings < orient::MIN_SWINGS => {
            warnings.push(format!(
                "which way is down cannot be told from this log ({} small swing(s) to and fro, {} needed): the axes are taken as given",
                o.swings,
                orient::MIN_SWINGS
            ));
            (orientation, Cow::Borrowed(log))
        }
        _ => (orientation, Cow::Borrowed(log)),
    }
}

/// The log with its sensor calibrated, the calibration, and its rests.
struct Calibrated<'a> {
    calibration: Option<Calibration>,
    log: Cow<'a, AccelLog>,
    /// Rests (start, end, mean angle; s, s, rad) on the calibrated readings.
    still: Vec<(f64, f64, f64)>,
    /// The quiet stretches it was fitted on (empty without a calibration).
    stretches: Vec<Stretch>,
}

/// Rests from the plain angle atan2(tangential, radial), smoothed over ±0.5 s.
fn plain_rests(log: &AccelLog, burst: &[bool], interval: f64) -> Vec<(f64, f64, f64)> {
    let n = log.t.len();
    let plain: Vec<f64> = (0..n).map(|k| log.tangential[k].atan2(log.radial[k])).collect();
    let (level, slow, _) = quadratic_fits(&log.t, &unwrap_fill(&log.t, &plain, burst), burst, 0.5);
    rests(&log.t, &level, &slow, interval)
}

/// The sensor calibrated from the log's quiet stretches (rests, free
/// swings, falls from the balance): per-axis gains and offsets, its tilt,
/// and its place; without enough free stretches, the rests' scale and tilt.
fn calibrate_log<'a>(
    log: &Cow<'a, AccelLog>,
    burst: &[bool],
    interval: f64,
    warnings: &mut Vec<String>,
) -> Calibrated<'a> {
    let n = log.t.len();
    let still0 = plain_rests(log, burst, interval);
    let (calibration, stretches) = {
        let plain: Vec<f64> = (0..n).map(|k| log.tangential[k].atan2(log.radial[k])).collect();
        let (fine, _, _) = quadratic_fits(&log.t, &unwrap_fill(&log.t, &plain, burst), burst, 0.1);
        let turns = orient::turning_points(&fine, 5f64.to_radians());
        let stretches = calibrate::quiet_stretches(log, burst, &still0, (&fine, &turns));
        let c = calibrate::calibrate(log, &stretches).filter(|c| c.free >= MIN_FREE && c.length.is_some());
        (c, stretches)
    };
    let Some(c) = calibration else {
        warnings.push(
            "the log has no free swing nor fall from the balance to calibrate the sensor on: its offsets are not told from a tilt (the bottoms may be off by tens of ms)".into(),
        );
        let log = match calibrate_from_rests(log, burst, &still0, warnings) {
            Some(l) => Cow::Owned(l),
            None => log.clone(),
        };
        return Calibrated {
            calibration,
            log,
            still: still0,
            stretches: vec![],
        };
    };
    calibration_warnings(&c, warnings);
    let gain = 0.5 * (c.gain[0] + c.gain[1]);
    let (tangential, radial): (Vec<f64>, Vec<f64>) = (0..n).map(|k| c.apply(log.tangential[k], log.radial[k])).unzip();
    let calibrated = AccelLog {
        tangential,
        radial,
        axle: log.axle.iter().map(|a| a / gain).collect(),
        ..(**log).clone()
    };
    // The rests again, on the calibrated readings.
    let still = plain_rests(&calibrated, burst, interval);
    Calibrated {
        calibration,
        log: Cow::Owned(calibrated),
        still,
        stretches,
    }
}

/// What the calibration found, and whether its free swings tell enough.
fn calibration_warnings(c: &Calibration, warnings: &mut Vec<String>) {
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
}

/// Where the sensor's place came from, when it was read from the log.
fn place_warning(a: &Angle, falls: Option<&Falls>, warnings: &mut Vec<String>) {
    let (h, across) = (a.h, a.d);
    match (a.fitted, falls) {
        (true, Some(f)) => warnings.push(format!(
            "sensor place read from {} fall(s) from the balance: {h:.3} m above the pivot, {across:.3} m across the axis (the bell's equivalent pendulum {:.3} m; give --sensor-m when known)",
            f.count, f.length
        )),
        (true, None) => warnings.push(format!(
            "sensor place fitted: {h:.3} m above the pivot, {across:.3} m across the axis (give --sensor-m when known)"
        )),
        _ => {}
    }
}

/// A warning when the radial axis clipped alone at the ringing's bottoms:
/// how many, and for how long at most (those samples' radial readings are
/// lost; the bottoms are timed from the tangential axis alone).
fn radial_clip_warning(t: &[f64], rclip: &[bool], strokes: &[LogStroke], warnings: &mut Vec<String>) {
    let ringing = strokes.iter().filter(|s| s.phase == PhaseKind::Ringing).count();
    let mut clipped = 0;
    let mut longest = 0.0f64;
    for s in strokes.iter().filter(|s| s.phase == PhaseKind::Ringing) {
        let k = t.partition_point(|&x| x < s.bdc).min(t.len() - 1);
        if !(rclip[k] || rclip[k.saturating_sub(1)]) {
            continue;
        }
        clipped += 1;
        let (mut a, mut b) = (k, k);
        while a > 0 && rclip[a - 1] {
            a -= 1;
        }
        while b + 1 < t.len() && rclip[b + 1] {
            b += 1;
        }
        longest = longest.max(t[b] - t[a]);
    }
    if clipped > 0 {
        warnings.push(format!(
            "the radial axis clips at the bottom of {clipped} of {ringing} ringing swing(s) (for up to {:.0} ms: the sensor is far from the pivot for its range): those readings are left out and the bottoms timed from the tangential axis alone, the angle there less sure",
            1e3 * longest
        ));
    }
}

/// The strokes (method step 3) from the angle `(theta, smooth)`, or, when
/// the angle could not be read, from the tangential reading's zeros.
fn read_strokes(
    log: &AccelLog,
    (theta, smooth): (&[f64], &[f64]),
    a: &Angle,
    (burst, shaken, onsets): (&[bool], &[bool], &[usize]),
    rests: &[(f64, f64, f64)],
    (falls, interval): (Option<&Falls>, f64),
    warnings: &mut Vec<String>,
) -> Vec<LogStroke> {
    if a.misfit > MAX_MISFIT {
        warnings.push(format!(
            "the swing's own accelerations at the sensor are too large to read the angle (the corrected force is {:.0} % off g): bottoms from the tangential reading's zeros, amplitudes from the turning points",
            100.0 * a.misfit
        ));
        return strokes_by_zeros(log, theta, (burst, onsets), rests);
    }
    // Two bottoms come at least half a small swing apart (π √(L/g) for
    // a free pendulum, the shortest): within 60 % of that the second is
    // the strike's shaking read as a crossing. Without L, 0.3 s.
    let min_gap = falls.map_or(0.3, |f| (0.6 * std::f64::consts::PI * (f.length / G).sqrt()).max(0.3));
    strokes(
        log,
        theta,
        smooth,
        (&a.rate, &a.joint_rate, &a.acc, a.h, a.d),
        (burst, shaken, onsets, &a.cubic),
        rests,
        (min_gap, interval, falls.map_or(0.0, |f| f.kappa)),
    )
}

/// The times (s) of the burst onsets that are a clapper's strike beyond
/// doubt: within 60 ms some axis departs by half a g or more from the
/// sample before (a strike shakes the headstock far harder, often past the
/// sensor's range; a ringer's tug at the rope jolts the reading less).
fn strong_onsets(log: &AccelLog, onsets: &[usize]) -> Vec<f64> {
    let axes = [&log.radial, &log.tangential, &log.axle];
    onsets
        .iter()
        .filter(|&&k| {
            k > 0
                && (k..log.t.len())
                    .take_while(|&j| log.t[j] - log.t[k] <= STRIKE_S)
                    .any(|j| axes.iter().any(|a| (a[j] - a[k - 1]).abs() >= 0.5 * G))
        })
        .map(|&k| log.t[k])
        .collect()
}

/// Where clappering starts while raising: the first strike ([`strong_onsets`],
/// s) of the first raising phase. One before the raising's
/// first bottom read (the clapper struck as the ringer pulled the bell off
/// from hanging, its swing too slow through the bottom to be read: Data141
/// at 38.85 s, read as 40.1 s when only the strokes' strikes counted) is
/// in the swing that rises to the turning point the first stroke falls
/// from; else the first raising stroke's strike (its bottom if a gap
/// hides the strike).
fn clappering_start(onsets: &[f64], phases: &[Phase], strokes: &[LogStroke]) -> Option<ClapperingStart> {
    let raising = phases.iter().find(|p| p.kind == PhaseKind::Raising)?;
    let mut ours = strokes
        .iter()
        .filter(|s| s.phase == PhaseKind::Raising && s.bdc >= raising.start);
    let first = ours.clone().next()?;
    let early = onsets.iter().copied().find(|&x| x >= raising.start && x < first.bdc);
    if let Some(x) = early {
        return Some(ClapperingStart {
            t: x,
            amplitude: first.amplitude,
            // Rising to the side the first stroke falls from, it fell from the other.
            hand: !first.hand,
        });
    }
    ours.find(|s| s.strike.is_some() || s.strike_hidden)
        .map(|s| ClapperingStart {
            t: s.strike.unwrap_or(s.bdc),
            amplitude: s.amplitude,
            hand: s.hand,
        })
}

/// The side the bell was set on before it was rung (θ's sign; `None`
/// without a set).
fn set_side(t: &[f64], theta: &[f64], phases: &[Phase], strokes: &[LogStroke]) -> Option<f64> {
    let n = t.len();
    phases
        .iter()
        .enumerate()
        .find(|(i, p)| p.kind == PhaseKind::Up && phases.get(i + 1).is_some_and(|q| q.kind == PhaseKind::Ringing))
        .or_else(|| phases.iter().enumerate().find(|(_, p)| p.kind == PhaseKind::Up))
        .map(|(_, p)| {
            // The side the first stroke after it fell from (the set's own
            // angle, a degree from the balance, may read either side).
            strokes.iter().find(|s| s.bdc > p.end).map_or_else(
                || {
                    let mid = t.partition_point(|&x| x < 0.5 * (p.start + p.end)).min(n - 1);
                    theta[mid].signum()
                },
                |s| s.from_side,
            )
        })
}

/// The odd-struckness `odd` (s, and its standard error) kept only when it
/// says something: else `None` and why (an independent tester's logs read
/// −113.7 ± 38625 ms; and −43.3 ± 1.9 ms for a truth of −4.2, −98.7 ±
/// 13.2 for −14.9, hand and back swapped, where the angle could not be
/// read: `angle_read` false, the strokes from the tangential zeros).
fn odd_struck_checked(
    odd: Option<(f64, f64)>,
    set_side: Option<f64>,
    angle_read: bool,
) -> (Option<(f64, f64)>, Option<String>) {
    let Some((o, se)) = odd else {
        return (None, None);
    };
    let why = if se.is_nan() || se > MAX_ODD_SE {
        format!(
            "odd-struckness withheld: {:+.1} ms with a standard error of {:.1} ms (over {:.0} ms) says nothing",
            o * 1e3,
            se * 1e3,
            MAX_ODD_SE * 1e3
        )
    } else if !angle_read {
        format!(
            "odd-struckness withheld ({:+.1} ± {:.1} ms): the angle could not be read, so which side a swing falls from, and so which stroke is the handstroke, is not sure",
            o * 1e3,
            se * 1e3
        )
    } else if set_side.is_none() {
        format!(
            "odd-struckness withheld ({:+.1} ± {:.1} ms): the bell is not seen set, so which stroke is the handstroke is not known",
            o * 1e3,
            se * 1e3
        )
    } else {
        return (odd, None);
    };
    (None, Some(why))
}

/// The ringing's odd-struckness and its standard error: the strokes'
/// spread, and the calibration's share: the larger of its covariance's
/// (an error in the bottoms' zero moves hand and back bottoms opposite
/// ways, so the difference by twice the mean bottom error) and `jack`, the
/// jackknife's over the calibration's free stretches (s), which also
/// holds what the covariance leaves out (a model the stretches fit
/// differently).
fn odd_struck_with_se(strokes: &[LogStroke], jack: Option<f64>) -> Option<(f64, f64, f64)> {
    odd_struck(strokes).map(|(o, se)| {
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
        let cal = cal.max(jack.unwrap_or(0.0));
        (o, se.hypot(cal), cal)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stroke(bdc: f64, strike: Option<f64>, hand: bool) -> LogStroke {
        LogStroke {
            bdc,
            hand,
            strike,
            strike_hidden: false,
            strike_theta: None,
            amplitude: 0.4,
            from_side: 1.0,
            phase: PhaseKind::Raising,
            speed_peak: None,
            bdc_se: None,
            stand: None,
            amplitude_timed: false,
        }
    }

    /// An odd-struckness whose standard error is over 50 ms (an
    /// independent tester's log read −113.7 ± 38625 ms), or read with no
    /// set to tell hand from back, is withheld with why; one with a
    /// modest error on a set bell is kept.
    #[test]
    fn an_odd_struckness_that_says_nothing_is_withheld() {
        let (o, why) = odd_struck_checked(Some((-0.1137, 38.6252)), Some(1.0), true);
        assert!(o.is_none());
        assert!(why.expect("why").contains("standard error of 38625.2 ms"));
        let (o, why) = odd_struck_checked(Some((0.0728, 0.0015)), None, true);
        assert!(o.is_none());
        assert!(why.expect("why").contains("not seen set"));
        let (o, why) = odd_struck_checked(Some((-0.0433, 0.0019)), Some(1.0), false);
        assert!(o.is_none());
        assert!(why.expect("why").contains("angle could not be read"));
        assert_eq!(
            odd_struck_checked(Some((-0.0326, 0.0032)), Some(-1.0), true),
            (Some((-0.0326, 0.0032)), None)
        );
        assert_eq!(odd_struck_checked(None, None, false), (None, None));
    }

    /// A strike before the raising's first bottom read starts the
    /// clappering (Data141: 38.85 s, read as 40.1 s, the first stroke's
    /// strike); one before the raising (a knock while down) does not; with
    /// none before the first bottom, the first stroke's strike.
    #[test]
    fn clappering_starts_at_the_first_strike_of_the_raising() {
        let phases = [
            Phase {
                kind: PhaseKind::Down,
                start: 0.0,
                end: 31.5,
            },
            Phase {
                kind: PhaseKind::Raising,
                start: 31.5,
                end: 120.0,
            },
        ];
        let strokes = [stroke(39.49, Some(40.1), true), stroke(40.14, None, false)];
        let c = clappering_start(&[20.0, 38.85, 40.1], &phases, &strokes).expect("a start");
        assert_eq!(c.t, 38.85);
        assert!(!c.hand, "the swing before a handstroke");
        let c = clappering_start(&[20.0, 40.1], &phases, &strokes).expect("a start");
        assert_eq!(c.t, 40.1);
        assert!(c.hand);
    }
}
