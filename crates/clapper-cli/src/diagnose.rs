//! `clapper diagnose`: a bell or a whole ring, for the bell-hanger.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use clapper_app::diagnosis::{diagnose_bells_with, report_page, text, OddStruckOptions};
use clapper_app::simulate::Preset;
use clapper_app::strikes::{beside, strike_options, voices_from_nominals, StrikesReport};
use clapper_io::bell_file::LoadedBell;

#[derive(Args, Debug)]
pub struct DiagnoseArgs {
    /// A bell file (TOML), a ring (`[[bell]]` tables, or CSV with one bell a row).
    #[arg(value_name = "FILE", required_unless_present = "preset", conflicts_with = "preset")]
    pub file: Option<PathBuf>,
    /// A bell of the paper's Table 1.
    #[arg(long, value_enum)]
    pub preset: Option<Preset>,
    /// Print every number as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write a self-contained HTML report (charts embedded); `-` is
    /// standard output.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
    /// The tower's readings, applied to every bell: pivot offset, contact
    /// angles or tape gaps, friction. A bell that is then odd-struck gets
    /// the adjustment that evens it.
    #[command(flatten)]
    pub hanging: crate::simulate::HangingArgs,
    /// Odd-struckness to aim for (ms, handstroke minus backstroke within
    /// plus or minus this).
    #[arg(long, value_name = "MS", default_value_t = 1.0)]
    pub odd_tolerance: f64,
    /// A recording of the ring (.wav): its odd-struckness and double strikes
    /// heard (as `clapper strikes`), set beside the model's, bell by bell in
    /// the ring file's order. Needs --nominals or --templates.
    #[arg(long, value_name = "REC.wav")]
    pub recording: Option<PathBuf>,
    /// The bells' nominals (Hz), treble first, to hear them in the recording.
    #[arg(long, value_name = "F1,F2,..", value_parser = crate::strikes::parse_list, requires = "recording", conflicts_with = "templates")]
    pub nominals: Option<crate::strikes::Nominals>,
    /// A folder of each bell struck alone (1.wav, 2.wav, ...), to hear them in the recording.
    #[arg(long, value_name = "DIR", requires = "recording")]
    pub templates: Option<PathBuf>,
}

pub fn run(args: DiagnoseArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--report", args.report.as_deref())], args.json)?;
    let (bells, source): (Vec<LoadedBell>, String) = match (&args.file, args.preset) {
        (Some(p), _) => (clapper_io::load_bells(p)?, p.display().to_string()),
        (None, preset) => {
            let preset = preset.unwrap_or(Preset::Lab);
            (vec![preset.loaded()], format!("preset {}", preset.name()))
        }
    };
    if let Some(p) = &args.report {
        // `-` is standard output (the help says so); a file names its kind.
        if !crate::files::is_stdout(p) && !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("html")) {
            bail!("report file {} must end in .html", p.display());
        }
    }
    let h = &args.hanging;
    // The readings as a request's options: one mapping to the model's
    // hanging, the one simulate and chart use.
    let mut req = clapper_app::simulate::SimulateRequest::default();
    crate::simulate::set_hanging!(req, args.hanging);
    let input = req.stroke_options().hanging;
    let mut bells = bells;
    for b in &mut bells {
        b.bell = input
            .apply(b.bell)
            .with_context(|| format!("the tower readings for {}", b.name))?;
    }
    if !(args.odd_tolerance.is_finite() && args.odd_tolerance > 0.0) {
        bail!("--odd-tolerance {} must be a time > 0 ms", args.odd_tolerance);
    }
    let odd = OddStruckOptions {
        ball_below_pivot_m: h.ball_below_pivot,
        tolerance_ms: args.odd_tolerance,
    };
    // The recording is heard first: a bad file fails before the simulations.
    let heard = hear(&args)?;
    let rep = diagnose_bells_with(&bells, &odd)?;
    let recording = heard.map(|(h, name)| beside(&rep, &h, &name));
    if let Some(path) = &args.report {
        let html = report_page(&rep, &bells, &source)?;
        crate::files::write_atomically(path, |tmp| {
            std::fs::write(tmp, html).with_context(|| format!("cannot write {}", path.display()))
        })?;
    }
    if args.json {
        print_json(&rep, recording.as_ref())?;
    } else {
        crate::say_text!("{}", text(&rep, &source));
        if let Some(r) = &recording {
            crate::say_text!("{}", r.text());
        }
        if let Some(p) = args.report.as_deref().filter(|p| !crate::files::is_stdout(p)) {
            crate::say!("\nreport written to {}", p.display());
        }
    }
    Ok(())
}

/// The recording of --recording heard with the bells' voices, and its
/// name; `None` without one.
fn hear(args: &DiagnoseArgs) -> Result<Option<(StrikesReport, String)>> {
    Ok(match &args.recording {
        Some(rec) => {
            let voices = match (&args.nominals, &args.templates) {
                (Some(n), _) => voices_from_nominals(&n.0, clapper_app::strikes::Voice::Tower)?,
                (None, Some(dir)) => crate::strikes::template_voices(dir)?,
                (None, None) => bail!(
                    "--recording needs the bells' voices: --nominals F1,F2,.. (Hz, treble first) or --templates DIR"
                ),
            };
            let sig = clapper_io::signal_file::read_recording(rec)?;
            let name = rec.display().to_string();
            let report = StrikesReport::new(&sig, &voices, &strike_options(0.3)?).with_context(|| name.clone())?;
            Some((report, name))
        }
        None => None,
    })
}

/// Print the diagnosis as JSON, the recording after it when one was heard.
fn print_json(
    rep: &clapper_app::diagnosis::DiagnosisReport,
    recording: Option<&clapper_app::strikes::RecordingBeside>,
) -> Result<()> {
    // The diagnosis as ever (its keys in their order), the recording
    // after it when one was heard.
    #[derive(serde::Serialize)]
    struct WithRecording<'a> {
        #[serde(flatten)]
        diagnosis: &'a clapper_app::diagnosis::DiagnosisReport,
        #[serde(skip_serializing_if = "Option::is_none")]
        recording: Option<&'a clapper_app::strikes::RecordingBeside>,
    }
    let out = WithRecording {
        diagnosis: rep,
        recording,
    };
    crate::say!("{}", serde_json::to_string_pretty(&out)?);
    Ok(())
}
