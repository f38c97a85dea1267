//! `specula render`: pictures of materials on a sphere or a speedshape (paper Fig. 16, 17).

use anyhow::{bail, Result};
use specula_visual::grid::{self, Tile};
use specula_visual::linear_image::ImageFormat;
use specula_visual::{Lighting, RenderSettings, Scene, ShapeKind};
use std::path::PathBuf;
use std::time::Instant;

/// Render a material on a sphere or a speedshape under a point light or an environment.
///
/// The object is seen by a pinhole camera from 4 units away (sphere radius 1, 34 deg field of
/// view). Light reaches it directly (no inter-reflection): from an environment (default: a
/// built-in studio with softboxes) or from one point light. The material's lobe is
/// importance-sampled by a GGX proxy fitted to it and combined with sampling the environment
/// by brightness (multiple importance sampling), so mirror-like materials converge without
/// sparkles.
///
/// The output type follows the extension: .png is tone-mapped (ACES filmic, sRGB), .exr keeps
/// the linear radiance.
///
/// Several BRDFs with --side-by-side give one labelled picture of all of them under the same light;
/// with exactly two, a third tile shows their relative difference |A-B|/max(A,B) in false
/// colour (black 0, yellow 100 percent) and its mean is printed.
///
/// Examples:
///
///   specula render chrome --out chrome.png
///
///   specula render silver-925 --shape speedshape --light point --out s.png
///
///   specula render silver-925 chrome --side-by-side --out compare.png
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
    /// The environment: studio, constant, constant:RADIANCE, or a latitude-longitude .exr or
    /// .hdr file (y up, Mitsuba's envmap layout: the image's left and right edges are behind
    /// the object, its centre behind the camera). Default: studio.
    #[arg(long, value_name = "ENV")]
    pub env: Option<String>,
    /// Light the object with a point light (intensity 60 W/sr, upper left, in front) on black
    /// instead of an environment.
    #[arg(long, value_enum)]
    pub light: Option<LightKind>,
    /// Camera rays per pixel. The default converges: two seeds agree within 3 percent per pixel
    /// on average (15 percent in the rings around highlights); fewer make quick drafts. Range: a
    /// whole number from 1 to 65536.
    #[arg(long, default_value_t = specula_visual::render::DEFAULT_SAMPLES_PER_PIXEL, value_parser = crate::range::SAMPLES_PER_PIXEL)]
    pub spp: usize,
    /// Width and height of the picture (of each tile with --side-by-side), pixels. Range: a
    /// whole number from 8 to 8192.
    #[arg(long, default_value_t = 512, value_parser = crate::range::IMAGE_PX)]
    pub size: usize,
    /// Exposure of the PNG in stops (+1 doubles the brightness). Ignored for .exr. Range:
    /// stops from -20 to 20.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = crate::range::EXPOSURE_STOPS)]
    pub exposure: f64,
    /// Put several BRDFs side by side in one labelled picture (PNG only).
    #[arg(long)]
    pub side_by_side: bool,
    /// Seed of the random numbers (equal seeds give equal pictures).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// The kinds of light besides an environment.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub(crate) enum LightKind {
    /// One point light.
    Point,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let format = ImageFormat::of_path(&args.out)?;
    if args.brdfs.len() > 1 && !args.side_by_side {
        bail!(
            "{} BRDFs given: add --side-by-side to show them side by side",
            args.brdfs.len()
        );
    }
    if args.side_by_side && format != ImageFormat::Png {
        bail!(
            "{}: a --side-by-side picture is written as .png",
            args.out.display()
        );
    }
    let lighting = Lighting::chosen(args.light.is_some(), args.env.as_deref())?;
    let brdfs = args
        .brdfs
        .iter()
        .map(|spec| specula_formats::load_brdf(spec))
        .collect::<Result<Vec<_>, _>>()?;
    let scene = Scene::new(args.shape, lighting);
    let settings = RenderSettings {
        seed: args.seed,
        ..RenderSettings::square(args.size, args.spp)
    };
    let pixels = (args.size * args.size) as u64;
    let bar = crate::progress::bar(pixels * brdfs.len() as u64, "rendering");
    let mut renders = Vec::with_capacity(brdfs.len());
    for (i, brdf) in brdfs.iter().enumerate() {
        let start = Instant::now();
        let offset = i as u64 * pixels;
        let image = specula_visual::render(brdf.as_ref(), &scene, &settings, &|done| {
            bar.set_position(offset + done)
        });
        eprintln!(
            "rendered {} ({} x {}, {} spp) in {:.2} s",
            brdf.name(),
            args.size,
            args.size,
            args.spp,
            start.elapsed().as_secs_f64()
        );
        renders.push(image);
    }
    bar.finish_and_clear();
    if !args.side_by_side {
        renders[0].save(&args.out, args.exposure)?;
        outln!("wrote {}", args.out.display());
        return Ok(());
    }
    let labels = tile_labels(&args.brdfs);
    let mut tiles: Vec<Tile> = labels
        .iter()
        .zip(&renders)
        .map(|(label, image)| Tile {
            label: label.clone(),
            image: image.to_display(args.exposure),
        })
        .collect();
    if renders.len() == 2 {
        let diff = grid::difference(&renders[0], &renders[1])?;
        outln!(
            "mean relative difference {:.4} ({} against {})",
            diff.mean_relative,
            labels[0],
            labels[1]
        );
        tiles.push(Tile {
            label: "|A-B| / max(A,B), 0-100 %".into(),
            image: diff.image,
        });
    }
    specula_visual::linear_image::save_png(&grid::compose(&tiles)?, &args.out)?;
    outln!("wrote {}", args.out.display());
    Ok(())
}

