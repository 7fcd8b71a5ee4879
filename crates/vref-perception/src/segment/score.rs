//! How well a label image matches the ground truth, by the protocol of
//! the unseen-object segmentation literature (UOIS-Net, UCN) as
//! ../shared/data/osd/PROVENANCE.md states it:
//!
//! - ground-truth objects are the labels at or above a threshold (20 in
//!   OSD; lower ones are the table and no reading, never objects);
//!   every non-zero predicted label is one predicted object;
//! - objects are paired one to one by the Hungarian method on the Dice
//!   score F of each pair;
//! - overlap P = the paired intersections / all predicted object pixels,
//!   R = the same / all ground-truth object pixels;
//! - boundary P/R: the same over 1-pixel outlines (an object's pixels
//!   with a 4-neighbour outside it or beyond the image), a pixel counting
//!   as hit when within `ceil(0.003 * diagonal)` pixels (Euclidean) of
//!   its partner's outline;
//! - %75: pairs with F > 0.75 over ground-truth objects.
//!
//! Predicted pixels over the table or over no reading count as predicted
//! object pixels (they are false positives); only the ground truth's
//! table and no-reading labels are not objects.

use std::collections::BTreeMap;

/// Precision, recall and their harmonic mean.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Prf {
    pub precision: f64,
    pub recall: f64,
    pub f: f64,
}

impl Prf {
    fn new(hit_p: f64, total_p: f64, hit_r: f64, total_r: f64) -> Self {
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        let (precision, recall) = (ratio(hit_p, total_p), ratio(hit_r, total_r));
        let f = if precision + recall > 0.0 {
            2.0 * precision * recall / (precision + recall)
        } else {
            0.0
        };
        Self {
            precision,
            recall,
            f,
        }
    }
}

/// One image's scores.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ImageScore {
    pub overlap: Prf,
    pub boundary: Prf,
    /// Ground-truth objects paired with F > 0.75, over ground-truth
    /// objects.
    pub p75: f64,
    pub gt_objects: usize,
    pub predicted_objects: usize,
}

/// Why two label images cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScoreError {
    #[error(
        "a {width}x{height} image has {expected} pixels, but the prediction has {predicted} and the ground truth {truth}"
    )]
    Size {
        width: u32,
        height: u32,
        expected: usize,
        predicted: usize,
        truth: usize,
    },
}

/// One object's pixels (indices) and outline pixels.
#[derive(Debug, Default)]
struct Object {
    pixels: usize,
    outline: Vec<(u32, u32)>,
}

/// Objects of a label image: labels `>= first` (0 is never one).
fn objects(labels: &[u16], width: usize, first: u16) -> (BTreeMap<u16, usize>, Vec<Object>) {
    let mut index = BTreeMap::new();
    let mut objects: Vec<Object> = Vec::new();
    let height = labels.len().checked_div(width).unwrap_or(0);
    for (i, &l) in labels.iter().enumerate() {
        if l == 0 || l < first {
            continue;
        }
        let k = *index.entry(l).or_insert_with(|| {
            objects.push(Object::default());
            objects.len() - 1
        });
        let (u, v) = (i % width, i / width);
        let inside = |uu: Option<usize>, vv: Option<usize>| match (uu, vv) {
            (Some(uu), Some(vv)) if uu < width && vv < height => labels[vv * width + uu] == l,
            _ => false,
        };
        let edge = !inside(u.checked_sub(1), Some(v))
            || !inside(Some(u + 1), Some(v))
            || !inside(Some(u), v.checked_sub(1))
            || !inside(Some(u), Some(v + 1));
        if let Some(o) = objects.get_mut(k) {
            o.pixels += 1;
            if edge {
                o.outline.push((u as u32, v as u32));
            }
        }
    }
    (index, objects)
}

