//! Floors enclosed by an object: the inside bottom of a pot or a bowl
//! stands a few millimetres above the table, too low to seed, and meets
//! the inner wall in a concave crease, where the wall's segment stops. It
//! is a surface of its own, as the crease rule makes every other one.

/// Share of an enclosed region's outline that may be pixels without a
/// reading (the crease and the rim drop a few); the rest must be objects.
const MAX_UNREAD_OUTLINE: f32 = 0.1;

/// What the search for enclosed floors reads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Floors<'a> {
    pub z: &'a [f32],
    /// Height above the support (warp taken off).
    pub height: &'a [f32],
    pub width: usize,
    /// Regions smaller than this are left alone.
    pub min_pixels: u32,
    /// The growth height, above which a reading belongs to an object. A
    /// region's median must stand above half of it (a pot's floor stands
    /// 2-5 mm above the table, about the growth height, and half of the
    /// readings of a floor at it are below it); table seen through a ring
    /// stays table.
    pub grow_height: f32,
}

/// Scratch of the search, reused from frame to frame.
#[derive(Debug, Default)]
pub(crate) struct FloorScratch {
    /// Per pixel, the last segment whose box searched it (plus one).
    seen: Vec<u32>,
    queue: Vec<u32>,
    heights: Vec<f32>,
    /// Per segment, its box: first and last column, first and last row.
    boxes: Vec<[usize; 4]>,
}

impl FloorScratch {
    pub(crate) fn capacity(&self) -> usize {
        self.seen.capacity()
            + self.queue.capacity()
            + self.heights.capacity()
            + self.boxes.capacity()
    }
}

/// Gives every connected region of unlabelled readings that objects
/// enclose a label of its own (`next_label` on) and returns how many it
/// labelled. Enclosed: the region lies inside one segment's bounding box
/// without touching the box's edge, and its outline is objects, with at
/// most a tenth of it pixels without a reading. It must also hold at
/// least `min_pixels` and stand above half the growth height (its
/// median). Searching each segment's box, not the whole image, keeps
/// the table's own region out of the search.
pub(crate) fn label_floors(
    floors: Floors<'_>,
    labels: &mut [u32],
    next_label: u32,
    s: &mut FloorScratch,
) -> u32 {
    let Floors {
        z,
        height,
        width,
        min_pixels,
        grow_height,
    } = floors;
    let pixels = z.len();
    if width == 0 {
        return 0;
    }
    s.boxes.clear();
    s.boxes
        .resize(next_label as usize, [usize::MAX, 0, usize::MAX, 0]);
    for (i, &l) in labels.iter().enumerate() {
        if l != 0 {
            let b = &mut s.boxes[l as usize];
            let (u, v) = (i % width, i / width);
            *b = [b[0].min(u), b[1].max(u), b[2].min(v), b[3].max(v)];
        }
    }
    s.seen.clear();
    s.seen.resize(pixels, 0);
    let mut added = 0;
    for segment in 1..next_label as usize {
        let [u0, u1, v0, v1] = s.boxes[segment];
        if u0 == usize::MAX || u1 < u0 + 2 || v1 < v0 + 2 {
            continue;
        }
        let stamp = segment as u32;
        for v in v0 + 1..v1 {
            for u in u0 + 1..u1 {
                let start = v * width + u;
                if s.seen[start] == stamp || labels[start] != 0 || z[start] <= 0.0 {
                    continue;
                }
                s.seen[start] = stamp;
                s.queue.clear();
                s.queue.push(start as u32);
                let (mut objects, mut unread, mut open) = (0u32, 0u32, false);
                let mut head = 0;
                while head < s.queue.len() {
                    // Every pixel queued is inside the box's edge, so its
                    // four neighbours are in the box and the image.
                    let p = s.queue[head] as usize;
                    head += 1;
                    for q in [p - 1, p + 1, p - width, p + width] {
                        if labels[q] != 0 {
                            objects += 1;
                        } else if z[q] <= 0.0 {
                            unread += 1;
                        } else if !inside(q, width, [u0, u1, v0, v1]) {
                            // Open to the box's edge: not enclosed by
                            // this segment.
                            open = true;
                        } else if s.seen[q] != stamp {
                            s.seen[q] = stamp;
                            s.queue.push(q as u32);
                        }
                    }
                }
                let size = s.queue.len() as u32;
                let outline = objects + unread;
                let enclosed =
                    !open && objects > 0 && (unread as f32) <= MAX_UNREAD_OUTLINE * outline as f32;
                if !enclosed || size < min_pixels {
                    continue;
                }
                s.heights.clear();
                s.heights
                    .extend(s.queue.iter().map(|&p| height[p as usize]));
                let middle = s.heights.len() / 2;
                let (_, &mut median, _) = s.heights.select_nth_unstable_by(middle, f32::total_cmp);
                if median <= 0.5 * grow_height {
                    continue;
                }
                let id = next_label + added;
                for &p in &s.queue {
                    labels[p as usize] = id;
                }
                added += 1;
            }
        }
    }
    added
}

