//! `clapper sample-data`: write the synthetic sample recordings of
//! `examples/data/` (clapper-app's `sample_data`).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

/// Arguments of `clapper sample-data`.
#[derive(Args, Debug)]
pub struct SampleDataArgs {
    /// Folder to write into (made if missing); the checkout's own set is
    /// examples/data.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// Write every sample file into `--out`.
pub fn run(args: SampleDataArgs) -> Result<()> {
    crate::files::make_folder(&args.out, "--out")?;
    let files = clapper_app::sample_data::sample_files()?;
    for f in &files {
        crate::files::write_bytes(&args.out.join(f.name), &f.bytes)?;
    }
    let kb: usize = files.iter().map(|f| f.bytes.len()).sum::<usize>() / 1024;
    println!(
        "wrote {} synthetic sample files ({kb} KiB) to {}: {}",
        files.len(),
        args.out.display(),
        files.iter().map(|f| f.name).collect::<Vec<_>>().join(", ")
    );
    Ok(())
}
