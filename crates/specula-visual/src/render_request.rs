//! What a user asks of pictures of materials (`specula render`, the Python package's
//! `render`): the object, the light, the picture's size and rays per pixel, and where to
//! write it, every range checked in one place ([`RenderRequest::validate`]) so that both
//! front ends refuse the same values with the same words (the errors name the Python
//! argument: `size`, `spp`, `exposure`).

use crate::error::VisualError;
use crate::grid::{self, Tile};
use crate::linear_image::{save_png, ImageFormat};
use crate::render::render_until;
use crate::render::{IMAGE_PX, SAMPLES_PER_PIXEL};
use crate::{Lighting, LinearImage, RenderSettings, Scene, ShapeKind};
use specula_core::progress::{Progress, Stopped};
use specula_core::request::{parse_choice, ChoiceError, EXPOSURE_STOPS};
use specula_core::Brdf;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

/// The kinds of light besides an environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    /// One point light (intensity 60 W/sr, upper left, in front) on black.
    Point,
}

impl std::str::FromStr for LightKind {
    type Err = ChoiceError;

    /// `point`.
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice("light", text, &[LightKind::Point], &["point"], |_| "point")
    }
}

impl fmt::Display for LightKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("point")
    }
}

/// Pictures of one or more materials on an object.
#[derive(Clone, Debug)]
pub struct RenderRequest {
    /// The object.
    pub shape: ShapeKind,
    /// The environment ([`Lighting::chosen`]); none: the studio, unless `light` is given.
    pub env: Option<String>,
    /// A light instead of an environment.
    pub light: Option<LightKind>,
    /// Camera rays per pixel, in [`SAMPLES_PER_PIXEL`].
    pub spp: usize,
    /// Width and height of the picture (of each tile side by side), in [`IMAGE_PX`].
    pub size_px: usize,
    /// Exposure of a PNG in stops, in [`EXPOSURE_STOPS`].
    pub exposure_stops: f64,
    /// Several materials side by side in one labelled PNG.
    pub side_by_side: bool,
    /// Seed of the random numbers (equal seeds give equal pictures).
    pub seed: u64,
    /// The picture to write: `.png` (tone-mapped) or `.exr` (linear); none: not written.
    pub out: Option<PathBuf>,
}

/// The pictures of a [`RenderRequest`].
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The linear radiance of each material, in the order given.
    pub images: Vec<LinearImage>,
    /// Wall time of each material's render, seconds, in the order given.
    pub seconds: Vec<f64>,
    /// With two materials side by side: the mean relative difference of their pictures and
    /// the two tiles' labels.
    pub difference: Option<(f64, [String; 2])>,
}

impl RenderRequest {
    /// Refuses a value out of its range, an output that is neither `.png` nor `.exr`,
    /// several materials (`materials`) without `side_by_side`, a side-by-side picture not
    /// written as PNG, and a light together with an environment.
    pub fn validate(&self, materials: usize) -> Result<(), VisualError> {
        self.check(materials)?;
        self.scene().map(|_| ())
    }

    /// [`Self::validate`] but for the light, which [`Self::scene`] checks as it loads it.
    fn check(&self, materials: usize) -> Result<(), VisualError> {
        SAMPLES_PER_PIXEL.check("spp", self.spp)?;
        IMAGE_PX.check("size", self.size_px)?;
        EXPOSURE_STOPS.check("exposure", self.exposure_stops)?;
        let format = self.out.as_deref().map(ImageFormat::of_path).transpose()?;
        if materials > 1 && !self.side_by_side {
            return Err(VisualError::Data(format!(
                "{materials} BRDFs given: add --side-by-side to show them side by side"
            )));
        }
        if let (true, Some(out), Some(ImageFormat::Exr)) = (self.side_by_side, &self.out, format) {
            return Err(VisualError::Data(format!(
                "{}: a --side-by-side picture is written as .png",
                out.display()
            )));
        }
        Ok(())
    }

