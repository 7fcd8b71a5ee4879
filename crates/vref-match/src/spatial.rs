use std::cell::OnceCell;

use vref_scene::SceneGraph;

use crate::edge_product::{
    Kernel, block_slot, block_slots, edge_product, extend_kernel_row, padded,
};

/// Kernel tables above this many entries (4 bytes each) are not stored;
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
    /// The robot edge length of each column of the table, contiguous for
    /// the table's vectorised `exp`: the robot edges in order for an edge
    /// list; for a fully connected robot graph the layout of
    /// [`block_slots`], infinite (kernel 0) on its padding.
    slot_lengths: Vec<f64>,
    /// Kernel values, row `e` for human edge `e`, columns as
    /// `slot_lengths`, built on the first product (a method that never multiplies by
    /// S, like `appearance`, never pays for it); never built when larger
    /// than `table_limit` entries.
    table: OnceCell<Vec<Kernel>>,
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
        let robot_complete = robot.edges().is_none();
        Self {
            n: human.len(),
            m: robot.len(),
            beta,
            human_edges,
            slot_lengths: slot_lengths(&robot_edges, robot.len(), robot_complete),
            robot_edges,
            table: OnceCell::new(),
            table_limit: limit,
            robot_complete,
        }
    }

    /// Fully connected graphs given by their distance matrices (`n x n`
    /// and `m x m`, row-major).
    pub fn from_distances(n: usize, m: usize, human: &[f64], robot: &[f64], beta: f64) -> Self {
        let robot_edges = complete_edges(m, robot);
        Self {
            n,
            m,
            beta,
            human_edges: complete_edges(n, human),
            slot_lengths: slot_lengths(&robot_edges, m, true),
            robot_edges,
            table: OnceCell::new(),
            table_limit: MAX_TABLE_ENTRIES,
            robot_complete: true,
        }
    }

    /// Like [`SpatialAffinity::from_distances`], with the kernel table
    /// built now: values of edge pairs whose four objects did not change
    /// are taken from `previous` instead of recomputed. `human_old[i]` is
    /// the index human object `i` had in `previous` if it did not move
    /// (likewise `robot_old`); `previous` must be fully connected too.
    pub fn updated(
        previous: SpatialAffinity,
        human_old: &[Option<usize>],
        robot_old: &[Option<usize>],
        human: &[f64],
        robot: &[f64],
    ) -> Self {
        let (n, m) = (human_old.len(), robot_old.len());
        let next = Self::from_distances(n, m, human, robot, previous.beta);
        let width = next.slot_lengths.len();
        let entries = next.human_edges.len().saturating_mul(width);
        // Same objects in the same places, only some human objects moved:
        // the old table is kept and only the rows of human edges that touch
        // a moved object are recomputed (copying megabytes into fresh
        // memory cost more than the kernel values it saved).
        let in_place = n == previous.n
            && m == previous.m
            && previous.robot_complete
            && entries <= next.table_limit
            && robot_old.iter().enumerate().all(|(a, old)| *old == Some(a))
            && human_old
                .iter()
                .enumerate()
                .all(|(i, old)| old.is_none_or(|k| k == i));
        if in_place {
            if let Some(mut table) = previous.table.into_inner() {
                let mut fresh = Vec::with_capacity(width);
                for (edge, row) in next.human_edges.iter().zip(table.chunks_exact_mut(width)) {
                    if human_old[edge.i].is_none() || human_old[edge.j].is_none() {
                        fresh.clear();
                        extend_kernel_row(&mut fresh, edge.length, &next.slot_lengths, next.beta);
                        row.copy_from_slice(&fresh);
                    }
                }
                // A fresh cell cannot be full: `set` only fails on a full cell.
                let _ = next.table.set(table);
            }
            return next;
        }
        let Some(old_table) = previous
            .table()
            .filter(|_| entries <= next.table_limit && previous.robot_complete)
        else {
            return next;
        };
        let old_edge = |edge: &Edge, map: &[Option<usize>], count: usize| -> Option<usize> {
            let (i, j) = (map[edge.i]?, map[edge.j]?);
            Some(complete_edge_index(i.min(j), i.max(j), count))
        };
        // The old table's column of each of the new one's, where both
        // robot objects kept their position.
        let old_columns: Vec<Option<usize>> = block_slots(m)
            .into_iter()
            .map(|slot| {
                let (a, b) = slot?;
                let (a, b) = (robot_old[a]?, robot_old[b]?);
                Some(block_slot(a.min(b), a.max(b), previous.m))
            })
            .collect();
        // The new columns' lengths, for the kernel values computed anew by
        // the same (vectorised, dispatched) code as a fresh table's, so that
        // the table equals a fresh one bit for bit.
        let new_lengths: Vec<f64> = next
            .slot_lengths
            .iter()
            .zip(&old_columns)
            .filter(|(_, column)| column.is_none())
            .map(|(&length, _)| length)
            .collect();
        let old_width = previous.slot_lengths.len();
        let mut table = Vec::with_capacity(entries);
        let mut fresh = Vec::with_capacity(new_lengths.len());
        // Robot objects all unchanged and in place: a kept human edge's row
        // is its old row, copied whole.
        let robot_same =
            m == previous.m && robot_old.iter().enumerate().all(|(a, old)| *old == Some(a));
        for e in &next.human_edges {
            match old_edge(e, human_old, previous.n) {
                Some(oe) if robot_same => {
                    table.extend_from_slice(&old_table[oe * old_width..(oe + 1) * old_width]);
                }
                Some(oe) => {
                    let old_row = &old_table[oe * old_width..(oe + 1) * old_width];
                    fresh.clear();
                    extend_kernel_row(&mut fresh, e.length, &new_lengths, next.beta);
                    let mut fresh = fresh.iter();
                    table.extend(old_columns.iter().map(|column| match column {
                        Some(c) => old_row[*c],
                        None => fresh.next().copied().unwrap_or(0.0),
                    }));
                }
                None => extend_kernel_row(&mut table, e.length, &next.slot_lengths, next.beta),
            }
        }
        // A fresh cell cannot be full: `set` only fails on a full cell.
        let _ = next.table.set(table);
        next
    }

    /// The kernel table, built now if it has not been and may be.
    fn table(&self) -> Option<&[Kernel]> {
        let entries = self
            .human_edges
            .len()
            .saturating_mul(self.slot_lengths.len());
        if entries > self.table_limit {
            return None;
        }
        let table = self.table.get_or_init(|| {
            let mut table = Vec::with_capacity(entries);
            for e in &self.human_edges {
                extend_kernel_row(&mut table, e.length, &self.slot_lengths, self.beta);
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

    /// Robot graph fully connected: one human edge `{i, j}` adds `K x_j`
    /// to row i of out and `K x_i` to row j, K symmetric, held as
    /// [`edge_product`] lays it out, whose loops run over whole vectors of
    /// contiguous row slices instead of four scattered read-modify-writes
    /// per kernel value. Rows whose length is not whole vectors are copied
    /// into zero-padded rows first.
    fn mul_complete(&self, x: &[f64], out: &mut [f64]) {
        let (n, m, p) = (self.n, self.m, padded(self.m));
        if p == m {
            self.mul_padded(x, out);
            return;
        }
        let mut x_padded = vec![0.0; n * p];
        let mut out_padded = vec![0.0; n * p];
        for (to, from) in x_padded.chunks_exact_mut(p).zip(x.chunks_exact(m)) {
            to[..m].copy_from_slice(from);
        }
        self.mul_padded(&x_padded, &mut out_padded);
        for (to, from) in out.chunks_exact_mut(m).zip(out_padded.chunks_exact(p)) {
            to.copy_from_slice(&from[..m]);
        }
    }

    /// [`SpatialAffinity::mul_complete`] on rows of [`padded`] length.
    fn mul_padded(&self, x: &[f64], out: &mut [f64]) {
        let (m, p) = (self.m, padded(self.m));
        let mut scratch = Vec::new();
        for (e, he) in self.human_edges.iter().enumerate() {
            let (i, j) = (he.i.min(he.j), he.i.max(he.j));
            if i == j {
                continue;
            }
            let row = self.kernel_row(e, &mut scratch);
            let (low, high) = out.split_at_mut(j * p);
            let (oi, oj) = (&mut low[i * p..(i + 1) * p], &mut high[..p]);
            let (xi, xj) = (&x[i * p..(i + 1) * p], &x[j * p..(j + 1) * p]);
            edge_product(m, row, xi, xj, oi, oj);
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
                let k = f64::from(k);
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
    fn kernel_row<'a>(&'a self, e: usize, scratch: &'a mut Vec<Kernel>) -> &'a [Kernel] {
        let width = self.slot_lengths.len();
        match self.table() {
            Some(table) => &table[e * width..(e + 1) * width],
            None => {
                let length = self.human_edges[e].length;
                scratch.clear();
                extend_kernel_row(scratch, length, &self.slot_lengths, self.beta);
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

/// The robot lengths of the table's columns (see
/// [`SpatialAffinity::slot_lengths`]).
fn slot_lengths(robot_edges: &[Edge], m: usize, complete: bool) -> Vec<f64> {
    if !complete {
        return robot_edges.iter().map(|f| f.length).collect();
    }
    block_slots(m)
        .into_iter()
        .map(|slot| match slot {
            Some((a, b)) => robot_edges[complete_edge_index(a, b, m)].length,
            None => f64::INFINITY,
        })
        .collect()
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
    fn updated_table_equals_a_fresh_one() {
        let (n, m) = (7, 6);
        let distances = |count: usize, shift: f64| -> Vec<f64> {
            (0..count * count)
                .map(|k| {
                    let (i, j) = (k / count, k % count);
                    if i == j {
                        0.0
                    } else {
                        0.1 * (i + j) as f64 + shift * (i * j) as f64
                    }
                })
                .collect()
        };
        let previous =
            SpatialAffinity::from_distances(n, m, &distances(n, 0.01), &distances(m, 0.02), 0.3);
        assert!(previous.table().is_some());
        // Human object 2 and robot object 4 moved (their distances change);
        // the others kept their index.
        let human_old: Vec<Option<usize>> = (0..n).map(|i| (i != 2).then_some(i)).collect();
        let robot_old: Vec<Option<usize>> = (0..m).map(|a| (a != 4).then_some(a)).collect();
        let mut human = distances(n, 0.01);
        let mut robot = distances(m, 0.02);
        for k in 0..n {
            if k != 2 {
                human[2 * n + k] += 0.05;
                human[k * n + 2] += 0.05;
            }
        }
        for k in 0..m {
            if k != 4 {
                robot[4 * m + k] += 0.07;
                robot[k * m + 4] += 0.07;
            }
        }
        let updated =
            SpatialAffinity::updated(previous.clone(), &human_old, &robot_old, &human, &robot);
        let fresh = SpatialAffinity::from_distances(n, m, &human, &robot, 0.3);
        assert_eq!(updated.table(), fresh.table());
        assert_ne!(updated.table(), previous.table());
        // Only the human object moved: the old table is updated in place.
        let in_place: Vec<Option<usize>> = (0..m).map(Some).collect();
        let robot = distances(m, 0.02);
        let updated =
            SpatialAffinity::updated(previous.clone(), &human_old, &in_place, &human, &robot);
        let fresh = SpatialAffinity::from_distances(n, m, &human, &robot, 0.3);
        assert_eq!(updated.table(), fresh.table());
        assert_ne!(updated.table(), previous.table());
        // Human object 2 left: the others' rows are copied whole.
        let kept: Vec<usize> = (0..n).filter(|&i| i != 2).collect();
        let human_old: Vec<Option<usize>> = kept.iter().map(|&i| Some(i)).collect();
        let old_human = distances(n, 0.01);
        let human: Vec<f64> = kept
            .iter()
            .flat_map(|&i| kept.iter().map(move |&j| (i, j)))
            .map(|(i, j)| old_human[i * n + j])
            .collect();
        let updated =
            SpatialAffinity::updated(previous.clone(), &human_old, &in_place, &human, &robot);
        let fresh = SpatialAffinity::from_distances(n - 1, m, &human, &robot, 0.3);
        assert_eq!(updated.table(), fresh.table());
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
