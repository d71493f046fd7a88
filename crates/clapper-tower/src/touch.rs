//! A ring rung through a touch: strike times from the rows and the band's
//! speed, each bell's strokes placed at its strikes, the forces and
//! moments summed in the tower's directions, the sway, the spectra and
//! the resonance risk (docs/tower.md §3 to §5).

use clapper_core::bell::Bell;
use clapper_core::stroke::SimConfig;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use serde::Serialize;

use crate::spectrum::{spectrum, Spectrum};
use crate::stroke_loads::{bell_strokes, theta0_for, BellStrokes};
use crate::sway::{respond, Sway, SwayHistory};
use crate::{FramePlace, Tower, TowerError};

/// One bell of the ring, in its frame.
#[derive(Clone, Debug, PartialEq)]
pub struct RingBell {
    /// Its name.
    pub name: String,
    /// The bell.
    pub bell: Bell,
    /// Its place in the frame.
    pub place: FramePlace,
    /// Its clapper's R, if its own (else the configuration's).
    pub restitution: Option<f64>,
}

/// How the band rings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Timing {
    /// Time between successive strikes in a row (s).
    pub interval_s: f64,
    /// The gap before each handstroke row, in intervals (1: the open
    /// handstroke lead).
    pub handstroke_gap: f64,
    /// Standard deviation of each strike's error (ms): the band's striking.
    pub striking_sd_ms: f64,
    /// Seed of the striking errors.
    pub seed: u64,
    /// The touch's clock: sampling interval of forces and sway (s).
    pub dt_s: f64,
    /// The balance angle every bell is rung from (rad); `None`: each bell's
    /// fitted so that its stroke lasts half a whole pull.
    pub theta0: Option<f64>,
}

/// The shortest sampling interval of the histories (s).
pub const MIN_DT_S: f64 = 0.001;
/// The most samples in a touch's histories: about 400 MB of them (a
/// peal of eight at 0.01 s is about 1,100,000).
pub const MAX_HISTORY_SAMPLES: usize = 4_000_000;

/// Changes in a peal, for the peal speed.
pub const PEAL_CHANGES: f64 = 5040.0;

impl Timing {
    /// The interval for a peal speed: `hours` for 5,040 changes on
    /// `n_bells` bells with the handstroke gap `gap` (intervals).
    pub fn interval_for_peal_speed(hours: f64, n_bells: usize, gap: f64) -> f64 {
        hours * 3600.0 / (PEAL_CHANGES / 2.0 * (2.0 * n_bells as f64 + gap))
    }

    /// A whole pull (handstroke and backstroke rows with the gap) (s).
    pub fn whole_pull(&self, n_bells: usize) -> f64 {
        self.interval_s * (2.0 * n_bells as f64 + self.handstroke_gap)
    }

    /// The time of place `place` (from 0) of row `row` (from 0, a
    /// handstroke), before the band's error: a handstroke row's gap before
    /// it, the first row's too.
    pub fn strike_time(&self, n_bells: usize, row: usize, place: usize) -> f64 {
        self.interval_s * ((row * n_bells + place) as f64 + (row / 2 + 1) as f64 * self.handstroke_gap)
    }

    fn validate(&self) -> Result<(), TowerError> {
        let bad = |what: String| Err(TowerError::Ring(format!("timing: {what}")));
        if !(self.interval_s.is_finite() && self.interval_s > 0.0) {
            return bad(format!(
                "the interval between strikes, {} ms, is out of range: above 0 ms",
                self.interval_s * 1e3
            ));
        }
        if !(self.handstroke_gap.is_finite() && self.handstroke_gap >= 0.0) {
            return bad(format!(
                "the handstroke gap, {} intervals, is out of range: 0 or more",
                self.handstroke_gap
            ));
        }
        if !(self.striking_sd_ms.is_finite() && self.striking_sd_ms >= 0.0) {
            return bad(format!(
                "the striking errors' standard deviation, {} ms, is out of range: 0 ms or more",
                self.striking_sd_ms
            ));
        }
        if !(self.dt_s.is_finite() && (MIN_DT_S..=0.05).contains(&self.dt_s)) {
            return bad(format!(
                "the histories' sampling interval, {} s, is out of range: from {MIN_DT_S} s to 0.05 s",
                clapper_core::param::readable(self.dt_s)
            ));
        }
        Ok(())
    }
}

