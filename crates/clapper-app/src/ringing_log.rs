//! A real bell's motion from an accelerometer log (`clapper ringing-log`):
//! the report (its JSON keeps issue 24's names: `bell`, `phases`,
//! `strokes` with `bdc_s`, `stroke`, `strike_s`, `bdc_to_strike_ms`,
//! `amplitude_deg`, and `odd_struck_ms`), the summary text, and, with a
//! bell file, the model beside the log: the simulated BDC-to-strike at each
//! stroke's measured amplitude, the pivot offset that would make the
//! model as odd-struck as the log, and the pendulum period from the log's
//! swings against the file's.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use clapper_core::elliptic::complete_k;
use clapper_core::prelude::*;
use clapper_core::ringing::odd_struck;
use clapper_io::LoadedBell;
use clapper_signal::ringing_log::{analyse_log, AccelLog, LogAnalysis, LogOptions, LogStroke, PhaseKind};
use clapper_signal::striking::mean_sd;
use serde::Serialize;

use crate::AppError;

/// One phase, as reported.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PhaseReport {
    /// When it ended (s).
    pub end_s: f64,
    /// "down", "raising", "up", "ringing" or "lowering".
    pub kind: &'static str,
    /// As the issue names the phases: "down", "raising", "set", "ringing
    /// with stands", "ringing without stands", "lowering from its first
    /// swing" (straight after a set or stand, no ringing between) or
    /// "lowering".
    pub name: &'static str,
    /// Stands on the stay within it (ringing), sets left out.
    pub stands: usize,
    /// When it started (s).
    pub start_s: f64,
}

/// A stroke's end on the stay, as reported.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StandReport {
    /// Its angle from the bottom (deg): where the next stroke falls from.
    pub angle_deg: f64,
    /// How long it stood (s), when read.
    pub duration_s: Option<f64>,
    /// A set (a rest at the balance), not a stand within the ringing.
    pub set: bool,
}

/// One swing, as reported.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StrokeReport {
    /// The turning point it fell from (deg).
    pub amplitude_deg: f64,
    /// Bottom dead centre (s).
    pub bdc_s: f64,
    /// Bottom dead centre to strike (ms).
    pub bdc_to_strike_ms: Option<f64>,
    /// The model's BDC-to-strike at this amplitude (ms), with a bell file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_bdc_to_strike_ms: Option<f64>,
    /// The phase it is in.
    pub phase: &'static str,
    /// "hand" or "back".
    pub stroke: &'static str,
    /// The clapper's first strike (s).
    pub strike_s: Option<f64>,
    /// True when a gap in the log hides the strike (`strike_s` is null:
    /// not known, rather than not struck); left out when false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub strike_hidden: bool,
    /// The bell's angle at the strike (deg).
    pub strike_theta_deg: Option<f64>,
    /// The moment of greatest speed near the bottom (s): a check on
    /// `bdc_s` that needs no zero of the angle.
    pub speed_peak_s: Option<f64>,
    /// The standard error of `bdc_s` the sensor's calibration leaves (ms).
    pub bdc_se_ms: Option<f64>,
    /// The stay it rose to after its strike, if it stood there (null: it
    /// turned back short of the stay).
    pub stand: Option<StandReport>,
    /// True when `amplitude_deg` was read from the swing's time, the
    /// headstock's ringing hiding its turning point; left out when false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub amplitude_timed: bool,
}

/// Mean and spread of a phase's BDC-to-strike at one stroke.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Spread {
    /// Mean (ms).
    pub mean_ms: Option<f64>,
    /// Strokes with a strike.
    pub n: usize,
    /// Standard deviation (ms).
    pub sd_ms: Option<f64>,
}

/// A phase's strokes summed up.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PhaseSummary {
    /// Mean amplitude (deg).
    pub amplitude_mean_deg: f64,
    /// Backstrokes' BDC-to-strike.
    pub back: Spread,
    /// Handstrokes' BDC-to-strike.
    pub hand: Spread,
    /// The phase.
    pub kind: &'static str,
    /// Its strokes.
    pub strokes: usize,
}