    /// The scene: the object under the chosen light.
    fn scene(&self) -> Result<Scene, VisualError> {
        let lighting = Lighting::chosen(self.light.is_some(), self.env.as_deref())?;
        Ok(Scene::new(self.shape, lighting))
    }
}

/// Renders `materials` (each with the source as the user named it, for the tiles' labels)
/// as `request` asks, writes the picture when it names a file, and returns the pictures.
/// `progress` counts the pixels over all the materials; when `stop` is raised the render
/// ends at its next tile with [`Stopped`] and nothing is written.
pub fn render_pictures(
    request: &RenderRequest,
    materials: &[(String, Arc<dyn Brdf>)],
    stop: &AtomicBool,
    progress: &dyn Progress,
) -> Result<Rendered, VisualError> {
    request.check(materials.len())?;
    let scene = request.scene()?;
    let settings = RenderSettings {
        seed: request.seed,
        ..RenderSettings::square(request.size_px, request.spp)
    };
    let pixels = (request.size_px * request.size_px) as u64;
    let mut images = Vec::with_capacity(materials.len());
    let mut seconds = Vec::with_capacity(materials.len());
    progress.start("rendering", Some(pixels * materials.len() as u64));
    for (i, (_, brdf)) in materials.iter().enumerate() {
        let start = Instant::now();
        let offset = i as u64 * pixels;
        let image = render_until(brdf.as_ref(), &scene, &settings, stop, &|done| {
            progress.set(offset + done)
        });
        let Some(image) = image else {
            progress.finish();
            return Err(Stopped {
                done: i as u64,
                total: materials.len() as u64,
                what: "pictures",
            }
            .into());
        };
        seconds.push(start.elapsed().as_secs_f64());
        images.push(image);
    }
    progress.finish();
    let mut rendered = Rendered {
        images,
        seconds,
        difference: None,
    };
    if let Some(out) = &request.out {
        if request.side_by_side {
            let specs: Vec<&str> = materials.iter().map(|(spec, _)| spec.as_str()).collect();
            rendered.difference = write_side_by_side(&rendered.images, &specs, request, out)?;
        } else if let Some(image) = rendered.images.first() {
            image.save(out, request.exposure_stops)?;
        }
    }
    Ok(rendered)
}

/// Writes the labelled tiles of `images` to `out`, with a difference tile when there are two,
/// and returns that difference.
fn write_side_by_side(
    images: &[LinearImage],
    specs: &[&str],
    request: &RenderRequest,
    out: &Path,
) -> Result<Option<(f64, [String; 2])>, VisualError> {
    let labels = tile_labels(specs);
    let mut tiles: Vec<Tile> = labels
        .iter()
        .zip(images)
        .map(|(label, image)| Tile {
            label: label.clone(),
            image: image.to_display(request.exposure_stops),
        })
        .collect();
    let mut difference = None;
    if let ([a, b], [label_a, label_b]) = (images, labels.as_slice()) {
        let diff = grid::difference(a, b)?;
        difference = Some((diff.mean_relative, [label_a.clone(), label_b.clone()]));
        tiles.push(Tile {
            label: "|A-B| / max(A,B), 0-100 %".into(),
            image: diff.image,
        });
    }
    save_png(&grid::compose(&tiles)?, out)?;
    Ok(difference)
}

