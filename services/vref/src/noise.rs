//! A camera's per-reading depth noise for the commands that take one's own
//! frames (`vref match`, `vref segment`): measured on the frame itself,
//! where the configuration describes other cameras.

use vref_perception::folder::RgbdImages;
use vref_perception::{DepthLaw, pixel_noise};

/// The law `sigma = c z^2` that `who`'s frame shows; `None` (with a
/// warning) where it has too little depth to tell.
pub fn measured_law(images: &RgbdImages, who: &str) -> Option<DepthLaw> {
    let Some(measured) = pixel_noise(&images.depth) else {
        tracing::warn!("{who}: too little depth to measure its noise");
        return None;
    };
    tracing::info!(
        frame = who,
        c = measured.c,
        samples = measured.samples,
        "depth noise measured: sigma = c z^2"
    );
    Some(DepthLaw {
        a: 0.0,
        b: 0.0,
        c: measured.c,
    })
}
