//! `specula render`: pictures of materials on a sphere or a speedshape (paper Fig. 16, 17).

use crate::interrupt::{blame_stop_unresumable, stop_on_ctrl_c};
use anyhow::{Context, Result};
use specula_visual::{render_pictures, LightKind, RenderRequest, ShapeKind};
use std::path::PathBuf;

/// Render a material on a sphere or a speedshape under a point light or an environment.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDFs: preset names, material .toml files, MERL .binary files, RGL .bsdf files or
    /// model:name fits.
    #[arg(required = true)]
    pub brdfs: Vec<String>,
    /// The picture to write: .png (tone-mapped) or .exr (linear radiance).
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// The object: sphere or speedshape.
    #[arg(long, default_value = "sphere")]
    pub shape: ShapeKind,
    /// The environment: studio, constant, constant:RADIANCE, or a latitude-longitude .exr or .hdr
    /// file (y up, Mitsuba's envmap layout: the image's left and right edges are behind the object,
    /// its centre behind the camera).
    #[arg(long, value_name = "ENV")]
    pub env: Option<String>,
    /// Light the object with a point light (`point`: intensity 60 W/sr, upper left, in front)
    /// on black instead of an environment.
    #[arg(long)]
    pub light: Option<LightKind>,
    /// Camera rays per pixel. Range: a whole number from 1 to 65536.
    #[arg(long, default_value_t = specula_visual::render::DEFAULT_SAMPLES_PER_PIXEL, value_parser = crate::range::SAMPLES_PER_PIXEL)]
    pub spp: usize,
    /// Width and height of the picture (of each tile with --side-by-side), pixels. Range: a whole
    /// number from 8 to 8192.
    #[arg(long, default_value_t = 512, value_parser = crate::range::IMAGE_PX)]
    pub size: usize,
    /// Exposure of the PNG in stops (+1 doubles the brightness). Range: stops from -20 to 20.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = crate::range::EXPOSURE_STOPS)]
    pub exposure: f64,
    /// Put several BRDFs side by side in one labelled picture (PNG only).
    #[arg(long)]
    pub side_by_side: bool,
    /// Seed of the random numbers (equal seeds give equal pictures).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let request = RenderRequest {
        shape: args.shape,
        env: args.env,
        light: args.light,
        spp: args.spp,
        size_px: args.size,
        exposure_stops: args.exposure,
        side_by_side: args.side_by_side,
        seed: args.seed,
        out: Some(args.out.clone()),
    };
    request.validate(args.brdfs.len())?;
    let mut materials = Vec::with_capacity(args.brdfs.len());
    for spec in args.brdfs {
        let brdf = specula_formats::load_brdf(&spec)?;
        materials.push((spec, brdf));
    }
    let stop = stop_on_ctrl_c().context("cannot watch for Ctrl-C")?;
    let progress = crate::progress::Terminal::default();
    let rendered = render_pictures(&request, &materials, &stop, &progress)
        .map_err(|e| blame_stop_unresumable(e.into(), &stop))?;
    for ((_, brdf), seconds) in materials.iter().zip(&rendered.seconds) {
        eprintln!(
            "rendered {} ({} x {}, {} spp) in {seconds:.2} s",
            brdf.name(),
            args.size,
            args.size,
            args.spp
        );
    }
    if let Some((difference, [a, b])) = rendered.difference {
        outln!("mean relative difference {difference:.4} ({a} against {b})");
    }
    outln!("wrote {}", args.out.display());
    Ok(())
}
