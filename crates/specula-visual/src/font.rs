//! Fonts for labels and plot axes, embedded (DejaVu Sans, from the `dejavu` crate) so that no
//! system font is needed: plotters draws text with ab_glyph from the registered bytes.

use std::sync::Once;

/// The family name every label and plot in this crate uses.
pub const FAMILY: &str = "sans-serif";

/// Registers the embedded fonts with plotters (once per process).
pub fn ensure_registered() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        use plotters::style::FontStyle;
        // The bytes are a valid TrueType font shipped by the crate; a failure here is a
        // broken build, not bad input.
        let fonts = [
            (FontStyle::Normal, dejavu::sans::regular()),
            (FontStyle::Bold, dejavu::sans::bold()),
            (FontStyle::Italic, dejavu::sans::oblique()),
        ];
        for (style, bytes) in fonts {
            if plotters::style::register_font(FAMILY, style, bytes).is_err() {
                panic!("the embedded DejaVu font does not parse");
            }
        }
    });
}
