//! Image files to the front end's image types, decoded by the `image`
//! crate. Every error names the file.

use std::path::Path;

use image::{DynamicImage, GrayImage, ImageReader, RgbImage};

use crate::{DepthPixels, LoadError};

/// The default of `[perception] max_image_pixels`: a 4096x4096 picture,
/// twice a 4K camera's.
pub const MAX_IMAGE_PIXELS: u64 = 4096 * 4096;

/// Most pixels an image may have (`[perception] max_image_pixels`): a
/// file's size is read from its header and checked before a byte of it
/// is decoded, so a huge file (or one whose header only claims to be
/// huge) cannot take the memory of every process that loads it (8000x8000
/// cost 0.9 GB each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageLimit {
    pub max_pixels: u64,
}

impl Default for ImageLimit {
    fn default() -> Self {
        Self {
            max_pixels: MAX_IMAGE_PIXELS,
        }
    }
}

impl ImageLimit {
    /// Whether a `width` x `height` image is within the limit.
    pub fn allows(self, width: u32, height: u32) -> bool {
        u64::from(width) * u64::from(height) <= self.max_pixels
    }

    /// Refuses the image at `path` (its header stating `width` x
    /// `height`) when it is larger than the limit.
    pub fn check(self, path: &Path, (width, height): (u32, u32)) -> Result<(), LoadError> {
        if self.allows(width, height) {
            Ok(())
        } else {
            Err(LoadError::TooLarge {
                path: path.to_owned(),
                width,
                height,
                max_pixels: self.max_pixels,
            })
        }
    }
}

/// The width and height the header of the image file at `path` states,
/// without decoding a pixel.
pub fn image_size(path: &Path) -> Result<(u32, u32), LoadError> {
    open(path)?
        .into_dimensions()
        .map_err(|source| LoadError::Decode {
            path: path.to_owned(),
            source,
        })
}

fn open(path: &Path) -> Result<ImageReader<std::io::BufReader<std::fs::File>>, LoadError> {
    ImageReader::open(path)
        .and_then(ImageReader::with_guessed_format)
        .map_err(|source| LoadError::Open {
            path: path.to_owned(),
            source,
        })
}

/// The image at `path` decoded, once its header's size is found within
/// `limit` (and, for a JPEG, its end found).
pub(crate) fn decode(path: &Path, limit: ImageLimit) -> Result<DynamicImage, LoadError> {
    let decode_error = |source| LoadError::Decode {
        path: path.to_owned(),
        source,
    };
    let reader = open(path)?;
    if reader.format() == Some(image::ImageFormat::Jpeg) && !ends_a_jpeg(path)? {
        // The decoder fills what a cut-off JPEG lacks with grey, without
        // an error: a half-written frame would be measured as if whole.
        return Err(LoadError::Truncated {
            path: path.to_owned(),
        });
    }
    limit.check(path, reader.into_dimensions().map_err(decode_error)?)?;
    open(path)?.decode().map_err(decode_error)
}

/// Whether a JPEG's end-of-image marker (FF D9) is among the file's last
/// kilobyte (some writers pad after it; the coded data never holds it,
/// since a coded FF is always followed by 00).
fn ends_a_jpeg(path: &Path) -> Result<bool, LoadError> {
    use std::io::{Read, Seek, SeekFrom};
    let open_error = |source| LoadError::Open {
        path: path.to_owned(),
        source,
    };
    let mut file = std::fs::File::open(path).map_err(open_error)?;
    let len = file.metadata().map_err(open_error)?.len();
    file.seek(SeekFrom::Start(len.saturating_sub(1024)))
        .map_err(open_error)?;
    let mut tail = Vec::with_capacity(1024);
    file.read_to_end(&mut tail).map_err(open_error)?;
    Ok(tail.windows(2).any(|w| w == [0xFF, 0xD9]))
}

/// A colour image as 8-bit RGB, refused before decoding when larger than
/// `limit`: 8-bit grey is expanded, an alpha channel dropped (tools save
/// captures as RGBA) and 16-bit colour scaled to 8 bits. 16-bit grey is
/// refused: it is a depth image more likely than a colour one.
pub fn load_colour(path: &Path, limit: ImageLimit) -> Result<RgbImage, LoadError> {
    match decode(path, limit)? {
        DynamicImage::ImageRgb8(image) => Ok(image),
        colour @ (DynamicImage::ImageLuma8(_)
        | DynamicImage::ImageLumaA8(_)
        | DynamicImage::ImageRgba8(_)
        | DynamicImage::ImageRgb16(_)
        | DynamicImage::ImageRgba16(_)) => Ok(colour.to_rgb8()),
        other => Err(LoadError::NotColour {
            path: path.to_owned(),
            found: other.color(),
        }),
    }
}

/// A 16-bit grey depth image; any other pixel type is refused (a depth
/// image squeezed into 8 bits has lost its range).
pub fn load_depth(path: &Path, limit: ImageLimit) -> Result<DepthPixels, LoadError> {
    match decode(path, limit)? {
        DynamicImage::ImageLuma16(image) => Ok(image),
        other => Err(LoadError::NotDepth16 {
            path: path.to_owned(),
            found: other.color(),
        }),
    }
}

/// An 8-bit grey instance mask (non-zero: the object).
pub fn load_mask(path: &Path, limit: ImageLimit) -> Result<GrayImage, LoadError> {
    match decode(path, limit)? {
        DynamicImage::ImageLuma8(image) => Ok(image),
        other => Err(LoadError::NotMask {
            path: path.to_owned(),
            found: other.color(),
        }),
    }
}
