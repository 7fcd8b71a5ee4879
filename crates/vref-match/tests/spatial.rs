#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use proptest::prelude::*;
use vref_match::SpatialAffinity;
use vref_scene::{Limits, SceneGraph, SceneObject};

/// S exactly as ALGORITHMS.md Eq. 3 writes it, as a dense (nm)^2 matrix
/// over the row-major layout `i * m + a`.
fn dense(h: &SceneGraph, r: &SceneGraph, beta: f64) -> Vec<f64> {
    let (n, m) = (h.len(), r.len());
    let linked = |g: &SceneGraph, i: usize, j: usize| match g.edges() {
        None => i != j,
        Some(e) => e.contains(&(i.min(j), i.max(j))),
    };
    let dist = |g: &SceneGraph, i: usize, j: usize| {
        (g.objects()[i].position - g.objects()[j].position).norm()
    };
    let mut s = vec![0.0; (n * m) * (n * m)];
    for i in 0..n {
        for a in 0..m {
            for j in 0..n {
                for b in 0..m {
                    if i != j && a != b && linked(h, i, j) && linked(r, a, b) {
                        let d = dist(h, i, j) - dist(r, a, b);
                        s[(i * m + a) * (n * m) + j * m + b] = (-(d * d) / beta).exp();
                    }
                }
            }
        }
    }
    s
}

fn graph_strategy() -> impl Strategy<Value = SceneGraph> {
    (1usize..=7)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), n),
                prop::collection::vec((0..n, 0..n), 0..=2 * n),
                any::<bool>(),
            )
        })
        .prop_map(|(positions, pairs, connected)| {
            let objects = positions
                .iter()
                .enumerate()
                .map(|(k, p)| SceneObject::new(k as u64 * 7, *p, vec![]))
                .collect();
            let edges = (!connected).then(|| {
                pairs
                    .into_iter()
                    .filter(|(i, j)| i != j)
                    .map(|(i, j)| [i as u64 * 7, j as u64 * 7])
                    .collect()
            });
            SceneGraph::new(objects, edges, &Limits::default()).unwrap()
        })
}

proptest! {
    #[test]
    fn product_equals_the_dense_definition(
        h in graph_strategy(),
        r in graph_strategy(),
        beta in 0.05f64..2.0,
        seed in prop::collection::vec(0.0f64..1.0, 49),
    ) {
        let (n, m) = (h.len(), r.len());
        let len = n * m;
        let x: Vec<f64> = (0..len).map(|k| seed[k % seed.len()] + k as f64 * 0.01).collect();
        let s = dense(&h, &r, beta);
        let expected: Vec<f64> = (0..len).map(|row| (0..len).map(|col| s[row * len + col] * x[col]).sum()).collect();
        let spatial = SpatialAffinity::new(&h, &r, beta);
        let mut got = vec![f64::NAN; len];
        spatial.mul(&x, &mut got);
        for (g, e) in got.iter().zip(&expected) {
            prop_assert!((g - e).abs() <= 1e-9 * (1.0 + e.abs()), "got {} expected {}", g, e);
        }
        let sums = spatial.row_sums();
        for row in 0..len {
            let e: f64 = s[row * len..(row + 1) * len].iter().sum();
            prop_assert!((sums[row] - e).abs() <= 1e-9 * (1.0 + e));
        }
    }
}

#[test]
fn two_point_graphs_have_the_expected_entries() {
    let g = |d: f64| {
        let objects = vec![
            SceneObject::new(1, [0.0; 3], vec![]),
            SceneObject::new(2, [d, 0.0, 0.0], vec![]),
        ];
        SceneGraph::new(objects, None, &Limits::default()).unwrap()
    };
    let spatial = SpatialAffinity::new(&g(1.0), &g(1.5), 0.5);
    // Only (0,0)-(1,1) and (0,1)-(1,0) are consistent pairs of pairs.
    let k = (-(0.5f64 * 0.5) / 0.5).exp();
    let mut out = vec![0.0; 4];
    spatial.mul(&[1.0, 0.0, 0.0, 0.0], &mut out);
    assert_eq!(out, vec![0.0, 0.0, 0.0, k]);
    spatial.mul(&[0.0, 1.0, 0.0, 0.0], &mut out);
    assert_eq!(out, vec![0.0, 0.0, k, 0.0]);
}