/// Where clappering starts while raising.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClapperingReport {
    /// The swing's amplitude (deg).
    pub amplitude_deg: f64,
    /// "hand" or "back".
    pub stroke: &'static str,
    /// When (s).
    pub t_s: f64,
}

/// The model beside the log (with a bell file).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelReport {
    /// The bell file's bell.
    pub bell: String,
    /// The model's odd-struckness at the ringing's mean amplitude, the bell
    /// as the file hangs it (ms).
    pub odd_struck_ms: Option<f64>,
    /// The clapper pivot's offset across the bell's axis that makes the
    /// model as odd-struck as the log (mm, toward the back side), and the
    /// odd-struckness it gives (ms).
    pub pivot_offset_for_log_mm: Option<[f64; 2]>,
    /// The bell's small-swing period from the file (s).
    pub tb_file_s: f64,
    /// The small-swing period from the log's swings under 90 deg (s), each
    /// corrected for its amplitude (2K(sin(A/2))/π); rope-driven swings, so
    /// a rough figure.
    pub tb_log_s: Option<f64>,
    /// Swings that went into it.
    pub tb_log_swings: usize,
}

/// Whether the log looks like a bell's (issue 46).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlausibilityReport {
    /// The readings' median magnitude (g): about 1 for a bell's log.
    pub gravity_g: f64,
    /// The fraction of neighbouring quiet samples between which the angle
    /// turns faster than a bell can: near 0 for a bell's log.
    pub angle_jumps: f64,
    /// The median time from one bottom to the next over neighbouring swings
    /// under 90 deg (s): half the pendulum's period, 0.55 to 3 s for a bell
    /// (null when too few such swings were read).
    pub half_swing_s: Option<f64>,
    /// The median change between neighbouring such half swings' times, over
    /// the longer: at most 0.25 for a bell (a pendulum's: a few hundredths).
    pub swing_irregularity: Option<f64>,
    /// Whether it looks like a bell's log (else nothing is read from it).
    pub plausible: bool,
}

/// What `clapper ringing-log --json` prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LogReport {
    /// The bell's name, if the log gives one.
    pub bell: Option<String>,
    /// Clappering's start while raising.
    pub clappering_starts: Option<ClapperingReport>,
    /// The model beside the log, with a bell file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelReport>,
    /// Mean handstroke minus mean backstroke BDC-to-strike while ringing (ms).
    pub odd_struck_ms: Option<f64>,
    /// Its standard error (ms): the strokes' scatter and the calibration's
    /// share together.
    pub odd_struck_se_ms: Option<f64>,
    /// The calibration's share of it (ms): the larger of the calibration's
    /// covariance propagated and its jackknife (refitted without each part
    /// of the log's free stretches, the bottoms re-read with each).
    pub odd_struck_calibration_se_ms: Option<f64>,
    /// Why the odd-struckness is null though the ringing was read (its
    /// standard error too large, or hand and back not told apart).
    pub odd_struck_withheld: Option<String>,
    /// Each phase's strokes summed up.
    pub phase_summary: Vec<PhaseSummary>,
    /// The phases.
    pub phases: Vec<PhaseReport>,
    /// The median sample interval (ms).
    pub sample_interval_ms: f64,
    /// The sensor's distance above the pivot (m).
    pub sensor_m: f64,
    /// The sensor's distance across the bell's axis (m), fitted.
    pub sensor_across_m: f64,
    /// How well the angle was read: the corrected force's median departure
    /// from g while the bell moves, as a fraction of g.
    pub angle_misfit_g: f64,
    /// Whether it was fitted from the log (not given).
    pub sensor_fitted: bool,
    /// Every swing.
    pub strokes: Vec<StrokeReport>,
    /// Whether the log looks like a bell's at all.
    pub plausibility: PlausibilityReport,
    /// Things worth knowing.
    pub warnings: Vec<String>,
}

/// A log read: the report, and the analysis (angle per sample, bursts) for plots.
pub struct LogReading {
    /// The report.
    pub report: LogReport,
    /// The analysis.
    pub analysis: LogAnalysis,
}

fn hand(s: &LogStroke) -> &'static str {
    if s.hand {
        "hand"
    } else {
        "back"
    }
}

