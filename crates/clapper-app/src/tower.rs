//! `clapper tower`: a ring rung through a touch in its tower (issue 47,
//! docs/tower.md): the forces on the frame, their spectra, the tower's
//! sway and the resonance risk, and which bells to turn.

use clapper_core::stroke::SimConfig;
use clapper_io::bell_file::LoadedBell;
use clapper_tower::rows::{parse_row, row_text, MAX_TOUCH_ROWS};
use clapper_tower::spectrum::Spectrum;
use clapper_tower::touch::{BellSummary, SwaySummary, TurnEffect, MIN_DT_S};
use clapper_tower::{ring_touch, touch_rows, FramePlace, RingBell, Timing, TouchResult, TouchSpec, Tower};
use serde::{Deserialize, Serialize};

use crate::AppError;

/// What to ring and how. The defaults are the command line's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TowerRequest {
    /// A method's title ("Plain Bob Major"), or "rounds" (the default).
    pub method: Option<String>,
    /// A method's place notation instead of a known title's.
    pub place_notation: Option<String>,
    /// Its stage (bells), with `place_notation`.
    pub stage: Option<u8>,
    /// Plain leads rung.
    pub leads: Option<usize>,
    /// Changes rung (rounds: rows; a method: its plain course repeated).
    pub changes: Option<usize>,
    /// Rows given one by one ("12345678"), instead of a method.
    pub rows: Option<Vec<String>>,
    /// Peal speed: hours for 5,040 changes. Default 3.
    pub peal_hours: f64,
    /// The interval between strikes (ms) instead of the peal speed.
    pub interval_ms: Option<f64>,
    /// The handstroke gap (intervals). Default 1.
    pub handstroke_gap: f64,
    /// The band's striking: each strike's standard deviation (ms). Default 0.
    pub striking_sd_ms: f64,
    /// Seed of the striking errors. Default 1.
    pub seed: u64,
    /// Sampling interval of the histories (s). Default 0.01.
    pub dt_s: f64,
    /// Every bell rung from this balance angle (deg); default: each bell's
    /// fitted to the band's speed.
    pub theta0_deg: Option<f64>,
    /// R of every clapper [default: each bell file's, else 0.2].
    pub restitution: Option<f64>,
    /// Bells (from 1) turned 90 deg in the frame before ringing.
    pub turn: Vec<usize>,
}

impl Default for TowerRequest {
    fn default() -> Self {
        Self {
            method: None,
            place_notation: None,
            stage: None,
            leads: None,
            changes: None,
            rows: None,
            peal_hours: 3.0,
            interval_ms: None,
            handstroke_gap: 1.0,
            striking_sd_ms: 0.0,
            seed: 1,
            dt_s: 0.01,
            theta0_deg: None,
            restitution: None,
            turn: vec![],
        }
    }
}

/// A spectral line of the horizontal force.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Line {
    /// Frequency (Hz).
    pub frequency_hz: f64,
    /// Its frequency over the whole pull's.
    pub harmonic: f64,
    /// Amplitude east-west (N).
    pub east_n: f64,
    /// Amplitude north-south (N).
    pub north_n: f64,
}

/// Peaks over the touch.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Peaks {
    /// Largest |force east| (N).
    pub force_east_n: f64,
    /// Largest |force north| (N).
    pub force_north_n: f64,
    /// Largest resultant horizontal force (N).
    pub force_resultant_n: f64,
    /// Largest vertical load above the bells' weight (N).
    pub vertical_n: f64,
    /// Largest |moment tilting east| about the base (N m).
    pub moment_east_n_m: f64,
    /// Largest |moment tilting north| (N m).
    pub moment_north_n_m: f64,
    /// Largest |torsion| (N m).
    pub torsion_n_m: f64,
}

/// One direction's sway and its resonance risk.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DirectionReport {
    /// "east-west" or "north-south".
    pub direction: &'static str,
    /// Its numbers.
    #[serde(flatten)]
    pub summary: SwaySummary,
    /// Dynamic amplification of the nearest harmonic:
    /// 1/√((1 − ρ²)² + (2ζρ)²), ρ the harmonic's frequency over the tower's.
    pub amplification: f64,
    /// "resonant" (the harmonic within the tower's half-power band,
    /// |1 − ρ| ≤ ζ), "near" (within 3ζ) or "clear".
    pub risk: &'static str,
}

