use std::cell::OnceCell;

use vref_scene::SceneGraph;

/// Kernel tables above this many entries (8 bytes each) are not stored;
/// their values are recomputed in every product instead.
const MAX_TABLE_ENTRIES: usize = 1 << 23;

/// An undirected edge between objects `i < j` of one graph, with its length.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Edge {
    i: usize,
    j: usize,
    length: f64,
}

/// The spatial affinity S of ALGORITHMS.md Eq. 3, never built densely:
/// `S[(i,a),(j,b)] = exp(-(s_ij - s'_ab)^2 / beta)` for edges `{i,j}` and
/// `{a,b}`, else 0.
///
/// Because both distance matrices are symmetric, one kernel value serves
/// the four entries `(ia,jb), (jb,ia), (ib,ja), (ja,ib)`, so S is held as a
/// table over pairs of undirected edges: `|E| x |E'|` values instead of
/// `(n m)^2`, and sparse edge lists (Delaunay) shrink it further.
#[derive(Debug, Clone)]
pub struct SpatialAffinity {
    n: usize,
    m: usize,
    beta: f64,
    human_edges: Vec<Edge>,
    robot_edges: Vec<Edge>,
    /// Kernel values, row `e` for human edge `e`, column `f` for robot edge
    /// `f`, built on the first product (a method that never multiplies by
    /// S, like `appearance`, never pays for it); never built when larger
    /// than `table_limit` entries.
    table: OnceCell<Vec<f64>>,
    table_limit: usize,
    /// Whether the robot graph is fully connected (no edge list), which
    /// allows the vectorised product.
    robot_complete: bool,
}

impl SpatialAffinity {
    /// `beta` must be positive and finite (checked by [`crate::Params`]).
    pub fn new(human: &SceneGraph, robot: &SceneGraph, beta: f64) -> Self {
        Self::with_table_limit(human, robot, beta, MAX_TABLE_ENTRIES)
    }

    fn with_table_limit(human: &SceneGraph, robot: &SceneGraph, beta: f64, limit: usize) -> Self {
        let human_edges = edges_of(human);
        let robot_edges = edges_of(robot);
        Self {
            n: human.len(),
            m: robot.len(),
            beta,
            human_edges,
            robot_edges,
            table: OnceCell::new(),
            table_limit: limit,
            robot_complete: robot.edges().is_none(),
        }
    }

    /// Fully connected graphs given by their distance matrices (`n x n`
    /// and `m x m`, row-major).
    pub fn from_distances(n: usize, m: usize, human: &[f64], robot: &[f64], beta: f64) -> Self {
        Self {
            n,
            m,
            beta,
            human_edges: complete_edges(n, human),
            robot_edges: complete_edges(m, robot),
            table: OnceCell::new(),
            table_limit: MAX_TABLE_ENTRIES,
            robot_complete: true,
        }
    }

    /// Like [`SpatialAffinity::from_distances`], with the kernel table
    /// built now: values of edge pairs whose four objects did not change
    /// are copied from `previous` instead of recomputed. `human_old[i]` is
    /// the index human object `i` had in `previous` if it did not move
    /// (likewise `robot_old`); `previous` must be fully connected too.
    pub fn updated(
        previous: &SpatialAffinity,
        human_old: &[Option<usize>],
        robot_old: &[Option<usize>],
        human: &[f64],
        robot: &[f64],
    ) -> Self {
        let (n, m) = (human_old.len(), robot_old.len());
        let next = Self::from_distances(n, m, human, robot, previous.beta);
        let entries = next
            .human_edges
            .len()
            .saturating_mul(next.robot_edges.len());
        let Some(old_table) = previous.table().filter(|_| entries <= next.table_limit) else {
            return next;
        };
        let old_edge = |edge: &Edge, map: &[Option<usize>], count: usize| -> Option<usize> {
            let (i, j) = (map[edge.i]?, map[edge.j]?);
            Some(complete_edge_index(i.min(j), i.max(j), count))
        };
        let robot_slots: Vec<Option<usize>> = next
            .robot_edges
            .iter()
            .map(|f| old_edge(f, robot_old, previous.m))
            .collect();
        let old_width = previous.robot_edges.len();
        let mut table = Vec::with_capacity(entries);
        for e in &next.human_edges {
            match old_edge(e, human_old, previous.n) {
                Some(oe) => {
                    let old_row = &old_table[oe * old_width..(oe + 1) * old_width];
                    table.extend(next.robot_edges.iter().zip(&robot_slots).map(|(f, slot)| {
                        match slot {
                            Some(of) => old_row[*of],
                            None => kernel(e.length, f.length, next.beta),
                        }
                    }));
                }
                None => table.extend(
                    next.robot_edges
                        .iter()
                        .map(|f| kernel(e.length, f.length, next.beta)),
                ),
            }
        }
        // A fresh cell cannot be full: `set` only fails on a full cell.
        let _ = next.table.set(table);
        next
    }