fn spread(v: &[f64]) -> Spread {
    let ms = mean_sd(v);
    Spread {
        mean_ms: ms.map(|(m, _)| m * 1e3),
        n: v.len(),
        // One strike has no spread.
        sd_ms: ms.filter(|_| v.len() > 1).map(|(_, sd)| sd * 1e3),
    }
}

/// Read `log` (and set it beside `bell`, the bell file read, if given).
pub fn read_log(log: &AccelLog, opts: &LogOptions, bell: Option<LoadedBell>) -> Result<LogReading, AppError> {
    let a = analyse_log(log, opts).map_err(|e| AppError::Request(e.to_string()))?;
    let model_times = match &bell {
        Some(b) => model_times(b, &a)?,
        None => BTreeMap::new(),
    };
    let strokes = a
        .strokes
        .iter()
        .map(|s| StrokeReport {
            amplitude_deg: s.amplitude.to_degrees(),
            bdc_s: s.bdc,
            bdc_to_strike_ms: s.bdc_to_strike().map(|x| x * 1e3),
            model_bdc_to_strike_ms: model_times
                .get(&key(s.amplitude))
                .and_then(|t| if s.hand { t.0 } else { t.1 })
                .map(|x| x * 1e3),
            phase: s.phase.name(),
            stroke: hand(s),
            strike_s: s.strike,
            strike_hidden: s.strike_hidden,
            strike_theta_deg: s.strike_theta.map(f64::to_degrees),
            speed_peak_s: s.speed_peak,
            bdc_se_ms: s.bdc_se.map(|x| x * 1e3),
            stand: s.stand.map(|x| StandReport {
                angle_deg: x.angle.to_degrees(),
                duration_s: x.duration,
                set: x.set,
            }),
            amplitude_timed: s.amplitude_timed,
        })
        .collect();
    let phase_summary = phase_summaries(&a.strokes);
    let model = match bell {
        Some(b) => Some(model_report(&b, &a)?),
        None => None,
    };
    let report = LogReport {
        bell: log.name.clone(),
        clappering_starts: a.clappering_starts.map(|c| ClapperingReport {
            amplitude_deg: c.amplitude.to_degrees(),
            stroke: if c.hand { "hand" } else { "back" },
            t_s: c.t,
        }),
        model,
        odd_struck_ms: a.odd_struck.map(|o| o.0 * 1e3),
        odd_struck_se_ms: a.odd_struck.map(|o| o.1 * 1e3),
        odd_struck_calibration_se_ms: a.odd_struck_calibration_se.map(|x| x * 1e3),
        odd_struck_withheld: a.odd_struck_withheld.clone(),
        phase_summary,
        phases: phase_reports(&a),
        sample_interval_ms: a.interval * 1e3,
        sensor_m: a.sensor_along,
        sensor_across_m: a.sensor_across,
        angle_misfit_g: a.angle_misfit,
        sensor_fitted: a.sensor_fitted,
        strokes,
        plausibility: PlausibilityReport {
            gravity_g: a.plausibility.gravity,
            angle_jumps: a.plausibility.jumps,
            half_swing_s: a.plausibility.half_swing,
            swing_irregularity: a.plausibility.irregularity,
            plausible: a.plausibility.plausible(),
        },
        warnings: a.warnings.clone(),
    };
    Ok(LogReading { report, analysis: a })
}

/// The phases, named as the issue names them, with their stands.
fn phase_reports(a: &LogAnalysis) -> Vec<PhaseReport> {
    a.phases
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let stands = a
                .strokes
                .iter()
                .filter(|s| s.phase == p.kind && s.bdc >= p.start && s.bdc <= p.end)
                .filter(|s| s.stand.is_some_and(|x| !x.set))
                .count();
            let after_set = i > 0 && a.phases[i - 1].kind == PhaseKind::Up;
            let name = match p.kind {
                PhaseKind::Up => "set",
                PhaseKind::Ringing if stands > 0 => "ringing with stands",
                PhaseKind::Ringing => "ringing without stands",
                PhaseKind::Lowering if after_set => "lowering from its first swing",
                k => k.name(),
            };
            PhaseReport {
                end_s: p.end,
                kind: p.kind.name(),
                name,
                stands,
                start_s: p.start,
            }
        })
        .collect()
}

