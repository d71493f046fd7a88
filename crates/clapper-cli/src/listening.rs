//! `clapper listening-test make | analyse`: the double-strike listening
//! test of Section 4.3 (Fig 13).

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use clapper_core::listening;
use clapper_plot::chart::{ChartFigure, Panel, Scale};
use clapper_plot::RGBColor;
use clapper_signal::synth::{lab_partials, synthesize, Strike, SynthSpec};

#[derive(Args, Debug)]
pub struct ListeningArgs {
    #[command(subcommand)]
    pub command: ListeningCommand,
}

#[derive(Subcommand, Debug)]
pub enum ListeningCommand {
    /// Write the 100 stimuli (WAV) and an answer sheet per listener, each in
    /// a fresh random order.
    Make(MakeArgs),
    /// Average the answers, leave out listeners who stand apart, fit the
    /// hyperbola of (33) and draw the score map (Fig 13).
    Analyse(AnalyseArgs),
}

#[derive(Args, Debug)]
pub struct MakeArgs {
    /// Folder to write into.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Seed of the random orders (the same seed gives the same sheets).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Number of answer sheets.
    #[arg(long, default_value_t = 20)]
    pub listeners: u64,
    /// Sample rate (Hz).
    #[arg(long, default_value_t = 44100.0)]
    pub rate: f64,
}

