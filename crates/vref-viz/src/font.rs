//! The one font every picture uses, compiled in: CI machines and users'
//! machines need not have any font installed.

use std::sync::OnceLock;

use plotters::style::{FontStyle, register_font};

use crate::RenderError;

/// DejaVu Sans (licence: assets/LICENSE-DejaVu.txt).
const DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The family name plotters asks for by default (axis labels, legends), so
/// that every text it draws finds the bundled font.
pub(crate) const FAMILY: &str = "sans-serif";

/// Registers the bundled font once per process.
pub(crate) fn ensure_registered() -> Result<(), RenderError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok =
        *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok { Ok(()) } else { Err(RenderError::Font) }
}