/// Each phase's strokes summed up: their mean amplitude and the spread
/// of their bottom-to-strike times, hand and back.
fn phase_summaries(strokes: &[LogStroke]) -> Vec<PhaseSummary> {
    let kinds = [PhaseKind::Raising, PhaseKind::Ringing, PhaseKind::Lowering];
    kinds
        .iter()
        .filter_map(|&k| {
            let of: Vec<&LogStroke> = strokes.iter().filter(|s| s.phase == k).collect();
            (!of.is_empty()).then(|| {
                let times = |h: bool| -> Vec<f64> {
                    of.iter()
                        .filter(|s| s.hand == h)
                        .filter_map(|s| s.bdc_to_strike())
                        .collect()
                };
                PhaseSummary {
                    amplitude_mean_deg: of.iter().map(|s| s.amplitude.to_degrees()).sum::<f64>() / of.len() as f64,
                    back: spread(&times(false)),
                    hand: spread(&times(true)),
                    kind: k.name(),
                    strokes: of.len(),
                }
            })
        })
        .collect()
}

/// Amplitudes to the half degree: the model is simulated once for each.
fn key(amplitude: f64) -> i64 {
    (amplitude.to_degrees() * 2.0).round() as i64
}

/// The model's (hand, back) BDC-to-strike (s) by amplitude key.
type ModelTimes = BTreeMap<i64, (Option<f64>, Option<f64>)>;

/// The model's (hand, back) BDC-to-strike (s) at each ringing or large
/// amplitude of the log (90 deg and over: below, ringing up or down, the
/// rope's pull, which the model of a stroke leaves out, matters).
fn model_times(b: &LoadedBell, a: &LogAnalysis) -> Result<ModelTimes, AppError> {
    let cfg = config(b)?;
    let mut out = BTreeMap::new();
    for s in a.strokes.iter().filter(|s| s.amplitude >= 90f64.to_radians()) {
        let k = key(s.amplitude);
        if out.contains_key(&k) || out.len() >= 400 {
            continue;
        }
        let theta0 = (k as f64 / 2.0).min(179.5).to_radians();
        let o = odd_struck(&b.bell, &SimConfig { theta0, ..cfg }, Style::Right)?;
        out.insert(k, (o.hand.bdc_to_strike(), o.back.bdc_to_strike()));
    }
    Ok(out)
}

/// `clapper simulate`'s settings for the bell: R and R2 the file's, else
/// the defaults (θ0 is set per stroke).
fn config(b: &LoadedBell) -> Result<SimConfig, AppError> {
    crate::simulate::SimulateRequest::default().config_for(b)
}

