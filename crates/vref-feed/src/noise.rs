//! Which per-reading depth noise a camera's frame is measured with, where
//! vref segments and measures frames itself: `vref match`, `vref
//! segment`, the `rgbd:` and `rosbag:` sources and vref-ros2 all take it
//! from here, so that one frame is segmented alike by each.

use vref_perception::{DepthImage, DepthLaw, FrameLaw, NoiseSource};

/// The law `who`'s frame is measured with ([`FrameLaw::of`]), logged: the
/// measured `c` at info, a frame too bare to measure at warn.
pub fn frame_law(
    source: NoiseSource,
    depth: &DepthImage,
    configured: DepthLaw,
    who: &str,
) -> DepthLaw {
    let found = FrameLaw::of(source, depth, configured);
    match found {
        FrameLaw::Measured(m) => tracing::info!(
            frame = who,
            c = m.c,
            samples = m.samples,
            "depth noise measured: sigma = c z^2"
        ),
        FrameLaw::Unmeasured(_) => {
            tracing::warn!(
                frame = who,
                "too little depth to measure its noise: the configured law"
            );
        }
        FrameLaw::Configured(_) => {}
    }
    found.law()
}
