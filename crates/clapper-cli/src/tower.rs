//! `clapper tower`: a ring rung through a touch in its tower (docs/tower.md).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use clapper_app::tower::{history_csv, spectrum_csv, tower, TowerAnswer, TowerRequest};
use clapper_plot::tower::{thin, tower_plot, Curve, TowerPlot};
use clapper_plot::RGBColor;

/// What to ring, in which tower, and what to write.
#[derive(Args, Debug)]
pub struct TowerArgs {
    /// The ring: a CSV or TOML ring file; its bells may give their place
    /// in the frame (swing or swing_deg, frame_x_m, frame_y_m,
    /// pivot_height_m) and a TOML ring its tower ([tower] table).
    pub ring: PathBuf,
    /// The tower's sway (TOML: tables `[east_west]` and `[north_south]`, each with
    /// frequency_hz, damping_ratio, modal_mass_kg) [default: the ring's
    /// [tower] table; without either, forces only].
    #[arg(long, value_name = "FILE")]
    pub tower: Option<PathBuf>,
    /// A method by title ("Plain Bob Major", "Stedman Triples", ...) or
    /// "rounds" [default: rounds].
    #[arg(long, value_name = "TITLE")]
    pub method: Option<String>,
    /// A method's place notation instead (with --stage), e.g. x18x18x18x18,12.
    #[arg(long, value_name = "PN", requires = "stage")]
    pub place_notation: Option<String>,
    /// The place notation's number of bells.
    #[arg(long, value_name = "N")]
    pub stage: Option<u8>,
    /// Plain leads rung [default: 1].
    #[arg(long, value_name = "N", conflicts_with = "changes")]
    pub leads: Option<usize>,
    /// Changes rung (a method's plain course repeated; rounds' rows) [default
    /// for rounds: four per bell].
    #[arg(long, value_name = "N")]
    pub changes: Option<usize>,
    /// Rows read from a file instead, one a line ("12345678"; # comments).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["method", "place_notation"])]
    pub rows: Option<PathBuf>,
    /// Peal speed: hours for 5,040 changes.
    #[arg(long, value_name = "HOURS", default_value_t = 3.0)]
    pub peal_speed: f64,
    /// The interval between successive strikes (ms) instead of the peal speed.
    #[arg(long, value_name = "MS", conflicts_with = "peal_speed")]
    pub interval: Option<f64>,
    /// The gap before each handstroke row (intervals).
    #[arg(long, value_name = "N", default_value_t = 1.0)]
    pub handstroke_gap: f64,
    /// The band's striking errors: each strike's standard deviation (ms).
    #[arg(long, value_name = "MS", default_value_t = 0.0)]
    pub striking_sd: f64,
    /// Seed of the striking errors.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Sampling interval of the histories (s).
    #[arg(long, value_name = "S", default_value_t = 0.01)]
    pub dt: f64,
    /// Every bell rung from this balance angle (deg) [default: each bell's
    /// fitted so that a stroke lasts half a whole pull].
    #[arg(long, value_name = "DEG")]
    pub theta0: Option<f64>,
    /// R of every clapper [default: each bell file's, else 0.2].
    #[arg(long, value_name = "R")]
    pub restitution: Option<f64>,
    /// Bells (from 1) turned 90 deg in the frame, e.g. 7,8.
    #[arg(long, value_name = "BELLS", value_delimiter = ',')]
    pub turn: Vec<usize>,
    /// Print the report as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write the histories (forces, moments, sway) as CSV.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write the forces' spectra (to 5 Hz) as CSV.
    #[arg(long, value_name = "FILE")]
    pub spectrum_csv: Option<PathBuf>,
    /// Plot force and sway against time and the spectrum with the tower's
    /// frequencies marked (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// Rows from a rows file: one a line, blank lines and # comments skipped.
fn read_rows(text: &str) -> Vec<String> {
    text.lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty())
        .map(str::to_string)
        .collect()
}