/// What one bell does through the touch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BellSummary {
    /// Its name.
    pub name: String,
    /// Weight of bell and clapper (N).
    pub weight_n: f64,
    /// The balance angle it is rung from (deg).
    pub theta0_deg: f64,
    /// Handstroke's duration, balance to balance (s).
    pub hand_stroke_s: f64,
    /// Backstroke's duration (s).
    pub back_stroke_s: f64,
    /// Peak horizontal load over the weight, hand and back.
    pub horizontal_factor: f64,
    /// Peak downward load over the weight.
    pub vertical_factor: f64,
    /// Its place in the frame.
    pub place: FramePlace,
}

/// Peaks of one direction's sway and the energy it took.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SwaySummary {
    /// The direction's oscillator.
    pub sway: Sway,
    /// Peak |displacement| at the bell chamber (m).
    pub peak_displacement_m: f64,
    /// Peak |acceleration| (m/s²).
    pub peak_acceleration_m_s2: f64,
    /// Work the frame's force did on the tower (J).
    pub input_work_j: f64,
    /// Work the tower's damping took (J).
    pub damping_work_j: f64,
    /// Energy held at the end less at the start (J).
    pub stored_change_j: f64,
    /// The ringing's harmonic nearest the tower's frequency: its number
    /// (of the whole pull's frequency) and frequency (Hz).
    pub nearest_harmonic: (u32, f64),
    /// The tower's frequency over that harmonic's.
    pub frequency_ratio: f64,
    /// The force's spectral amplitude within 2 % of the tower's frequency (N).
    pub force_at_frequency_n: f64,
}

/// A bell turned 90 deg in the frame, and what it does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TurnEffect {
    /// Bell, from 0.
    pub bell: usize,
    /// Its name.
    pub name: String,
    /// Peak resultant horizontal force after turning it (N).
    pub peak_force_n: f64,
    /// Peak resultant sway displacement after turning it (m), with a tower.
    pub peak_sway_m: Option<f64>,
    /// Its change against the layout as it is (per cent; negative: less).
    pub change_percent: f64,
}

/// A touch rung in the tower.
#[derive(Clone, Debug, PartialEq)]
pub struct TouchResult {
    /// The touch's clock: time of the first sample (s) and the interval.
    pub t0: f64,
    /// Sampling interval (s).
    pub dt: f64,
    /// The rows rung.
    pub rows: Vec<Vec<u8>>,
    /// The timing.
    pub timing: Timing,
    /// A whole pull (s).
    pub whole_pull_s: f64,
    /// Each bell.
    pub bells: Vec<BellSummary>,
    /// Each bell's strike times (s), one per row.
    pub strikes: Vec<Vec<f64>>,
    /// Horizontal force on the frame towards east (N).
    pub force_east: Vec<f64>,
    /// Towards north (N).
    pub force_north: Vec<f64>,
    /// Vertical load less the bells' weight, downwards (N).
    pub vertical: Vec<f64>,
    /// Overturning moment about the base tilting the tower east (N m):
    /// east forces times their pivots' heights, plus vertical loads times
    /// their distance east of the centre line.
    pub moment_east: Vec<f64>,
    /// Likewise north (N m).
    pub moment_north: Vec<f64>,
    /// Twisting moment about the tower's vertical centre line,
    /// anticlockwise seen from above (N m).
    pub torsion: Vec<f64>,
    /// Spectrum of the east force.
    pub spectrum_east: Spectrum,
    /// Spectrum of the north force.
    pub spectrum_north: Spectrum,
    /// With a tower: its sway east-west and north-south.
    pub sway: Option<[SwayHistory; 2]>,
    /// Summaries of the two directions' sway.
    pub sway_summary: Option<[SwaySummary; 2]>,
    /// Each bell turned 90 deg, one at a time, most helpful first.
    pub turns: Vec<TurnEffect>,
}

impl TouchResult {
    /// Time of sample `i` (s).
    pub fn time(&self, i: usize) -> f64 {
        self.t0 + i as f64 * self.dt
    }

    /// Peak resultant horizontal force (N).
    pub fn peak_force(&self) -> f64 {
        peak_resultant(&self.force_east, &self.force_north)
    }

    /// Peak resultant sway displacement (m).
    pub fn peak_sway(&self) -> Option<f64> {
        self.sway
            .as_ref()
            .map(|[e, n]| peak_resultant(&e.displacement, &n.displacement))
    }
}

