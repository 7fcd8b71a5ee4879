//! Connected segments of the uncut object pixels, grown back over the
//! cuts and the objects' feet, the small ones dropped.

use super::enclosed::{FloorScratch, Floors, label_floors};
use super::merge::{MergeRule, MergeScratch, merge};
use super::split::jump_limit;

/// Scratch of the labelling, sized to the image once.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    pub labels: Vec<u32>,
    queue: Vec<u32>,
    steps: Vec<u8>,
    sizes: Vec<u32>,
    renumber: Vec<u32>,
    merge: MergeScratch,
    floors: FloorScratch,
}

impl Scratch {
    pub(crate) fn resize(&mut self, pixels: usize) {
        self.labels.resize(pixels, 0);
        self.steps.resize(pixels, 0);
        if self.queue.capacity() < pixels {
            self.queue.reserve(pixels - self.queue.len());
        }
    }

    pub(crate) fn capacity(&self) -> usize {
        self.labels.capacity()
            + self.queue.capacity()
            + self.steps.capacity()
            + self.sizes.capacity()
            + self.renumber.capacity()
            + self.merge.capacity()
            + self.floors.capacity()
    }
}

/// Depth continuity between two neighbours: both read, and closer than
/// `ratio` of the depth.
fn joined(z: &[f32], a: usize, b: usize, rule: &Rule) -> bool {
    let (za, zb) = (z[a], z[b]);
    za > 0.0
        && zb > 0.0
        && (za - zb).abs() <= jump_limit(za.min(zb), rule.jump_ratio, rule.tolerance)
}

/// The four neighbours of `i` inside the image.
pub(crate) fn neighbours(i: usize, width: usize, pixels: usize) -> impl Iterator<Item = usize> {
    let u = i % width;
    [
        (u > 0).then(|| i - 1),
        (u + 1 < width).then(|| i + 1),
        i.checked_sub(width),
        Some(i + width).filter(|&j| j < pixels),
    ]
    .into_iter()
    .flatten()
}

/// What the labelling reads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Layers<'a> {
    pub z: &'a [f32],
    /// Height above the support.
    pub height: &'a [f32],
    /// High enough above the plane to start an object, and not cut.
    pub seed: &'a [bool],
    /// High enough above the plane to belong to an object.
    pub grow: &'a [bool],
    /// Colour, three bytes a pixel (the merge of pieces reads it).
    pub rgb: &'a [u8],
    pub width: usize,
}

/// Settings of the labelling.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rule {
    pub jump_ratio: f32,
    pub min_pixels: u32,
    pub grow_steps: u8,
    /// The seed height's noise term at 1 m (`tolerance z^2` at depth z),
    /// the growth height, and the focal length in pixels: growth from a
    /// pixel at depth z reaches as far as the band between the two
    /// heights spans in the image, `fy (tolerance z - grow / z)`, when that
    /// is more than `grow_steps`, so a far object's foot, cut by a seed
    /// height that grows with z^2, is grown back as a near one's is.
    pub tolerance: f32,
    pub grow_height: f32,
    pub fy: f32,
    pub merge: MergeRule,
}

impl Rule {
    /// Growth steps allowed from a pixel at depth `z`.
    fn reach(&self, z: f32) -> u8 {
        let band = self.fy * (self.tolerance * z - self.grow_height / z.max(1e-3));
        let band = if band.is_finite() {
            band.ceil().clamp(0.0, 255.0)
        } else {
            0.0
        };
        self.grow_steps.max(band as u8)
    }
}