/// A pair of curves, east-west in blue and north-south in orange.
fn east_north(east: Vec<(f64, f64)>, north: Vec<(f64, f64)>) -> Vec<Curve> {
    let (blue, orange) = (RGBColor(49, 130, 189), RGBColor(230, 85, 13));
    vec![
        Curve {
            label: "east-west".into(),
            points: east,
            colour: blue,
        },
        Curve {
            label: "north-south".into(),
            points: north,
            colour: orange,
        },
    ]
}

fn plot(path: &std::path::Path, a: &TowerAnswer) -> Result<()> {
    let r = &a.result;
    const MAX: usize = 6000;
    let series = |x: &[f64], scale: f64| -> Vec<(f64, f64)> {
        let pts: Vec<(f64, f64)> = x.iter().enumerate().map(|(i, v)| (r.time(i), v * scale)).collect();
        thin(&pts, MAX)
    };
    let forces = east_north(series(&r.force_east, 1e-3), series(&r.force_north, 1e-3));
    let sway = match &r.sway {
        Some([e, n]) => east_north(series(&e.displacement, 1e3), series(&n.displacement, 1e3)),
        None => vec![],
    };
    let spec = |s: &clapper_tower::spectrum::Spectrum| -> Vec<(f64, f64)> {
        let pts: Vec<(f64, f64)> = s
            .amplitude
            .iter()
            .enumerate()
            .map(|(i, v)| (s.frequency(i), v * 1e-3))
            .take_while(|p| p.0 <= 4.0)
            .collect();
        thin(&pts, MAX)
    };
    let spectra = east_north(spec(&r.spectrum_east), spec(&r.spectrum_north));
    let marks = a
        .report
        .tower
        .map(|t| {
            vec![
                (
                    format!("tower E-W {:.2} Hz", t.east_west.frequency_hz),
                    t.east_west.frequency_hz,
                ),
                (
                    format!("tower N-S {:.2} Hz", t.north_south.frequency_hz),
                    t.north_south.frequency_hz,
                ),
            ]
        })
        .unwrap_or_default();
    let p = TowerPlot {
        title: a.report.touch.clone(),
        forces,
        sway,
        spectra,
        marks,
    };
    crate::files::write_atomically(path, |tmp| Ok(tower_plot(tmp, &p)?))
}

/// `clapper tower`.
pub fn run(args: TowerArgs) -> Result<()> {
    if let Some(p) = &args.plot {
        clapper_plot::format_of(p)?;
    }
    crate::files::claim_stdout(
        &[
            ("--csv", args.csv.as_deref()),
            ("--spectrum-csv", args.spectrum_csv.as_deref()),
        ],
        args.json,
    )?;
    let ring_text = crate::files::read_text(&args.ring, "a ring file")?;
    let csv = args.ring.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let tower_text = match &args.tower {
        Some(p) => Some(crate::files::read_text(p, "a tower file")?),
        None => None,
    };
    let rows = match &args.rows {
        Some(p) => Some(read_rows(&crate::files::read_text(p, "a rows file")?)),
        None => None,
    };
    let req = TowerRequest {
        method: args.method.clone(),
        place_notation: args.place_notation.clone(),
        stage: args.stage,
        leads: args.leads,
        changes: args.changes,
        rows,
        peal_hours: args.peal_speed,
        interval_ms: args.interval,
        handstroke_gap: args.handstroke_gap,
        striking_sd_ms: args.striking_sd,
        seed: args.seed,
        dt_s: args.dt,
        theta0_deg: args.theta0,
        restitution: args.restitution,
        turn: args.turn.clone(),
    };
    let name = crate::files::title_name(&args.ring);
    let answer = tower(&req, &ring_text, csv, &name, tower_text.as_deref())
        .with_context(|| format!("cannot ring {}", args.ring.display()))?;
    if let Some(p) = &args.csv {
        crate::files::write_bytes(p, history_csv(&answer.result))?;
    }
    if let Some(p) = &args.spectrum_csv {
        crate::files::write_bytes(p, spectrum_csv(&answer.result, 5.0))?;
    }
    if let Some(p) = &args.plot {
        plot(p, &answer)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&answer.report)?);
    } else if crate::files::stdout_is_data() {
        eprint!("{}", answer.report.text());
    } else {
        print!("{}", answer.report.text());
    }
    Ok(())
}