fn peak_resultant(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max(x.hypot(*y)))
}

fn peak_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// A standard normal deviate (Box-Muller): the band's error in one strike.
fn normal(rng: &mut Pcg64) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Each bell's strokes placed at its strikes: the stroke starts its
/// time-to-strike before the strike and runs until it ends or the next
/// stroke starts (the ringer checks the bell at the balance).
struct Placed<'a> {
    strokes: &'a [BellStrokes],
    strikes: &'a [Vec<f64>],
    t0: f64,
    dt: f64,
    n: usize,
}

impl Placed<'_> {
    /// Start of bell `b`'s stroke for row `k`.
    fn start(&self, b: usize, k: usize) -> f64 {
        let s = &self.strokes[b];
        let load = if k % 2 == 0 { &s.hand } else { &s.back };
        self.strikes[b][k] - load.to_strike
    }

    /// Bell `b`'s horizontal load along its swing (added to `h`) and its
    /// vertical load less its weight (to `v`).
    fn add(&self, b: usize, h: &mut [f64], mut v: Option<&mut [f64]>) {
        let s = &self.strokes[b];
        let rows = self.strikes[b].len();
        for k in 0..rows {
            let load = if k % 2 == 0 { &s.hand } else { &s.back };
            let start = self.start(b, k);
            let mut end = start + load.duration;
            if k + 1 < rows {
                end = end.min(self.start(b, k + 1));
            }
            let j0 = ((start - self.t0) / self.dt).ceil().max(0.0) as usize;
            let j1 = (((end - self.t0) / self.dt).ceil().max(0.0) as usize).min(self.n);
            for j in j0..j1 {
                let (hh, vv) = load.at(self.t0 + j as f64 * self.dt - start);
                h[j] += hh;
                if let Some(v) = v.as_deref_mut() {
                    v[j] += vv;
                }
            }
        }
    }
}

/// Ring `rows` on `bells` as `timing` says, each stroke simulated with
/// `cfg` (its θ0 replaced by the fitted or given balance angle); with a
/// `tower`, its sway too.
pub fn ring_touch(
    bells: &[RingBell],
    rows: &[Vec<u8>],
    timing: &Timing,
    cfg: &SimConfig,
    tower: Option<&Tower>,
) -> Result<TouchResult, TowerError> {
    timing.validate()?;
    if let Some(t) = tower {
        t.validate()?;
    }
    let n_bells = bells.len();
    if n_bells == 0 {
        return Err(TowerError::Ring("no bells".into()));
    }
    crate::rows::check_rows(rows, n_bells)?;
    let pull = timing.whole_pull(n_bells);
    let strokes = all_strokes(bells, timing, cfg, pull)?;
    let strikes = strike_times(rows, timing, n_bells);
    let dt = timing.dt_s;
    let (t0, n) = span(&strokes, &strikes, rows.len(), dt);
    // Bounded before the histories are allocated.
    if n > MAX_HISTORY_SAMPLES {
        return Err(TowerError::Ring(format!(
            "{n} samples of {dt} s: the histories hold at most {MAX_HISTORY_SAMPLES} (a longer sampling interval or a shorter touch)"
        )));
    }
    let placed = Placed {
        strokes: &strokes,
        strikes: &strikes,
        t0,
        dt,
        n,
    };
    let loads = Loads::of(bells, &placed);
    let (fe, fnn) = (loads.east, loads.north);
    let sway = tower.map(|t| [respond(&t.east_west, &fe, dt), respond(&t.north_south, &fnn, dt)]);
    let spectrum_east = spectrum(&fe, dt);
    let spectrum_north = spectrum(&fnn, dt);
    let sway_summary = match (tower, &sway) {
        (Some(t), Some([se, sn])) => Some([
            summarise(&t.east_west, se, &fe, &spectrum_east, dt, pull),
            summarise(&t.north_south, sn, &fnn, &spectrum_north, dt, pull),
        ]),
        _ => None,
    };
    let mut result = TouchResult {
        t0,
        dt,
        rows: rows.to_vec(),
        timing: *timing,
        whole_pull_s: pull,
        bells: bell_summaries(bells, &strokes),
        strikes: strikes.clone(),
        force_east: fe,
        force_north: fnn,
        vertical: loads.vertical,
        moment_east: loads.moment_east,
        moment_north: loads.moment_north,
        torsion: loads.torsion,
        spectrum_east,
        spectrum_north,
        sway,
        sway_summary,
        turns: vec![],
    };
    result.turns = turns(bells, &placed, &result, tower);
    Ok(result)
}