/// Labels segments 1..=count into `out` (0: none) and returns `count`;
/// more than `u16::MAX` segments keeps the first ones in scan order.
pub(crate) fn label(layers: Layers<'_>, rule: Rule, s: &mut Scratch, out: &mut [u16]) -> usize {
    let Layers {
        z,
        height,
        seed,
        grow,
        rgb,
        width,
    } = layers;
    let pixels = z.len();
    let Scratch {
        labels,
        queue,
        steps,
        sizes,
        renumber,
        merge: merge_scratch,
        floors,
    } = s;
    labels.fill(0);
    sizes.clear();
    sizes.push(0);
    // Flood fill of the seeds, depth-continuous steps only.
    for start in 0..pixels {
        if !seed[start] || labels[start] != 0 {
            continue;
        }
        let id = sizes.len() as u32;
        let mut size = 1u32;
        labels[start] = id;
        queue.clear();
        queue.push(start as u32);
        while let Some(p) = queue.pop() {
            let p = p as usize;
            for q in neighbours(p, width, pixels) {
                if seed[q] && labels[q] == 0 && joined(z, p, q, &rule) {
                    labels[q] = id;
                    size += 1;
                    queue.push(q as u32);
                }
            }
        }
        sizes.push(size);
    }
    // Fragments too small to stand for an object would otherwise claim
    // the cut pixels around them: only segments of a quarter of the
    // minimum seed the growth.
    let seed_min = (rule.min_pixels / 4).max(1);
    for l in labels.iter_mut() {
        if *l != 0 && sizes[*l as usize] < seed_min {
            *l = 0;
        }
    }
    // Growth, breadth first from every segment at once, so that a cut
    // pixel goes to the segment nearest along the surface.
    queue.clear();
    steps.fill(0);
    for (i, &l) in labels.iter().enumerate() {
        if l != 0 {
            queue.push(i as u32);
        }
    }
    let mut head = 0;
    while head < queue.len() {
        let p = queue[head] as usize;
        head += 1;
        let step = steps[p];
        if step >= rule.reach(z[p]) {
            continue;
        }
        let id = labels[p];
        for q in neighbours(p, width, pixels) {
            if grow[q] && labels[q] == 0 && joined(z, p, q, &rule) {
                labels[q] = id;
                steps[q] = step + 1;
                queue.push(q as u32);
            }
        }
    }
    merge(
        labels,
        sizes.len(),
        rgb,
        width,
        rule.merge,
        |p, q| joined(z, p, q, &rule),
        merge_scratch,
    );
    // After the merge, which would join a floor to its wall by colour.
    let floor = Floors {
        z,
        height,
        width,
        min_pixels: rule.min_pixels,
        grow_height: rule.grow_height,
    };
    let added = label_floors(floor, labels, sizes.len() as u32, floors);
    sizes.resize(sizes.len() + added as usize, 0);
    sizes.iter_mut().for_each(|s| *s = 0);
    for &l in labels.iter() {
        sizes[l as usize] += 1;
    }
    // Renumbered in order of first appearance, so that the labels do not
    // depend on how the fill ran.
    renumber.clear();
    renumber.resize(sizes.len(), 0);
    let mut count = 0usize;
    for (o, &l) in out.iter_mut().zip(labels.iter()) {
        *o = 0;
        if l == 0 || sizes[l as usize] < rule.min_pixels {
            continue;
        }
        let slot = &mut renumber[l as usize];
        if *slot == 0 {
            if count >= usize::from(u16::MAX) {
                continue;
            }
            count += 1;
            *slot = count as u32;
        }
        *o = *slot as u16;
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn growth_reaches_across_the_seed_band_at_range_and_keeps_grow_steps_near() {
        let rule = Rule {
            jump_ratio: 0.02,
            min_pixels: 200,
            grow_steps: 8,
            tolerance: 0.01,
            grow_height: 0.003,
            fy: 451.0,
            merge: MergeRule {
                colour: 0.0,
                border: 0.2,
                max_pixels: 2000,
            },
        };
        // At 1 m the band (7 mm, 3 px) is narrower than grow_steps.
        assert_eq!(rule.reach(1.0), 8);
        // At 3 m: 451 (0.03 - 0.001) = 13.1 pixels.
        assert_eq!(rule.reach(3.0), 14);
        assert_eq!(rule.reach(0.0), 8);
        assert_eq!(rule.reach(f32::NAN), 8);
    }
}