/// The answer: the report, and the histories for the CSV and the plot.
#[derive(Clone, Debug)]
pub struct TowerAnswer {
    /// The report (JSON and text).
    pub report: TowerReport,
    /// The histories.
    pub result: TouchResult,
}

/// What `clapper tower` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TowerReport {
    /// The touch rung.
    pub touch: String,
    /// Rows rung.
    pub rows: usize,
    /// Its first and last rows.
    pub first_row: String,
    /// The last row.
    pub last_row: String,
    /// From the first sample to the last (s).
    pub duration_s: f64,
    /// Interval between strikes (ms).
    pub interval_ms: f64,
    /// A whole pull (s).
    pub whole_pull_s: f64,
    /// The band's striking (ms).
    pub striking_sd_ms: f64,
    /// Each bell.
    pub bells: Vec<BellSummary>,
    /// Peaks of forces and moments.
    pub peaks: Peaks,
    /// The strongest lines of the horizontal force between 0.1 and 5 Hz.
    pub lines: Vec<Line>,
    /// The tower, if given.
    pub tower: Option<Tower>,
    /// Its sway in each direction, with a tower.
    pub sway: Vec<DirectionReport>,
    /// Peak resultant sway (m), with a tower.
    pub peak_sway_m: Option<f64>,
    /// Each bell turned 90 deg alone, most helpful first.
    pub turns: Vec<TurnEffect>,
    /// What was assumed where the ring file said nothing.
    pub assumed: Vec<String>,
}

fn request_error(e: impl std::fmt::Display) -> AppError {
    AppError::Request(e.to_string())
}

fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The ring's bells in their frame, and what was assumed for them.
fn ring_bells(loaded: &[LoadedBell], turn: &[usize]) -> Result<(Vec<RingBell>, Vec<String>), AppError> {
    let mut assumed = vec![];
    let missing = |what: &str, f: &dyn Fn(&LoadedBell) -> bool| -> Option<String> {
        let names: Vec<&str> = loaded.iter().filter(|b| !f(b)).map(|b| b.name.as_str()).collect();
        (!names.is_empty()).then(|| format!("{what} for {}", names.join(", ")))
    };
    if let Some(m) = missing("swing N-S (0 deg)", &|b| b.frame.swing_deg.is_some()) {
        assumed.push(m);
    }
    if let Some(m) = missing("pivot on the tower's centre line", &|b| {
        b.frame.x_m.is_some() && b.frame.y_m.is_some()
    }) {
        assumed.push(m);
    }
    if let Some(m) = missing("pivot height 0 (moments about the frame's level)", &|b| {
        b.frame.pivot_height_m.is_some()
    }) {
        assumed.push(m);
    }
    for &t in turn {
        if t == 0 || t > loaded.len() {
            return Err(AppError::Request(format!(
                "--turn {t}: bells count from 1 to {}",
                loaded.len()
            )));
        }
    }
    let bells = loaded
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let place = FramePlace {
                swing_deg: b.frame.swing_deg.unwrap_or(0.0),
                x_m: b.frame.x_m.unwrap_or(0.0),
                y_m: b.frame.y_m.unwrap_or(0.0),
                pivot_height_m: b.frame.pivot_height_m.unwrap_or(0.0),
            };
            RingBell {
                name: b.name.clone(),
                bell: b.bell,
                restitution: b.restitution,
                place: if turn.contains(&(i + 1)) { place.turned() } else { place },
            }
        })
        .collect();
    Ok((bells, assumed))
}

