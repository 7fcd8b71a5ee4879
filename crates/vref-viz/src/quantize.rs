//! Reduction of an RGB picture to at most 256 colours, for an indexed PNG
//! a third the size of an RGB one: these pictures are mostly a few flat
//! colours plus their anti-aliased edges, and the rarest edge shades can
//! move to their nearest neighbour unseen.

use std::collections::HashMap;

/// An indexed picture: `palette` holds RGB triples, `indices` one entry
/// per pixel.
pub(crate) struct Indexed {
    pub palette: Vec<u8>,
    pub indices: Vec<u8>,
}

/// Keeps the 256 most frequent colours and maps every other to the nearest
/// of them. Exact when there are 256 colours or fewer.
pub(crate) fn quantize(rgb: &[u8]) -> Indexed {
    let mut counts: HashMap<[u8; 3], usize> = HashMap::new();
    for p in rgb.chunks_exact(3) {
        *counts.entry([p[0], p[1], p[2]]).or_default() += 1;
    }
    let mut by_frequency: Vec<([u8; 3], usize)> = counts.into_iter().collect();
    // The colour itself breaks ties, so that equal pictures give equal files.
    by_frequency.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let kept: Vec<[u8; 3]> = by_frequency.iter().take(256).map(|&(c, _)| c).collect();
    let index: HashMap<[u8; 3], u8> = by_frequency
        .iter()
        .map(|&(colour, _)| (colour, nearest(&kept, colour)))
        .collect();
    Indexed {
        palette: kept.iter().flatten().copied().collect(),
        indices: rgb
            .chunks_exact(3)
            .map(|p| index.get(&[p[0], p[1], p[2]]).copied().unwrap_or(0))
            .collect(),
    }
}

fn nearest(palette: &[[u8; 3]], colour: [u8; 3]) -> u8 {
    let distance = |c: &[u8; 3]| -> i32 {
        c.iter()
            .zip(colour)
            .map(|(&a, b)| (i32::from(a) - i32::from(b)).pow(2))
            .sum()
    };
    let best = (0..palette.len())
        .min_by_key(|&k| distance(&palette[k]))
        .unwrap_or(0);
    // At most 256 entries, so every index fits.
    u8::try_from(best).unwrap_or(u8::MAX)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::quantize;

    fn colour_of(indexed: &super::Indexed, pixel: usize) -> [u8; 3] {
        let k = usize::from(indexed.indices[pixel]) * 3;
        [
            indexed.palette[k],
            indexed.palette[k + 1],
            indexed.palette[k + 2],
        ]
    }

    #[test]
    fn few_colours_are_kept_exactly() {
        let rgb = [255, 255, 255, 0, 150, 70, 255, 255, 255, 215, 35, 35];
        let indexed = quantize(&rgb);
        assert_eq!(indexed.palette.len(), 9);
        for (pixel, expected) in rgb.chunks_exact(3).enumerate() {
            assert_eq!(colour_of(&indexed, pixel), expected);
        }
    }

    #[test]
    fn rare_colours_go_to_their_nearest_frequent_one() {
        // 300 greys: each of the frequent ones (0, 2, 4, ...) appears
        // twice, each rare one (odd) once after them.
        let mut rgb = Vec::new();
        for g in (0u8..=255).step_by(2).chain((0u8..=255).step_by(2)) {
            rgb.extend([g, g, g]);
        }
        let frequent = rgb.len() / 3;
        for g in (1u8..=255).step_by(2).take(172) {
            rgb.extend([g, g, g]);
        }
        let indexed = quantize(&rgb);
        assert!(indexed.palette.len() <= 256 * 3);
        for pixel in 0..frequent {
            assert_eq!(colour_of(&indexed, pixel), [rgb[pixel * 3]; 3]);
        }
        for pixel in frequent..rgb.len() / 3 {
            let [g, ..] = colour_of(&indexed, pixel);
            assert!(
                g.abs_diff(rgb[pixel * 3]) <= 1,
                "{g} for {}",
                rgb[pixel * 3]
            );
        }
    }
}