    /// The kernel table, built now if it has not been and may be.
    fn table(&self) -> Option<&[f64]> {
        let entries = self
            .human_edges
            .len()
            .saturating_mul(self.robot_edges.len());
        if entries > self.table_limit {
            return None;
        }
        let table = self.table.get_or_init(|| {
            let mut table = Vec::with_capacity(entries);
            for e in &self.human_edges {
                table.extend(
                    self.robot_edges
                        .iter()
                        .map(|f| kernel(e.length, f.length, self.beta)),
                );
            }
            table
        });
        Some(table)
    }

    /// Number of human and robot objects.
    pub fn shape(&self) -> (usize, usize) {
        (self.n, self.m)
    }

    /// `out = S x`.
    pub fn mul(&self, x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        if self.robot_complete {
            self.mul_complete(x, out);
        } else {
            self.mul_scatter(x, out);
        }
    }

    /// Robot graph fully connected: its edges come in the order
    /// `(0,1), (0,2), .., (0,m-1), (1,2), ..`, so the robot edges `{a, b > a}`
    /// of one human edge `{i, j}` touch the contiguous tails `b > a` of rows
    /// i and j of x and out. The four updates of one kernel value then
    /// become two dot products and two axpys over contiguous slices, which
    /// the compiler vectorises, instead of four scattered read-modify-writes.
    fn mul_complete(&self, x: &[f64], out: &mut [f64]) {
        let m = self.m;
        let mut scratch = Vec::new();
        for (e, he) in self.human_edges.iter().enumerate() {
            let (i, j) = (he.i.min(he.j), he.i.max(he.j));
            if i == j {
                continue;
            }
            let row = self.kernel_row(e, &mut scratch);
            let (low, high) = out.split_at_mut(j * m);
            let (oi, oj) = (&mut low[i * m..(i + 1) * m], &mut high[..m]);
            let (xi, xj) = (&x[i * m..(i + 1) * m], &x[j * m..(j + 1) * m]);
            let mut offset = 0;
            for a in 0..m {
                let tail = m - a - 1;
                let k = &row[offset..offset + tail];
                offset += tail;
                let (oia, oi_tail) = oi[a..].split_at_mut(1);
                let (oja, oj_tail) = oj[a..].split_at_mut(1);
                let (si, sj) = edge_block(
                    k,
                    &xi[a + 1..],
                    &xj[a + 1..],
                    xi[a],
                    xj[a],
                    oi_tail,
                    oj_tail,
                );
                oia[0] += si;
                oja[0] += sj;
            }
        }
    }

    /// Any robot edge list: each kernel value updates its four entries.
    fn mul_scatter(&self, x: &[f64], out: &mut [f64]) {
        let m = self.m;
        let mut scratch = Vec::new();
        for (e, he) in self.human_edges.iter().enumerate() {
            let (ri, rj) = (he.i * m, he.j * m);
            let row = self.kernel_row(e, &mut scratch);
            for (&k, re) in row.iter().zip(&self.robot_edges) {
                if k == 0.0 {
                    continue;
                }
                let (a, b) = (re.i, re.j);
                out[ri + a] += k * x[rj + b];
                out[rj + b] += k * x[ri + a];
                out[ri + b] += k * x[rj + a];
                out[rj + a] += k * x[ri + b];
            }
        }
    }

    /// The kernel values of human edge `e` against every robot edge: a row
    /// of the table, or computed into `scratch` when there is no table.
    fn kernel_row<'a>(&'a self, e: usize, scratch: &'a mut Vec<f64>) -> &'a [f64] {
        let width = self.robot_edges.len();
        match self.table() {
            Some(table) => &table[e * width..(e + 1) * width],
            None => {
                let length = self.human_edges[e].length;
                scratch.clear();
                scratch.extend(
                    self.robot_edges
                        .iter()
                        .map(|f| kernel(length, f.length, self.beta)),
                );
                scratch
            }
        }
    }

    /// Row sums of S (equal to its column sums: S is symmetric).
    pub fn row_sums(&self) -> Vec<f64> {
        let ones = vec![1.0; self.n * self.m];
        let mut sums = vec![0.0; self.n * self.m];
        self.mul(&ones, &mut sums);
        sums
    }
}

