//! The bundled font, registered once per process as plotters' `sans-serif` family.

use super::FigureError;
use plotters::style::{register_font, FontStyle};
use std::sync::OnceLock;

/// DejaVu Sans 2.37 (Debian `fonts-dejavu-core`), Bitstream Vera + Arev licence: see
/// `pipeline/assets/fonts/LICENSE-DejaVu.txt`.
static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Family name the figures use; plotters' `FontFamily::SansSerif` looks this name up.
pub(crate) const FAMILY: &str = "sans-serif";

static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();

/// Registers the bundled font (idempotent, thread-safe).
pub(crate) fn ensure_font() -> Result<(), FigureError> {
    REGISTERED
        .get_or_init(|| {
            register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS)
                .map_err(|_| "ab_glyph rejected DejaVuSans.ttf".to_string())
        })
        .clone()
        .map_err(FigureError::Font)
}
