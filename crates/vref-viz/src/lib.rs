//! Pictures of vref results, as PNG files: one scene's predicted
//! correspondences ([`MatchPicture`]) and accuracy curves ([`line_plot`]).
//!
//! Text is drawn with a font compiled into this crate, so rendering needs
//! nothing from the machine: no system fonts, no system libraries.

mod canvas;
mod error;
mod font;
mod image_match;
mod line_plot;
mod lookup;
mod match_picture;
mod projection;
mod quantize;
mod status_match;

pub use canvas::Size;
pub use error::{RenderError, SceneLookupError};
pub use image_match::{ImageMatchPicture, ImageObject, ViewImage};
pub use line_plot::{
    Axes, Scale, line_plot, line_plot_scaled, render_line_plot, render_line_plot_scaled,
};
pub use lookup::find_scene;
pub use match_picture::MatchPicture;
pub use projection::{Projection, UnknownProjection};
pub use status_match::{Answer, AnswerPicture, AnswerStatus};