/// The touch asked for, and its description.
fn touch_spec(req: &TowerRequest, n_bells: usize) -> Result<(TouchSpec, String), AppError> {
    if let Some(rows) = &req.rows {
        let rows: Vec<Vec<u8>> = rows
            .iter()
            .map(|r| parse_row(r))
            .collect::<Result<_, _>>()
            .map_err(request_error)?;
        let d = format!("{} rows given", rows.len());
        return Ok((TouchSpec::Rows { rows }, d));
    }
    let method = req.method.as_deref().unwrap_or("rounds");
    if method.eq_ignore_ascii_case("rounds") && req.place_notation.is_none() {
        if req.leads.is_some() {
            return Err(AppError::Request("rounds has no leads: give --changes".into()));
        }
        let rows = req.changes.unwrap_or(4 * n_bells);
        return Ok((TouchSpec::Rounds { rows }, format!("rounds, {rows} rows")));
    }
    let how = match (req.leads, req.changes) {
        (Some(l), None) => format!("{l} lead(s)"),
        (None, Some(c)) => format!("{c} changes"),
        (None, None) => "1 lead".into(),
        _ => return Err(AppError::Request("give --leads or --changes, not both".into())),
    };
    Ok((
        TouchSpec::Method {
            title: method.to_string(),
            place_notation: req.place_notation.clone(),
            stage: req.stage,
            leads: req.leads,
            changes: req.changes,
        },
        format!("{method}, {how}"),
    ))
}

/// A ring, its tower and what to ring, as the web API and Python take
/// them: `{"toml": RING} or {"csv": RING}, "tower": TOML?, "request": {...}}`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TowerInput {
    /// The ring as TOML text (`[[bell]]` tables; may hold `[tower]`).
    #[serde(default)]
    pub toml: Option<String>,
    /// The ring as CSV text, one bell a row.
    #[serde(default)]
    pub csv: Option<String>,
    /// The tower file's text.
    #[serde(default)]
    pub tower: Option<String>,
    /// What to ring.
    #[serde(default)]
    pub request: TowerRequest,
}

/// [`tower`] on a [`TowerInput`], refusing touches of more than
/// `max_rows` rows (a server's bound on its memory: 5,040 rows of eight
/// bells hold about 100 MB of histories).
pub fn tower_input(input: &TowerInput, max_rows: Option<usize>) -> Result<TowerAnswer, AppError> {
    let (text, csv) = match (&input.toml, &input.csv) {
        (Some(t), None) => (t, false),
        (None, Some(c)) => (c, true),
        _ => return Err(AppError::Request("give the ring as one of toml or csv".into())),
    };
    tower_bounded(&input.request, text, csv, "bell", input.tower.as_deref(), max_rows)
}

/// Ring `req` on the ring read from `ring_text` (CSV when `csv`), in the
/// tower read from `tower_text` or else the ring's own `[tower]` table.
pub fn tower(
    req: &TowerRequest,
    ring_text: &str,
    csv: bool,
    name: &str,
    tower_text: Option<&str>,
) -> Result<TowerAnswer, AppError> {
    tower_bounded(req, ring_text, csv, name, tower_text, None)
}

fn tower_bounded(
    req: &TowerRequest,
    ring_text: &str,
    csv: bool,
    name: &str,
    tower_text: Option<&str>,
    max_rows: Option<usize>,
) -> Result<TowerAnswer, AppError> {
    let loaded = if csv {
        clapper_io::parse_ring_csv(ring_text)?
    } else {
        clapper_io::parse_bells(ring_text, name)?
    };
    let tower = match tower_text {
        Some(t) => Some(clapper_io::tower_file::parse_tower(t)?),
        None if !csv => clapper_io::tower_file::ring_tower(ring_text)?,
        None => None,
    };
    let (bells, assumed) = ring_bells(&loaded, &req.turn)?;
    let n = bells.len();
    let (spec, touch) = touch_spec(req, n)?;
    if let (Some(max), TouchSpec::Rounds { rows: k }) = (max_rows, &spec) {
        if *k > max {
            return Err(AppError::Request(format!("{k} rows: at most {max} here")));
        }
    }
    if let (Some(max), TouchSpec::Method { changes: Some(k), .. }) = (max_rows, &spec) {
        if *k > max {
            return Err(AppError::Request(format!("{k} changes: at most {max} here")));
        }
    }
    check_request(req)?;
    let rows = touch_rows(&spec, n).map_err(request_error)?;
    if let Some(max) = max_rows.filter(|m| rows.len() > m + 1) {
        return Err(AppError::Request(format!("{} rows: at most {max} here", rows.len())));
    }
    let interval_s = match req.interval_ms {
        Some(ms) => ms / 1000.0,
        None => Timing::interval_for_peal_speed(req.peal_hours, n, req.handstroke_gap),
    };
    let timing = Timing {
        interval_s,
        handstroke_gap: req.handstroke_gap,
        striking_sd_ms: req.striking_sd_ms,
        seed: req.seed,
        dt_s: req.dt_s,
        theta0: req.theta0_deg.map(f64::to_radians),
    };
    // Each bell's own R where its file gives one, unless the request sets one for all.
    let mut bells = bells;
    if let Some(r) = req.restitution {
        bells.iter_mut().for_each(|b| b.restitution = Some(r));
    }
    let cfg = SimConfig::default();
    let result = ring_touch(&bells, &rows, &timing, &cfg, tower.as_ref()).map_err(request_error)?;
    let report = report(&result, touch, tower, assumed);
    Ok(TowerAnswer { report, result })
}

