#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

//! Image files as the front end loads them: a cut-off JPEG is refused by
//! name instead of decoded as if whole, and every image is checked against
//! the size cap (`[perception] max_image_pixels`) from its header alone.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::path::Path;

use image::{GrayImage, Luma, Rgb, RgbImage};
use vref_perception::folder::{RgbdImages, load_labels};
use vref_perception::{
    ImageLimit, LoadError, MAX_IMAGE_PIXELS, PerceptionSettings, image_size, load_colour,
    load_depth, load_mask,
};

/// The system allocator, noting the largest single allocation of the
/// threads that asked it to.
struct Largest;

thread_local! {
    static LARGEST: Cell<Option<usize>> = const { Cell::new(None) };
}

fn note(size: usize) {
    let _ = LARGEST.try_with(|l| {
        if let Some(m) = l.get() {
            l.set(Some(m.max(size)));
        }
    });
}

// SAFETY: every call goes unchanged to the system allocator; noting the
// size neither allocates nor touches the memory.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Largest {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: the caller's contract is System's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: as above.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Largest = Largest;

/// `f`'s value and the largest allocation this thread made while it ran.
fn largest_allocation<T>(f: impl FnOnce() -> T) -> (T, usize) {
    LARGEST.with(|l| l.set(Some(0)));
    let value = f();
    (value, LARGEST.with(|l| l.replace(None)).unwrap_or(0))
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

fn chunk(png: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    png.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = png.len();
    png.extend_from_slice(kind);
    png.extend_from_slice(data);
    let crc = crc32(&png[start..]);
    png.extend_from_slice(&crc.to_be_bytes());
}

/// A valid PNG signature and header claiming `width` x `height` pixels of
/// `colour_type` (0 grey, 2 RGB) at `bit_depth`, followed by a few bytes
/// of image data: a file of well under a kilobyte whose pixels would take
/// gigabytes.
fn png_claiming(width: u32, height: u32, bit_depth: u8, colour_type: u8) -> Vec<u8> {
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut header = Vec::new();
    header.extend_from_slice(&width.to_be_bytes());
    header.extend_from_slice(&height.to_be_bytes());
    header.extend_from_slice(&[bit_depth, colour_type, 0, 0, 0]);
    chunk(&mut png, b"IHDR", &header);
    // A zlib stream of one empty stored block: a few bytes of "data".
    chunk(
        &mut png,
        b"IDAT",
        &[0x78, 0x01, 0x01, 0x00, 0x00, 0xFF, 0xFF, 0, 0, 0, 1],
    );
    chunk(&mut png, b"IEND", &[]);
    png
}

fn too_large(e: &LoadError) -> (u32, u32, u64) {
    match e {
        LoadError::TooLarge {
            width,
            height,
            max_pixels,
            ..
        } => (*width, *height, *max_pixels),
        other => panic!("expected TooLarge, got {other}"),
    }
}

#[test]
fn a_cut_off_jpeg_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.jpg");
    RgbImage::from_fn(64, 48, |u, v| Rgb([u as u8 * 3, v as u8 * 5, 90]))
        .save(&whole)
        .unwrap();
    let limit = ImageLimit::default();
    assert_eq!(load_colour(&whole, limit).unwrap().dimensions(), (64, 48));
    let bytes = std::fs::read(&whole).unwrap();
    let cut = dir.path().join("cut.jpg");
    std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let e = load_colour(&cut, limit).unwrap_err();
    assert!(matches!(e, LoadError::Truncated { .. }), "{e}");
    assert!(e.to_string().contains("cut.jpg"), "{e}");
}

#[test]
fn the_default_cap_is_4096_by_4096_and_the_settings_give_it() {
    assert_eq!(MAX_IMAGE_PIXELS, 4096 * 4096);
    assert_eq!(ImageLimit::default().max_pixels, MAX_IMAGE_PIXELS);
    assert_eq!(
        PerceptionSettings::default().image_limit(),
        ImageLimit::default()
    );
    let limit = ImageLimit::default();
    assert!(limit.allows(4096, 4096) && limit.allows(8192, 2048));
    assert!(!limit.allows(4097, 4096));
}

/// A header claiming 100000 x 100000 pixels (10 GB as 8-bit grey, 60 GB as
/// 16-bit RGB) is refused from the header by every loader, label images
/// included, without allocating anything near the claim.
#[test]
fn a_header_claiming_a_huge_image_is_refused_without_allocating_it() {
    let dir = tempfile::tempdir().unwrap();
    let limit = ImageLimit::default();
    let files = [
        ("grey8.png", png_claiming(100_000, 100_000, 8, 0)),
        ("grey16.png", png_claiming(100_000, 100_000, 16, 0)),
        ("rgb8.png", png_claiming(100_000, 100_000, 8, 2)),
    ];
    for (name, bytes) in &files {
        assert!(bytes.len() < 100, "{name}: {} bytes", bytes.len());
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        assert_eq!(image_size(&path).unwrap(), (100_000, 100_000), "{name}");
        let (errors, largest) = largest_allocation(|| {
            [
                load_colour(&path, limit).map(drop).unwrap_err(),
                load_depth(&path, limit).map(drop).unwrap_err(),
                load_mask(&path, limit).map(drop).unwrap_err(),
            ]
        });
        for e in &errors {
            assert_eq!(too_large(e), (100_000, 100_000, MAX_IMAGE_PIXELS), "{name}");
            assert!(e.to_string().contains(name), "{e}");
        }
        assert!(
            largest < 1 << 20,
            "{name}: an allocation of {largest} bytes"
        );
        let (labels, largest) = largest_allocation(|| load_labels(&path, limit));
        match labels {
            Err(vref_perception::folder::FolderError::Load(e)) => {
                assert_eq!(
                    too_large(&e),
                    (100_000, 100_000, MAX_IMAGE_PIXELS),
                    "{name}"
                );
            }
            other => panic!("{name}: labels {other:?}"),
        }
        assert!(
            largest < 1 << 20,
            "{name}: an allocation of {largest} bytes"
        );
    }
}

