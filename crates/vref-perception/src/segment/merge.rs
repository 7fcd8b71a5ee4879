//! Pieces of one object joined back: a crease inside an object (a blob's
//! fold, a teddy's arm against its body) cuts it like a crease between two
//! objects, but the piece it cuts off is small, shares much of its outline
//! with the rest across continuous depth, and has its colour.

/// What the merge reads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MergeRule {
    /// Mean absolute R, G, B difference below which two segments may be
    /// one object (0: never).
    pub colour: f32,
    /// Share of the small segment's outline that must touch the other.
    pub border: f32,
    /// Larger segments never join another.
    pub max_pixels: u32,
}

/// Scratch of the merge, kept between frames.
#[derive(Debug, Default)]
pub(crate) struct MergeScratch {
    size: Vec<u32>,
    colour: Vec<[u64; 3]>,
    outline: Vec<u32>,
    /// (small segment, neighbour) for every outline pixel of `small` next to
    /// `neighbour` across continuous depth, once per pixel and neighbour.
    touching: Vec<(u32, u32)>,
    parent: Vec<u32>,
    /// (small segment, the neighbour it joins, outline pixels they share).
    joins: Vec<(u32, u32, u32)>,
}

impl MergeScratch {
    pub(crate) fn capacity(&self) -> usize {
        self.size.capacity() * 4
            + self.colour.capacity() * 24
            + self.outline.capacity() * 4
            + self.touching.capacity() * 8
            + self.parent.capacity() * 4
            + self.joins.capacity() * 12
    }
}

fn root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

