//! Synthetic frames drawn pixel by pixel: flat objects at known depths.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use image::{GrayImage, ImageBuffer, Luma, Rgb, RgbImage};
use vref_perception::{DepthImage, Intrinsics};

pub const W: u32 = 640;
pub const H: u32 = 480;

pub fn intrinsics() -> Intrinsics {
    Intrinsics::new(500.0, 500.0, 320.0, 240.0).unwrap()
}

/// A disc object: centre pixel, radius in pixels, depth in metres, and
/// how it looks at offset (dx, dy) from its centre (in units of its
/// radius, so that it looks the same at any size).
pub struct Disc {
    pub centre: (f64, f64),
    pub radius: f64,
    pub depth: f64,
    pub look: fn(f64, f64) -> [u8; 3],
}

/// Red left half, blue right half, a dark stripe across: colour and
/// gradients both.
pub fn two_tone(dx: f64, dy: f64) -> [u8; 3] {
    if dy.abs() < 0.15 {
        [30, 30, 30]
    } else if dx < 0.0 {
        [200, 40, 30]
    } else {
        [40, 60, 210]
    }
}

pub fn yellow(_: f64, _: f64) -> [u8; 3] {
    [220, 200, 40]
}

/// Colour, depth (millimetres, background at `background_m`) and one
/// mask per disc.
pub fn draw(discs: &[Disc], background_m: f64) -> (RgbImage, DepthImage, Vec<GrayImage>) {
    let mut colour = RgbImage::from_pixel(W, H, Rgb([120, 120, 120]));
    let background = (background_m * 1000.0) as u16;
    let mut depth: ImageBuffer<Luma<u16>, Vec<u16>> =
        ImageBuffer::from_pixel(W, H, Luma([background]));
    let mut masks = Vec::new();
    for disc in discs {
        let mut mask = GrayImage::new(W, H);
        for v in 0..H {
            for u in 0..W {
                let dx = (f64::from(u) - disc.centre.0) / disc.radius;
                let dy = (f64::from(v) - disc.centre.1) / disc.radius;
                if dx * dx + dy * dy <= 1.0 {
                    mask.put_pixel(u, v, Luma([255]));
                    colour.put_pixel(u, v, Rgb((disc.look)(dx, dy)));
                    depth.put_pixel(u, v, Luma([(disc.depth * 1000.0).round() as u16]));
                }
            }
        }
        masks.push(mask);
    }
    (colour, DepthImage::new(depth, 0.001).unwrap(), masks)
}

pub fn cosine(a: &[f32], b: &[f32]) -> f32 {
    let dot: f32 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    let na: f32 = a.iter().map(|x| x * x).sum::<f32>().sqrt();
    let nb: f32 = b.iter().map(|x| x * x).sum::<f32>().sqrt();
    dot / (na * nb)
}