/// How many of `a`'s outline pixels lie within `radius` of `b`'s.
fn near(a: &[(u32, u32)], b: &[(u32, u32)], radius: u32) -> usize {
    let Some(&(u0, v0)) = b.first() else {
        return 0;
    };
    let (mut umin, mut umax, mut vmin, mut vmax) = (u0, u0, v0, v0);
    for &(u, v) in b {
        (umin, umax) = (umin.min(u), umax.max(u));
        (vmin, vmax) = (vmin.min(v), vmax.max(v));
    }
    let (umin, vmin) = (umin.saturating_sub(radius), vmin.saturating_sub(radius));
    let (bw, bh) = (
        (umax + radius - umin + 1) as usize,
        (vmax + radius - vmin + 1) as usize,
    );
    let mut grid = vec![false; bw * bh];
    let r = radius as i64;
    for &(u, v) in b {
        for dv in -r..=r {
            for du in -r..=r {
                if du * du + dv * dv > r * r {
                    continue;
                }
                let (uu, vv) = (i64::from(u) + du, i64::from(v) + dv);
                let (gu, gv) = (uu - i64::from(umin), vv - i64::from(vmin));
                if gu >= 0 && gv >= 0 && (gu as usize) < bw && (gv as usize) < bh {
                    grid[gv as usize * bw + gu as usize] = true;
                }
            }
        }
    }
    a.iter()
        .filter(|&&(u, v)| {
            let (gu, gv) = (u.wrapping_sub(umin) as usize, v.wrapping_sub(vmin) as usize);
            gu < bw && gv < bh && grid[gv * bw + gu]
        })
        .count()
}

/// Scores `predicted` against `truth` (both `width` x `height`), ground
/// truth objects being the labels at or above `first_object`.
pub fn score_image(
    predicted: &[u16],
    truth: &[u16],
    width: u32,
    height: u32,
    first_object: u16,
) -> Result<ImageScore, ScoreError> {
    let n = width as usize * height as usize;
    if predicted.len() != n || truth.len() != n {
        return Err(ScoreError::Size {
            width,
            height,
            expected: n,
            predicted: predicted.len(),
            truth: truth.len(),
        });
    }
    let w = width as usize;
    let (gt_index, gt) = objects(truth, w, first_object.max(1));
    let (pred_index, pred) = objects(predicted, w, 1);
    let (ng, np) = (gt.len(), pred.len());
    let mut intersection = vec![0usize; ng * np];
    for (&t, &p) in truth.iter().zip(predicted) {
        if let (Some(&g), Some(&q)) = (gt_index.get(&t), pred_index.get(&p)) {
            intersection[g * np + q] += 1;
        }
    }
    let dice = |g: usize, q: usize| {
        let i = intersection[g * np + q] as f64;
        let total = (gt[g].pixels + pred[q].pixels) as f64;
        if total > 0.0 { 2.0 * i / total } else { 0.0 }
    };
    let mut f = vec![0.0; ng * np];
    for g in 0..ng {
        for q in 0..np {
            f[g * np + q] = dice(g, q);
        }
    }
    let pairs = assign(&f, ng, np);
    let gt_pixels: usize = gt.iter().map(|o| o.pixels).sum();
    let pred_pixels: usize = pred.iter().map(|o| o.pixels).sum();
    let hit: usize = pairs.iter().map(|&(g, q)| intersection[g * np + q]).sum();
    let overlap = Prf::new(hit as f64, pred_pixels as f64, hit as f64, gt_pixels as f64);
    let radius = (0.003 * f64::from(width).hypot(f64::from(height))).ceil() as u32;
    let (mut hit_p, mut hit_r) = (0usize, 0usize);
    for &(g, q) in &pairs {
        hit_p += near(&pred[q].outline, &gt[g].outline, radius);
        hit_r += near(&gt[g].outline, &pred[q].outline, radius);
    }
    let gt_outline: usize = gt.iter().map(|o| o.outline.len()).sum();
    let pred_outline: usize = pred.iter().map(|o| o.outline.len()).sum();
    let boundary = Prf::new(
        hit_p as f64,
        pred_outline as f64,
        hit_r as f64,
        gt_outline as f64,
    );
    let good = pairs.iter().filter(|&&(g, q)| f[g * np + q] > 0.75).count();
    let p75 = if ng > 0 { good as f64 / ng as f64 } else { 0.0 };
    Ok(ImageScore {
        overlap,
        boundary,
        p75,
        gt_objects: ng,
        predicted_objects: np,
    })
}

/// Mean scores over images (each image counts once).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct MeanScore {
    pub images: usize,
    pub overlap: Prf,
    pub boundary: Prf,
    pub p75: f64,
}

impl MeanScore {
    pub fn of(scores: &[ImageScore]) -> Self {
        let n = scores.len().max(1) as f64;
        let mean = |get: &dyn Fn(&ImageScore) -> f64| scores.iter().map(get).sum::<f64>() / n;
        Self {
            images: scores.len(),
            overlap: Prf {
                precision: mean(&|s| s.overlap.precision),
                recall: mean(&|s| s.overlap.recall),
                f: mean(&|s| s.overlap.f),
            },
            boundary: Prf {
                precision: mean(&|s| s.boundary.precision),
                recall: mean(&|s| s.boundary.recall),
                f: mean(&|s| s.boundary.f),
            },
            p75: mean(&|s| s.p75),
        }
    }
}

