//! `clapper diagnose`: a bell or a whole ring, for the bell-hanger.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use clapper_app::diagnosis::{diagnose_bells, report_page, text};
use clapper_app::simulate::Preset;
use clapper_io::bell_file::LoadedBell;

#[derive(Args, Debug)]
pub struct DiagnoseArgs {
    /// A bell file (TOML), a ring ([[bell]] tables, or CSV with one bell a row).
    #[arg(value_name = "FILE", required_unless_present = "preset", conflicts_with = "preset")]
    pub file: Option<PathBuf>,
    /// A bell of the paper's Table 1.
    #[arg(long, value_enum)]
    pub preset: Option<Preset>,
    /// Print every number as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write a self-contained HTML report (charts embedded).
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
}

pub fn run(args: DiagnoseArgs) -> Result<()> {
    let (bells, source): (Vec<LoadedBell>, String) = match (&args.file, args.preset) {
        (Some(p), _) => (clapper_io::load_bells(p)?, p.display().to_string()),
        (None, preset) => {
            let preset = preset.unwrap_or(Preset::Lab);
            (vec![preset.loaded()], format!("preset {}", preset.name()))
        }
    };
    if let Some(p) = &args.report {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("html")) {
            bail!("report file {} must end in .html", p.display());
        }
    }
    let rep = diagnose_bells(&bells)?;
    if let Some(path) = &args.report {
        let html = report_page(&rep, &bells, &source)?;
        crate::files::write_atomically(path, |tmp| {
            std::fs::write(tmp, html).with_context(|| format!("cannot write {}", path.display()))
        })?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rep)?);
    } else {
        print!("{}", text(&rep, &source));
        if let Some(p) = &args.report {
            println!("\nreport written to {}", p.display());
        }
    }
    Ok(())
}
