//! `specula fit`: an analytic material for renderers, fitted to any BRDF.

use crate::range;
use anyhow::{Context, Result};
use specula_core::atomic_file::write_bytes;
use specula_core::materials::Base;
use specula_core::tabulate::tabulate;
use specula_core::GridSpec;
use specula_formats::material_fit::{
    fit_models, ExportReason, FitChoice, MaterialFit, METAL_MIN_K,
};
use specula_formats::renderer_export::{
    gltf_document, mitsuba_scene, mitsuba_warning, pbrt_material,
};
use std::path::{Path, PathBuf};

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
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let spinner = crate::progress::spinner("fitting");
    let table = tabulate(brdf.as_ref(), GridSpec::paper().phi_h_deg.to_radians());
    let fits = fit_models(
        &table,
        args.model.models(),
        args.max_elevation,
        &brdf.name(),
    )
    .with_context(|| format!("{}: cannot fit", args.brdf))?;
    spinner.finish_and_clear();
    outln!("model,set,cells,relative_rmse,log_rmse,slice_mae");
    for fit in &fits {
        print_errors(fit, args.max_elevation);
    }
    for fit in &fits {
        outln!("{}: {}", fit.model.label(), parameters(fit));
    }
    let best = &fits[0].material;
    let exporting =
        args.out.is_some() || args.mitsuba.is_some() || args.pbrt.is_some() || args.gltf.is_some();
    if exporting {
        outln!(
            "exported model: {} ({})",
            fits[0].model.label(),
            ExportReason::of(&fits)
        );
        if let Base::Conductor(c) = &best.base {
            if !fits[0].is_metal_like() {
                outln!(
                    "note: the conductor's k is at most {:.2}, not a metal's (at least {METAL_MIN_K}): the data look dielectric; --model coat fits a dielectric",
                    c.k.max_element()
                );
            }
        }
    }
    if let Some(path) = &args.out {
        save(path, &best.to_toml_string())?;
    }
    if let Some(path) = &args.mitsuba {
        save(path, &mitsuba_scene(best)?)?;
        if let Some(warning) = mitsuba_warning(best) {
            outln!("note: {warning}");
        }
    }
    if let Some(path) = &args.pbrt {
        save(path, &pbrt_material(best)?)?;
    }
    if let Some(path) = &args.gltf {
        save(path, &gltf_document(best)?)?;
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
            "{},{set},{},{:.6},{:.6},{:.6e}",
            fit.model.label(),
            e.cells,
            e.relative_rmse,
            e.log_rmse,
            e.slice_mae
        );
    }
}

fn save(path: &Path, text: &str) -> Result<()> {
    write_bytes(path, text.as_bytes())
        .with_context(|| format!("{}: cannot write", path.display()))?;
    outln!("wrote {}", path.display());
    Ok(())
}
