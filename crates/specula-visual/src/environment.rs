//! Environment lighting: radiance arriving from every direction, stored as a latitude-longitude
//! image and sampled in proportion to its luminance (for multiple importance sampling with the
//! material's lobe, see [`crate::render`]).
//!
//! Mapping (Mitsuba 3's `envmap` with an identity transform, checked against it): y is up;
//! the image column `u = atan2(x, -z) / 2 pi` (wrapped into `[0, 1)`), the row
//! `v = acos(y) / pi`. The image's left and right edges (u = 0) are the direction -z, which
//! the standard camera looks along (the backdrop); a quarter across is +x; the centre is +z,
//! behind the camera (what a mirror sphere shows in its middle).

use crate::color::luminance;
use crate::distribution::Distribution2D;
use crate::error::VisualError;
use crate::linear_image::LinearImage;
use glam::DVec3;
use std::f64::consts::{PI, TAU};
use std::path::Path;

/// Width of the built-in studio environment's image; its height is half.
const STUDIO_WIDTH: usize = 512;
/// Widest grid of the sampling distribution (its height is half): each of its cells holds the
/// summed luminance of the texels it covers. Coarser than the image, it stays in the
/// processor's cache, which makes sampling several times faster; the density is still exact.
const SAMPLING_WIDTH: usize = 256;

/// Radiance from all directions, with its luminance-proportional sampling distribution.
#[derive(Debug, Clone)]
pub struct Environment {
    name: String,
    width: usize,
    height: usize,
    /// Linear RGB radiance, row-major from the top (y = +1); single precision halves the
    /// memory traffic of the renderer's lookups.
    texels: Vec<[f32; 3]>,
    distribution: Distribution2D,
}

impl Environment {
    /// An environment from a latitude-longitude image of linear radiance.
    pub fn from_image(name: impl Into<String>, image: LinearImage) -> Result<Self, VisualError> {
        if image.width < 2 || image.height < 1 {
            return Err(VisualError::Data(String::from(
                "an environment image needs at least 2 x 1 pixels",
            )));
        }
        if image
            .pixels
            .iter()
            .any(|p| !p.is_finite() || p.min_element() < 0.0)
        {
            return Err(VisualError::Data(String::from(
                "an environment image must hold finite, non-negative radiance",
            )));
        }
        let (width, height) = (image.width, image.height);
        let (sampling_width, sampling_height) =
            (width.min(SAMPLING_WIDTH), height.min(SAMPLING_WIDTH / 2));
        let mut weights = vec![0.0; sampling_width * sampling_height];
        for (i, p) in image.pixels.iter().enumerate() {
            let (x, y) = (i % width, i / width);
            let cell = (y * sampling_height / height) * sampling_width + x * sampling_width / width;
            weights[cell] += luminance(*p).max(0.0);
        }
        for (i, w) in weights.iter_mut().enumerate() {
            let row = i / sampling_width;
            *w *= (PI * (row as f64 + 0.5) / sampling_height as f64).sin();
        }
        Ok(Self {
            name: name.into(),
            width,
            height,
            texels: image
                .pixels
                .iter()
                .map(|p| [p.x as f32, p.y as f32, p.z as f32])
                .collect(),
            distribution: Distribution2D::new(&weights, sampling_width),
        })
    }