/// The request's numbers in their ranges, each refused in its option's
/// words and units; counts bounded before anything is allocated.
fn check_request(req: &TowerRequest) -> Result<(), AppError> {
    use clapper_core::param::readable;
    let refuse = |m: String| Err(AppError::Request(m));
    let max = MAX_TOUCH_ROWS;
    if let Some(c) = req.changes.filter(|&c| c == 0 || c > max) {
        return refuse(format!("--changes {c}: a touch of 1 to {max} changes"));
    }
    // Every lead is at least two changes.
    if let Some(l) = req.leads.filter(|&l| l == 0 || l > max / 2) {
        return refuse(format!("--leads {l}: from 1 lead to a touch of at most {max} changes"));
    }
    let in_range = |v: f64, lo: f64, hi: f64| v.is_finite() && (lo..=hi).contains(&v);
    if !in_range(req.peal_hours, 1.0, 12.0) {
        return refuse(format!(
            "--peal-speed {} h: a peal rung in 1 to 12 hours",
            readable(req.peal_hours)
        ));
    }
    if let Some(ms) = req.interval_ms.filter(|&ms| !in_range(ms, 20.0, 5000.0)) {
        return refuse(format!(
            "--interval {} ms: strikes from 20 to 5000 ms apart",
            readable(ms)
        ));
    }
    if !in_range(req.handstroke_gap, 0.0, 4.0) {
        return refuse(format!(
            "--handstroke-gap {} intervals: from 0 to 4 intervals",
            readable(req.handstroke_gap)
        ));
    }
    if !in_range(req.striking_sd_ms, 0.0, 200.0) {
        return refuse(format!(
            "--striking-sd {} ms: a band's striking errors from 0 to 200 ms",
            readable(req.striking_sd_ms)
        ));
    }
    if !in_range(req.dt_s, MIN_DT_S, 0.05) {
        return refuse(format!(
            "--dt {} s: histories sampled every {MIN_DT_S} to 0.05 s",
            readable(req.dt_s)
        ));
    }
    if let Some(r) = req.restitution.filter(|&r| !in_range(r, 0.0, 1.0)) {
        return refuse(format!(
            "--restitution {}: a coefficient of restitution from 0 to 1",
            readable(r)
        ));
    }
    Ok(())
}

/// Dynamic amplification of a harmonic at ρ = its frequency over the tower's.
fn amplification(rho: f64, zeta: f64) -> f64 {
    1.0 / ((1.0 - rho * rho).powi(2) + (2.0 * zeta * rho).powi(2)).sqrt()
}

