//! `specula fit`: an analytic material for renderers, fitted to any BRDF.

use crate::range;
use anyhow::{Context, Result};
use specula_core::atomic_file::write_bytes;
use specula_core::tabulate::tabulate;
use specula_core::GridSpec;
use specula_formats::material_fit::{fit_models, FitChoice, MaterialFit};
use specula_formats::renderer_export::{
    gltf_document, mitsuba_scene, mitsuba_warning, pbrt_material,
};
use std::path::{Path, PathBuf};

/// Fit the analytic materials renderers have to a BRDF and export the best one.
///
/// Models (both GGX, evaluated by Specula's own models, as Mitsuba 3 does):
///
///   conductor  a rough metal: roughness alpha and a complex index eta + i k per channel
///              (Mitsuba roughconductor, pbrt-v4 conductor, glTF metallic 1);
///
///   coat       a rough dielectric coat (alpha, index) over a Lambertian base of albedo rho
///              per channel (Mitsuba roughplastic, nonlinear; pbrt-v4 coateddiffuse; glTF
///              dielectric with KHR_materials_ior).
///
/// The source is tabulated into the MERL grid and each model is fitted (Nelder-Mead) to the
/// log error ln(1 + f cos theta_i) of `specula compare` over cells whose light and camera are
/// within --max-elevation. Printed per model: its parameters and `specula compare`'s
/// figures of the fit against the source (relative_rmse, log_rmse, slice_mae), over all cells
/// and within the limit. The exports hold the model with the lower log_rmse within the limit.
/// glTF roughness is sqrt(alpha) (glTF 2.0: alpha = roughness^2). Mitsuba's roughplastic is
/// single-scattering: for coats rougher than alpha 0.05 it renders the base darker than the
/// fit (a note says so).
#[derive(clap::Args)]
#[command(after_help = "Examples:
  specula fit silver-925 --model conductor --mitsuba silver.xml
  specula fit measured.binary --out fit.toml --pbrt fit.pbrt --gltf fit.gltf
  specula fit ../shared/data/measured/rgl_bsdf/paper_white_rgb.bsdf --model coat")]
pub(crate) struct Args {
    /// The BRDF to fit: a preset, a material .toml, a measured file or a model:name fit.
    pub brdf: String,
    /// Which models to fit: `conductor`, `coat` or `both` (the better one is exported).
    #[arg(long, default_value_t = FitChoice::Both)]
    pub model: FitChoice,
    /// Largest elevation (degrees from the normal) of light and camera of the fitted cells.
    /// Range: degrees above 0 and at most 90.
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
        let why = if fits.len() > 1 {
            format!(
                ", the lower log_rmse within {} deg of the {} models fitted",
                args.max_elevation,
                fits.len()
            )
        } else {
            String::new()
        };
        outln!("exported model: {}{why}", fits[0].model.label());
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
