use vref_scene::SceneGraph;

/// The `n x n` matrix of distances between a graph's objects, row-major.
/// Pairs that are not edges of a graph with an edge list are NaN: they
/// carry no spatial affinity (ALGORITHMS.md Eq. 3).
pub fn distance_matrix(graph: &SceneGraph) -> Vec<f64> {
    let objects = graph.objects();
    let n = objects.len();
    let distance = |i: usize, j: usize| (objects[i].position - objects[j].position).norm();
    match graph.edges() {
        None => {
            let mut d = vec![0.0; n * n];
            for i in 0..n {
                for j in i + 1..n {
                    let v = distance(i, j);
                    d[i * n + j] = v;
                    d[j * n + i] = v;
                }
            }
            d
        }
        Some(edges) => {
            let mut d = vec![f64::NAN; n * n];
            for &(i, j) in edges {
                let v = distance(i, j);
                d[i * n + j] = v;
                d[j * n + i] = v;
            }
            d
        }
    }
}