/// Joins segments of `labels` (ids below `count`, 0 none) by `rule`;
/// `continuous(p, q)` says whether neighbours `p` and `q` lie on one
/// surface. Each small segment joins the neighbour holding most of its
/// outline, the segments taken smallest first, so the result does not
/// depend on how the labels were numbered.
pub(crate) fn merge(
    labels: &mut [u32],
    count: usize,
    rgb: &[u8],
    width: usize,
    rule: MergeRule,
    continuous: impl Fn(usize, usize) -> bool,
    s: &mut MergeScratch,
) {
    if rule.colour <= 0.0 || count < 3 {
        return;
    }
    let pixels = labels.len();
    s.size.clear();
    s.size.resize(count, 0);
    s.colour.clear();
    s.colour.resize(count, [0; 3]);
    s.outline.clear();
    s.outline.resize(count, 0);
    s.touching.clear();
    for p in 0..pixels {
        let a = labels[p];
        if a == 0 {
            continue;
        }
        s.size[a as usize] += 1;
        for (c, sum) in s.colour[a as usize].iter_mut().enumerate() {
            *sum += u64::from(rgb[3 * p + c]);
        }
        let mut edge = false;
        let mut seen = [0u32; 4];
        for (k, q) in super::components::neighbours(p, width, pixels).enumerate() {
            let b = labels[q];
            if b == a {
                continue;
            }
            edge = true;
            if b != 0 && !seen.contains(&b) && continuous(p, q) {
                seen[k] = b;
                s.touching.push((a, b));
            }
        }
        if edge {
            s.outline[a as usize] += 1;
        }
    }
    s.touching.sort_unstable();
    s.parent.clear();
    s.parent.extend(0..count as u32);
    // Each small segment's candidates: larger neighbours of its colour
    // holding enough of its outline; it joins the one holding most.
    let MergeScratch {
        size,
        colour,
        outline,
        touching,
        parent,
        joins,
    } = s;
    let mean = |l: u32| -> [f32; 3] {
        let n = size[l as usize].max(1) as f32;
        colour[l as usize].map(|c| c as f32 / n)
    };
    joins.clear();
    let mut i = 0;
    while i < touching.len() {
        let (a, b) = touching[i];
        let mut n = 0u32;
        while i < touching.len() && touching[i] == (a, b) {
            n += 1;
            i += 1;
        }
        let (size_a, size_b) = (size[a as usize], size[b as usize]);
        if size_a > rule.max_pixels
            || (size_a, a) > (size_b, b)
            || (n as f32) < rule.border * outline[a as usize].max(1) as f32
        {
            continue;
        }
        let (ma, mb) = (mean(a), mean(b));
        let difference = ma.iter().zip(&mb).map(|(x, y)| (x - y).abs()).sum::<f32>() / 3.0;
        if difference >= rule.colour {
            continue;
        }
        match joins.last_mut() {
            Some(last) if last.0 == a => {
                if n > last.2 {
                    *last = (a, b, n);
                }
            }
            _ => joins.push((a, b, n)),
        }
    }
    // Smallest first, so the result does not depend on the numbering.
    joins.sort_by_key(|&(a, _, _)| (size[a as usize], a));
    for &(a, b, _) in joins.iter() {
        let (ra, rb) = (root(parent, a), root(parent, b));
        if ra != rb {
            parent[ra as usize] = rb;
        }
    }
    for l in labels.iter_mut() {
        if *l != 0 {
            *l = root(parent, *l);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 x 10 image: segment 1 the left 14 columns, segment 2 the
    /// right 6 (a piece sharing its whole left side with segment 1).
    fn two_pieces(right_colour: u8) -> (Vec<u32>, Vec<u8>) {
        let (w, h) = (20, 10);
        let mut labels = vec![0u32; w * h];
        let mut rgb = vec![0u8; 3 * w * h];
        for v in 0..h {
            for u in 0..w {
                let i = v * w + u;
                labels[i] = if u < 14 { 1 } else { 2 };
                let c = if u < 14 { 100 } else { right_colour };
                rgb[3 * i..3 * i + 3].copy_from_slice(&[c, c, c]);
            }
        }
        (labels, rgb)
    }

    const RULE: MergeRule = MergeRule {
        colour: 30.0,
        border: 0.2,
        max_pixels: 2000,
    };

    fn merged(labels: &[u32]) -> usize {
        let mut ids: Vec<u32> = labels.iter().copied().filter(|&l| l != 0).collect();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }

    #[test]
    fn a_piece_of_the_same_colour_joins_and_one_of_another_colour_stays() {
        let mut s = MergeScratch::default();
        let (mut labels, rgb) = two_pieces(110);
        merge(&mut labels, 3, &rgb, 20, RULE, |_, _| true, &mut s);
        assert_eq!(merged(&labels), 1);
        assert!(
            labels.iter().all(|&l| l == 1),
            "the smaller joins the larger"
        );

        let (mut labels, rgb) = two_pieces(180);
        merge(&mut labels, 3, &rgb, 20, RULE, |_, _| true, &mut s);
        assert_eq!(merged(&labels), 2);
    }

    #[test]
    fn a_jump_between_them_a_large_piece_or_the_rule_off_keeps_them_apart() {
        let mut s = MergeScratch::default();
        let (mut labels, rgb) = two_pieces(110);
        merge(&mut labels, 3, &rgb, 20, RULE, |_, _| false, &mut s);
        assert_eq!(merged(&labels), 2);
        let small = MergeRule {
            max_pixels: 50,
            ..RULE
        };
        merge(&mut labels, 3, &rgb, 20, small, |_, _| true, &mut s);
        assert_eq!(merged(&labels), 2);
        let off = MergeRule {
            colour: 0.0,
            ..RULE
        };
        merge(&mut labels, 3, &rgb, 20, off, |_, _| true, &mut s);
        assert_eq!(merged(&labels), 2);
    }

    #[test]
    fn numbering_the_segments_the_other_way_joins_the_same_pixels() {
        let mut s = MergeScratch::default();
        let (mut labels, rgb) = two_pieces(110);
        for l in labels.iter_mut() {
            *l = 3 - *l;
        }
        merge(&mut labels, 3, &rgb, 20, RULE, |_, _| true, &mut s);
        assert!(
            labels.iter().all(|&l| l == 2),
            "the smaller joins the larger"
        );
    }
}