fn frame_folder(dir: &Path) {
    std::fs::write(
        dir.join("camera.json"),
        r#"{"fx": 525.0, "fy": 525.0, "cx": 31.5, "cy": 23.5}"#,
    )
    .unwrap();
    RgbImage::from_pixel(64, 48, Rgb([200, 180, 20]))
        .save(dir.join("rgb.png"))
        .unwrap();
    image::ImageBuffer::<Luma<u16>, Vec<u16>>::from_pixel(64, 48, Luma([800]))
        .save(dir.join("depth.png"))
        .unwrap();
}

/// A frame folder whose masks.png claims to be huge is refused naming it,
/// not decoded.
#[test]
fn a_frame_folder_refuses_huge_masks_from_their_header() {
    let dir = tempfile::tempdir().unwrap();
    frame_folder(dir.path());
    let limit = ImageLimit::default();
    let masks = dir.path().join("masks.png");
    GrayImage::from_pixel(64, 48, Luma([1]))
        .save(&masks)
        .unwrap();
    assert!(RgbdImages::load(dir.path(), limit).unwrap().masks.is_some());
    std::fs::write(&masks, png_claiming(70_000, 70_000, 16, 0)).unwrap();
    let (loaded, largest) = largest_allocation(|| RgbdImages::load(dir.path(), limit));
    let e = loaded.unwrap_err();
    let text = e.to_string();
    for part in ["masks.png", "70000x70000", "max_image_pixels"] {
        assert!(text.contains(part), "{part}: {text}");
    }
    assert!(largest < 1 << 20, "an allocation of {largest} bytes");
}

/// A cap lowered in the settings refuses an ordinary image, naming the
/// file, its size and the setting; every image of a frame folder is held
/// to it.
#[test]
fn a_lowered_cap_refuses_a_normal_image_naming_file_size_and_setting() {
    let dir = tempfile::tempdir().unwrap();
    frame_folder(dir.path());
    let rgb = dir.path().join("rgb.png");
    let depth = dir.path().join("depth.png");
    let roomy = ImageLimit {
        max_pixels: 64 * 48,
    };
    assert_eq!(load_colour(&rgb, roomy).unwrap().dimensions(), (64, 48));
    assert!(RgbdImages::load(dir.path(), roomy).is_ok());
    let settings = PerceptionSettings {
        max_image_pixels: 64 * 48 - 1,
        ..PerceptionSettings::default()
    };
    let tight = settings.image_limit();
    for e in [
        load_colour(&rgb, tight).map(drop).unwrap_err(),
        load_depth(&depth, tight).map(drop).unwrap_err(),
    ] {
        assert_eq!(too_large(&e), (64, 48, 64 * 48 - 1));
    }
    let text = load_colour(&rgb, tight).unwrap_err().to_string();
    for part in ["rgb.png", "64x48", "3071", "[perception] max_image_pixels"] {
        assert!(text.contains(part), "{part}: {text}");
    }
    let text = RgbdImages::load(dir.path(), tight).unwrap_err().to_string();
    assert!(
        text.contains("rgb.png") && text.contains("max_image_pixels"),
        "{text}"
    );
}

#[test]
fn the_cap_setting_is_checked() {
    for bad in [0, (1 << 32) + 1] {
        let settings = PerceptionSettings {
            max_image_pixels: bad,
            ..PerceptionSettings::default()
        };
        let e = settings.validate().unwrap_err();
        assert!(e.to_string().contains("perception.max_image_pixels"), "{e}");
    }
    assert!(PerceptionSettings::default().validate().is_ok());
}

/// Colour as capture tools save it: RGBA loses its alpha, 16-bit RGB is
/// scaled to 8 bits, grey is expanded; 16-bit grey (a depth image given
/// as colour) is refused naming the file.
#[test]
fn colour_images_with_alpha_or_16_bits_load_as_rgb() {
    let dir = tempfile::tempdir().unwrap();
    let limit = ImageLimit::default();
    let path = dir.path().join("rgba.png");
    image::RgbaImage::from_pixel(2, 2, image::Rgba([10, 20, 30, 128]))
        .save(&path)
        .unwrap();
    assert_eq!(
        load_colour(&path, limit).unwrap().get_pixel(1, 1).0,
        [10, 20, 30]
    );
    let path = dir.path().join("rgb16.png");
    image::ImageBuffer::<Rgb<u16>, Vec<u16>>::from_pixel(2, 2, Rgb([0, 257 * 100, 65535]))
        .save(&path)
        .unwrap();
    assert_eq!(
        load_colour(&path, limit).unwrap().get_pixel(0, 0).0,
        [0, 100, 255]
    );
    let path = dir.path().join("grey.png");
    GrayImage::from_pixel(2, 2, Luma([7])).save(&path).unwrap();
    assert_eq!(
        load_colour(&path, limit).unwrap().get_pixel(0, 1).0,
        [7, 7, 7]
    );
    let path = dir.path().join("depth.png");
    image::ImageBuffer::<Luma<u16>, Vec<u16>>::from_pixel(2, 2, Luma([900]))
        .save(&path)
        .unwrap();
    let err = load_colour(&path, limit).unwrap_err();
    assert!(matches!(err, LoadError::NotColour { .. }), "{err}");
    assert!(
        err.to_string()
            .contains("depth.png: a colour image must be"),
        "{err}"
    );
}
