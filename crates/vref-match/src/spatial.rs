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
    /// `f`; `None` when too large to store.
    table: Option<Vec<f64>>,
}

impl SpatialAffinity {
    /// `beta` must be positive and finite (checked by [`crate::Params`]).
    pub fn new(human: &SceneGraph, robot: &SceneGraph, beta: f64) -> Self {
        Self::with_table_limit(human, robot, beta, MAX_TABLE_ENTRIES)
    }

    fn with_table_limit(human: &SceneGraph, robot: &SceneGraph, beta: f64, limit: usize) -> Self {
        let human_edges = edges_of(human);
        let robot_edges = edges_of(robot);
        let entries = human_edges.len().saturating_mul(robot_edges.len());
        let table = (entries <= limit).then(|| {
            let mut table = Vec::with_capacity(entries);
            for e in &human_edges {
                table.extend(robot_edges.iter().map(|f| kernel(e.length, f.length, beta)));
            }
            table
        });
        Self {
            n: human.len(),
            m: robot.len(),
            beta,
            human_edges,
            robot_edges,
            table,
        }
    }

    /// Number of human and robot objects.
    pub fn shape(&self) -> (usize, usize) {
        (self.n, self.m)
    }

    /// `out = S x`.
    pub fn mul(&self, x: &[f64], out: &mut [f64]) {
        let m = self.m;
        out.fill(0.0);
        let width = self.robot_edges.len();
        for (e, he) in self.human_edges.iter().enumerate() {
            let (ri, rj) = (he.i * m, he.j * m);
            for (f, re) in self.robot_edges.iter().enumerate() {
                let k = match &self.table {
                    Some(table) => table[e * width + f],
                    None => kernel(he.length, re.length, self.beta),
                };
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

    /// Row sums of S (equal to its column sums: S is symmetric).
    pub fn row_sums(&self) -> Vec<f64> {
        let ones = vec![1.0; self.n * self.m];
        let mut sums = vec![0.0; self.n * self.m];
        self.mul(&ones, &mut sums);
        sums
    }
}

fn kernel(d: f64, d2: f64, beta: f64) -> f64 {
    let diff = d - d2;
    (-(diff * diff) / beta).exp()
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
        assert!(stored.table.is_some() && recomputed.table.is_none());
        let x: Vec<f64> = (0..30).map(|k| (k as f64 * 0.37).fract()).collect();
        let (mut a, mut b) = (vec![0.0; 30], vec![0.0; 30]);
        stored.mul(&x, &mut a);
        recomputed.mul(&x, &mut b);
        assert_eq!(a, b);
    }
}
