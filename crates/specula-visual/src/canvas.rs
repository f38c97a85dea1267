//! The drawing surface of every plot and label: plotters' bitmap backend with text laid out
//! at fractional pen positions.
//!
//! plotters 0.3.7 draws each glyph of a string at the integer part of its pen position and
//! drops the glyph's left side bearing, so letters sit unevenly ("sil ver", "m easured").
//! [`Canvas`] hands every shape to [`BitMapBackend`] and lays text out itself with
//! `ab_glyph`: each glyph is positioned at its exact pen position (advance plus kerning) and
//! rasterised there, as a text renderer does.

use crate::font;
use ab_glyph::{point, Font, FontRef, OutlinedGlyph, PxScale, ScaleFont};
use plotters::prelude::BitMapBackend;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
    FontStyle,
};

/// A bitmap drawing backend over an RGB buffer, with properly spaced text.
pub struct Canvas<'a> {
    bitmap: BitMapBackend<'a>,
}

impl<'a> Canvas<'a> {
    /// A canvas over `buffer`, `size.0` x `size.1` pixels of 3 bytes (RGB).
    pub fn with_buffer(buffer: &'a mut [u8], size: (u32, u32)) -> Self {
        Self {
            bitmap: BitMapBackend::with_buffer(buffer, size),
        }
    }
}

/// A line of text laid out on a baseline at `ascent` below the layout box's top.
struct Line {
    glyphs: Vec<OutlinedGlyph>,
    /// Width and height of the layout box (advances, ascent to descent), pixels.
    width: f32,
    height: f32,
}

/// Lays `text` out in the embedded face of `style` at `size_px` (plotters' font size: the
/// font's height in pixels).
fn layout(text: &str, size_px: f64, style: FontStyle) -> Line {
    let face: &FontRef<'static> = font::face(style);
    let font = face.as_scaled(PxScale::from(size_px as f32));
    let mut pen_x = 0.0f32;
    let mut previous = None;
    let mut glyphs = Vec::new();
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(previous) = previous {
            pen_x += font.kern(previous, id);
        }
        let glyph = id.with_scale_and_position(font.scale(), point(pen_x, font.ascent()));
        glyphs.extend(font.outline_glyph(glyph));
        pen_x += font.h_advance(id);
        previous = Some(id);
    }
    Line {
        glyphs,
        width: pen_x,
        height: font.ascent() - font.descent(),
    }
}

impl DrawingBackend for Canvas<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.bitmap.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.bitmap.blit_bitmap(pos, size, src)
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let line = layout(text, style.size(), style.style());
        let dx = match style.anchor().h_pos {
            HPos::Left => 0.0,
            HPos::Right => -line.width,
            HPos::Center => -line.width / 2.0,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0.0,
            VPos::Center => -line.height / 2.0,
            VPos::Bottom => -line.height,
        };
        let transform = style.transform();
        for glyph in &line.glyphs {
            let bounds = glyph.px_bounds();
            let mut pixels = Vec::new();
            glyph.draw(|x, y, coverage| pixels.push((x, y, coverage)));
            for (x, y, coverage) in pixels {
                if coverage <= 0.0 {
                    continue;
                }
                let gx = (bounds.min.x + x as f32 + dx).round() as i32;
                let gy = (bounds.min.y + y as f32 + dy).round() as i32;
                let (tx, ty) = transform.transform(gx, gy);
                let shade = BackendColor {
                    alpha: color.alpha * f64::from(coverage.min(1.0)),
                    rgb: color.rgb,
                };
                self.bitmap.draw_pixel((pos.0 + tx, pos.1 + ty), shade)?;
            }
        }
        Ok(())
    }

    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let line = layout(text, style.size(), style.style());
        Ok((line.width.ceil() as u32, line.height.ceil() as u32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    /// The first column with ink of `text` drawn at x = 10 in the regular face at 60 px.
    fn first_inked_column(text: &str) -> usize {
        let (w, h) = (200usize, 90usize);
        let mut buffer = vec![255u8; w * h * 3];
        {
            font::ensure_registered();
            let root = Canvas::with_buffer(&mut buffer, (w as u32, h as u32)).into_drawing_area();
            let style = (font::FAMILY, 60.0).into_font().color(&BLACK);
            root.draw_text(text, &style, (10, 10)).unwrap();
            root.present().unwrap();
        }
        (0..w)
            .find(|&x| (0..h).any(|y| buffer[(y * w + x) * 3] < 128))
            .expect("the text left ink")
    }

    #[test]
    fn each_letter_keeps_its_side_bearing() {
        // A glyph's ink starts its left side bearing after the pen position (the font's
        // metrics, read here through ab_glyph's own accessor). plotters 0.3.7's text drawing
        // drops the bearing, which drew 'l' from column 11 instead of 15 here: the
        // uneven "sil ver".
        let font = font::face(FontStyle::Normal).as_scaled(PxScale::from(60.0));
        for c in ['l', 'i', 'o', 'v', 'r', 's', 'e'] {
            let bearing = font.h_side_bearing(font.glyph_id(c));
            let expected = 10.0 + bearing;
            let got = first_inked_column(&c.to_string()) as f32;
            assert!(
                (got - expected).abs() <= 1.0,
                "'{c}': ink from column {got}, the bearing puts it at {expected}"
            );
        }
    }

    #[test]
    fn estimated_width_matches_the_advances() {
        let short = layout("ab", 20.0, FontStyle::Normal).width;
        let long = layout("abab", 20.0, FontStyle::Normal).width;
        assert!((long - 2.0 * short).abs() < 1.0, "{short} {long}");
    }
}
