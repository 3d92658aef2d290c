//! The font of every plot: DejaVu Sans, embedded in the program (licence in `fonts/LICENSE-DejaVu.txt`)
//! so that plots need no system fonts, fontconfig or freetype.

use std::sync::Once;

use plotters::style::FontStyle;

/// The family name plots ask for; SVG files name it too, so viewers substitute their own sans-serif.
pub const FAMILY: &str = "sans-serif";

static DEJAVU_SANS: &[u8] = include_bytes!("../../fonts/DejaVuSans.ttf");

/// Registers the embedded font with plotters, once per process.
pub fn register() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        if plotters::style::register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_err() {
            panic!("the embedded DejaVu Sans font does not parse");
        }
    });
}
