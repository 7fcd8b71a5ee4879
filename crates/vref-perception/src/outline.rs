//! A mask's outline as closed polygons along its pixels' edges, for
//! drawing a mask over its image (Foxglove's image annotations, pictures).
//!
//! Vertices are pixel corners: `[x, y]` with the origin at the top-left
//! corner of the top-left pixel, x right, y down, so every vertex lies in
//! `[0, width] x [0, height]` and a polygon drawn over the image runs
//! exactly between the mask's pixels and the others. Tracing along edges
//! rather than listing boundary pixels gives polygons that a viewer can
//! stroke, and only their corners: a straight run of edges is one side.

use std::collections::HashMap;

use image::GrayImage;

/// Directions of a boundary edge, in clockwise order on screen (y down):
/// turning right from direction `d` is `(d + 1) % 4`.
const RIGHT: u8 = 0;
const DOWN: u8 = 1;
const LEFT: u8 = 2;
const UP: u8 = 3;

/// One pixel edge between the mask and the rest, directed so that the
/// mask lies on its right (on screen): outer boundaries then run
/// clockwise, holes anticlockwise.
#[derive(Debug, Clone, Copy)]
struct Edge {
    from: [u32; 2],
    direction: u8,
}

impl Edge {
    fn to(self) -> [u32; 2] {
        let [x, y] = self.from;
        match self.direction {
            RIGHT => [x + 1, y],
            DOWN => [x, y + 1],
            LEFT => [x - 1, y],
            _ => [x, y - 1],
        }
    }
}

/// Every boundary of the mask's non-zero pixels (outside the image counts
/// as outside the mask), each as a closed polygon of its corners in
/// order, the last joined to the first. Outer boundaries run clockwise on
/// screen, holes anticlockwise, so the polygons' signed areas
/// ([`signed_area`]) add up to the mask's pixel count. Pixels that touch
/// only at a corner belong to separate polygons (4-connectivity: a
/// segmenter's diagonal specks are not joined). An empty mask has none.
pub fn outline_polygons(mask: &GrayImage) -> Vec<Vec<[u32; 2]>> {
    let (w, h) = mask.dimensions();
    let inside = |x: i64, y: i64| {
        x >= 0
            && y >= 0
            && x < i64::from(w)
            && y < i64::from(h)
            && mask.get_pixel(x as u32, y as u32).0[0] != 0
    };
    let mut edges = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (xi, yi) = (i64::from(x), i64::from(y));
            if !inside(xi, yi) {
                continue;
            }
            // Each side towards a pixel outside, clockwise round the pixel.
            if !inside(xi, yi - 1) {
                edges.push(Edge {
                    from: [x, y],
                    direction: RIGHT,
                });
            }
            if !inside(xi + 1, yi) {
                edges.push(Edge {
                    from: [x + 1, y],
                    direction: DOWN,
                });
            }
            if !inside(xi, yi + 1) {
                edges.push(Edge {
                    from: [x + 1, y + 1],
                    direction: LEFT,
                });
            }
            if !inside(xi - 1, yi) {
                edges.push(Edge {
                    from: [x, y + 1],
                    direction: UP,
                });
            }
        }
    }
    // A corner starts one boundary edge, or two where two mask pixels
    // meet only at that corner.
    let mut starting: HashMap<[u32; 2], [Option<usize>; 2]> = HashMap::new();
    for (i, e) in edges.iter().enumerate() {
        let slot = starting.entry(e.from).or_insert([None, None]);
        if slot[0].is_none() {
            slot[0] = Some(i);
        } else {
            slot[1] = Some(i);
        }
    }
    // The edge after `e`: the only one leaving its end, or at a corner
    // two pixels share, the right turn, which stays with e's pixel.
    let next = |e: Edge| -> Option<usize> {
        let candidates = starting.get(&e.to())?;
        match candidates {
            [Some(a), None] => Some(*a),
            [Some(a), Some(b)] => {
                let right = (e.direction + 1) % 4;
                Some(if edges[*a].direction == right { *a } else { *b })
            }
            _ => None,
        }
    };
    let mut used = vec![false; edges.len()];
    let mut polygons = Vec::new();
    for first in 0..edges.len() {
        if used[first] {
            continue;
        }
        let mut cycle = Vec::new();
        let mut current = first;
        // Every edge has one successor and one predecessor, so the walk
        // comes back to `first`; the bound only guards against a bug.
        while !used[current] && cycle.len() <= edges.len() {
            used[current] = true;
            cycle.push(edges[current]);
            match next(edges[current]) {
                Some(n) => current = n,
                None => break,
            }
        }
        // A corner is where the direction changes.
        let corners: Vec<[u32; 2]> = (0..cycle.len())
            .filter(|&i| cycle[i].direction != cycle[(i + cycle.len() - 1) % cycle.len()].direction)
            .map(|i| cycle[i].from)
            .collect();
        if !corners.is_empty() {
            polygons.push(corners);
        }
    }
    polygons
}

