//! `clapper listening-test make | analyse`: the double-strike listening
//! test of Section 4.3 (Fig 13).

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::{Args, Subcommand};
use clapper_app::listening::{figure, text, Stimulus, StimulusSet};
use clapper_io::answers::{answer_sheet_csv, SheetRow};

use crate::files::write_bytes;

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
    crate::files::make_folder(dir, "--out")?;
    let set = StimulusSet::new(args.rate)?;
    write_bytes(&dir.join("reference.wav"), set.wav(&set.reference)?)?;
    for s in &set.stimuli {
        write_bytes(&dir.join(&s.name), set.wav(&s.signal)?)?;
    }
    let index: Vec<SheetRow> = set.stimuli.iter().map(|s| sheet_row(None, 0, s)).collect();
    write_bytes(&dir.join("stimuli.csv"), answer_sheet_csv(&index)?)?;
    for l in 0..args.listeners {
        let listener = format!("listener{:02}", l + 1);
        let rows: Vec<SheetRow> = set
            .sheet(args.seed, l)
            .into_iter()
            .enumerate()
            .map(|(trial, s)| sheet_row(Some(&listener), trial + 1, s))
            .collect();
        write_bytes(&dir.join(format!("answers-{listener}.csv")), answer_sheet_csv(&rows)?)?;
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

fn sheet_row(listener: Option<&str>, trial: usize, s: &Stimulus) -> SheetRow {
    SheetRow {
        listener: listener.map(str::to_string),
        trial,
        stimulus: s.name.clone(),
        amplitude_ratio: s.ratio,
        delay_ms: s.delay_ms,
        answer: None,
    }
}

fn analyse(args: AnalyseArgs) -> Result<()> {
    let mut answers = vec![];
    for f in &args.files {
        answers.extend(clapper_io::answers::read_answers(f)?);
    }
    let (an, rep) = clapper_app::listening::analyse(&answers)?;
    if let Some(path) = &args.plot {
        crate::chart::draw(path, &figure(&an))?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rep)?);
    } else {
        print!("{}", text(&rep));
    }
    Ok(())
}