fn report(r: &TouchResult, touch: String, tower: Option<Tower>, assumed: Vec<String>) -> TowerReport {
    let f_pull = 1.0 / r.whole_pull_s;
    let lines = lines(&r.spectrum_east, &r.spectrum_north, f_pull);
    let sway = r
        .sway_summary
        .iter()
        .flat_map(|s| s.iter().zip(["east-west", "north-south"]))
        .map(|(s, direction)| {
            let rho = s.nearest_harmonic.1 / s.sway.frequency_hz;
            let amplification = amplification(rho, s.sway.damping_ratio);
            DirectionReport {
                direction,
                summary: *s,
                amplification,
                risk: if (1.0 - rho).abs() <= s.sway.damping_ratio {
                    "resonant"
                } else if (1.0 - rho).abs() <= 3.0 * s.sway.damping_ratio {
                    "near"
                } else {
                    "clear"
                },
            }
        })
        .collect();
    let vertical_max = r.vertical.iter().fold(0.0f64, |m, &v| m.max(v));
    TowerReport {
        touch,
        rows: r.rows.len(),
        first_row: row_text(&r.rows[0]),
        last_row: row_text(r.rows.last().expect("rows checked non-empty")),
        duration_s: r.dt * (r.force_east.len().saturating_sub(1)) as f64,
        interval_ms: r.timing.interval_s * 1000.0,
        whole_pull_s: r.whole_pull_s,
        striking_sd_ms: r.timing.striking_sd_ms,
        bells: r.bells.clone(),
        peaks: Peaks {
            force_east_n: peak(&r.force_east),
            force_north_n: peak(&r.force_north),
            force_resultant_n: r.peak_force(),
            vertical_n: vertical_max,
            moment_east_n_m: peak(&r.moment_east),
            moment_north_n_m: peak(&r.moment_north),
            torsion_n_m: peak(&r.torsion),
        },
        lines,
        tower,
        sway,
        peak_sway_m: r.peak_sway(),
        turns: r.turns.clone(),
        assumed,
    }
}

/// The strongest lines of the two directions together.
fn lines(e: &Spectrum, n: &Spectrum, f_pull: f64) -> Vec<Line> {
    let both = Spectrum {
        df: e.df,
        amplitude: e.amplitude.iter().zip(&n.amplitude).map(|(a, b)| a.hypot(*b)).collect(),
    };
    both.lines(0.1, 5.0, 8)
        .into_iter()
        .map(|(f, _)| {
            let i = (f / e.df).round() as usize;
            Line {
                frequency_hz: f,
                harmonic: f / f_pull,
                east_n: e.amplitude.get(i).copied().unwrap_or(0.0),
                north_n: n.amplitude.get(i).copied().unwrap_or(0.0),
            }
        })
        .collect()
}