#[derive(Args, Debug)]
pub struct AnalyseArgs {
    /// Filled answer sheets (CSV with listener, amplitude_ratio, delay_ms,
    /// answer: +1 single, -1 double); several files are combined.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Draw the score map with its zero contour, D = 1 and D = 10 (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Stimulus: a lab-bell strike, and the same strike `ratio` as loud `delay` later.
fn stimulus(rate: f64, ratio: f64, delay_ms: f64) -> Result<clapper_signal::Signal> {
    let first = Strike {
        t: 0.05,
        impulse: 1.0,
        pulse: 3e-4,
    };
    let mut strikes = vec![first];
    if ratio > 0.0 {
        strikes.push(Strike {
            t: first.t + delay_ms * 1e-3,
            impulse: ratio,
            pulse: 3e-4,
        });
    }
    Ok(synthesize(&SynthSpec {
        rate,
        duration: 1.5,
        modes: lab_partials(),
        strikes,
        rests: vec![],
        rest_damping: 1.0,
        acceleration: false,
    })?)
}

pub fn run(args: ListeningArgs) -> Result<()> {
    match args.command {
        ListeningCommand::Make(a) => make(a),
        ListeningCommand::Analyse(a) => analyse(a),
    }
}

fn make(args: MakeArgs) -> Result<()> {
    if args.listeners == 0 || args.listeners > 1000 {
        bail!("--listeners {} must be 1 to 1000", args.listeners);
    }
    let dir = &args.out;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let (rg, dg) = (listening::ratios(), listening::delays_ms());
    let mut index = String::from("stimulus,amplitude_ratio,delay_ms\n");
    // All stimuli share one peak scale, so their loudness compares.
    let reference = stimulus(args.rate, 0.0, 0.0)?;
    let mut sigs = vec![];
    for (i, &r) in rg.iter().enumerate() {
        for (j, &d) in dg.iter().enumerate() {
            sigs.push((format!("s{:03}.wav", i * 10 + j), r, d, stimulus(args.rate, r, d)?));
        }
    }
    let peak = sigs
        .iter()
        .flat_map(|s| s.3.samples.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = |sig: &clapper_signal::Signal| {
        let own = sig.samples.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        0.9 * own / peak
    };
    clapper_io::signal_file::write_wav(&dir.join("reference.wav"), &reference, scale(&reference))?;
    for (name, r, d, sig) in &sigs {
        clapper_io::signal_file::write_wav(&dir.join(name), sig, scale(sig))?;
        let _ = writeln!(index, "{name},{r:.1},{d:.0}");
    }
    std::fs::write(dir.join("stimuli.csv"), index)?;
    for l in 0..args.listeners {
        let mut sheet = String::from("listener,trial,stimulus,amplitude_ratio,delay_ms,answer\n");
        for (trial, k) in listening::order(args.seed, l).into_iter().enumerate() {
            let _ = writeln!(
                sheet,
                "listener{:02},{},{},{:.1},{:.0},",
                l + 1,
                trial + 1,
                sigs[k].0,
                sigs[k].1,
                sigs[k].2
            );
        }
        std::fs::write(dir.join(format!("answers-listener{:02}.csv", l + 1)), sheet)?;
    }
    println!(
        "wrote 100 stimuli (lab-bell strikes, ratio 0.1 to 1, delay 10 to 100 ms), reference.wav, stimuli.csv and {} \
         answer sheets to {}\nplay each listener's stimuli in the sheet's order; fill 'answer' with 1 (single \
         strike) or -1 (double strike)",
        args.listeners,
        dir.display()
    );
    Ok(())
}

fn analyse(args: AnalyseArgs) -> Result<()> {
    let mut answers = vec![];
    for f in &args.files {
        answers.extend(clapper_io::answers::read_answers(f)?);
    }
    if answers.is_empty() {
        bail!("no answers: fill the 'answer' column with 1 (single) or -1 (double)");
    }
    let an = listening::analyse(&answers)?;
    if let Some(path) = &args.plot {
        let (rg, dg) = (listening::ratios(), listening::delays_ms());
        let mut values = vec![];
        let mut region = vec![];
        for row in &an.scores {
            for &s in row {
                values.push(s.is_finite().then_some(s));
                region.push(s > 0.0);
            }
        }
        let mut lines = vec![];
        if let Some(f) = &an.fit {
            for (d, label, colour) in [
                (1.0, "D = 1 (fitted)", RGBColor(255, 255, 255)),
                (10.0, "D = 10", RGBColor(255, 255, 255)),
            ] {
                let pts: Vec<(f64, f64)> = (0..=400)
                    .filter_map(|k| {
                        let r = 0.05 + 1.0 * k as f64 / 400.0;
                        f.delay_at(r, d).map(|t| (t, r))
                    })
                    .collect();
                lines.push((label.to_string(), pts, colour));
            }
        }
        let fig = ChartFigure {
            title: format!(
                "Fig 13: mean answer (+1 single, -1 double), {} listener(s); black: zero contour",
                an.used.len()
            ),
            panels: vec![Panel {
                title: String::new(),
                xs: dg.to_vec(),
                ys: rg.to_vec(),
                values: {
                    // Panels are row-major by y (ratio) then x (delay): as the scores are.
                    values
                },
                region,
            }],
            scale: Scale::Continuous {
                min: -1.0,
                max: 1.0,
                label: "mean answer (+1 single, -1 double)".into(),
            },
            markers: vec![],
            axes: (
                "delay between strikes (ms)".into(),
                "amplitude ratio of the second strike".into(),
            ),
            lines,
        };
        crate::chart::draw(path, &fig)?;
    }
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "listeners_used": an.used,
                "excluded": an.excluded.iter().map(|(n, r)| serde_json::json!({"listener": n, "correlation": r})).collect::<Vec<_>>(),
                "scores": an.scores.iter().map(|r| r.iter().map(|v| if v.is_finite() { Some(*v) } else { None }).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "fit": an.fit.map(|f| serde_json::json!({
                    "a": f.a, "b_ms": f.b, "c_ms": f.c, "sigma_a": f.sigma[0], "sigma_b_ms": f.sigma[1], "sigma_c_ms": f.sigma[2], "width_ms": f.width,
                })),
            })
        );
    } else {
        println!(
            "{} answer(s) from {} listener(s)",
            answers.len(),
            an.used.len() + an.excluded.len()
        );
        for (n, r) in &an.excluded {
            println!(
                "  left out {n}: correlation {r:.2} with the others' mean (below {})",
                listening::EXCLUDE_BELOW
            );
        }
        match &an.fit {
            Some(f) => println!(
                "zero contour fitted by (A - a)(dt - b) = c:\n  a = {:.3} +- {:.3}\n  b = {:.1} +- {:.1} ms\n  c = {:.2} +- {:.2} ms\n  (the paper: a = 0.2, b = 22 ms, c = 2.25 ms); D = (A - a)(dt - b)/c",
                f.a, f.sigma[0], f.b, f.sigma[1], f.c, f.sigma[2]
            ),
            None => println!("the score map has no clear zero contour to fit"),
        }
    }
    Ok(())
}