fn model_report(b: &LoadedBell, a: &LogAnalysis) -> Result<ModelReport, AppError> {
    let cfg = config(b)?;
    let ringing: Vec<&LogStroke> = a.strokes.iter().filter(|s| s.phase == PhaseKind::Ringing).collect();
    let mean_amp =
        (!ringing.is_empty()).then(|| ringing.iter().map(|s| s.amplitude).sum::<f64>() / ringing.len() as f64);
    let odd_at = |offset: f64, theta0: f64| -> Result<Option<f64>, AppError> {
        let mut bell = b.bell;
        bell.hanging.pivot_offset = offset;
        Ok(odd_struck(&bell, &SimConfig { theta0, ..cfg }, Style::Right)?.odd_struck())
    };
    let (mut model_odd, mut offset_for_log) = (None, None);
    if let Some(theta0) = mean_amp.map(|x| x.min(179f64.to_radians())) {
        let d0 = b.bell.hanging.pivot_offset;
        model_odd = odd_at(d0, theta0)?;
        if let (Some(now), Some((target, _))) = (model_odd, a.odd_struck) {
            // Newton's method on the offset, the slope over half a millimetre.
            let (mut d, mut v) = (d0, now);
            for _ in 0..6 {
                if (v - target).abs() < 2e-4 {
                    break;
                }
                let (Some(p), Some(m)) = (odd_at(d + 5e-4, theta0)?, odd_at(d - 5e-4, theta0)?) else {
                    break;
                };
                let slope = (p - m) / 1e-3;
                if slope == 0.0 || !slope.is_finite() {
                    break;
                }
                d = (d - (v - target) / slope).clamp(-0.05, 0.05);
                match odd_at(d, theta0)? {
                    Some(nv) => v = nv,
                    None => break,
                }
            }
            if (v - target).abs() < 1e-3 {
                offset_for_log = Some([d * 1e3, v * 1e3]);
            }
        }
    }
    // The small-swing period from consecutive bottoms of swings under 90 deg.
    let mut periods: Vec<f64> = a
        .strokes
        .windows(2)
        .filter(|w| {
            w[0].amplitude < 90f64.to_radians() && w[1].amplitude < 90f64.to_radians() && w[1].bdc - w[0].bdc < 5.0
        })
        .map(|w| {
            let amp = 0.5 * (w[0].amplitude + w[1].amplitude);
            let k = (amp / 2.0).sin();
            let factor = 2.0 * complete_k((1.0 - k * k).sqrt()) / std::f64::consts::PI;
            2.0 * (w[1].bdc - w[0].bdc) / factor
        })
        .collect();
    periods.sort_by(f64::total_cmp);
    Ok(ModelReport {
        bell: b.name.clone(),
        odd_struck_ms: model_odd.map(|x| x * 1e3),
        pivot_offset_for_log_mm: offset_for_log,
        tb_file_s: b.bell.tb(),
        tb_log_s: periods.get(periods.len() / 2).copied(),
        tb_log_swings: periods.len(),
    })
}

fn opt(v: Option<f64>, digits: usize, unit: &str) -> String {
    v.map_or("none".into(), |x| format!("{x:.digits$} {unit}"))
}

/// A line for each phase, with its stands.
fn phase_lines(r: &LogReport, o: &mut String) {
    for p in &r.phases {
        let stands = if p.stands > 0 {
            format!(" ({} stand{})", p.stands, if p.stands == 1 { "" } else { "s" })
        } else {
            String::new()
        };
        let _ = writeln!(o, "  {:<29} {:>8.1} s to {:>8.1} s{stands}", p.name, p.start_s, p.end_s);
    }
}

/// A line for each stand on the stay (sets left out: the phases show
/// them), and how many amplitudes were read from the swing's time.
fn stand_lines(r: &LogReport, o: &mut String) {
    for s in &r.strokes {
        let Some(x) = s.stand.as_ref().filter(|x| !x.set) else {
            continue;
        };
        let _ = writeln!(
            o,
            "stand after the {} at {:.1} s ({}): {:.1} deg{}",
            s.stroke,
            s.bdc_s,
            s.phase,
            x.angle_deg,
            x.duration_s.map_or(String::new(), |d| format!(", {d:.1} s"))
        );
    }
    let timed = r.strokes.iter().filter(|s| s.amplitude_timed).count();
    if timed > 0 {
        let _ = writeln!(
            o,
            "{timed} amplitude(s) read from the swing's time: the headstock's ringing hid the turning point"
        );
    }
}

/// A line for each phase's swings: amplitude and BDC to strike.
fn summary_lines(r: &LogReport, o: &mut String) {
    for s in &r.phase_summary {
        let line = |x: &Spread| match (x.mean_ms, x.sd_ms) {
            (Some(m), Some(sd)) => format!("{m:.1} ms ± {sd:.1} ({})", x.n),
            (Some(m), None) => format!("{m:.1} ms ({})", x.n),
            _ => "no strikes".into(),
        };
        let _ = writeln!(
            *o,
            "  {}: {} swings, mean amplitude {:.1} deg; BDC to strike: hand {}, back {}",
            s.kind,
            s.strokes,
            s.amplitude_mean_deg,
            line(&s.hand),
            line(&s.back)
        );
    }
}

