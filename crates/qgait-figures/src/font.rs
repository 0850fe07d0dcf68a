//! Registers the DejaVu Sans font (shipped inside the `dejavu` crate) with plotters, so text
//! renders identically on any machine, with no system fonts installed.

use std::sync::OnceLock;

use plotters::style::{register_font, FontStyle};

/// The font family name the figures use.
pub const FAMILY: &str = "sans-serif";

/// Registers the font once per process; whether it is registered.
pub fn ensure_registered() -> bool {
    static DONE: OnceLock<bool> = OnceLock::new();
    *DONE.get_or_init(|| {
        register_font(FAMILY, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(FAMILY, FontStyle::Bold, dejavu::sans::bold()).is_ok()
            && register_font(FAMILY, FontStyle::Oblique, dejavu::sans::oblique()).is_ok()
            && register_font(FAMILY, FontStyle::Italic, dejavu::sans::oblique()).is_ok()
    })
}