/// Whether pixel `i` lies inside the box, its edge excluded.
fn inside(i: usize, width: usize, [u0, u1, v0, v1]: [usize; 4]) -> bool {
    let (u, v) = (i % width, i / width);
    u0 < u && u < u1 && v0 < v && v < v1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 12 x 12 image: a ring of object (label 1) around a 6 x 6 floor
    /// at `inside` metres above the support, table outside.
    fn pot(inside: f32) -> (Vec<f32>, Vec<f32>, Vec<u32>) {
        let w = 12;
        let (mut z, mut height, mut labels) = (vec![1.0; w * w], vec![0.0; w * w], vec![0; w * w]);
        for v in 2..10 {
            for u in 2..10 {
                let i = v * w + u;
                let inner = (3..9).contains(&u) && (3..9).contains(&v);
                if inner {
                    height[i] = inside;
                } else {
                    labels[i] = 1;
                    height[i] = 0.05;
                    z[i] = 0.95;
                }
            }
        }
        (z, height, labels)
    }

    fn floors<'a>(z: &'a [f32], height: &'a [f32]) -> Floors<'a> {
        Floors {
            z,
            height,
            width: 12,
            min_pixels: 30,
            grow_height: 0.003,
        }
    }

    /// The floors of a 12-pixel-wide image whose one segment is label 1.
    fn search(z: &[f32], height: &[f32], labels: &mut [u32]) -> u32 {
        label_floors(floors(z, height), labels, 2, &mut FloorScratch::default())
    }

    #[test]
    fn a_raised_floor_inside_an_object_is_a_segment_of_its_own() {
        let (z, height, mut labels) = pot(0.005);
        let added = search(&z, &height, &mut labels);
        assert_eq!(added, 1);
        assert_eq!(labels[6 * 12 + 6], 2);
        // The table outside touches the image's edge: never labelled.
        assert_eq!(labels[0], 0);
    }

    #[test]
    fn the_table_seen_through_a_ring_stays_table() {
        let (z, height, mut labels) = pot(0.0005);
        let added = search(&z, &height, &mut labels);
        assert_eq!(added, 0);
        assert_eq!(labels[6 * 12 + 6], 0);
    }

    #[test]
    fn a_floor_open_to_missing_readings_is_not_enclosed() {
        let (mut z, height, mut labels) = pot(0.005);
        // A gap in the ring with no readings: the outline is half unread.
        for v in 3..9 {
            for u in [2, 9] {
                labels[v * 12 + u] = 0;
                z[v * 12 + u] = 0.0;
            }
        }
        let added = search(&z, &height, &mut labels);
        assert_eq!(added, 0);
    }

    #[test]
    fn a_segment_at_the_image_edge_is_searched_safely() {
        // The object fills the image's edge rows and columns: its box is
        // the whole image.
        let w = 12;
        let (z, height) = (vec![1.0; w * w], vec![0.005; w * w]);
        let mut labels = vec![0; w * w];
        for i in 0..w {
            for j in [i, w * w - 1 - i, i * w, i * w + w - 1] {
                labels[j] = 1;
            }
        }
        let added = search(&z, &height, &mut labels);
        assert_eq!(added, 1);
        assert_eq!(labels[6 * w + 6], 2);
    }

    #[test]
    fn a_small_floor_is_left_alone() {
        let (z, height, mut labels) = pot(0.005);
        let mut f = floors(&z, &height);
        f.min_pixels = 37;
        let added = label_floors(f, &mut labels, 2, &mut FloorScratch::default());
        assert_eq!(added, 0);
    }
}
