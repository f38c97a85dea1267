//! Fonts for labels and plot axes, embedded (DejaVu Sans, from the `dejavu` crate) so that no
//! system font is needed: plotters sizes and styles text by the registered family, and
//! [`crate::canvas::Canvas`] draws it with ab_glyph from the same bytes ([`face`]).

use ab_glyph::FontRef;
use plotters_backend::FontStyle;
use std::sync::{Once, OnceLock};

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

/// The embedded face of a style: DejaVu Sans regular, bold, or oblique (for italic and
/// oblique).
pub fn face(style: FontStyle) -> &'static FontRef<'static> {
    static FACES: OnceLock<[FontRef<'static>; 3]> = OnceLock::new();
    let faces = FACES.get_or_init(|| {
        // As in `ensure_registered`: the crate's bytes parse, or the build is broken.
        let parse = |bytes: &'static [u8]| {
            FontRef::try_from_slice(bytes).expect("the embedded DejaVu font parses")
        };
        [
            parse(dejavu::sans::regular()),
            parse(dejavu::sans::bold()),
            parse(dejavu::sans::oblique()),
        ]
    });
    match style {
        FontStyle::Normal => &faces[0],
        FontStyle::Bold => &faces[1],
        FontStyle::Oblique | FontStyle::Italic => &faces[2],
    }
}
