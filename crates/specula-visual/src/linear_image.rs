//! A linear-radiance RGB image: what the renderer produces. Saved as OpenEXR (linear, 32-bit
//! float) or as a tone-mapped sRGB PNG, chosen by the file extension.

use crate::color::display_rgb8;
use crate::error::VisualError;
use glam::DVec3;
use image::{Rgb32FImage, RgbImage};
use std::path::Path;

/// A width x height grid of linear RGB values, row by row from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearImage {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// `width * height` pixels, row-major, top row first.
    pub pixels: Vec<DVec3>,
}

/// The kinds of file a render can be written to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// Tone-mapped 8-bit sRGB.
    Png,
    /// Linear 32-bit float OpenEXR.
    Exr,
}

impl ImageFormat {
    /// The format named by a path's extension (`.png` or `.exr`).
    pub fn of_path(path: &Path) -> Result<Self, VisualError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            Some("exr") => Ok(ImageFormat::Exr),
            _ => Err(VisualError::Data(format!(
                "{}: unknown image type (use .png for a tone-mapped picture or .exr for linear radiance)",
                path.display()
            ))),
        }
    }
}

impl LinearImage {
    /// A black image.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            pixels: vec![DVec3::ZERO; width * height],
        }
    }

    /// The pixel at column `x`, row `y` from the top.
    pub fn get(&self, x: usize, y: usize) -> DVec3 {
        self.pixels[y * self.width + x]
    }

    /// The tone-mapped 8-bit sRGB picture at the given exposure (stops).
    pub fn to_display(&self, exposure_ev: f64) -> RgbImage {
        RgbImage::from_fn(self.width as u32, self.height as u32, |x, y| {
            image::Rgb(display_rgb8(self.get(x as usize, y as usize), exposure_ev))
        })
    }

    /// The linear float image (f32 channels).
    pub fn to_rgb32f(&self) -> Rgb32FImage {
        Rgb32FImage::from_fn(self.width as u32, self.height as u32, |x, y| {
            let p = self.get(x as usize, y as usize);
            image::Rgb([p.x as f32, p.y as f32, p.z as f32])
        })
    }

    /// Writes a PNG (tone-mapped at `exposure_ev`) or an EXR (linear), by extension.
    pub fn save(&self, path: &Path, exposure_ev: f64) -> Result<(), VisualError> {
        match ImageFormat::of_path(path)? {
            ImageFormat::Png => return save_png(&self.to_display(exposure_ev), path),
            ImageFormat::Exr => specula_core::atomic_file::write_with(path, |out| {
                self.to_rgb32f()
                    .write_to(out, image::ImageFormat::OpenExr)
                    .map_err(std::io::Error::other)
            }),
        }
        .map_err(|cause| VisualError::Write {
            path: path.to_path_buf(),
            what: "the image",
            cause,
        })
    }

    /// Reads a linear image from an OpenEXR (`.exr`) or Radiance (`.hdr`) file.
    pub fn load(path: &Path) -> Result<Self, VisualError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if !matches!(extension.as_deref(), Some("exr") | Some("hdr")) {
            return Err(VisualError::Data(format!(
                "{}: not a high-dynamic-range image (expected .exr or .hdr)",
                path.display()
            )));
        }
        let decoded = image::open(path)
            .map_err(|cause| VisualError::Read {
                path: path.to_path_buf(),
                cause,
            })?
            .into_rgb32f();
        let (width, height) = (decoded.width() as usize, decoded.height() as usize);
        let pixels = decoded
            .pixels()
            .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
            .collect();
        Ok(Self {
            width,
            height,
            pixels,
        })
    }
}

/// Writes an 8-bit picture as PNG, atomically ([`specula_core::atomic_file`]); errors name
/// the file.
pub fn save_png(image: &RgbImage, path: &Path) -> Result<(), VisualError> {
    specula_core::atomic_file::write_with(path, |out| {
        image
            .write_to(out, image::ImageFormat::Png)
            .map_err(std::io::Error::other)
    })
    .map_err(|cause| VisualError::Write {
        path: path.to_path_buf(),
        what: "the PNG",
        cause,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exr_round_trips_linear_values() {
        let dir = tempfile::tempdir().unwrap();
        let mut img = LinearImage::new(5, 3);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            *p = DVec3::new(i as f64 * 0.25, 100.0 + i as f64, 1e-3);
        }
        let path = dir.path().join("a.exr");
        img.save(&path, 0.0).unwrap();
        let back = LinearImage::load(&path).unwrap();
        assert_eq!((back.width, back.height), (5, 3));
        for (a, b) in img.pixels.iter().zip(&back.pixels) {
            assert!((*a - *b).abs().max_element() < 1e-4 * a.max_element().max(1.0));
        }
    }

    #[test]
    fn png_is_tone_mapped_and_unknown_extensions_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mut img = LinearImage::new(2, 1);
        img.pixels[1] = DVec3::splat(1000.0);
        let path = dir.path().join("a.png");
        img.save(&path, 0.0).unwrap();
        let png = image::open(&path).unwrap().into_rgb8();
        assert_eq!(png.get_pixel(0, 0).0, [0, 0, 0]);
        assert_eq!(png.get_pixel(1, 0).0, [255, 255, 255]);
        let err = img.save(&dir.path().join("a.jpg"), 0.0).unwrap_err();
        assert!(err.to_string().contains("a.jpg"), "{err}");
        let err = LinearImage::load(&dir.path().join("missing.exr")).unwrap_err();
        assert!(format!("{err:#}").contains("missing.exr"));
    }
}