/// Each bell's handstroke and backstroke, from its balance angle: the
/// timing's, or the one that fits half a whole pull `pull` (s).
fn all_strokes(
    bells: &[RingBell],
    timing: &Timing,
    cfg: &SimConfig,
    pull: f64,
) -> Result<Vec<BellStrokes>, TowerError> {
    bells
        .iter()
        .map(|b| {
            let theta0 = match timing.theta0 {
                Some(t) => t,
                None => {
                    theta0_for(&b.bell, cfg, pull / 2.0).map_err(|e| TowerError::Ring(format!("{}: {e}", b.name)))?
                }
            };
            bell_strokes(&b.bell, cfg, theta0).map_err(|e| TowerError::Ring(format!("{}: {e}", b.name)))
        })
        .collect()
}

/// Each bell's strike times (s), row by row: the row's rhythm plus the
/// band's errors.
fn strike_times(rows: &[Vec<u8>], timing: &Timing, n_bells: usize) -> Vec<Vec<f64>> {
    let mut rng = Pcg64::seed_from_u64(timing.seed);
    let sd = timing.striking_sd_ms / 1000.0;
    let mut strikes = vec![Vec::with_capacity(rows.len()); n_bells];
    for (k, row) in rows.iter().enumerate() {
        for (p, &b) in row.iter().enumerate() {
            let err = if sd > 0.0 { sd * normal(&mut rng) } else { 0.0 };
            strikes[b as usize].push(timing.strike_time(n_bells, k, p) + err);
        }
    }
    strikes
}

/// The histories' start (s, a whole step of `dt`) and length (steps):
/// from the first stroke's start to the last stroke's end.
fn span(strokes: &[BellStrokes], strikes: &[Vec<f64>], rows: usize, dt: f64) -> (f64, usize) {
    let mut first = f64::INFINITY;
    let mut last = f64::NEG_INFINITY;
    for (b, s) in strokes.iter().enumerate() {
        first = first.min(strikes[b][0] - s.hand.to_strike);
        let k = rows - 1;
        let load = if k % 2 == 0 { &s.hand } else { &s.back };
        last = last.max(strikes[b][k] - load.to_strike + load.duration);
    }
    let t0 = (first / dt).floor() * dt;
    let n = ((last - t0) / dt).ceil() as usize + 1;
    (t0, n)
}

/// The whole ring's loads on the frame, step by step.
struct Loads {
    /// Horizontal force east (N).
    east: Vec<f64>,
    /// Horizontal force north (N).
    north: Vec<f64>,
    /// Vertical force above the bells' weight (N).
    vertical: Vec<f64>,
    /// Moment tilting east about the base (N m).
    moment_east: Vec<f64>,
    /// Moment tilting north about the base (N m).
    moment_north: Vec<f64>,
    /// Torsion about the vertical (N m).
    torsion: Vec<f64>,
}

impl Loads {
    /// Every bell's loads, each along its own swing, summed.
    fn of(bells: &[RingBell], placed: &Placed<'_>) -> Loads {
        let n = placed.n;
        let mut fe = vec![0.0; n];
        let mut fnn = vec![0.0; n];
        let mut vert = vec![0.0; n];
        let mut me = vec![0.0; n];
        let mut mn = vec![0.0; n];
        let mut tor = vec![0.0; n];
        let mut h = vec![0.0; n];
        let mut v = vec![0.0; n];
        for (b, rb) in bells.iter().enumerate() {
            h.iter_mut().for_each(|x| *x = 0.0);
            v.iter_mut().for_each(|x| *x = 0.0);
            placed.add(b, &mut h, Some(&mut v));
            let (ue, un) = rb.place.direction();
            let p = &rb.place;
            for j in 0..n {
                let (e, no) = (ue * h[j], un * h[j]);
                fe[j] += e;
                fnn[j] += no;
                vert[j] += v[j];
                me[j] += e * p.pivot_height_m + v[j] * p.x_m;
                mn[j] += no * p.pivot_height_m + v[j] * p.y_m;
                tor[j] += p.x_m * no - p.y_m * e;
            }
        }
        Loads {
            east: fe,
            north: fnn,
            vertical: vert,
            moment_east: me,
            moment_north: mn,
            torsion: tor,
        }
    }
}