/// The signed area of a closed polygon, in pixels: positive when it runs
/// clockwise on screen (y down), as outer boundaries do.
pub fn signed_area(polygon: &[[u32; 2]]) -> f64 {
    let n = polygon.len();
    let twice: f64 = (0..n)
        .map(|i| {
            let [x0, y0] = polygon[i].map(f64::from);
            let [x1, y1] = polygon[(i + 1) % n].map(f64::from);
            x0 * y1 - x1 * y0
        })
        .sum();
    twice / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask(w: u32, h: u32, on: impl Fn(u32, u32) -> bool) -> GrayImage {
        GrayImage::from_fn(w, h, |x, y| image::Luma([if on(x, y) { 255 } else { 0 }]))
    }

    fn pixels(m: &GrayImage) -> f64 {
        m.pixels().filter(|p| p.0[0] != 0).count() as f64
    }

    /// Every side is axis-aligned, no two sides in a row are collinear,
    /// and every corner lies on the image (corners included).
    fn well_formed(polygon: &[[u32; 2]], w: u32, h: u32) {
        let n = polygon.len();
        assert!(n >= 4 && n.is_multiple_of(2), "{polygon:?}");
        for i in 0..n {
            let [a, b, c] = [0, 1, 2].map(|k| polygon[(i + k) % n]);
            assert!(a[0] == b[0] || a[1] == b[1], "diagonal side {a:?} {b:?}");
            let straight = (a[0] == b[0] && b[0] == c[0]) || (a[1] == b[1] && b[1] == c[1]);
            assert!(!straight, "collinear {a:?} {b:?} {c:?}");
            assert!(a[0] <= w && a[1] <= h, "{a:?} off a {w}x{h} image");
        }
    }

    #[test]
    fn an_empty_mask_has_no_outline() {
        assert!(outline_polygons(&mask(8, 6, |_, _| false)).is_empty());
        assert!(outline_polygons(&GrayImage::new(0, 0)).is_empty());
    }

    #[test]
    fn a_square_is_its_four_sides() {
        let m = mask(8, 8, |x, y| (2..5).contains(&x) && (2..5).contains(&y));
        let polygons = outline_polygons(&m);
        assert_eq!(polygons, vec![vec![[2, 2], [5, 2], [5, 5], [2, 5]]]);
        assert_eq!(signed_area(&polygons[0]), 9.0);
    }

    #[test]
    fn one_pixel_is_a_unit_square() {
        let m = mask(3, 3, |x, y| x == 1 && y == 1);
        assert_eq!(
            outline_polygons(&m),
            vec![vec![[1, 1], [2, 1], [2, 2], [1, 2]]]
        );
    }

    #[test]
    fn a_mask_filling_the_image_runs_along_its_border() {
        let m = mask(4, 3, |_, _| true);
        assert_eq!(
            outline_polygons(&m),
            vec![vec![[0, 0], [4, 0], [4, 3], [0, 3]]]
        );
    }

    #[test]
    fn a_hole_is_a_second_polygon_the_other_way_round() {
        // A 5x5 square with its middle 1x1 and a 2x1 slot cut out.
        let m = mask(7, 7, |x, y| {
            (1..6).contains(&x) && (1..6).contains(&y) && !(x == 3 && (3..5).contains(&y))
        });
        let polygons = outline_polygons(&m);
        assert_eq!(polygons.len(), 2, "{polygons:?}");
        let areas: Vec<f64> = polygons.iter().map(|p| signed_area(p)).collect();
        assert_eq!(areas, vec![25.0, -2.0]);
        assert_eq!(polygons[1].len(), 4);
        for p in &polygons {
            well_formed(p, 7, 7);
        }
    }

    #[test]
    fn pixels_touching_at_a_corner_are_separate() {
        let m = mask(4, 4, |x, y| (x, y) == (1, 1) || (x, y) == (2, 2));
        let polygons = outline_polygons(&m);
        assert_eq!(
            polygons,
            vec![
                vec![[1, 1], [2, 1], [2, 2], [1, 2]],
                vec![[2, 2], [3, 2], [3, 3], [2, 3]],
            ]
        );
    }

    #[test]
    fn a_ragged_blob_encloses_exactly_its_pixels() {
        // A disc, a bar through it off the image's edge, a diagonal line of
        // specks and a ring with a hole: signed areas add up to the pixels.
        let (w, h) = (40, 30);
        let m = mask(w, h, |x, y| {
            let (dx, dy) = (x as f64 - 12.3, y as f64 - 14.8);
            let disc = dx * dx + dy * dy < 64.0;
            let bar = y == 14 && x > 10;
            let specks = x == y + 20 && x.is_multiple_of(2);
            let (rx, ry) = (x as f64 - 30.0, y as f64 - 6.0);
            let r2 = rx * rx + ry * ry;
            disc || bar || specks || (9.0..25.0).contains(&r2)
        });
        let polygons = outline_polygons(&m);
        let total: f64 = polygons.iter().map(|p| signed_area(p)).sum();
        assert_eq!(total, pixels(&m));
        assert!(
            polygons.iter().any(|p| signed_area(p) < 0.0),
            "the ring's hole"
        );
        for p in &polygons {
            well_formed(p, w, h);
        }
    }
}
