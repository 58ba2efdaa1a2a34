//! The one font kdray draws text with (plot labels, heatmap scales): DejaVu
//! Sans, embedded in the binary (assets/fonts), registered with plotters'
//! ab_glyph backend: no system fonts, fontconfig or freetype.

use std::sync::OnceLock;

use crate::error::{Error, Result};

const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
/// The family name plotters knows the font by.
pub const FAMILY: &str = "sans-serif";

/// Registers the font (once per process).
pub fn register() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FAMILY, plotters::style::FontStyle::Normal, FONT).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(Error::Output("the embedded font is invalid".into()))
    }
}
