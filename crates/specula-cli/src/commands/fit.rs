//! `specula fit`: an analytic material for renderers, fitted to any BRDF.

use crate::output::error_figure;
use crate::range;
use anyhow::Result;
use specula_formats::material_fit::{FitChoice, MaterialFit};
use specula_formats::{run_fit, FitExports, FitRequest};
use std::path::PathBuf;

/// Fit the analytic materials renderers have to a BRDF and export the best one.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF to fit: a preset, a material .toml, a measured file or a model:name fit.
    pub brdf: String,
    /// Which models to fit: `conductor`, `coat` or `both` (the better one is exported).
    #[arg(long, default_value_t = FitChoice::Both)]
    pub model: FitChoice,
    /// Largest elevation (degrees from the normal) of light and camera of the fitted cells. Range:
    /// degrees above 0 and at most 90.
    #[arg(long, default_value_t = 75.0, value_parser = range::ELEVATION_DEG)]
    pub max_elevation: f64,
    /// Write the fitted material as a Specula material .toml (loadable by every command).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write a Mitsuba 3 scene (.xml): a sphere with the material under a white environment.
    #[arg(long)]
    pub mitsuba: Option<PathBuf>,
    /// Write the pbrt-v4 `Material` directive.
    #[arg(long)]
    pub pbrt: Option<PathBuf>,
    /// Write a glTF 2.0 document (.gltf) holding the material.
    #[arg(long)]
    pub gltf: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let request = FitRequest {
        model: args.model,
        max_elevation_deg: args.max_elevation,
        exports: FitExports {
            out: args.out,
            mitsuba: args.mitsuba,
            pbrt: args.pbrt,
            gltf: args.gltf,
        },
    };
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let spinner = crate::progress::spinner("fitting");
    let outcome = run_fit(&request, brdf.as_ref(), &args.brdf);
    spinner.finish_and_clear();
    let outcome = outcome?;
    outln!("model,set,cells,relative_rmse,log_rmse,slice_mae");
    for fit in &outcome.fits {
        print_errors(fit, args.max_elevation);
    }
    for fit in &outcome.fits {
        outln!("{}: {}", fit.model.label(), parameters(fit));
    }
    if !outcome.written.is_empty() {
        let model = outcome.exported().model.label();
        outln!("exported model: {model} ({})", outcome.reason);
        for note in &outcome.notes {
            outln!("note: {note}");
        }
    }
    for path in &outcome.written {
        outln!("wrote {}", path.display());
    }
    Ok(())
}

/// The fitted parameters as the material file states them, on one line.
fn parameters(fit: &MaterialFit) -> String {
    fit.material
        .to_toml_string()
        .lines()
        .filter(|l| l.contains('=') && !l.starts_with("name"))
        .map(str::trim)
        .collect::<Vec<_>>()
        .join("; ")
}

fn print_errors(fit: &MaterialFit, max_elevation_deg: f64) {
    for (set, e) in [
        ("all".to_string(), fit.error_all),
        (format!("within {max_elevation_deg} deg"), fit.error_within),
    ] {
        outln!(
            "{},{set},{},{},{},{:.6e}",
            fit.model.label(),
            e.cells,
            error_figure(e.relative_rmse),
            error_figure(e.log_rmse),
            e.slice_mae
        );
    }
}