/// A tile's label: the source as the user named it (a file by its file name, so that a
/// measured table and its truth read apart), with its role A or B when two are compared.
fn tile_labels(specs: &[&str]) -> Vec<String> {
    let names = specs.iter().map(|spec| {
        let path = Path::new(spec);
        match path.file_name() {
            Some(name) if path.is_file() => name.to_string_lossy().into_owned(),
            _ => spec.to_string(),
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
    use specula_core::materials::preset;
    use specula_core::progress::NoProgress;

    fn request(out: PathBuf) -> RenderRequest {
        RenderRequest {
            shape: ShapeKind::Sphere,
            env: None,
            light: None,
            spp: 2,
            size_px: 16,
            exposure_stops: 0.0,
            side_by_side: false,
            seed: 1,
            out: Some(out),
        }
    }

    fn materials(names: &[&str]) -> Vec<(String, Arc<dyn Brdf>)> {
        names
            .iter()
            .map(|name| {
                let brdf: Arc<dyn Brdf> = Arc::new(preset(name).unwrap());
                (name.to_string(), brdf)
            })
            .collect()
    }

    fn run(request: &RenderRequest, names: &[&str]) -> Result<Rendered, VisualError> {
        render_pictures(
            request,
            &materials(names),
            &AtomicBool::new(false),
            &NoProgress,
        )
    }

    #[test]
    fn a_raised_stop_ends_the_render_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("a.png");
        let stop = AtomicBool::new(true);
        let error = render_pictures(
            &request(png.clone()),
            &materials(&["chrome"]),
            &stop,
            &NoProgress,
        )
        .unwrap_err();
        assert_eq!(error.to_string(), "stopped: 0 of 1 pictures done");
        assert!(!png.exists());
    }

    #[test]
    fn renders_png_exr_and_side_by_side() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("a.png");
        run(&request(png.clone()), &["chrome"]).unwrap();
        assert_eq!(image::image_dimensions(&png).unwrap(), (16, 16));
        let exr = dir.path().join("a.exr");
        let point = RenderRequest {
            light: Some(LightKind::Point),
            shape: ShapeKind::Speedshape,
            ..request(exr.clone())
        };
        run(&point, &["silver-925"]).unwrap();
        assert_eq!(LinearImage::load(&exr).unwrap().width, 16);
        let grid = dir.path().join("g.png");
        let side = RenderRequest {
            side_by_side: true,
            env: Some("constant:0.5".into()),
            ..request(grid.clone())
        };
        let rendered = run(&side, &["chrome", "green-paint"]).unwrap();
        let (w, _) = image::image_dimensions(&grid).unwrap();
        assert!(w > 3 * 16, "three tiles: {w}");
        let (difference, labels) = rendered.difference.unwrap();
        assert!(difference > 0.0 && difference <= 1.0, "{difference}");
        assert_eq!(labels, ["A: chrome", "B: green-paint"]);
    }

    #[test]
    fn tiles_are_labelled_by_source_and_role() {
        let dir = tempfile::tempdir().unwrap();
        let table = dir.path().join("A.binary");
        std::fs::write(&table, b"x").unwrap();
        let table = table.display().to_string();
        let specs = [table.as_str(), "green-paint"];
        assert_eq!(tile_labels(&specs), ["A: A.binary", "B: green-paint"]);
        assert_eq!(tile_labels(&specs[1..]), ["green-paint"]);
    }

    #[test]
    fn bad_requests_are_refused_with_a_reason() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a.png");
        let message = |r: RenderRequest, n: usize| r.validate(n).unwrap_err().to_string();
        assert!(message(request(out.clone()), 2).contains("--side-by-side"));
        let exr = RenderRequest {
            side_by_side: true,
            ..request(dir.path().join("a.exr"))
        };
        assert!(message(exr, 1).contains(".png"));
        assert!(message(request(dir.path().join("a.jpg")), 1).contains("a.jpg"));
        let both = RenderRequest {
            light: Some(LightKind::Point),
            env: Some("studio".into()),
            ..request(out.clone())
        };
        assert!(message(both, 1).contains("choose one"));
        let missing = RenderRequest {
            env: Some("/no/such.exr".into()),
            ..request(out.clone())
        };
        assert!(message(missing, 1).contains("/no/such.exr"));
        let small = RenderRequest {
            size_px: 4,
            ..request(out.clone())
        };
        assert_eq!(
            message(small, 1),
            "size 4: expected a whole number from 8 to 8192"
        );
        assert_eq!(
            "spot".parse::<LightKind>().unwrap_err().to_string(),
            "light 'spot': expected one of point"
        );
    }
}