/// A tile's label: the source as the user named it (a file by its file name, so that a
/// measured table and its truth read apart), with its role A or B when two are compared.
fn tile_labels(specs: &[String]) -> Vec<String> {
    let names = specs.iter().map(|spec| {
        let path = std::path::Path::new(spec);
        match path.file_name() {
            Some(name) if path.is_file() => name.to_string_lossy().into_owned(),
            _ => spec.clone(),
        }
    });
    if specs.len() == 2 {
        names
            .zip(["A", "B"])
            .map(|(name, role)| format!("{role}: {name}"))
            .collect()
    } else {
        names.collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(brdfs: &[&str], out: PathBuf) -> Args {
        Args {
            brdfs: brdfs.iter().map(|s| s.to_string()).collect(),
            out,
            shape: ShapeKind::Sphere,
            env: None,
            light: None,
            spp: 2,
            size: 16,
            exposure: 0.0,
            side_by_side: false,
            seed: 1,
        }
    }

    #[test]
    fn renders_png_exr_and_grids() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("a.png");
        run(args(&["chrome"], png.clone())).unwrap();
        assert_eq!(image::image_dimensions(&png).unwrap(), (16, 16));
        let exr = dir.path().join("a.exr");
        run(Args {
            light: Some(LightKind::Point),
            shape: ShapeKind::Speedshape,
            ..args(&["silver-925"], exr.clone())
        })
        .unwrap();
        assert_eq!(specula_visual::LinearImage::load(&exr).unwrap().width, 16);
        let grid = dir.path().join("g.png");
        run(Args {
            side_by_side: true,
            env: Some("constant:0.5".into()),
            ..args(&["chrome", "green-paint"], grid.clone())
        })
        .unwrap();
        let (w, _) = image::image_dimensions(&grid).unwrap();
        assert!(w > 3 * 16, "three tiles: {w}");
    }

    #[test]
    fn tiles_are_labelled_by_source_and_role() {
        let dir = tempfile::tempdir().unwrap();
        let table = dir.path().join("A.binary");
        std::fs::write(&table, b"x").unwrap();
        let specs = [table.display().to_string(), "green-paint".to_string()];
        assert_eq!(tile_labels(&specs), ["A: A.binary", "B: green-paint"]);
        assert_eq!(tile_labels(&specs[1..]), ["green-paint"]);
    }

    #[test]
    fn bad_requests_are_refused_with_a_reason() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a.png");
        let message = |a: Args| format!("{:#}", run(a).unwrap_err());
        assert!(message(args(&["chrome", "steel"], out.clone())).contains("--side-by-side"));
        assert!(message(Args {
            side_by_side: true,
            ..args(&["chrome"], dir.path().join("a.exr"))
        })
        .contains(".png"));
        assert!(message(args(&["chrome"], dir.path().join("a.jpg"))).contains("a.jpg"));
        assert!(message(Args {
            light: Some(LightKind::Point),
            env: Some("studio".into()),
            ..args(&["chrome"], out.clone())
        })
        .contains("choose one"));
        assert!(message(Args {
            env: Some("/no/such.exr".into()),
            ..args(&["chrome"], out.clone())
        })
        .contains("/no/such.exr"));
        assert!(message(args(&["no-such-material"], out)).contains("no-such-material"));
    }
}
