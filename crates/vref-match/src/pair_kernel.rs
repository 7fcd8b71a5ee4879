//! The spatial affinity restricted to candidate pairs (the live tier).

use crate::fast_exp::exp_neg;

/// S of ALGORITHMS.md Eq. 3 restricted to a set C of candidate pairs:
/// a dense `|C| x |C|` table of kernel values. With x zero outside C,
/// `S x` on C equals the full product's entries on C, so a method run on
/// it is the exact method with every other pair's correspondence held at
/// zero.
#[derive(Debug, Clone)]
pub struct PairAffinity {
    n: usize,
    m: usize,
    /// Flat indices `i * m + a` of the candidate pairs, ascending.
    pairs: Vec<usize>,
    /// Kernel values, row `p` and column `q` for candidate pairs `p`, `q`.
    table: Vec<f64>,
}

impl PairAffinity {
    /// `human` (`n x n`) and `robot` (`m x m`) are distance matrices, NaN
    /// where two objects are not joined by an edge.
    pub fn new(
        n: usize,
        m: usize,
        pairs: Vec<usize>,
        human: &[f64],
        robot: &[f64],
        beta: f64,
    ) -> Self {
        let geometry = Geometry::new(n, m, human, robot, beta, &pairs);
        let table = table(&geometry, pairs.len(), None);
        Self { n, m, pairs, table }
    }

    /// No candidate pairs between `n` human and `m` robot objects.
    pub fn none(n: usize, m: usize) -> Self {
        Self {
            n,
            m,
            pairs: Vec::new(),
            table: Vec::new(),
        }
    }

    /// Like [`PairAffinity::new`], but copies the kernel values of pairs
    /// that `previous` held and whose objects did not change, instead of
    /// recomputing them. `human_old[i]` is the index human object `i` had
    /// in `previous` if it did not move (likewise `robot_old`).
    #[allow(clippy::too_many_arguments)]
    pub fn updated(
        previous: PairAffinity,
        human_old: &[Option<usize>],
        robot_old: &[Option<usize>],
        n: usize,
        m: usize,
        pairs: Vec<usize>,
        human: &[f64],
        robot: &[f64],
        beta: f64,
    ) -> Self {
        let geometry = Geometry::new(n, m, human, robot, beta, &pairs);
        let in_place = n == previous.n
            && m == previous.m
            && pairs == previous.pairs
            && human_old
                .iter()
                .enumerate()
                .all(|(i, o)| o.is_none_or(|k| k == i))
            && robot_old
                .iter()
                .enumerate()
                .all(|(a, o)| o.is_none_or(|k| k == a));
        if in_place {
            let mut next = previous;
            next.refresh(human_old, robot_old, &geometry);
            return next;
        }
        let old_slot = |f: usize| -> Option<usize> {
            let (i, a) = (human_old[f / m]?, robot_old[f % m]?);
            previous.pairs.binary_search(&(i * previous.m + a)).ok()
        };
        let slots: Vec<Option<usize>> = pairs.iter().map(|&f| old_slot(f)).collect();
        let table = table(&geometry, pairs.len(), Some((&previous, &slots)));
        Self { n, m, pairs, table }
    }

    /// Same objects, same candidate pairs, some objects moved (`None` in
    /// `human_old` / `robot_old`): recomputes only the rows and columns of
    /// the pairs that hold a moved object.
    fn refresh(
        &mut self,
        human_old: &[Option<usize>],
        robot_old: &[Option<usize>],
        geometry: &Geometry<'_>,
    ) {
        let m = self.m;
        let moved: Vec<usize> = (0..self.pairs.len())
            .filter(|&p| {
                let f = self.pairs[p];
                human_old[f / m].is_none() || robot_old[f % m].is_none()
            })
            .collect();
        if moved.is_empty() {
            return;
        }
        let c = self.pairs.len();
        for &p in &moved {
            geometry.fill_row(p, &mut self.table[p * c..(p + 1) * c]);
        }
        for &p in &moved {
            for q in 0..c {
                self.table[q * c + p] = self.table[p * c + q];
            }
        }
    }

    /// Number of human and robot objects.
    pub fn shape(&self) -> (usize, usize) {
        (self.n, self.m)
    }

    /// The candidate pairs, as flat indices `i * m + a`.
    pub fn pairs(&self) -> &[usize] {
        &self.pairs
    }