/// Each bell's line of the report: its weight, balance, strokes and peak
/// loads over its weight.
fn bell_summaries(bells: &[RingBell], strokes: &[BellStrokes]) -> Vec<BellSummary> {
    bells
        .iter()
        .zip(strokes)
        .map(|(b, s)| BellSummary {
            name: b.name.clone(),
            weight_n: s.weight,
            theta0_deg: s.theta0.to_degrees(),
            hand_stroke_s: s.hand.duration,
            back_stroke_s: s.back.duration,
            horizontal_factor: s.hand.peak_horizontal().max(s.back.peak_horizontal()) / s.weight,
            vertical_factor: 1.0 + s.hand.peak_vertical().max(s.back.peak_vertical()) / s.weight,
            place: b.place,
        })
        .collect()
}

/// Each bell turned 90 deg alone: the peak force and sway after.
fn turns(bells: &[RingBell], placed: &Placed<'_>, r: &TouchResult, tower: Option<&Tower>) -> Vec<TurnEffect> {
    let base = match r.peak_sway() {
        Some(s) => s,
        None => r.peak_force(),
    };
    let mut h = vec![0.0; placed.n];
    let mut out: Vec<TurnEffect> = bells
        .iter()
        .enumerate()
        .map(|(b, rb)| {
            h.iter_mut().for_each(|x| *x = 0.0);
            placed.add(b, &mut h, None);
            let (ue, un) = rb.place.direction();
            let (te, tn) = rb.place.turned().direction();
            let fe: Vec<f64> = r.force_east.iter().zip(&h).map(|(f, h)| f + (te - ue) * h).collect();
            let fnn: Vec<f64> = r.force_north.iter().zip(&h).map(|(f, h)| f + (tn - un) * h).collect();
            let peak_force_n = peak_resultant(&fe, &fnn);
            let peak_sway_m = tower.map(|t| {
                let e = respond(&t.east_west, &fe, r.dt);
                let n = respond(&t.north_south, &fnn, r.dt);
                peak_resultant(&e.displacement, &n.displacement)
            });
            let now = peak_sway_m.unwrap_or(peak_force_n);
            TurnEffect {
                bell: b,
                name: rb.name.clone(),
                peak_force_n,
                peak_sway_m,
                change_percent: 100.0 * (now / base - 1.0),
            }
        })
        .collect();
    out.sort_by(|a, b| a.change_percent.total_cmp(&b.change_percent));
    out
}

/// One direction's peaks, energy and resonance.
fn summarise(s: &Sway, h: &SwayHistory, force: &[f64], spec: &Spectrum, dt: f64, pull: f64) -> SwaySummary {
    let n = force.len();
    let mut input = 0.0;
    let mut damping = 0.0;
    let c = s.damping();
    for i in 0..n.saturating_sub(1) {
        let f = 0.5 * (force[i] + force[i + 1]);
        input += f * (h.displacement[i + 1] - h.displacement[i]);
        let (v0, v1) = (h.velocity[i], h.velocity[i + 1]);
        // ∫ v² over the step for v linear in it (close for dt << period).
        damping += c * dt * (v0 * v0 + v0 * v1 + v1 * v1) / 3.0;
    }
    let energy =
        |i: usize| 0.5 * s.modal_mass_kg * h.velocity[i].powi(2) + 0.5 * s.stiffness() * h.displacement[i].powi(2);
    let f_pull = 1.0 / pull;
    let k = (s.frequency_hz / f_pull).round().max(1.0);
    SwaySummary {
        sway: *s,
        peak_displacement_m: peak_abs(&h.displacement),
        peak_acceleration_m_s2: peak_abs(&h.acceleration),
        input_work_j: input,
        damping_work_j: damping,
        stored_change_j: if n > 0 { energy(n - 1) - energy(0) } else { 0.0 },
        nearest_harmonic: (k as u32, k * f_pull),
        frequency_ratio: s.frequency_hz / (k * f_pull),
        force_at_frequency_n: spec
            .peak_in(0.98 * s.frequency_hz, 1.02 * s.frequency_hz)
            .map_or(0.0, |p| p.1),
    }
}