/// The summary `clapper ringing-log` prints.
pub fn text(r: &LogReport) -> String {
    let mut o = String::new();
    if !r.plausibility.plausible {
        let _ = writeln!(
            o,
            "{}: samples every {:.1} ms, not read as a ringing log",
            r.bell.as_deref().unwrap_or("the log"),
            r.sample_interval_ms
        );
        for w in &r.warnings {
            let _ = writeln!(o, "warning: {w}");
        }
        return o;
    }
    let _ = writeln!(
        o,
        "{}: {} swing(s), samples every {:.1} ms, sensor {:.3} m above the pivot{} and {:.3} m across",
        r.bell.as_deref().unwrap_or("the bell"),
        r.strokes.len(),
        r.sample_interval_ms,
        r.sensor_m,
        if r.sensor_fitted { " (fitted)" } else { "" },
        r.sensor_across_m
    );
    phase_lines(r, &mut o);
    summary_lines(r, &mut o);
    let _ = writeln!(
        o,
        "odd-struck (hand minus back, ringing): {}{}{}",
        opt(r.odd_struck_ms, 1, "ms"),
        r.odd_struck_se_ms.map_or(String::new(), |se| format!(
            " ± {se:.1} ms{}",
            r.odd_struck_calibration_se_ms
                .map_or(String::new(), |c| format!(" (the calibration's share {c:.1} ms)"))
        )),
        if r.odd_struck_withheld.is_some() {
            " (withheld: see the warnings)"
        } else {
            ""
        }
    );
    if let Some(c) = &r.clappering_starts {
        let _ = writeln!(
            o,
            "raising: clappering starts at {:.1} s, a {} of {:.0} deg",
            c.t_s, c.stroke, c.amplitude_deg
        );
    }
    stand_lines(r, &mut o);
    if let Some(m) = &r.model {
        let _ = writeln!(
            o,
            "beside the model ({}): odd-struck {} at the ringing's amplitude; {}; period from the log {} ({} swings) against the file's {:.3} s",
            m.bell,
            opt(m.odd_struck_ms, 1, "ms"),
            m.pivot_offset_for_log_mm.map_or("no pivot offset found that matches the log".into(), |[d, v]| format!(
                "a clapper pivot {d:+.1} mm across the axis gives the log's {v:.1} ms"
            )),
            opt(m.tb_log_s, 3, "s"),
            m.tb_log_swings,
            m.tb_file_s
        );
    }
    for w in &r.warnings {
        let _ = writeln!(o, "warning: {w}");
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_io::bell_file::BellSource;
    use clapper_signal::ringing_log_synth::{synth_log, LogSpec};

    #[test]
    fn the_model_finds_the_offset_that_made_the_log() {
        // A log of the tenor hung 3 mm off, read beside the tenor hung
        // true: the offset that matches the log is about 3 mm.
        let mut odd = Bell::gsm_tenor();
        odd.hanging.pivot_offset = 0.003;
        let mut spec = LogSpec::new(odd, 11);
        spec.strokes = 16;
        let (log, truth) = synth_log(&spec).expect("log");
        let file = LoadedBell::new("tenor".into(), Bell::gsm_tenor(), BellSource::MassProperties);
        let r = read_log(&log, &LogOptions::default(), Some(file)).expect("read").report;
        let m = r.model.clone().expect("model");
        let [d, v] = m.pivot_offset_for_log_mm.expect("an offset");
        assert!(
            (d - 3.0).abs() < 0.3,
            "offset {d} mm (odd-struck {v} ms, truth {:?})",
            truth.odd_struck
        );
        assert!(
            m.odd_struck_ms.expect("model").abs() < 1.0,
            "a true bell is not odd-struck"
        );
        // The model's BDC-to-strike beside the log's, ringing.
        let ringing: Vec<&StrokeReport> = r.strokes.iter().filter(|s| s.phase == "ringing").collect();
        assert!(ringing.iter().all(|s| s.model_bdc_to_strike_ms.is_some()));
        // The period from the small swings is the bell's, roughly.
        let tb = m.tb_log_s.expect("a period");
        assert!((tb / m.tb_file_s - 1.0).abs() < 0.1, "{tb} against {}", m.tb_file_s);
        assert!(text(&r).contains("odd-struck"));
    }
}
