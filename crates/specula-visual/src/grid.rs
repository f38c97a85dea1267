//! Side-by-side pictures: renders of several materials under the same light in one labelled
//! image, and a false-colour difference image of two (paper Fig. 16, 17 compare materials so).

use crate::canvas::Canvas;
use crate::color::{false_colour, luminance};
use crate::error::VisualError;
use crate::font;
use crate::linear_image::LinearImage;
use image::RgbImage;
use plotters::prelude::*;

/// Background of the grid.
const BACKGROUND: [u8; 3] = [28, 28, 30];
/// Most tiles in one row.
const MAX_COLUMNS: usize = 4;

/// One labelled picture of a grid.
#[derive(Debug, Clone)]
pub struct Tile {
    /// The caption drawn with the picture.
    pub label: String,
    /// The picture.
    pub image: RgbImage,
}

/// The pixel-wise relative difference of two renders.
#[derive(Debug, Clone)]
pub struct Difference {
    /// `|L_a - L_b| / max(L_a, L_b)` of the luminance, false-coloured from black (0) to pale
    /// yellow (1 or more).
    pub image: RgbImage,
    /// The mean of that ratio over the pixels where either render is brighter than 1 percent
    /// of their mean luminance.
    pub mean_relative: f64,
}

/// Compares two renders of the same size (see [`Difference`]).
pub fn difference(a: &LinearImage, b: &LinearImage) -> Result<Difference, VisualError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(VisualError::Data(format!(
            "renders differ in size ({} x {} and {} x {})",
            a.width, a.height, b.width, b.height
        )));
    }
    let mean = |img: &LinearImage| {
        img.pixels.iter().map(|p| luminance(*p)).sum::<f64>() / img.pixels.len().max(1) as f64
    };
    let floor = 0.01 * mean(a).max(mean(b)).max(f64::MIN_POSITIVE);
    let mut total = 0.0;
    let mut counted = 0usize;
    let ratios: Vec<f64> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(pa, pb)| {
            let (la, lb) = (luminance(*pa), luminance(*pb));
            let top = la.max(lb);
            if top <= floor {
                return 0.0;
            }
            let r = (la - lb).abs() / top;
            total += r;
            counted += 1;
            r
        })
        .collect();
    let image = RgbImage::from_fn(a.width as u32, a.height as u32, |x, y| {
        image::Rgb(false_colour(ratios[y as usize * a.width + x as usize]))
    });
    Ok(Difference {
        image,
        mean_relative: if counted > 0 {
            total / counted as f64
        } else {
            0.0
        },
    })
}

/// Lays the tiles out in rows of up to four, each with its label underneath.
pub fn compose(tiles: &[Tile]) -> Result<RgbImage, VisualError> {
    let Some(first) = tiles.first() else {
        return Err(VisualError::Data(String::from("nothing to lay out")));
    };
    let (w, h) = first.image.dimensions();
    if tiles.iter().any(|t| t.image.dimensions() != (w, h)) {
        return Err(VisualError::Data(String::from(
            "all pictures of a grid must have the same size",
        )));
    }
    let font_px = (w as f64 / 18.0).clamp(12.0, 28.0);
    let label_h = (font_px * 1.8) as u32;
    let gap = 6u32;
    let columns = tiles.len().min(MAX_COLUMNS) as u32;
    let rows = tiles.len().div_ceil(MAX_COLUMNS) as u32;
    let width = columns * w + (columns + 1) * gap;
    let height = rows * (h + label_h) + (rows + 1) * gap;
    let mut out = RgbImage::from_pixel(width, height, image::Rgb(BACKGROUND));
    for (i, tile) in tiles.iter().enumerate() {
        let (col, row) = (i as u32 % columns, i as u32 / columns);
        let x = gap + col * (w + gap);
        let y = gap + row * (h + label_h + gap);
        image::imageops::replace(&mut out, &tile.image, x as i64, y as i64);
    }
    font::ensure_registered();
    {
        let root = Canvas::with_buffer(out.as_mut(), (width, height)).into_drawing_area();
        let style = TextStyle::from((font::FAMILY, font_px).into_font())
            .color(&RGBColor(235, 235, 235))
            .pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ));
        for (i, tile) in tiles.iter().enumerate() {
            let (col, row) = (i as u32 % columns, i as u32 / columns);
            let cx = gap + col * (w + gap) + w / 2;
            let cy = gap + row * (h + label_h + gap) + h + label_h / 2;
            let label = fit_label(&tile.label, w as f64, font_px);
            root.draw_text(&label, &style, (cx as i32, cy as i32))
                .map_err(VisualError::draw(format!("the label '{label}'")))?;
        }
        root.present().map_err(VisualError::draw("the grid"))?;
    }
    Ok(out)
}

/// Shortens a label to about the width of its tile (DejaVu Sans averages 0.55 em a glyph).
fn fit_label(label: &str, width_px: f64, font_px: f64) -> String {
    let max_chars = ((width_px / (0.55 * font_px)) as usize).max(4);
    if label.chars().count() <= max_chars {
        label.to_string()
    } else {
        let head: String = label.chars().take(max_chars - 3).collect();
        format!("{head}...")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn difference_is_zero_for_equal_images_and_one_for_black_against_lit() {
        let mut a = LinearImage::new(4, 4);
        a.pixels.fill(DVec3::splat(0.5));
        let d = difference(&a, &a).unwrap();
        assert_eq!(d.mean_relative, 0.0);
        let mut b = a.clone();
        b.pixels[0] = DVec3::ZERO;
        let d = difference(&a, &b).unwrap();
        assert!((d.mean_relative - 1.0 / 16.0).abs() < 1e-12);
        assert_eq!(d.image.get_pixel(0, 0).0, false_colour(1.0));
        assert!(difference(&a, &LinearImage::new(3, 4)).is_err());
    }

    #[test]
    fn grid_places_tiles_and_draws_labels() {
        let tile = |v: u8, label: &str| Tile {
            label: label.into(),
            image: RgbImage::from_pixel(64, 48, image::Rgb([v, v, v])),
        };
        let tiles = [
            tile(200, "chrome"),
            tile(100, "silver-925"),
            tile(50, "difference"),
        ];
        let grid = compose(&tiles).unwrap();
        // Three tiles of 64 with four gaps of 6; one row of 48 plus a 21-pixel label (12 px font).
        assert_eq!(grid.dimensions(), (216, 81));
        assert_eq!(grid.get_pixel(6 + 10, 6 + 10).0, [200, 200, 200]);
        assert_eq!(grid.get_pixel(6 + 70 + 10, 6 + 10).0, [100, 100, 100]);
        // Some label pixels are light: the text was drawn with the embedded font.
        let label_band = (0..grid.width())
            .flat_map(|x| (6 + 48..grid.height()).map(move |y| (x, y)))
            .filter(|(x, y)| grid.get_pixel(*x, *y).0[0] > 150)
            .count();
        assert!(label_band > 20, "{label_band} label pixels");
        assert!(compose(&[]).is_err());
    }
}
