#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

//! Image files as the front end loads them: a cut-off JPEG is refused by
//! name instead of decoded as if whole.

use image::{Rgb, RgbImage};
use vref_perception::{LoadError, load_colour};

#[test]
fn a_cut_off_jpeg_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.jpg");
    RgbImage::from_fn(64, 48, |u, v| Rgb([u as u8 * 3, v as u8 * 5, 90]))
        .save(&whole)
        .unwrap();
    assert_eq!(load_colour(&whole).unwrap().dimensions(), (64, 48));
    let bytes = std::fs::read(&whole).unwrap();
    let cut = dir.path().join("cut.jpg");
    std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let e = load_colour(&cut).unwrap_err();
    assert!(matches!(e, LoadError::Truncated { .. }), "{e}");
    assert!(e.to_string().contains("cut.jpg"), "{e}");
}