    /// `out = S x` on the candidate pairs; every other entry of `out` is 0.
    pub fn mul(&self, x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        let gathered: Vec<f64> = self.pairs.iter().map(|&f| x[f]).collect();
        let c = self.pairs.len();
        for (p, &fp) in self.pairs.iter().enumerate() {
            out[fp] = dot(&self.table[p * c..(p + 1) * c], &gathered);
        }
    }
}

/// The `c x c` kernel table of `geometry`'s candidate pairs. With `reuse`
/// (a previous table and, per pair, its slot there if neither of its
/// objects changed), values between two kept pairs are copied instead of
/// recomputed.
fn table(
    geometry: &Geometry<'_>,
    c: usize,
    reuse: Option<(&PairAffinity, &[Option<usize>])>,
) -> Vec<f64> {
    let mut table = vec![0.0; c * c];
    for (p, row) in table.chunks_exact_mut(c.max(1)).enumerate().take(c) {
        match reuse.and_then(|(previous, slots)| Some((previous, slots, slots[p]?))) {
            Some((previous, slots, op)) => {
                let oc = previous.pairs.len();
                let old_row = &previous.table[op * oc..(op + 1) * oc];
                for (q, value) in row.iter_mut().enumerate() {
                    *value = match slots[q] {
                        Some(oq) => old_row[oq],
                        None => geometry.kernel(p, q),
                    };
                }
            }
            None => geometry.fill_row(p, row),
        }
    }
    table
}

/// The two distance matrices and the bandwidth a kernel value needs, with
/// the candidate pairs split into their objects once, so that filling a
/// row divides nothing.
struct Geometry<'a> {
    n: usize,
    m: usize,
    human: &'a [f64],
    robot: &'a [f64],
    inv_beta: f64,
    /// Human and robot object of every candidate pair.
    rows: Vec<usize>,
    cols: Vec<usize>,
}

impl<'a> Geometry<'a> {
    fn new(
        n: usize,
        m: usize,
        human: &'a [f64],
        robot: &'a [f64],
        beta: f64,
        pairs: &[usize],
    ) -> Self {
        Self {
            n,
            m,
            human,
            robot,
            inv_beta: 1.0 / beta,
            rows: pairs.iter().map(|&f| f / m).collect(),
            cols: pairs.iter().map(|&f| f % m).collect(),
        }
    }

    /// Kernel of candidate pairs `p = (i, a)` and `q = (j, b)`:
    /// `exp(-(s_ij - s'_ab)^2 / beta)`, zero when the pairs share an
    /// object or either distance is not an edge (NaN).
    #[inline]
    fn kernel(&self, p: usize, q: usize) -> f64 {
        let (i, a, j, b) = (self.rows[p], self.cols[p], self.rows[q], self.cols[q]);
        if i == j || a == b {
            return 0.0;
        }
        let diff = self.human[i * self.n + j] - self.robot[a * self.m + b];
        exp_neg(diff * diff * self.inv_beta)
    }

    /// Row `p` of the table: the kernel of pair `p` against every pair.
    /// Exponents first, then one pass of [`exp_neg`] over the row, which the
    /// compiler vectorises; pairs sharing an object get an infinite
    /// exponent, hence 0.
    fn fill_row(&self, p: usize, row: &mut [f64]) {
        let (i, a) = (self.rows[p], self.cols[p]);
        let human_row = &self.human[i * self.n..(i + 1) * self.n];
        let robot_row = &self.robot[a * self.m..(a + 1) * self.m];
        for ((value, &j), &b) in row.iter_mut().zip(&self.rows).zip(&self.cols) {
            let diff = human_row[j] - robot_row[b];
            *value = if j == i || b == a {
                f64::INFINITY
            } else {
                diff * diff * self.inv_beta
            };
        }
        row.iter_mut().for_each(|v| *v = exp_neg(*v));
    }
}

/// Lanes of independent partial sums: enough to fill SIMD registers.
const LANES: usize = 4;

fn dot(u: &[f64], v: &[f64]) -> f64 {
    let whole = u.len() / LANES * LANES;
    let mut acc = [0.0; LANES];
    for (uc, vc) in u[..whole]
        .chunks_exact(LANES)
        .zip(v[..whole].chunks_exact(LANES))
    {
        for l in 0..LANES {
            acc[l] += uc[l] * vc[l];
        }
    }
    let mut sum: f64 = acc.iter().sum();
    for t in whole..u.len() {
        sum += u[t] * v[t];
    }
    sum
}