impl TowerReport {
    /// The report as the terminal shows it.
    pub fn text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{}: {} rows ({} .. {}), {:.1} s; interval {:.0} ms, whole pull {:.2} s ({:.3} Hz), striking sd {} ms",
            self.touch,
            self.rows,
            self.first_row,
            self.last_row,
            self.duration_s,
            self.interval_ms,
            self.whole_pull_s,
            1.0 / self.whole_pull_s,
            self.striking_sd_ms
        );
        let _ = writeln!(
            s,
            "{:<10} {:>8} {:>8} {:>7} {:>7} {:>9} {:>9}",
            "bell", "weight", "theta0", "swing", "stroke", "horiz/W", "vert/W"
        );
        for b in &self.bells {
            let _ = writeln!(
                s,
                "{:<10} {:>6.0} N {:>6.1}° {:>5.0}° {:>5.2} s {:>9.2} {:>9.2}",
                b.name,
                b.weight_n,
                b.theta0_deg,
                b.place.swing_deg,
                b.hand_stroke_s,
                b.horizontal_factor,
                b.vertical_factor
            );
        }
        let p = &self.peaks;
        let _ = writeln!(
            s,
            "peak horizontal force: east-west {:.2} kN, north-south {:.2} kN, resultant {:.2} kN; vertical above the weight {:.2} kN",
            p.force_east_n / 1e3,
            p.force_north_n / 1e3,
            p.force_resultant_n / 1e3,
            p.vertical_n / 1e3
        );
        let _ = writeln!(
            s,
            "peak moment about the base: tilting east {:.1} kN m, north {:.1} kN m; torsion {:.1} kN m",
            p.moment_east_n_m / 1e3,
            p.moment_north_n_m / 1e3,
            p.torsion_n_m / 1e3
        );
        self.lines_and_sway_text(&mut s);
        if let Some(p) = self.peak_sway_m {
            let _ = writeln!(s, "peak sway (resultant): {:.3} mm", p * 1e3);
        }
        let what = if self.peak_sway_m.is_some() {
            "peak sway"
        } else {
            "peak force"
        };
        let turns: Vec<String> = self
            .turns
            .iter()
            .take(3)
            .map(|t| format!("{} {:+.0} %", t.name, t.change_percent))
            .collect();
        let _ = writeln!(s, "a bell turned 90° changes the {what}: {}", turns.join(", "));
        for a in &self.assumed {
            let _ = writeln!(s, "assumed: {a}");
        }
        s
    }
    /// The report's strongest lines of the horizontal force and each
    /// direction's sway.
    fn lines_and_sway_text(&self, s: &mut String) {
        use std::fmt::Write;
        let lines: Vec<String> = self
            .lines
            .iter()
            .take(5)
            .map(|l| {
                format!(
                    "{:.3} Hz (x{:.2}): {:.2} kN",
                    l.frequency_hz,
                    l.harmonic,
                    l.east_n.hypot(l.north_n) / 1e3
                )
            })
            .collect();
        let _ = writeln!(s, "strongest lines of the horizontal force: {}", lines.join("; "));
        if self.sway.is_empty() {
            let _ = writeln!(
                s,
                "no tower given (--tower FILE, or a [tower] table in a TOML ring): no sway"
            );
        }
        for d in &self.sway {
            let m = &d.summary;
            let _ = writeln!(
                s,
                "sway {}: tower {:.3} Hz, nearest harmonic {} at {:.3} Hz (ratio {:.3}), amplification {:.1}: {}; peak {:.3} mm, {:.4} m/s² ({:.2} milli-g); energy in {:.3} J, damped {:.3} J, held at the end {:.3} J",
                d.direction,
                m.sway.frequency_hz,
                m.nearest_harmonic.0,
                m.nearest_harmonic.1,
                m.frequency_ratio,
                d.amplification,
                d.risk,
                m.peak_displacement_m * 1e3,
                m.peak_acceleration_m_s2,
                m.peak_acceleration_m_s2 / 9.81 * 1e3,
                m.input_work_j,
                m.damping_work_j,
                m.stored_change_j
            );
        }
    }
}

/// The histories as CSV: time, forces, moments and (with a tower) sway.
pub fn history_csv(r: &TouchResult) -> String {
    use std::fmt::Write;
    let mut s = String::from(
        "time_s,force_east_n,force_north_n,vertical_n,moment_east_n_m,moment_north_n_m,torsion_n_m,\
         sway_east_mm,sway_north_mm,accel_east_m_s2,accel_north_m_s2\n",
    );
    for i in 0..r.force_east.len() {
        let _ = write!(
            s,
            "{:.3},{:.2},{:.2},{:.2},{:.1},{:.1},{:.1}",
            r.time(i),
            r.force_east[i],
            r.force_north[i],
            r.vertical[i],
            r.moment_east[i],
            r.moment_north[i],
            r.torsion[i]
        );
        match &r.sway {
            Some([e, n]) => {
                let _ = writeln!(
                    s,
                    ",{:.5},{:.5},{:.6},{:.6}",
                    e.displacement[i] * 1e3,
                    n.displacement[i] * 1e3,
                    e.acceleration[i],
                    n.acceleration[i]
                );
            }
            None => s.push_str(",,,,\n"),
        }
    }
    s
}

/// The spectra as CSV up to `max_hz`.
pub fn spectrum_csv(r: &TouchResult, max_hz: f64) -> String {
    use std::fmt::Write;
    let mut s = String::from("frequency_hz,east_n,north_n\n");
    let e = &r.spectrum_east;
    for i in 0..e.amplitude.len() {
        let f = e.frequency(i);
        if f > max_hz {
            break;
        }
        let _ = writeln!(s, "{f:.5},{:.3},{:.3}", e.amplitude[i], r.spectrum_north.amplitude[i]);
    }
    s
}
