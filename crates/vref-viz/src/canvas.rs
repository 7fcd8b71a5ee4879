//! An in-memory RGB picture that plotters draws on and that is written out
//! as PNG.

use std::path::Path;

use plotters::backend::RGBPixel;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::quantize::quantize;
use crate::{RenderError, font};

/// Width and height of a picture in pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

impl Size {
    /// Smallest size the layouts still fit in.
    pub const MIN: Size = Size {
        width: 320,
        height: 240,
    };
    /// Largest side accepted: bounds the buffer (3 bytes a pixel) to a few
    /// hundred megabytes whatever a caller asks for.
    pub const MAX_SIDE: u32 = 10_000;

    pub const fn new(width: u32, height: u32) -> Self {
        Self { width, height }
    }

    fn check(self) -> Result<(), RenderError> {
        let fits = (Self::MIN.width..=Self::MAX_SIDE).contains(&self.width)
            && (Self::MIN.height..=Self::MAX_SIDE).contains(&self.height);
        if fits {
            Ok(())
        } else {
            Err(RenderError::BadSize {
                width: self.width,
                height: self.height,
                min_width: Self::MIN.width,
                min_height: Self::MIN.height,
                max_side: Self::MAX_SIDE,
            })
        }
    }
}

/// The drawing area handed to a picture's drawing code.
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a, RGBPixel>, Shift>;

/// Draws with `draw` on a white picture of `size` and encodes it as PNG.
pub(crate) fn render_png(
    size: Size,
    draw: impl FnOnce(&Area<'_>) -> Result<(), RenderError>,
) -> Result<Vec<u8>, RenderError> {
    size.check()?;
    font::ensure_registered()?;
    let mut pixels = vec![255u8; size.width as usize * size.height as usize * 3];
    {
        let backend = BitMapBackend::<RGBPixel>::with_buffer_and_format(
            &mut pixels,
            (size.width, size.height),
        )
        .map_err(drawing)?;
        let root = backend.into_drawing_area();
        draw(&root)?;
        root.present().map_err(drawing)?;
    }
    encode_png(&pixels, size)
}

/// Draws with `draw` on `pixels` (RGB, `size`: a photograph, say) and
/// encodes it as an RGB PNG (a photograph has far more than 256 colours).
pub(crate) fn render_png_over(
    size: Size,
    mut pixels: Vec<u8>,
    draw: impl FnOnce(&Area<'_>) -> Result<(), RenderError>,
) -> Result<Vec<u8>, RenderError> {
    size.check()?;
    font::ensure_registered()?;
    {
        let backend = BitMapBackend::<RGBPixel>::with_buffer_and_format(
            &mut pixels,
            (size.width, size.height),
        )
        .map_err(drawing)?;
        let root = backend.into_drawing_area();
        draw(&root)?;
        root.present().map_err(drawing)?;
    }
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, size.width, size.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::High);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&pixels)?;
    writer.finish()?;
    Ok(png)
}

/// Writes PNG bytes to `out`.
pub(crate) fn write(out: &Path, png: &[u8]) -> Result<(), RenderError> {
    std::fs::write(out, png).map_err(|source| RenderError::Write {
        path: out.to_owned(),
        source,
    })
}

/// Shorthand: `result.map_err(drawing)` for any of plotters' errors.
pub(crate) fn drawing<E: std::error::Error + Send + Sync + 'static>(error: E) -> RenderError {
    RenderError::Draw(Box::new(error))
}

fn encode_png(pixels: &[u8], size: Size) -> Result<Vec<u8>, RenderError> {
    let indexed = quantize(pixels);
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, size.width, size.height);
    encoder.set_color(png::ColorType::Indexed);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_palette(indexed.palette);
    // Pictures are committed to the repository: a smaller file is worth
    // the few extra milliseconds.
    encoder.set_compression(png::Compression::High);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&indexed.indices)?;
    writer.finish()?;
    Ok(png)
}
