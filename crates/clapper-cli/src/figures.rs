//! `clapper figures`: the paper's figures that the model computes, as SVG
//! and PNG with their CSV data, and an index page (built by
//! `clapper_app::figures`; drawn and written here).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use clapper_app::figures::{figures, Drawing};
use clapper_core::chart::Styles;

use crate::chart::{draw, run_sweep, SweepArgs};

#[derive(Args, Debug)]
pub struct FiguresArgs {
    /// Folder to write into (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Chart settings; the paper's are the defaults (its grid was 20 x 20).
    #[command(flatten)]
    pub sweep: SweepArgs,
}

pub fn run(args: FiguresArgs) -> Result<()> {
    let out = &args.out;
    crate::files::make_folder(out, "--out")?;
    let pool = args.sweep.pool()?;
    let base = args.sweep.spec(Styles::Both)?;
    let set = figures(&base, &mut |spec, what| {
        run_sweep(spec, &pool, what).map_err(|e| clapper_app::AppError::Request(format!("{e:#}")))
    })?;
    for (name, drawing) in &set.drawings {
        for ext in ["svg", "png"] {
            let path = out.join(format!("{name}.{ext}"));
            match drawing {
                Drawing::Chart(fig) => draw(&path, fig)?,
                Drawing::Stroke {
                    title,
                    samples,
                    phi_max_deg,
                    stroke_starts,
                } => {
                    let plot = clapper_plot::StrokePlot {
                        title,
                        phi_max_deg: *phi_max_deg,
                        stroke_starts: stroke_starts.clone(),
                    };
                    crate::files::write_atomically(&path, |tmp| Ok(clapper_plot::stroke_plot(tmp, samples, &plot)?))?
                }
                Drawing::Lines {
                    title,
                    x_label,
                    y_label,
                    series,
                } => crate::files::write_atomically(&path, |tmp| {
                    Ok(clapper_plot::line_plot(tmp, title, x_label, y_label, series)?)
                })?,
            }
        }
    }
    for (name, text) in &set.files {
        crate::files::write_bytes(&out.join(name), text)?;
    }
    println!(
        "wrote {} figures (SVG and PNG, with CSV) and index.md, index.html to {}",
        set.count,
        out.display()
    );
    Ok(())
}
