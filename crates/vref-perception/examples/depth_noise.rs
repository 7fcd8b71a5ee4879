//! Prints the per-reading depth noise each frame folder shows
//! (`vref_perception::pixel_noise`): `c` of `sigma = c z^2`, and the
//! second differences it rests on.
//!
//! cargo run --release -p vref-perception --example depth_noise -- FRAME_DIR...

use std::path::Path;

use vref_perception::folder::RgbdImages;
use vref_perception::{ImageLimit, pixel_noise};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for dir in std::env::args().skip(1) {
        let images = RgbdImages::load(Path::new(&dir), ImageLimit::default())?;
        match pixel_noise(&images.depth) {
            Some(n) => println!("{dir}\t{:.5}\t{}", n.c, n.samples),
            None => println!("{dir}\tnone"),
        }
    }
    Ok(())
}