    /// Reads an OpenEXR or Radiance HDR latitude-longitude image.
    pub fn from_file(path: &Path) -> Result<Self, VisualError> {
        let image = LinearImage::load(path)?;
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| path.display().to_string());
        Self::from_image(name, image).map_err(|cause| VisualError::Environment {
            path: path.to_path_buf(),
            cause: Box::new(cause),
        })
    }

    /// The same radiance from every direction.
    pub fn constant(radiance: DVec3) -> Self {
        let mut image = LinearImage::new(8, 4);
        image.pixels.fill(radiance.max(DVec3::ZERO));
        Self::from_image("constant", image).expect("a constant image is a valid environment")
    }

    /// The built-in studio: a pale cyclorama over a dark grey floor with a crisp horizon, a
    /// large warm key softbox to the upper left, a cool fill on the right, a strip light
    /// behind the object and one small bright spot, so that both glossy and mirror-like
    /// materials show structured highlights.
    pub fn studio() -> Self {
        let (width, height) = (STUDIO_WIDTH, STUDIO_WIDTH / 2);
        let mut image = LinearImage::new(width, height);
        for (i, p) in image.pixels.iter_mut().enumerate() {
            let u = ((i % width) as f64 + 0.5) / width as f64;
            let v = ((i / width) as f64 + 0.5) / height as f64;
            *p = studio_radiance(direction_of(u, v));
        }
        Self::from_image("studio", image).expect("the studio is a valid environment")
    }

    /// The environment named on the command line: `studio`, `constant` (radiance 1),
    /// `constant:VALUE`, or the path of an `.exr` / `.hdr` latitude-longitude image.
    pub fn from_spec(spec: &str) -> Result<Self, VisualError> {
        if spec.eq_ignore_ascii_case("studio") {
            return Ok(Self::studio());
        }
        if let Some(rest) = spec.strip_prefix("constant") {
            let value = match rest.strip_prefix(':') {
                None if rest.is_empty() => 1.0,
                Some(v) => v
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite() && *v >= 0.0)
                    .ok_or_else(|| {
                        VisualError::Data(format!(
                            "{spec}: the constant radiance must be a non-negative number"
                        ))
                    })?,
                None => {
                    return Err(VisualError::Data(format!(
                        "{spec}: write constant or constant:VALUE"
                    )))
                }
            };
            return Ok(Self::constant(DVec3::splat(value)));
        }
        let path = Path::new(spec);
        if !path.exists() {
            return Err(VisualError::Data(format!(
                "{spec}: no such environment file (or use studio, constant, constant:VALUE)"
            )));
        }
        Self::from_file(path)
    }

    /// The environment's name: `studio`, `constant`, or the file's stem.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The radiance arriving from direction `dir` (bilinear between texel centres).
    pub fn radiance(&self, dir: DVec3) -> DVec3 {
        let (u, v) = uv_of(dir);
        self.radiance_at(u, v)
    }

    /// The radiance from `dir` and the density per steradian with which
    /// [`Environment::sample`] draws it, sharing one conversion to image coordinates.
    pub fn eval(&self, dir: DVec3) -> (DVec3, f64) {
        let (u, v) = uv_of(dir);
        let sin_theta = (dir.x * dir.x + dir.z * dir.z).sqrt();
        (self.radiance_at(u, v), self.pdf_at(u, v, sin_theta))
    }

    /// A direction drawn in proportion to the luminance, with its density and radiance.
    /// `None` for the (measure-zero) poles.
    pub fn sample(&self, u0: f64, u1: f64) -> Option<EnvironmentSample> {
        let ((u, v), pdf_uv) = self.distribution.sample(u0, u1);
        let sin_theta = (PI * v).sin();
        if sin_theta <= 0.0 || pdf_uv <= 0.0 {
            return None;
        }
        Some(EnvironmentSample {
            dir: direction_of(u, v),
            pdf: pdf_uv / (2.0 * PI * PI * sin_theta),
            uv: (u, v),
        })
    }

    /// The radiance arriving along a sampled direction (computed only when needed).
    pub fn sample_radiance(&self, sample: &EnvironmentSample) -> DVec3 {
        self.radiance_at(sample.uv.0, sample.uv.1)
    }

    /// The density per steradian with which [`Environment::sample`] draws `dir`.
    pub fn pdf(&self, dir: DVec3) -> f64 {
        let (u, v) = uv_of(dir);
        self.pdf_at(u, v, (dir.x * dir.x + dir.z * dir.z).sqrt())
    }

    /// The density per steradian at image coordinates `(u, v)`, `sin_theta` being the sine of
    /// the direction's angle from the y axis.
    fn pdf_at(&self, u: f64, v: f64, sin_theta: f64) -> f64 {
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.distribution.pdf(u, v) / (2.0 * PI * PI * sin_theta)
    }

    /// Bilinear interpolation between texel centres at image coordinates `(u, v)`.
    fn radiance_at(&self, u: f64, v: f64) -> DVec3 {
        let (w, h) = (self.width, self.height);
        // Columns wrap around; rows stop at the poles.
        let x = (u * w as f64 - 0.5).rem_euclid(w as f64);
        let y = (v * h as f64 - 0.5).clamp(0.0, (h - 1) as f64);
        let (x0, y0) = ((x as usize).min(w - 1), (y as usize).min(h - 1));
        let (fx, fy) = (x - x0 as f64, y - y0 as f64);
        let x1 = if x0 + 1 == w { 0 } else { x0 + 1 };
        let y1 = (y0 + 1).min(h - 1);
        let texel = |c: usize, r: usize| {
            let [red, green, blue] = self.texels[r * w + c];
            DVec3::new(red as f64, green as f64, blue as f64)
        };
        let top = texel(x0, y0) * (1.0 - fx) + texel(x1, y0) * fx;
        let bottom = texel(x0, y1) * (1.0 - fx) + texel(x1, y1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// A direction drawn from an environment.
#[derive(Debug, Clone, Copy)]
pub struct EnvironmentSample {
    /// The drawn direction, unit length, world frame.
    pub dir: DVec3,
    /// Density per steradian.
    pub pdf: f64,
    /// Image coordinates of `dir`.
    uv: (f64, f64),
}

/// The image coordinates `(u, v)` in `[0, 1)` of a unit direction.
pub fn uv_of(dir: DVec3) -> (f64, f64) {
    let u = (dir.x.atan2(-dir.z) / TAU).rem_euclid(1.0);
    let v = dir.y.clamp(-1.0, 1.0).acos() / PI;
    (u, v.min(1.0 - f64::EPSILON))
}

/// The unit direction of image coordinates `(u, v)`.
pub fn direction_of(u: f64, v: f64) -> DVec3 {
    let phi = TAU * u;
    let (sin_t, cos_t) = (PI * v).sin_cos();
    let (sin_p, cos_p) = phi.sin_cos();
    DVec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p)
}

/// A rectangular softbox in azimuth and elevation with softened edges.
struct Softbox {
    azimuth_deg: f64,
    elevation_deg: f64,
    half_width_deg: f64,
    half_height_deg: f64,
    radiance: DVec3,
}

impl Softbox {
    fn contribution(&self, azimuth_deg: f64, elevation_deg: f64) -> DVec3 {
        let da = (azimuth_deg - self.azimuth_deg + 540.0).rem_euclid(360.0) - 180.0;
        let de = elevation_deg - self.elevation_deg;
        let inside = |d: f64, half: f64| 1.0 - smoothstep(half - 1.0, half + 1.0, d.abs());
        self.radiance * inside(da, self.half_width_deg) * inside(de, self.half_height_deg)
    }
}

fn smoothstep(edge0: f64, edge1: f64, x: f64) -> f64 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The studio's radiance towards `dir`. Azimuth 0 is +z (behind the camera), 90 deg is +x.
fn studio_radiance(dir: DVec3) -> DVec3 {
    let elevation_deg = dir.y.clamp(-1.0, 1.0).asin().to_degrees();
    let azimuth_deg = dir.x.atan2(dir.z).to_degrees();
    let mut radiance = if elevation_deg < 0.0 {
        // A dark grey floor, a little lighter towards the horizon.
        DVec3::new(0.10, 0.095, 0.09) * (0.7 + 0.3 * (elevation_deg / 20.0).exp())
    } else {
        // A pale cyclorama brightening towards the ceiling, with a darker band just above the
        // horizon so that mirror-like materials show a crisp horizon line.
        let height = (elevation_deg / 90.0).clamp(0.0, 1.0);
        let band = 1.0 - 0.6 * (-elevation_deg / 4.0).exp();
        DVec3::new(0.30, 0.31, 0.33) * (0.5 + 1.1 * height.sqrt()) * band
    };
    let lights = [
        Softbox {
            azimuth_deg: -50.0,
            elevation_deg: 40.0,
            half_width_deg: 22.0,
            half_height_deg: 14.0,
            radiance: DVec3::new(12.0, 11.4, 10.5),
        },
        Softbox {
            azimuth_deg: 70.0,
            elevation_deg: 15.0,
            half_width_deg: 10.0,
            half_height_deg: 20.0,
            radiance: DVec3::new(3.6, 4.0, 4.8),
        },
        Softbox {
            azimuth_deg: 180.0,
            elevation_deg: 50.0,
            half_width_deg: 40.0,
            half_height_deg: 4.0,
            radiance: DVec3::splat(8.0),
        },
        Softbox {
            azimuth_deg: 25.0,
            elevation_deg: 22.0,
            half_width_deg: 2.0,
            half_height_deg: 2.0,
            radiance: DVec3::splat(60.0),
        },
    ];
    for light in &lights {
        radiance += light.contribution(azimuth_deg, elevation_deg);
    }
    radiance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mapping_round_trips_and_follows_mitsuba() {
        for &(u, v) in &[(0.1, 0.2), (0.5, 0.5), (0.93, 0.77), (0.0, 0.01)] {
            let (u2, v2) = uv_of(direction_of(u, v));
            assert!((u - u2).abs() < 1e-12 && (v - v2).abs() < 1e-12, "{u} {v}");
        }
        // Mitsuba 3.9.1's envmap (scalar_rgb) lights +x from a texel a quarter across the
        // middle row, and -x, -z, +z from other columns (checked with emitter.eval).
        assert!((direction_of(0.0, 0.5) - DVec3::NEG_Z).length() < 1e-12);
        assert!((direction_of(0.25, 0.5) - DVec3::X).length() < 1e-12);
        assert!((direction_of(0.5, 0.5) - DVec3::Z).length() < 1e-12);
        assert!((direction_of(0.3, 0.0) - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn pdf_is_a_density_over_the_sphere_and_matches_sampling() {
        let env = Environment::studio();
        // Integrate the pdf over the sphere by midpoint quadrature in (u, v).
        let (n_u, n_v) = (512, 256);
        let mut total = 0.0;
        for j in 0..n_v {
            for i in 0..n_u {
                let (u, v) = ((i as f64 + 0.5) / n_u as f64, (j as f64 + 0.5) / n_v as f64);
                let d_omega = TAU / n_u as f64 * PI / n_v as f64 * (PI * v).sin();
                total += env.pdf(direction_of(u, v)) * d_omega;
            }
        }
        assert!((total - 1.0).abs() < 1e-3, "{total}");
        for k in 0..100 {
            let u = (
                ((k as f64 + 0.5) * 0.618) % 1.0,
                ((k as f64 + 0.5) * 0.377) % 1.0,
            );
            let sample = env.sample(u.0, u.1).unwrap();
            let (dir, pdf) = (sample.dir, sample.pdf);
            assert!((dir.length() - 1.0).abs() < 1e-12);
            assert!(
                (pdf - env.pdf(dir)).abs() < 1e-6 * pdf,
                "{pdf} vs {}",
                env.pdf(dir)
            );
            let (radiance, pdf_eval) = env.eval(dir);
            let sampled = env.sample_radiance(&sample);
            assert!((radiance - sampled).length() < 1e-6 * radiance.length().max(1.0));
            assert!((pdf_eval - pdf).abs() < 1e-6 * pdf);
        }
    }

    #[test]
    fn importance_sampling_estimates_the_irradiance() {
        // Irradiance on an upward patch, E = integral L cos over the upper hemisphere, by the
        // luminance-sampled estimator and by quadrature.
        let env = Environment::studio();
        let (n_u, n_v) = (1024, 512);
        let mut quadrature = DVec3::ZERO;
        for j in 0..n_v / 2 {
            for i in 0..n_u {
                let (u, v) = ((i as f64 + 0.5) / n_u as f64, (j as f64 + 0.5) / n_v as f64);
                let dir = direction_of(u, v);
                quadrature +=
                    env.radiance(dir) * dir.y * TAU / n_u as f64 * PI / n_v as f64 * (PI * v).sin();
            }
        }
        let n = 200_000;
        let mut estimate = DVec3::ZERO;
        for k in 0..n {
            let (u0, u1) = (
                ((k as f64 + 0.5) * 0.618_033_988_75) % 1.0,
                (k as f64 + 0.5) / n as f64,
            );
            if let Some(s) = env.sample(u0, u1) {
                if s.dir.y > 0.0 {
                    estimate += env.sample_radiance(&s) * s.dir.y / s.pdf;
                }
            }
        }
        estimate /= n as f64;
        let rel = ((estimate - quadrature).abs() / quadrature).max_element();
        assert!(rel < 0.01, "{estimate} vs {quadrature}");
    }

    #[test]
    fn specs_are_parsed() {
        assert_eq!(Environment::from_spec("studio").unwrap().name(), "studio");
        let c = Environment::from_spec("constant:0.25").unwrap();
        assert!((c.radiance(DVec3::Y) - DVec3::splat(0.25)).length() < 1e-12);
        assert!(
            (Environment::from_spec("constant")
                .unwrap()
                .radiance(DVec3::X)
                .x
                - 1.0)
                .abs()
                < 1e-12
        );
        for bad in ["constant:-1", "constant:x", "constantly", "/no/such.exr"] {
            let err = Environment::from_spec(bad).unwrap_err().to_string();
            assert!(err.contains(bad), "{err}");
        }
    }

    #[test]
    fn bad_images_are_refused() {
        let mut image = LinearImage::new(4, 2);
        image.pixels[3] = DVec3::new(f64::NAN, 0.0, 0.0);
        assert!(Environment::from_image("x", image).is_err());
        let c = Environment::constant(DVec3::splat(2.0));
        assert!(
            (c.radiance(DVec3::new(0.3, 0.4, 0.5).normalize()) - DVec3::splat(2.0)).length()
                < 1e-12
        );
    }
}
