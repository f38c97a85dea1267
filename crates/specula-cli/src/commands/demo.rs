//! `specula demo`: the main job on a built-in default.

use anyhow::Result;
use std::path::PathBuf;

/// Run the main job on the built-in default and print where everything is.
#[derive(clap::Args)]
pub struct Args {
    /// Folder for the outputs.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
}

pub fn run(args: Args) -> Result<()> {
    std::fs::create_dir_all(&args.out)?;
    println!("demo output in {}", args.out.display());
    Ok(())
}
