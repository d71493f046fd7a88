//! `clapper ring-up` and `clapper ring-down`.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use clapper_app::ring_up::{ring, summary, RingReport};
use clapper_app::simulate::SimulateRequest;
use clapper_core::ringer::{RingerConfig, DEFAULT_DOWN_DEG, DEFAULT_PULL_WINDOW_DEG, DEFAULT_STAY_DEG};
use clapper_plot::chart::Series;
use clapper_plot::RGBColor;

use crate::simulate::{set_hanging, BellArgs, HangingArgs, SolverArgs};

/// How the ringer rings it up or down, and what to print.
#[derive(Args, Debug)]
pub struct RingArgs {
    #[command(flatten)]
    pub source: BellArgs,
    /// Swings from start to finish (a ringer takes 10-20 whole pulls, two
    /// swings each, to raise a bell); sets the pull unless --pull-force.
    #[arg(long, value_name = "N", default_value_t = RingerConfig::default().swings)]
    pub swings: usize,
    /// The rope force (N) instead: the bell takes what swings it takes.
    #[arg(long, value_name = "N")]
    pub pull_force: Option<f64>,
    /// Wheel radius (m): where the rope acts on the bell.
    #[arg(long, value_name = "M", default_value_t = RingerConfig::default().wheel_radius)]
    pub wheel_radius: f64,
    /// Half-width of the pulled part of each swing, from the bottom (deg).
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_PULL_WINDOW_DEG)]
    pub pull_window: f64,
    /// The stay (deg, measured round the far side of the balance): the set
    /// bell rests on it, 180 minus this past the balance; ringing up ends
    /// set on it, ringing down starts from it.
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_STAY_DEG)]
    pub stay: f64,
    /// Ringing down: finished when a swing reaches no further (deg).
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_DOWN_DEG)]
    pub down: f64,
    /// Stronge's energy coefficient of restitution R [default: the bell
    /// file's, else 0.2].
    #[arg(long, value_name = "R")]
    pub restitution: Option<f64>,
    /// Override the bell's contact angle phi_max (deg).
    #[arg(long, value_name = "DEG")]
    pub phi_max: Option<f64>,
    #[command(flatten)]
    pub solver: SolverArgs,
    #[command(flatten)]
    pub hanging: HangingArgs,
    /// Print the result as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Plot the amplitude and the strikes swing by swing (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

impl RingArgs {
    fn ringer(&self) -> RingerConfig {
        RingerConfig {
            swings: self.swings,
            pull_force: self.pull_force,
            wheel_radius: self.wheel_radius,
            window: self.pull_window.to_radians(),
            stay: self.stay.to_radians(),
            down: self.down.to_radians(),
            ..RingerConfig::default()
        }
    }

    fn request(&self) -> SimulateRequest {
        let mut req = SimulateRequest {
            preset: self.source.preset,
            chart_point: self.source.chart_point.map(|(x, y)| [x, y]),
            restitution: self.restitution,
            phi_max: self.phi_max,
            ..SimulateRequest::default()
        };
        self.solver.set(&mut req);
        set_hanging!(req, self.hanging);
        req
    }
}

fn plot(path: &std::path::Path, r: &RingReport) -> Result<()> {
    let pts = |style: &str| -> Vec<(f64, f64)> {
        r.swings
            .iter()
            .filter(|s| s.style == Some(style))
            .map(|s| (s.number as f64, s.amplitude_deg))
            .collect()
    };
    let series = [
        Series {
            label: "angle reached (deg)".into(),
            points: r.swings.iter().map(|s| (s.number as f64, s.amplitude_deg)).collect(),
            markers: false,
            dashed: false,
            colour: RGBColor(90, 90, 90),
        },
        Series {
            label: "strikes right (leading side)".into(),
            points: pts("right"),
            markers: true,
            dashed: false,
            colour: RGBColor(49, 130, 189),
        },
        Series {
            label: "strikes wrong (trailing side)".into(),
            points: pts("wrong"),
            markers: true,
            dashed: false,
            colour: RGBColor(230, 85, 13),
        },
    ];
    let title = format!("Ringing {} {}", r.direction, r.bell);
    crate::files::write_atomically(path, |tmp| {
        Ok(clapper_plot::line_plot(
            tmp,
            &title,
            "swing",
            "angle reached (deg)",
            &series,
        )?)
    })
}

/// `clapper ring-up` (`up`) or `clapper ring-down`.
pub fn run(args: RingArgs, up: bool) -> Result<()> {
    if let Some(p) = &args.plot {
        clapper_plot::format_of(p)?;
    }
    let report = ring(&args.request(), args.source.file()?, &args.ringer(), up)?;
    if let Some(p) = &args.plot {
        plot(p, &report)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", summary(&report));
    }
    Ok(())
}
