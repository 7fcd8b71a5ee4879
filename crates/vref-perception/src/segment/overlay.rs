//! A picture of a label image over its colour image, for people to judge
//! a segmentation by eye.

use image::RgbImage;

/// Distinct, saturated colours; label `k` takes colour `k mod 12`.
const PALETTE: [[u8; 3]; 12] = [
    [230, 25, 75],
    [60, 180, 75],
    [0, 130, 200],
    [245, 130, 48],
    [145, 30, 180],
    [70, 240, 240],
    [240, 50, 230],
    [210, 245, 60],
    [0, 128, 128],
    [170, 110, 40],
    [128, 0, 0],
    [0, 0, 128],
];

/// `colour` with every labelled pixel tinted by its label's colour and
/// each object's outline drawn solid. `labels` must have `colour`'s size
/// (pixels beyond the shorter of the two are left as they are).
pub fn overlay(colour: &RgbImage, labels: &[u16]) -> RgbImage {
    let mut out = colour.clone();
    let (w, h) = (colour.width() as usize, colour.height() as usize);
    let at = |u: usize, v: usize| labels.get(v * w + u).copied().unwrap_or(0);
    for v in 0..h {
        for u in 0..w {
            let l = at(u, v);
            if l == 0 {
                continue;
            }
            let tint = PALETTE[usize::from(l) % PALETTE.len()];
            let edge = u == 0
                || v == 0
                || u + 1 == w
                || v + 1 == h
                || at(u - 1, v) != l
                || at(u + 1, v) != l
                || at(u, v - 1) != l
                || at(u, v + 1) != l;
            let pixel = out.get_pixel_mut(u as u32, v as u32);
            for (c, t) in pixel.0.iter_mut().zip(tint) {
                *c = if edge {
                    t
                } else {
                    ((u16::from(*c) + u16::from(t)) / 2) as u8
                };
            }
        }
    }
    out
}
