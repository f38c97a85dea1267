//! The renderer against Mitsuba 3 at equal settings (tools/mitsuba_render_check.py made the
//! references): an analytic rough conductor on the unit sphere, under the standard point light
//! and under a constant environment. The mean relative difference over the pixels fully
//! covered by the sphere (reference luminance above 0.1 percent of the brightest) must stay
//! under 2 percent.
//!
//! The RGL writer end to end (tools/rgl_export_check.py made the references): Mitsuba renders
//! the `.bsdf` file `specula convert` wrote with its `measured` plugin; Specula renders the
//! source itself (chrome, the green paint); within 3 percent. For the real RGL file
//! round-tripped (`cc_ibiza_sunset_rgb`), Mitsuba passes the camera direction as the file's
//! incident direction (its `si.wi`) and the light as the outgoing one, where Specula's
//! renderer evaluates `f(light, camera)`: a measured file is not reciprocal (each incident
//! slice has its own warped sample grid), so Mitsuba's render is closer to Specula's render
//! of the original file transposed, `f(camera, light)`, than of the file itself.

use glam::DVec3;
use specula_core::materials::{preset, Material};
use specula_core::Brdf;
use specula_visual::camera::Camera;
use specula_visual::color::luminance;
use specula_visual::{
    render, Environment, Lighting, LinearImage, RenderSettings, Scene, ShapeKind,
};
use std::path::PathBuf;
use std::sync::Arc;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Pixels whose four corners all see the unit sphere.
fn covered(camera: &Camera, x: usize, y: usize) -> bool {
    [(0, 0), (1, 0), (0, 1), (1, 1)].iter().all(|(dx, dy)| {
        let ray = camera.ray((x + dx) as f64, (y + dy) as f64);
        let b = ray.origin.dot(ray.dir);
        b * b - (ray.origin.length_squared() - 1.0) >= 0.0
    })
}

fn mean_relative_difference(ours: &LinearImage, reference: &LinearImage) -> (f64, usize) {
    assert_eq!(
        (ours.width, ours.height),
        (reference.width, reference.height)
    );
    let camera = Camera::standard(reference.width, reference.height);
    let brightest = (0..reference.height)
        .flat_map(|y| (0..reference.width).map(move |x| (x, y)))
        .filter(|(x, y)| covered(&camera, *x, *y))
        .map(|(x, y)| luminance(reference.get(x, y)))
        .fold(0.0, f64::max);
    let mut total = 0.0;
    let mut count = 0;
    for y in 0..reference.height {
        for x in 0..reference.width {
            let r = reference.get(x, y);
            if !covered(&camera, x, y) || luminance(r) <= 1e-3 * brightest {
                continue;
            }
            let o = ours.get(x, y);
            total += ((o - r).abs() / r.max(DVec3::splat(1e-12))).element_sum();
            count += 3;
        }
    }
    (total / count as f64, count / 3)
}

fn check(lighting: Lighting, reference: &str, spp: usize) {
    let material = Material::from_toml_file(data("mitsuba_conductor.toml")).unwrap();
    check_brdf(&material, lighting, reference, spp, 0.02, 1500);
}

/// Renders `brdf` as the reference was rendered and holds the mean relative difference under
/// `tolerance` over at least `min_pixels` pixels.
fn check_brdf(
    brdf: &dyn Brdf,
    lighting: Lighting,
    reference: &str,
    spp: usize,
    tolerance: f64,
    min_pixels: usize,
) {
    let name = reference;
    let reference = LinearImage::load(&data(reference)).unwrap();
    let scene = Scene::new(ShapeKind::Sphere, lighting);
    let settings = RenderSettings {
        width: reference.width,
        height: reference.height,
        samples_per_pixel: spp,
        seed: 7,
    };
    let ours = render(brdf, &scene, &settings, &|_| {});
    let (difference, pixels) = mean_relative_difference(&ours, &reference);
    println!(
        "{name} ({} px): mean relative difference {difference:.4} over {pixels} pixels",
        reference.width
    );
    assert!(pixels >= min_pixels, "too few pixels compared: {pixels}");
    assert!(
        difference < tolerance,
        "{name}: mean relative difference {difference}"
    );
}

/// Specula's render of `source` against Mitsuba's renders of the `.bsdf` written from it.
fn check_rgl_export(source: &dyn Brdf, material: &str) {
    check_brdf(
        source,
        Lighting::standard_point(),
        &format!("mitsuba_rgl_{material}_point.exr"),
        64,
        0.03,
        // A sharp conductor lights only its highlight (about 50 pixels) under a point light.
        40,
    );
    let env = Environment::constant(DVec3::ONE);
    check_brdf(
        source,
        Lighting::Environment(Arc::new(env)),
        &format!("mitsuba_rgl_{material}_constant.exr"),
        256,
        0.03,
        1500,
    );
}

#[test]
fn written_rgl_files_render_in_mitsuba_as_their_sources() {
    for material in ["chrome", "green-paint"] {
        check_rgl_export(&preset(material).unwrap(), material);
    }
}

/// `f(wo, wi)`: a BRDF with the roles of light and camera exchanged.
struct Transposed(Arc<dyn Brdf>);

impl Brdf for Transposed {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<specula_core::Rgb> {
        self.0.eval(wo, wi)
    }
    fn name(&self) -> String {
        self.0.name()
    }
}

/// Specula's render of `brdf` under the point light against `reference`: the mean relative
/// difference and the pixels compared.
fn point_light_difference(brdf: &dyn Brdf, reference: &str) -> (f64, usize) {
    let reference = LinearImage::load(&data(reference)).unwrap();
    let settings = RenderSettings {
        width: reference.width,
        height: reference.height,
        samples_per_pixel: 64,
        seed: 7,
    };
    let scene = Scene::new(ShapeKind::Sphere, Lighting::standard_point());
    mean_relative_difference(&render(brdf, &scene, &settings, &|_| {}), &reference)
}

/// The round-trip mismatch of the real file is mostly the order of light and camera: with
/// the source transposed the difference must fall below a quarter of the untransposed one
/// (measured: 40 % as it is, 7.8 % transposed; the rest is not explained yet).
#[test]
fn written_real_rgl_file_renders_in_mitsuba_as_its_source_transposed() {
    let file =
        specula_formats::input::measured_data_dir().join("rgl_bsdf/cc_ibiza_sunset_rgb.bsdf");
    if !file.is_file() {
        println!(
            "skipped: {} not found (the measured data of ../shared)",
            file.display()
        );
        return;
    }
    let source = specula_formats::load_brdf(file.to_str().unwrap()).unwrap();
    let reference = "mitsuba_rgl_cc_ibiza_sunset_rgb_point.exr";
    let (as_is, pixels) = point_light_difference(&source, reference);
    let (transposed, _) = point_light_difference(&Transposed(source), reference);
    println!("cc_ibiza_sunset_rgb, point light, {pixels} pixels: mean relative difference {as_is:.4} as it is, {transposed:.4} transposed");
    assert!(pixels >= 1500, "too few pixels compared: {pixels}");
    assert!(transposed < 0.25 * as_is, "{transposed} vs {as_is}");
}

#[test]
fn point_light_matches_mitsuba() {
    check(Lighting::standard_point(), "mitsuba_point.exr", 64);
}

#[test]
fn constant_environment_matches_mitsuba() {
    let env = Environment::constant(DVec3::ONE);
    check(
        Lighting::Environment(Arc::new(env)),
        "mitsuba_constant.exr",
        256,
    );
}