/// The one-to-one pairing of rows and columns of the `rows` x `cols`
/// score matrix `f` with the largest total (Hungarian method, O(n^3),
/// the shortest augmenting path form with potentials). Returns
/// (row, column) pairs; pairs of score 0 (no overlap) are left out.
pub fn assign(f: &[f64], rows: usize, cols: usize) -> Vec<(usize, usize)> {
    if rows == 0 || cols == 0 {
        return Vec::new();
    }
    // The method needs rows <= columns: transpose otherwise.
    let transposed = rows > cols;
    let (n, m) = if transposed {
        (cols, rows)
    } else {
        (rows, cols)
    };
    let cost = |i: usize, j: usize| {
        let value = if transposed {
            f[j * cols + i]
        } else {
            f[i * cols + j]
        };
        -value
    };
    // 1-based arrays as in the classic formulation; index 0 is the
    // virtual start.
    let mut u = vec![0.0f64; n + 1];
    let mut v = vec![0.0f64; m + 1];
    let mut p = vec![0usize; m + 1];
    let mut way = vec![0usize; m + 1];
    for i in 1..=n {
        p[0] = i;
        let mut j0 = 0usize;
        let mut minv = vec![f64::INFINITY; m + 1];
        let mut used = vec![false; m + 1];
        loop {
            used[j0] = true;
            let i0 = p[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0usize;
            for j in 1..=m {
                if !used[j] {
                    let cur = cost(i0 - 1, j - 1) - u[i0] - v[j];
                    if cur < minv[j] {
                        minv[j] = cur;
                        way[j] = j0;
                    }
                    if minv[j] < delta {
                        delta = minv[j];
                        j1 = j;
                    }
                }
            }
            if j1 == 0 {
                // Only on NaN scores: stop with what is paired.
                break;
            }
            for j in 0..=m {
                if used[j] {
                    u[p[j]] += delta;
                    v[j] -= delta;
                } else {
                    minv[j] -= delta;
                }
            }
            j0 = j1;
            if p[j0] == 0 {
                break;
            }
        }
        loop {
            let j1 = way[j0];
            p[j0] = p[j1];
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    let mut pairs = Vec::new();
    for (j, &row) in p.iter().enumerate().skip(1) {
        if row != 0 {
            let (r, c) = if transposed {
                (j - 1, row - 1)
            } else {
                (row - 1, j - 1)
            };
            if f[r * cols + c] > 0.0 {
                pairs.push((r, c));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn assignment_takes_the_best_total_not_the_greedy_pick() {
        // Greedy would take (0, 0) = 0.9 and be left with (1, 1) = 0.1.
        let f = [0.9, 0.8, 0.7, 0.1];
        assert_eq!(assign(&f, 2, 2), vec![(0, 1), (1, 0)]);
        // More rows than columns: one row stays unpaired.
        let f = [0.2, 0.9, 0.5];
        assert_eq!(assign(&f, 3, 1), vec![(1, 0)]);
    }

    #[test]
    fn a_perfect_prediction_scores_one_and_a_split_object_less() {
        let (w, h) = (20u32, 10u32);
        let mut truth = vec![0u16; 200];
        for v in 2..8 {
            for u in 2..18 {
                truth[v * 20 + u] = if u < 10 { 20 } else { 30 };
            }
        }
        let pred: Vec<u16> = truth.iter().map(|&t| t / 10).collect();
        let s = score_image(&pred, &truth, w, h, 20).unwrap();
        assert_eq!((s.overlap.f, s.boundary.f, s.p75), (1.0, 1.0, 1.0));
        // Both objects as one: half the pixels are paired.
        let merged: Vec<u16> = truth.iter().map(|&t| u16::from(t > 0)).collect();
        let s = score_image(&merged, &truth, w, h, 20).unwrap();
        assert!((s.overlap.precision - 0.5).abs() < 1e-12, "{s:?}");
        assert!((s.overlap.recall - 0.5).abs() < 1e-12);
        assert_eq!(s.p75, 0.0);
        assert!(s.boundary.f < 1.0);
    }
}