/// Lanes of the independent partial sums in [`edge_block`]: enough for the
/// compiler to fill SIMD registers without reassociating one float sum.
const LANES: usize = 4;

/// For one human edge `{i, j}` and robot object `a`, the robot edges
/// `{a, b}` for `b > a` with kernel values `k`: adds `k[b] x_j[a]` to
/// `out_i[b]` and `k[b] x_i[a]` to `out_j[b]`, and returns
/// `(sum_b k[b] x_j[b], sum_b k[b] x_i[b])`, the updates of `out_i[a]` and
/// `out_j[a]`. All slices start at `b = a + 1`.
#[allow(clippy::too_many_arguments)]
fn edge_block(
    k: &[f64],
    xi: &[f64],
    xj: &[f64],
    xia: f64,
    xja: f64,
    oi: &mut [f64],
    oj: &mut [f64],
) -> (f64, f64) {
    let len = k.len();
    let (xi, xj) = (&xi[..len], &xj[..len]);
    let (oi, oj) = (&mut oi[..len], &mut oj[..len]);
    let whole = len / LANES * LANES;
    let (mut si, mut sj) = ([0.0; LANES], [0.0; LANES]);
    for ((((kc, xic), xjc), oic), ojc) in k[..whole]
        .chunks_exact(LANES)
        .zip(xi.chunks_exact(LANES))
        .zip(xj.chunks_exact(LANES))
        .zip(oi.chunks_exact_mut(LANES))
        .zip(oj.chunks_exact_mut(LANES))
    {
        for l in 0..LANES {
            si[l] += kc[l] * xjc[l];
            sj[l] += kc[l] * xic[l];
            oic[l] += kc[l] * xja;
            ojc[l] += kc[l] * xia;
        }
    }
    let (mut si, mut sj) = (si.iter().sum::<f64>(), sj.iter().sum::<f64>());
    for t in whole..len {
        si += k[t] * xj[t];
        sj += k[t] * xi[t];
        oi[t] += k[t] * xja;
        oj[t] += k[t] * xia;
    }
    (si, sj)
}

fn kernel(d: f64, d2: f64, beta: f64) -> f64 {
    let diff = d - d2;
    (-(diff * diff) / beta).exp()
}

/// Edges `(0,1), (0,2), .., (1,2), ..` of a complete graph of `n` objects
/// with the lengths of distance matrix `d`.
fn complete_edges(n: usize, d: &[f64]) -> Vec<Edge> {
    (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
        .map(|(i, j)| Edge {
            i,
            j,
            length: d[i * n + j],
        })
        .collect()
}

/// Position of edge `(i, j)`, `i < j`, in [`complete_edges`] of `n` objects.
fn complete_edge_index(i: usize, j: usize, n: usize) -> usize {
    i * (2 * n - i - 1) / 2 + (j - i - 1)
}

fn edges_of(graph: &SceneGraph) -> Vec<Edge> {
    let objects = graph.objects();
    let edge = |i: usize, j: usize| Edge {
        i,
        j,
        length: (objects[i].position - objects[j].position).norm(),
    };
    match graph.edges() {
        Some(list) => list.iter().map(|&(i, j)| edge(i, j)).collect(),
        None => (0..objects.len())
            .flat_map(|i| (i + 1..objects.len()).map(move |j| (i, j)))
            .map(|(i, j)| edge(i, j))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use vref_scene::{Limits, SceneObject};

    use super::*;

    fn graph(n: usize, scale: f64) -> SceneGraph {
        let objects = (0..n)
            .map(|k| {
                let t = k as f64;
                SceneObject::new(
                    k as u64,
                    [scale * t.sin(), scale * (1.7 * t).cos(), 0.3 * t],
                    vec![],
                )
            })
            .collect();
        SceneGraph::new(objects, None, &Limits::default()).unwrap()
    }

    #[test]
    fn recomputed_kernel_equals_stored_table() {
        let (h, r) = (graph(6, 1.0), graph(5, 1.1));
        let stored = SpatialAffinity::with_table_limit(&h, &r, 0.3, usize::MAX);
        let recomputed = SpatialAffinity::with_table_limit(&h, &r, 0.3, 0);
        assert!(stored.table().is_some() && recomputed.table().is_none());
        let x: Vec<f64> = (0..30).map(|k| (k as f64 * 0.37).fract()).collect();
        let (mut a, mut b) = (vec![0.0; 30], vec![0.0; 30]);
        stored.mul(&x, &mut a);
        recomputed.mul(&x, &mut b);
        assert_eq!(a, b);
    }
}
